// btgen runtime: a scenario runner for any generated mission.
//
//     prog SCENARIO_FILE
//
// reads the scenario (errors and warnings on stderr as path:line:col, before
// any trace; exit status 1 on errors), then sends up to `ticks` ticks to the
// root as tests/conformance/FORMAT.md's Execution section says and prints
// the status trace on stdout (a run-time error, printed on stderr, ends the
// run after its tick with exit status 1):
//
//     tick <n>
//     <uid> <ID> "<name>" <FROM> -> <TO>
//     result <STATUS>
//
// Use it through runtime/src/main_driver.cpp, or call
// btgen::run_scenario_main<lab_tour::LabTour>(argc, argv) from your own main.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "btgen/clock.hpp"
#include "btgen/harness/scenario.hpp"
#include "btgen/harness/scenario_run.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"

namespace btgen {

// The scenario runner's observer: TraceWriter's trace and error, up to the
// first run-time error. 4.6.2 throws there, which ends the tick at once; the
// engine fails the node and goes on (a robot keeps running), so the runner
// prints nothing after the first error, giving 4.6.2's trace.
class TraceUntilError {
 public:
  explicit TraceUntilError(std::FILE* out) noexcept : trace_(out) {}

  void on_status_change(const NodeInfo& node, Status from, Status to) const noexcept {
    if (!stopped_) trace_.on_status_change(node, from, to);
  }

  void on_error(const RuntimeError& e) const noexcept {
    if (stopped_) return;
    trace_.on_error(e);
    stopped_ = true;
  }

 private:
  TraceWriter trace_;
  mutable bool stopped_ = false;
};

template <template <class, class, class> class Mission>
int run_scenario_main(int argc, char** argv) {
  using Runner = Mission<ScenarioLeaves, ManualClock, TraceUntilError>;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SCENARIO_FILE\n", argc > 0 ? argv[0] : "mission");
    return 2;
  }
  std::vector<Diagnostic> diags;
  Scenario scenario;
  const auto& nodes = Runner::nodes();
  bool ok = read_scenario(argv[1], scenario, diags);
  if (ok) {
    const auto& unrun = Runner::unrun_leaves();
    ok = check_scenario(scenario, nodes.data(), nodes.size(), diags, unrun.data(), unrun.size(), Runner::main_tree());
  }
  for (const auto& d : diags) std::fprintf(stderr, "%s\n", d.str().c_str());
  if (!ok) return 1;

  ScenarioLeaves leaves(scenario, nodes.data(), nodes.size());
  auto mission = std::make_unique<Runner>(leaves, ManualClock{}, TraceUntilError{stdout});
  const bool ran = run_scenario_ticks(
      *mission, scenario.ticks, scenario.clock_ms, [](long n) { std::printf("tick %ld\n", n); },
      [](Status s) { std::printf("result %s\n", std::string(to_string(s)).c_str()); });
  // !ran: a run-time error (TraceWriter printed it on stderr) ended the run
  // after its tick, without a result line, as the interpreter stops.
  const bool flushed = std::fflush(stdout) == 0;
  return ran && flushed ? 0 : 1;
}

}  // namespace btgen
