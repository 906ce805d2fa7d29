// lab_tour_robot: the Lab Tour mission (missions/LabTour.xml, compiled to
// C++ by btgen at build time) on a simulated Pepper robot that takes its
// facts from the environment knowledge base. `lab_tour_robot --help` lists
// the options; examples/lab_tour_robot/README.md explains the simulation.
#include <sys/stat.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "btgen/blackboard.hpp"
#include "btgen/btlog.hpp"
#include "btgen/clock.hpp"
#include "btgen/environment_knowledge_base.hpp"
#include "btgen/harness/scenario.hpp"
#include "btgen/monitor.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"
#ifdef LAB_TOUR_WITH_GROOT2
#include "btgen/groot2.hpp"
#endif
#include "lab_tour.hpp"
#include "leaves.hpp"
#include "options.hpp"
#include "pepper.hpp"
#include "speech.hpp"
#include "tour_plan.hpp"

#ifndef BTGEN_REPO_DIR
#define BTGEN_REPO_DIR ""
#endif

namespace {

using btgen::Status;
using lab_tour_robot::LabTourRobotLeaves;

constexpr const char* kProgram = "lab_tour_robot";

// The runtime's trace observer (btgen::TraceWriter, FORMAT.md), switched on by --trace.
class OptionalTrace {
 public:
  void on_status_change(const btgen::NodeInfo& node, Status from, Status to) const noexcept {
    if (enabled_) writer_.on_status_change(node, from, to);
  }
  void enable() noexcept { enabled_ = true; }
  // Run-time errors of the generated code (a port write that does not fit,
  // ...): always printed; the node concerned fails.
  void on_error(const btgen::RuntimeError& e) const noexcept {
    std::fflush(stdout);  // keep it in order with the narration when both go to one place
    std::fprintf(stderr, "%s: run-time error: %.*s: %.*s (node %u `%.*s`)\n", kProgram,
                 static_cast<int>(e.where.size()), e.where.data(), static_cast<int>(e.message.size()), e.message.data(),
                 e.node != nullptr ? static_cast<unsigned>(e.node->uid) : 0u,
                 e.node != nullptr ? static_cast<int>(e.node->name.size()) : 0,
                 e.node != nullptr ? e.node->name.data() : "");
  }

 private:
  btgen::TraceWriter writer_{stdout};
  bool enabled_ = false;
};

// Groot2 monitors (--groot2, --btlog) attach to the MonitorObserver; the trace comes after them.
using Mission = lab_tour::LabTour<LabTourRobotLeaves, btgen::ManualClock, btgen::MonitorObserver<OptionalTrace>>;

// The mission lives in static storage: one object of fixed size, no heap.
LabTourRobotLeaves g_leaves;
Mission g_mission(g_leaves);

bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

int bad_input(const std::string& message) {
  std::fprintf(stderr, "%s: error: %s\n", kProgram, message.c_str());
  return 2;
}

// The status a scenario scripts first for the leaf named `name`, if any.
const btgen::ScenarioLeaf* scripted(const btgen::Scenario& sc, const char* name) { return sc.leaf(name); }

}  // namespace

int main(int argc, char** argv) {
  lab_tour_robot::Options options;
  std::string error;
  if (!lab_tour_robot::parse_options(argc, argv, options, error)) {
    std::fprintf(stderr, "%s: error: %s\n%s", kProgram, error.c_str(), lab_tour_robot::usage_text(kProgram).c_str());
    return 2;
  }
  if (options.help) {
    std::fputs(lab_tour_robot::usage_text(kProgram).c_str(), stdout);
    return 0;
  }

  // The knowledge base: the default configuration is looked up in the
  // current folder, then in the btgen repository this program was built from.
  std::string config = options.kb_config;
  if (!options.kb_config_given && !file_exists(config)) {
    const std::string in_repo = std::string(BTGEN_REPO_DIR) + "/" + config;
    if (BTGEN_REPO_DIR[0] != '\0' && file_exists(in_repo)) config = in_repo;
  }
  btgen::KbResult<btgen::EnvironmentKnowledgeBase> loaded =
      btgen::EnvironmentKnowledgeBase::loadFromConfiguration(config, std::cout);
  std::cout.flush();
  if (!loaded) {
    for (const std::string& e : loaded.errors()) std::fprintf(stderr, "%s\n", e.c_str());
    std::fprintf(stderr, "%s: error: cannot load the knowledge base named by %s\n", kProgram, config.c_str());
    return 2;
  }
  const btgen::EnvironmentKnowledgeBase& kb = loaded.value();

  // The scenario, if any: read and checked against the mission before the run.
  btgen::Scenario scenario;
  if (!options.scenario.empty()) {
    std::vector<btgen::Diagnostic> diags;
    bool ok = btgen::read_scenario(options.scenario, scenario, diags);
    if (ok) ok = btgen::check_scenario(scenario, Mission::nodes().data(), Mission::nodes().size(), diags);
    for (const btgen::Diagnostic& d : diags) std::fprintf(stderr, "%s\n", d.str().c_str());
    if (!ok) return 2;
    if (!options.max_ticks_given) options.max_ticks = scenario.ticks;
    // The visitor's answer: the scenario's IsVisitorResponseYes says it.
    if (const btgen::ScenarioLeaf* leaf = scripted(scenario, "IsVisitorResponseYes")) {
      const bool yes = leaf->statuses.front() == Status::SUCCESS;
      if (options.answer_given && options.answer_yes != yes) {
        return bad_input("--answer " + std::string(options.answer_yes ? "yes" : "no") + " contradicts " +
                         scenario.path + ":" + std::to_string(leaf->line) + ", which scripts IsVisitorResponseYes " +
                         std::string(btgen::to_string(leaf->statuses.front())));
      }
      options.answer_yes = yes;
    }
  }
  std::unique_ptr<btgen::ScenarioLeaves> scenario_leaves;
  if (!options.scenario.empty()) {
    scenario_leaves =
        std::make_unique<btgen::ScenarioLeaves>(scenario, Mission::nodes().data(), Mission::nodes().size());
  }

  const lab_tour_robot::TourPlan plan = lab_tour_robot::plan_tour(kb);
  const lab_tour_robot::SpeechBook speech =
      lab_tour_robot::SpeechBook::build(kb, options.language, plan.home, plan.exit);
  lab_tour_robot::SimulatedPepper::Settings settings;
  settings.answer_yes = options.answer_yes;
  lab_tour_robot::SimulatedPepper pepper(kb, speech, plan, settings, Mission::node_count(), scenario_leaves.get(),
                                         stdout);
  g_leaves.attach(pepper, Mission::nodes().data(), Mission::nodes().size());
  if (options.trace) g_mission.observer().next().enable();

  // Groot2: a live publisher and a .btlog, both off the tick path (btgen/groot2.hpp, btgen/btlog.hpp).
  std::unique_ptr<btgen::btlog::FileLogger> btlog;
#ifdef LAB_TOUR_WITH_GROOT2
  std::unique_ptr<btgen::groot2::Publisher<Mission>> groot2;
#endif
  try {
    if (!options.btlog.empty()) btlog = std::make_unique<btgen::btlog::FileLogger>(g_mission, options.btlog);
    if (options.groot2_port != 0) {
#ifdef LAB_TOUR_WITH_GROOT2
      groot2 = std::make_unique<btgen::groot2::Publisher<Mission>>(
          g_mission, static_cast<unsigned>(options.groot2_port), options.groot2_address);
      std::printf("%s: Groot2 publisher on ports %ld and %ld\n", kProgram, options.groot2_port,
                  options.groot2_port + 1);
      // The names Groot2's blackboard panel and `btview blackboard -p PORT NAME` ask for.
      std::string names;
      for (std::string_view name : Mission::Groot2::kBlackboards) {
        names += (names.empty() ? "\"" : ", \"") + std::string(name) + "\"";
      }
      std::printf("%s: blackboards: %s\n", kProgram, names.c_str());
#else
      return bad_input("--groot2: this lab_tour_robot was built without ZeroMQ (install libzmq3-dev and cppzmq-dev)");
#endif
    }
  } catch (const std::exception& e) {
    return bad_input(std::string(options.groot2_port != 0 ? "--groot2/--btlog: " : "--btlog: ") + e.what());
  }

  {
    std::string tour, exhibits;
    for (std::int32_t id : kb.tour()) tour += (tour.empty() ? "" : " ") + std::to_string(id);
    for (std::int32_t id : plan.exhibits) exhibits += (exhibits.empty() ? "" : " ") + std::to_string(id);
    const std::string_view lang = lab_tour_robot::language_name(options.language);
    std::printf("%s: knowledge base %s: %zu locations, tour %s\n", kProgram, kb.path().c_str(), kb.locations().size(),
                tour.c_str());
    std::printf("%s: home %d, exhibits %s, tour ends at %d; language %.*s; visitor answers %s%s\n", kProgram, plan.home,
                exhibits.empty() ? "none" : exhibits.c_str(), plan.exit, static_cast<int>(lang.size()), lang.data(),
                options.answer_yes ? "yes" : "no",
                options.scenario.empty() ? "" : ("; statuses from " + options.scenario).c_str());
    if (speech.fallback_count() > 0) {
      std::printf("%s: %zu texts have no %.*s translation: said in English after \"[no %.*s translation]\"\n", kProgram,
                  speech.fallback_count(), static_cast<int>(lang.size()), lang.data(), static_cast<int>(lang.size()),
                  lang.data());
    }
  }

  const long clock_ms = options.scenario.empty() ? options.tick_ms : scenario.clock_ms;
  Status result = Status::IDLE;
  long n = 1;
  for (; n <= options.max_ticks; ++n) {
    if (n > 1) {
      g_mission.clock().advance(static_cast<std::uint64_t>(clock_ms));
      if (options.tick_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(options.tick_ms));
    }
    pepper.set_tick(n);
    if (options.trace) std::printf("tick %ld\n", n);
    result = g_mission.tick();
#ifdef LAB_TOUR_WITH_GROOT2
    if (groot2) groot2->sync();
#endif
    if (options.trace) std::printf("result %s\n", std::string(btgen::to_string(result)).c_str());
    if (options.tick_ms > 0) std::fflush(stdout);
    if (btgen::is_completed(result)) break;
  }

  int log_error = 0;
  // After the end: the .btlog is complete once its logger is gone (its thread drains the
  // ring), and the publisher stays up a little so that Groot2 and btview show the last
  // statuses instead of a connection that vanished with the final tick.
  const auto finish_monitors = [&]() {
    if (btlog) {
      // A full disk (or /dev/full) cuts the log short: the run then fails, saying so.
      log_error = btlog->close();
      btlog.reset();
      if (log_error != 0) {
        std::fprintf(stderr, "%s: error: %s: cannot write the log: %s\n", kProgram, options.btlog.c_str(),
                     std::strerror(log_error));
        return;
      }
      std::error_code ec;
      const std::filesystem::path full = std::filesystem::absolute(options.btlog, ec);
      std::printf("%s: wrote %s (replay it in Groot2; `btgen graph --btlog` draws it)\n", kProgram,
                  ec ? options.btlog.c_str() : full.string().c_str());
    }
#ifdef LAB_TOUR_WITH_GROOT2
    if (groot2 && options.linger_ms > 0) {
      std::printf("%s: the Groot2 publisher stays up %ld ms more so monitors show the end (--linger-ms)\n", kProgram,
                  options.linger_ms);
      std::fflush(stdout);
      std::this_thread::sleep_for(std::chrono::milliseconds(options.linger_ms));
    }
#endif
    std::fflush(stdout);
  };

  const btgen::KbLocation* where = kb.find(pepper.at());
  const std::string place =
      where != nullptr ? std::to_string(where->id) + " (" + where->description + ")" : std::string("between locations");
  if (!btgen::is_completed(result)) {
    pepper.set_tick(options.max_ticks);
    pepper.say("no result after %ld ticks: halting the mission", options.max_ticks);
    g_mission.halt();
    std::printf("%s: mission still %s after %ld ticks (halted); Pepper is at %s\n", kProgram,
                std::string(btgen::to_string(result)).c_str(), options.max_ticks, place.c_str());
    finish_monitors();
    return 1;
  }
  std::printf("%s: mission %s at tick %ld after %d navigations; Pepper is at %s%s: x %.2f, y %.2f, theta %.1f\n",
              kProgram, std::string(btgen::to_string(result)).c_str(), n, pepper.navigations(), place.c_str(),
              pepper.at() == plan.home ? ", home" : "", pepper.pose().x(), pepper.pose().y(), pepper.pose().z());
  finish_monitors();
  if (std::fflush(stdout) != 0 || log_error != 0) return 1;
  return result == Status::SUCCESS ? 0 : 1;
}
