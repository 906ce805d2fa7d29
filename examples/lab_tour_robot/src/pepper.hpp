// The simulated Pepper: the robot the Lab Tour's leaves drive.
//
// It keeps the robot's state (pose, where it stands, animate behaviour,
// overt attention mode) and the visitor's, and does what each leaf of
// missions/LabTour.xml asks, printing it: speech in the chosen language,
// navigation to a pose of the knowledge base over several ticks, pointing at
// a gesture target, the yes/no answer. Every method takes the leaf's port
// values as plain C++ values and returns the leaf's status; leaves.hpp
// connects them to the generated leaf interface.
//
// With a scenario (FORMAT.md), the scenario decides every status, call by
// call, exactly as `btgen run --scenario` does, and the robot does what that
// status means (a Navigate scripted SUCCESS arrives, FAILURE stops where it
// is). Without one, the simulation decides:
//   - the visitor appears on the second check of IsVisitorDiscovered;
//   - speech recognition is on, mutual gaze is found, and the visitor answers
//     the first yes/no question with --answer;
//   - speech and gestures take one RUNNING tick, then SUCCESS;
//   - navigation moves kMetresPerTick per tick (RUNNING), at least one tick,
//     then arrives (SUCCESS).
//
// Printing is the simulation's output, so the hooks here print (and may
// allocate inside stdio); the mission object itself is static and its tick
// allocates nothing.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "btgen/environment_knowledge_base.hpp"
#include "btgen/harness/scenario.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "speech.hpp"
#include "tour_plan.hpp"

namespace lab_tour_robot {

/// How far the simulated robot drives in one tick.
inline constexpr double kMetresPerTick = 1.0;

/// A location id read from a port: `known` is false when the port had no
/// value, and `why` then says why (btgen::describe(PortError)).
struct LocationPort {
  bool known = false;
  std::int32_t id = 0;
  std::string_view why = "no value";
};

enum class Attention : std::uint8_t { kDisabled, kScanning, kSocial };

class SimulatedPepper {
 public:
  struct Settings {
    bool answer_yes = true;  ///< the visitor's answer
    long visitor_check = 2;  ///< the IsVisitorDiscovered check that finds the visitor
  };

  /// `node_count` is the mission's number of nodes (per-node state is kept
  /// by node index). `scenario` may be null. `out` receives the narration.
  SimulatedPepper(const btgen::EnvironmentKnowledgeBase& kb, const SpeechBook& speech, const TourPlan& plan,
                  Settings settings, std::size_t node_count, btgen::ScenarioLeaves* scenario, std::FILE* out);

  /// The tick being run (for the narration's prefix).
  void set_tick(long tick) noexcept { tick_ = tick; }

  // ---- actions without ports -------------------------------------------
  btgen::Status startOfTree(const btgen::NodeInfo& node);
  btgen::Status setAnimate(const btgen::NodeInfo& node, bool on);
  btgen::Status setAttention(const btgen::NodeInfo& node, Attention mode);
  /// WelcomeGesture / GoodbyeGesture: one tick of gesturing.
  btgen::Status gestureStart(const btgen::NodeInfo& node, std::string_view what);
  btgen::Status gestureRunning(const btgen::NodeInfo& node);
  void gestureHalted(const btgen::NodeInfo& node);
  /// HandleFallBack: `failed` names the node whose failure it covers.
  btgen::Status handleFallBack(const btgen::NodeInfo& node, std::string_view failed);

  // ---- speech -------------------------------------------------------------
  /// A speech node saying the phrase `key` (its `message` port).
  btgen::Status speechStart(const btgen::NodeInfo& node, std::string_view key);
  /// DescribeExhibitSpeech_1 (post_gesture false) / _2 (true).
  btgen::Status describeStart(const btgen::NodeInfo& node, LocationPort location, bool post_gesture);
  btgen::Status speechRunning(const btgen::NodeInfo& node);
  void speechHalted(const btgen::NodeInfo& node);

  // ---- moving and pointing -------------------------------------------------
  btgen::Status navigateStart(const btgen::NodeInfo& node, LocationPort location);
  btgen::Status navigateRunning(const btgen::NodeInfo& node);
  void navigateHalted(const btgen::NodeInfo& node);
  btgen::Status pointStart(const btgen::NodeInfo& node, LocationPort location);
  btgen::Status pointRunning(const btgen::NodeInfo& node);
  void pointHalted(const btgen::NodeInfo& node);

  // ---- the knowledge base's tour (outputs are written only on SUCCESS) ------
  btgen::Status lookUpHome(const btgen::NodeInfo& node, std::int32_t& location_id);
  btgen::Status lookUpEntrance(const btgen::NodeInfo& node, std::int32_t& location_id);
  btgen::Status retrieveListOfExhibits(const btgen::NodeInfo& node, std::string& exhibits);
  /// Takes the first exhibit off `exhibits` (in: the list, out: the rest).
  btgen::Status selectExhibit(const btgen::NodeInfo& node, std::string_view exhibits, std::string& rest,
                              std::int32_t& location_id);
  btgen::Status isListWithExhibit(const btgen::NodeInfo& node, std::string_view exhibits);

  // ---- the visitor -------------------------------------------------------------
  btgen::Status isVisitorDiscovered(const btgen::NodeInfo& node);
  btgen::Status isMutualGazeDiscovered(const btgen::NodeInfo& node);
  btgen::Status isASREnabled(const btgen::NodeInfo& node);
  /// IsYesNoUttered and PressYesNoDialogue: `response` gets "yes" or "no" on SUCCESS.
  btgen::Status isYesNoUttered(const btgen::NodeInfo& node, std::string& response);
  btgen::Status pressYesNoDialogueStart(const btgen::NodeInfo& node, std::string& response);
  btgen::Status pressYesNoDialogueRunning(const btgen::NodeInfo& node, std::string& response);
  void pressYesNoDialogueHalted(const btgen::NodeInfo& node);
  /// `response` is the port's value; `known` false when it has none.
  btgen::Status isVisitorResponseYes(const btgen::NodeInfo& node, bool known, std::string_view response);

  /// An input port without a usable value: the leaf fails (and says why).
  btgen::Status portFailure(const btgen::NodeInfo& node, std::string_view port, std::string_view why);
  /// An output the blackboard refused (the mission reports the details): the leaf fails.
  btgen::Status writeFailure(const btgen::NodeInfo& node, std::string_view port);
  /// A halted action that has no halt of its own.
  void halted(const btgen::NodeInfo& node);

  // ---- state, for the summary and the tests -------------------------------------
  [[nodiscard]] const Eigen::Vector3d& pose() const noexcept { return pose_; }
  /// The location the robot stands at, or 0 when it is between locations.
  [[nodiscard]] std::int32_t at() const noexcept { return at_; }
  [[nodiscard]] int navigations() const noexcept { return navigations_; }
  [[nodiscard]] const TourPlan& plan() const noexcept { return plan_; }

  /// One narration line: "[tick N] <text>".
  void say(const char* format, ...) __attribute__((format(printf, 2, 3)));

 private:
  struct Activity {
    std::int32_t target = 0;  // location (navigation, pointing, speech about it)
    int step = 0;             // ticks done
    int steps = 1;            // ticks needed (simulation)
    Eigen::Vector3d from = Eigen::Vector3d::Zero();
  };

  /// The status the leaf returns: the scenario's next one if there is a
  /// scenario, else `simulated`.
  btgen::Status decide(const btgen::NodeInfo& node, btgen::Status simulated);
  /// "4 (Roomba)".
  [[nodiscard]] std::string place(std::int32_t id) const;
  [[nodiscard]] std::string cultural(std::int32_t id) const;
  void speak(const Utterance& u);
  btgen::Status fail(const btgen::NodeInfo& node, const char* why);

  const btgen::EnvironmentKnowledgeBase& kb_;
  const SpeechBook& speech_;
  TourPlan plan_;
  Settings settings_;
  btgen::ScenarioLeaves* scenario_;
  std::FILE* out_;
  std::vector<Activity> activity_;  // by node index

  long tick_ = 0;
  Eigen::Vector3d pose_ = Eigen::Vector3d::Zero();
  std::int32_t at_ = 0;
  bool animate_ = false;
  Attention attention_ = Attention::kDisabled;
  long visitor_checks_ = 0;
  int navigations_ = 0;
};

}  // namespace lab_tour_robot
