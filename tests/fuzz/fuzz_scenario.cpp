// libFuzzer target: the scenario reader and checker, then a run of a
// generated mission (tests/cpp/missions/control_flow.xml: every node kind of
// the C++ back end) on the scenario, as the scenario runner does, with the
// number of ticks capped so that one input stays fast.
#include <cstdlib>
#include <memory>
#include <vector>

#include "btgen/clock.hpp"
#include "btgen/harness/scenario.hpp"
#include "btgen/trace.hpp"
#include "control_flow.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using Runner = control_flow::ControlFlow<btgen::ScenarioLeaves, btgen::ManualClock, btgen::TraceWriter>;
  const std::string path = btgen_fuzz::write_file("s.scenario", data, size);
  std::vector<btgen::Diagnostic> diags;
  btgen::Scenario scenario;
  const auto& nodes = Runner::nodes();
  bool ok = btgen::read_scenario(path, scenario, diags);
  if (ok) {
    const auto& unrun = Runner::unrun_leaves();
    ok = btgen::check_scenario(scenario, nodes.data(), nodes.size(), diags, unrun.data(), unrun.size(),
                               Runner::main_tree());
  }
  for (const auto& d : diags) {
    if (d.line < 1 || d.col < 1 || d.str().empty()) std::abort();
  }
  if (!ok) {
    bool has_error = false;
    for (const auto& d : diags) has_error = has_error || d.error;
    if (!has_error) std::abort();  // a rejected scenario says why
    return 0;
  }
  static std::FILE* devnull = std::fopen("/dev/null", "w");
  btgen::ScenarioLeaves leaves(scenario, nodes.data(), nodes.size());
  auto mission = std::make_unique<Runner>(leaves, btgen::ManualClock{}, btgen::TraceWriter{devnull});
  const long ticks = scenario.ticks < 200 ? scenario.ticks : 200;
  for (long n = 1; n <= ticks; ++n) {
    if (n > 1) mission->clock().advance(static_cast<std::uint64_t>(scenario.clock_ms));
    const btgen::Status s = mission->tick();
    if (btgen::is_completed(s)) break;
  }
  return 0;
}
