// A scenario-driven mission under Groot2 monitors, stepped from stdin (tests and demos).
//
//     prog SCENARIO_FILE [--groot2 PORT] [--address ADDR] [--btlog FILE.btlog]
//          [--heartbeat-ms MS]
//
// Leaves follow the scenario (tests/conformance/FORMAT.md). The program
// prints `ready` once its monitors run, then reads commands, one a line:
// `tick` sends one tick and prints `result STATUS`; `sync` copies the
// blackboard for the publisher; `quit` (or end of input) stops the monitors
// (the .btlog is complete then) and exits 0. `--heartbeat-ms`: the publisher's
// heartbeat delay (its hooks are disabled after that long without a request).
// Compile with
//   -DBTGEN_MISSION_HEADER='"m.hpp"' -DBTGEN_MISSION_TEMPLATE=m::M
// and link btgen::groot2.
#ifndef BTGEN_MISSION_HEADER
#error "define BTGEN_MISSION_HEADER as the generated header"
#endif
#ifndef BTGEN_MISSION_TEMPLATE
#error "define BTGEN_MISSION_TEMPLATE as the mission class template"
#endif

#include BTGEN_MISSION_HEADER

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "btgen/btlog.hpp"
#include "btgen/clock.hpp"
#include "btgen/groot2.hpp"
#include "btgen/harness/scenario.hpp"
#include "btgen/monitor.hpp"

using Runner = BTGEN_MISSION_TEMPLATE<btgen::ScenarioLeaves, btgen::ManualClock, btgen::MonitorObserver<>>;

int main(int argc, char** argv) {
  const char* scenario_path = nullptr;
  long port = -1;
  std::string address = "*";
  std::string btlog;
  long heartbeat_ms = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--groot2" && i + 1 < argc)
      port = std::strtol(argv[++i], nullptr, 10);
    else if (a == "--address" && i + 1 < argc)
      address = argv[++i];
    else if (a == "--btlog" && i + 1 < argc)
      btlog = argv[++i];
    else if (a == "--heartbeat-ms" && i + 1 < argc)
      heartbeat_ms = std::strtol(argv[++i], nullptr, 10);
    else if (scenario_path == nullptr && a.rfind("--", 0) != 0)
      scenario_path = argv[i];
    else {
      std::fprintf(
          stderr, "usage: %s SCENARIO_FILE [--groot2 PORT] [--address ADDR] [--btlog FILE.btlog] [--heartbeat-ms MS]\n",
          argv[0]);
      return 2;
    }
  }
  if (scenario_path == nullptr || (port != -1 && (port < 1 || port > 65534))) {
    std::fprintf(stderr,
                 "usage: %s SCENARIO_FILE [--groot2 PORT] [--address ADDR] [--btlog FILE.btlog] [--heartbeat-ms MS]\n",
                 argv[0]);
    return 2;
  }
  std::vector<btgen::Diagnostic> diags;
  btgen::Scenario scenario;
  const auto& nodes = Runner::nodes();
  bool ok = btgen::read_scenario(scenario_path, scenario, diags);
  if (ok) {
    const auto& unrun = Runner::unrun_leaves();
    ok = btgen::check_scenario(scenario, nodes.data(), nodes.size(), diags, unrun.data(), unrun.size(),
                               Runner::main_tree());
  }
  for (const auto& d : diags) std::fprintf(stderr, "%s\n", d.str().c_str());
  if (!ok) return 1;

  btgen::ScenarioLeaves leaves(scenario, nodes.data(), nodes.size());
  auto mission = std::make_unique<Runner>(leaves);
  std::unique_ptr<btgen::groot2::Publisher<Runner>> publisher;
  std::unique_ptr<btgen::btlog::FileLogger> logger;
  try {
    if (port != -1) publisher = std::make_unique<btgen::groot2::Publisher<Runner>>(*mission, unsigned(port), address);
    if (publisher && heartbeat_ms > 0) publisher->set_max_heartbeat_delay(std::chrono::milliseconds(heartbeat_ms));
    if (!btlog.empty()) logger = std::make_unique<btgen::btlog::FileLogger>(*mission, btlog);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", argv[0], e.what());
    return 2;
  }
  std::printf("ready\n");
  std::fflush(stdout);
  char line[256];
  while (std::fgets(line, sizeof line, stdin) != nullptr) {
    if (std::strncmp(line, "tick", 4) == 0) {
      const btgen::Status s = mission->tick();
      if (publisher) publisher->sync();
      std::printf("result %s\n", std::string(btgen::to_string(s)).c_str());
    } else if (std::strncmp(line, "sync", 4) == 0) {
      if (publisher) publisher->sync();
      std::printf("ok\n");
    } else if (std::strncmp(line, "quit", 4) == 0) {
      break;
    } else {
      std::printf("unknown command\n");
    }
    std::fflush(stdout);
  }
  int status = 0;
  if (logger) {
    // (a full disk or /dev/full: the log is cut short; say so, as for any output)
    if (const int e = logger->close()) {
      std::fprintf(stderr, "%s: error: %s: cannot write the log: %s\n", argv[0], btlog.c_str(), std::strerror(e));
      status = 1;
    }
  }
  logger.reset();
  publisher.reset();
  return status;
}
