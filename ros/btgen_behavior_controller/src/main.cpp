// behaviorController: the Lab Tour (missions/labTour.xml, compiled to C++ by
// btgen when this package is built) on the CSSR4Africa robot, through the
// robot's ROS 1 services and topics. A drop-in for the CSSR4Africa
// behaviorController node; ../../README.md ("On the robot (ROS 1)") lists
// its parameters and what it expects of the robot.
//
// Exit status: 0 when the mission ends in SUCCESS (or the node is
// interrupted), 1 when it ends in FAILURE, 2 for a bad parameter or a bad
// knowledge base.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <initializer_list>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <ros/ros.h>

#include "btgen/environment_knowledge_base.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"
#include "lab_tour.hpp"
#include "leaves.hpp"
#include "phrases.hpp"

// ==== Groot2 hook ==============================================================================
// The btgen runtime has a Groot2 publisher (btgen/groot2.hpp,
// CMake target btgen::groot2). When that target exists, CMakeLists.txt
// defines BTGEN_BEHAVIOR_CONTROLLER_WITH_GROOT2 and the mission is published
// on ~groot2_port (and the next port), as BT::Groot2Publisher does in the
// production node. Without it, a non-zero ~groot2_port is reported and ignored.
#ifdef BTGEN_BEHAVIOR_CONTROLLER_WITH_GROOT2
#include <memory>

#include "btgen/groot2.hpp"
#include "btgen/monitor.hpp"
using Observer = btgen::MonitorObserver<btgen::NoObserver>;
#else
using Observer = btgen::NoObserver;
#endif
// ==== end of the Groot2 hook ====================================================================

#ifndef BTGEN_DEFAULT_KB_CONFIG
#define BTGEN_DEFAULT_KB_CONFIG "environmentKnowledgeBaseConfiguration.ini"
#endif

namespace {

using btgen::Status;
using btgen_behavior_controller::Interfaces;
using btgen_behavior_controller::Language;
using btgen_behavior_controller::Leaves;
using btgen_behavior_controller::Settings;
using Mission = lab_tour::LabTour<Leaves, btgen::SteadyClock, Observer>;

// SIGINT and SIGTERM: the node's own handler (roscpp's would shut ROS down
// at once, and nothing could be logged or halted after it).
std::atomic<bool> g_interrupted{false};
extern "C" void on_signal(int) { g_interrupted = true; }
bool running() { return ros::ok() && !g_interrupted; }

std::string where(const btgen::NodeInfo& n) { return std::string(n.source); }

// Every leaf parameter of the mission (its `name` attribute), checked before
// anything moves; false after reporting each bad one.
bool check_mission_parameters() {
  bool good = true;
  auto bad = [&good](const btgen::NodeInfo& n, const std::string& expected) {
    ROS_FATAL("behaviorController: %s: error: %.*s name=\"%.*s\": expected %s", where(n).c_str(),
              static_cast<int>(n.id.size()), n.id.data(), static_cast<int>(n.name.size()), n.name.data(),
              expected.c_str());
    good = false;
  };
  auto one_of = [](std::string_view v, std::initializer_list<std::string_view> options) {
    for (std::string_view o : options) {
      if (v == o) return true;
    }
    return false;
  };
  for (const btgen::NodeInfo& n : Mission::nodes()) {
    if (n.id == "SayText") {
      if (btgen_behavior_controller::utility_phrase(n.name, Language::kEnglish) == nullptr) {
        bad(n, "a utility phrase id: " + btgen_behavior_controller::utility_phrase_ids());
      }
    } else if (n.id == "DescribeExhibitSpeech") {
      if (!one_of(n.name, {"1", "2"})) bad(n, "1 (pre-gesture message) or 2 (post-gesture message)");
    } else if (n.id == "SetOvertAttentionMode") {
      if (!one_of(n.name, {"scanning", "social", "seeking", "disabled", "location"})) {
        bad(n, "scanning, social, seeking, disabled or location");
      }
    } else if (n.id == "SetAnimateBehavior") {
      if (!one_of(n.name, {"enabled", "disabled"})) bad(n, "enabled or disabled");
    } else if (n.id == "SetSpeechEvent") {
      if (!one_of(n.name, {"true", "false"})) bad(n, "true or false");
    } else if (n.id == "PerformIconicGesture") {
      if (!one_of(n.name, {"welcome", "goodbye"})) bad(n, "welcome or goodbye");
    }
  }
  return good;
}

// Waits until every service is advertised and both topics have a publisher
// connected to this node, saying what is still missing when that changes and
// every `report_s` seconds. False when the node is shut down first.
bool wait_for_robot(const Leaves& leaves, double report_s) {
  std::string last;
  auto last_report = std::chrono::steady_clock::now();
  bool reported = false;
  while (running()) {
    std::vector<std::string> missing;
    for (const char* service : Interfaces::services()) {
      if (!ros::service::exists(service, false)) missing.push_back(std::string("service ") + service);
    }
    if (leaves.attention_subscriber().getNumPublishers() == 0) {
      missing.push_back(std::string("a publisher of ") + Interfaces::kAttentionTopic);
    }
    if (leaves.speech_subscriber().getNumPublishers() == 0) {
      missing.push_back(std::string("a publisher of ") + Interfaces::kSpeechTopic);
    }
    if (missing.empty()) {
      ROS_INFO("behaviorController: all %zu services and both topics are available", Interfaces::services().size());
      return true;
    }
    std::string now;
    for (const std::string& m : missing) now += (now.empty() ? "" : ", ") + m;
    const auto t = std::chrono::steady_clock::now();
    if (!reported || now != last || std::chrono::duration<double>(t - last_report).count() >= report_s) {
      ROS_WARN("behaviorController: waiting for %s", now.c_str());
      last = now;
      last_report = t;
      reported = true;
    }
    ros::WallDuration(0.1).sleep();
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "behaviorController", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");

  // ---- Parameters ----------------------------------------------------------------------------
  double tick_rate = 10.0;
  std::string language = "English";
  bool asr_enabled = true;
  double response_timeout = 10.0;
  std::string kb_config = BTGEN_DEFAULT_KB_CONFIG;
  int groot2_port = 0;
  std::string groot2_address = "*";
  bool repeat = false;
  double wait_report_period = 3.0;
  pnh.param("tick_rate", tick_rate, tick_rate);
  pnh.param("language", language, language);
  pnh.param("asr_enabled", asr_enabled, asr_enabled);
  pnh.param("response_timeout", response_timeout, response_timeout);
  pnh.param("knowledge_base_config", kb_config, kb_config);
  pnh.param("groot2_port", groot2_port, groot2_port);
  pnh.param("groot2_address", groot2_address, groot2_address);
  pnh.param("repeat", repeat, repeat);
  pnh.param("wait_report_period", wait_report_period, wait_report_period);

  bool good = true;
  if (!(tick_rate > 0.0 && tick_rate <= 1000.0)) {
    ROS_FATAL("behaviorController: ~tick_rate %g: expected a rate in Hz, above 0 and at most 1000", tick_rate);
    good = false;
  }
  const std::optional<Language> lang = btgen_behavior_controller::parse_language(language);
  if (!lang) {
    ROS_FATAL("behaviorController: ~language \"%s\": expected English, IsiZulu or Kinyarwanda", language.c_str());
    good = false;
  }
  if (!(response_timeout > 0.0)) {
    ROS_FATAL("behaviorController: ~response_timeout %g: expected seconds above 0", response_timeout);
    good = false;
  }
  if (groot2_port < 0 || groot2_port > 65534) {
    ROS_FATAL("behaviorController: ~groot2_port %d: expected 0 (off) or a port up to 65534", groot2_port);
    good = false;
  }
  if (!check_mission_parameters()) good = false;

  // ---- The environment knowledge base ----------------------------------------------------------
  std::ostringstream verbose;
  btgen::KbResult<btgen::EnvironmentKnowledgeBase> loaded =
      btgen::EnvironmentKnowledgeBase::loadFromConfiguration(kb_config, verbose);
  if (!loaded) {
    for (const std::string& e : loaded.errors()) ROS_FATAL("%s", e.c_str());
    ROS_FATAL("behaviorController: cannot load the knowledge base named by ~knowledge_base_config %s",
              kb_config.c_str());
    return 2;
  }
  if (!verbose.str().empty()) ROS_INFO("%s", verbose.str().c_str());
  if (!good) return 2;
  const btgen::EnvironmentKnowledgeBase& kb = loaded.value();
  {
    std::string tour;
    for (std::int32_t id : kb.tour()) tour += (tour.empty() ? "" : " ") + std::to_string(id);
    ROS_INFO("behaviorController: knowledge base %s: %zu locations, tour %s; language %s; ASR %s; %g Hz",
             kb.path().c_str(), kb.locations().size(), tour.c_str(), btgen_behavior_controller::language_name(*lang),
             asr_enabled ? "enabled" : "disabled", tick_rate);
  }

  Settings settings;
  settings.language = *lang;
  settings.asr_enabled = asr_enabled;
  settings.response_timeout_s = response_timeout;
  Leaves leaves(nh, kb, settings, Mission::nodes().data(), Mission::node_count());
  ros::AsyncSpinner spinner(1);  // the topics' callbacks; service calls run on the leaves' worker
  spinner.start();

  // ---- The robot -------------------------------------------------------------------------------
  if (!wait_for_robot(leaves, wait_report_period)) {
    ROS_INFO("behaviorController: interrupted while waiting for the robot; shutting down");
    ros::shutdown();
    leaves.stop();
    return 0;
  }

  Mission mission(leaves);

  // ---- Groot2 hook (see the top of this file) ----------------------------------------------------
#ifdef BTGEN_BEHAVIOR_CONTROLLER_WITH_GROOT2
  std::unique_ptr<btgen::groot2::Publisher<Mission>> groot2;
  if (groot2_port != 0) {
    try {
      groot2 = std::make_unique<btgen::groot2::Publisher<Mission>>(mission, static_cast<unsigned>(groot2_port),
                                                                   groot2_address);
      ROS_INFO("behaviorController: Groot2 publisher on ports %d and %d of %s", groot2_port, groot2_port + 1,
               groot2_address.c_str());
    } catch (const std::exception& e) {
      ROS_FATAL("behaviorController: ~groot2_port %d: %s", groot2_port, e.what());
      leaves.stop();
      return 2;
    }
  }
#else
  if (groot2_port != 0) {
    ROS_WARN("behaviorController: ~groot2_port %d ignored: this btgen has no Groot2 publisher yet (%s)", groot2_port,
             groot2_address.c_str());
  }
#endif

  // ---- The mission -------------------------------------------------------------------------------
  ROS_INFO("behaviorController: starting the mission (%s, %zu nodes)", std::string(Mission::main_tree()).c_str(),
           Mission::node_count());
  ros::WallRate rate(tick_rate);
  Status result = Status::IDLE;
  long ticks = 0;
  int exit_status = 0;
  while (running()) {
    result = mission.tick();
    ++ticks;
#ifdef BTGEN_BEHAVIOR_CONTROLLER_WITH_GROOT2
    if (groot2) groot2->sync();
#endif
    if (btgen::is_completed(result)) {
      ROS_INFO("behaviorController: mission %s after %ld ticks", std::string(btgen::to_string(result)).c_str(), ticks);
      exit_status = result == Status::SUCCESS ? 0 : 1;
      if (!repeat) break;
      ticks = 0;
    }
    rate.sleep();
  }
  if (!btgen::is_completed(result) && result != Status::IDLE) {
    ROS_INFO("behaviorController: interrupted: halting the mission");
    exit_status = 0;
  }
  mission.halt();
  // roslaunch reports a `required` node that exits as "has died!", even after a clean end.
  ROS_INFO(
      "behaviorController: shutting down (exit status %d; roslaunch reports a required node that exits as "
      "\"has died!\": the mission ended, nothing crashed)",
      exit_status);
  // Unblocks a service call in progress, then joins the worker: nothing is called after this.
  ros::shutdown();
  leaves.stop();
  spinner.stop();
  return exit_status;
}
