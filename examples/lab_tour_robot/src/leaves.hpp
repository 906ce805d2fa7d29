// The Lab Tour's leaf hooks, as the generated mission (lab_tour.hpp) calls
// them, implemented by the simulated Pepper.
//
// One overload per leaf model of missions/LabTour.xml's TreeNodesModel: the
// generated Spec calls leaves.onStart/onRunning/onHalted(leaf::M&, node) for
// an Action and leaves.check(leaf::C&, node) for a Condition, so a model
// added to the mission without a hook here is a compile error, not a silent
// default. Ports are read with the model's generated getters (btgen::Input<T>:
// a value, or the btgen::PortError saying why there is none) and written with
// its setters (false when the write failed; the node then fails).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "btgen/node.hpp"
#include "btgen/port.hpp"
#include "btgen/status.hpp"
#include "lab_tour.hpp"
#include "pepper.hpp"

namespace lab_tour_robot {

namespace leaves_detail {

template <class M, class... Ms>
inline constexpr bool is_one_of = (std::is_same_v<M, Ms> || ...);

// Speech nodes that say the phrase named by their `message` port.
template <class M>
inline constexpr bool is_phrase_speech =
    is_one_of<M, lab_tour::leaf::WelcomeSpeech, lab_tour::leaf::QueryTourSpeech, lab_tour::leaf::SayYesNoSpeech,
              lab_tour::leaf::PressYesNoSpeech, lab_tour::leaf::MaybeAnotherTimeSpeech, lab_tour::leaf::FollowMeSpeech,
              lab_tour::leaf::EndTourSpeech, lab_tour::leaf::HereIsTheDoorSpeech, lab_tour::leaf::SayGoodByeSpeech>;

template <class M>
inline constexpr bool is_speech =
    is_phrase_speech<M> ||
    is_one_of<M, lab_tour::leaf::DescribeExhibitSpeech_1, lab_tour::leaf::DescribeExhibitSpeech_2>;

// Actions that finish in the tick they start.
template <class M>
inline constexpr bool is_instant =
    is_one_of<M, lab_tour::leaf::START_OF_TREE, lab_tour::leaf::EnableAnimateBehavior,
              lab_tour::leaf::DisableAnimateBehavior, lab_tour::leaf::DisabledOvertAttentionMode,
              lab_tour::leaf::ScanningOvertAttentionMode, lab_tour::leaf::SocialOvertAttentionMode,
              lab_tour::leaf::HandleFallBack, lab_tour::leaf::LookUpHome, lab_tour::leaf::LookUpEntrance,
              lab_tour::leaf::RetrieveListOfExhibits, lab_tour::leaf::SelectExhibit>;

}  // namespace leaves_detail

class LabTourRobotLeaves {
 public:
  using Status = btgen::Status;
  using NodeInfo = btgen::NodeInfo;

  /// Connects the hooks to the robot; `nodes` is the mission's node table
  /// (HandleFallBack names the node whose failure it covers).
  void attach(SimulatedPepper& pepper, const NodeInfo* nodes, std::size_t count) {
    pepper_ = &pepper;
    failed_before_.assign(count, std::string_view("the previous step"));
    for (std::size_t i = 0; i < count; ++i) {
      // The previous sibling: the child of the same parent created just before.
      for (std::size_t j = i; j-- > 0;) {
        if (nodes[j].parent == nodes[i].parent) {
          failed_before_[i] = nodes[j].name;
          break;
        }
      }
    }
  }

  // ---- Actions without ports ------------------------------------------------
  Status onStart(lab_tour::leaf::START_OF_TREE&, const NodeInfo& n) { return pepper_->startOfTree(n); }
  Status onStart(lab_tour::leaf::EnableAnimateBehavior&, const NodeInfo& n) { return pepper_->setAnimate(n, true); }
  Status onStart(lab_tour::leaf::DisableAnimateBehavior&, const NodeInfo& n) { return pepper_->setAnimate(n, false); }
  Status onStart(lab_tour::leaf::DisabledOvertAttentionMode&, const NodeInfo& n) {
    return pepper_->setAttention(n, Attention::kDisabled);
  }
  Status onStart(lab_tour::leaf::ScanningOvertAttentionMode&, const NodeInfo& n) {
    return pepper_->setAttention(n, Attention::kScanning);
  }
  Status onStart(lab_tour::leaf::SocialOvertAttentionMode&, const NodeInfo& n) {
    return pepper_->setAttention(n, Attention::kSocial);
  }
  Status onStart(lab_tour::leaf::HandleFallBack&, const NodeInfo& n) {
    return pepper_->handleFallBack(n, failed_before_[n.index]);
  }
  Status onStart(lab_tour::leaf::WelcomeGesture&, const NodeInfo& n) {
    return pepper_->gestureStart(n, "welcome gesture");
  }
  Status onStart(lab_tour::leaf::GoodbyeGesture&, const NodeInfo& n) {
    return pepper_->gestureStart(n, "goodbye gesture");
  }

  // Instant actions are RUNNING only when a scenario scripts it: the robot
  // then tries again (outputs are written only on SUCCESS).
  template <class M, std::enable_if_t<leaves_detail::is_instant<M>, int> = 0>
  Status onRunning(M& m, const NodeInfo& n) {
    return onStart(m, n);
  }
  template <class M, std::enable_if_t<leaves_detail::is_instant<M>, int> = 0>
  void onHalted(M&, const NodeInfo& n) {
    pepper_->halted(n);
  }

  Status onRunning(lab_tour::leaf::WelcomeGesture&, const NodeInfo& n) { return pepper_->gestureRunning(n); }
  Status onRunning(lab_tour::leaf::GoodbyeGesture&, const NodeInfo& n) { return pepper_->gestureRunning(n); }
  void onHalted(lab_tour::leaf::WelcomeGesture&, const NodeInfo& n) { pepper_->gestureHalted(n); }
  void onHalted(lab_tour::leaf::GoodbyeGesture&, const NodeInfo& n) { pepper_->gestureHalted(n); }

  // ---- Speech: a phrase key (`message`), or a location's message ---------------
  template <class M, std::enable_if_t<leaves_detail::is_phrase_speech<M>, int> = 0>
  Status onStart(M& m, const NodeInfo& n) {
    const btgen::Input<std::string_view> key = m.message();
    if (!key) return pepper_->portFailure(n, "message", btgen::describe(key.error()));
    return pepper_->speechStart(n, *key);
  }
  Status onStart(lab_tour::leaf::DescribeExhibitSpeech_1& m, const NodeInfo& n) {
    return pepper_->describeStart(n, location(m.location_id()), false);
  }
  Status onStart(lab_tour::leaf::DescribeExhibitSpeech_2& m, const NodeInfo& n) {
    return pepper_->describeStart(n, location(m.location_id()), true);
  }
  template <class M, std::enable_if_t<leaves_detail::is_speech<M>, int> = 0>
  Status onRunning(M&, const NodeInfo& n) {
    return pepper_->speechRunning(n);
  }
  template <class M, std::enable_if_t<leaves_detail::is_speech<M>, int> = 0>
  void onHalted(M&, const NodeInfo& n) {
    pepper_->speechHalted(n);
  }

  // ---- Moving and pointing ----------------------------------------------------------
  Status onStart(lab_tour::leaf::Navigate& m, const NodeInfo& n) {
    return pepper_->navigateStart(n, location(m.location_id()));
  }
  Status onRunning(lab_tour::leaf::Navigate&, const NodeInfo& n) { return pepper_->navigateRunning(n); }
  void onHalted(lab_tour::leaf::Navigate&, const NodeInfo& n) { pepper_->navigateHalted(n); }

  Status onStart(lab_tour::leaf::PerformDeicticGesture& m, const NodeInfo& n) {
    return pepper_->pointStart(n, location(m.location_id()));
  }
  Status onRunning(lab_tour::leaf::PerformDeicticGesture&, const NodeInfo& n) { return pepper_->pointRunning(n); }
  void onHalted(lab_tour::leaf::PerformDeicticGesture&, const NodeInfo& n) { pepper_->pointHalted(n); }

  // ---- The knowledge base's tour --------------------------------------------------------
  Status onStart(lab_tour::leaf::LookUpHome& m, const NodeInfo& n) {
    std::int32_t id = 0;
    const Status st = pepper_->lookUpHome(n, id);
    return st == Status::SUCCESS && !m.set_location_id(id) ? pepper_->writeFailure(n, "location_id") : st;
  }
  Status onStart(lab_tour::leaf::LookUpEntrance& m, const NodeInfo& n) {
    std::int32_t id = 0;
    const Status st = pepper_->lookUpEntrance(n, id);
    return st == Status::SUCCESS && !m.set_location_id(id) ? pepper_->writeFailure(n, "location_id") : st;
  }
  Status onStart(lab_tour::leaf::RetrieveListOfExhibits& m, const NodeInfo& n) {
    const Status st = pepper_->retrieveListOfExhibits(n, text_);
    return st == Status::SUCCESS && !m.set_exhibits(std::string_view(text_)) ? pepper_->writeFailure(n, "exhibits")
                                                                             : st;
  }
  Status onStart(lab_tour::leaf::SelectExhibit& m, const NodeInfo& n) {
    const btgen::Input<std::string_view> list = m.exhibits();
    if (!list) return pepper_->portFailure(n, "exhibits", btgen::describe(list.error()));
    std::int32_t id = 0;
    const Status st = pepper_->selectExhibit(n, *list, text_, id);  // copies the rest before writing it back
    if (st != Status::SUCCESS) return st;
    if (!m.set_exhibits(std::string_view(text_))) return pepper_->writeFailure(n, "exhibits");
    if (!m.set_location_id(id)) return pepper_->writeFailure(n, "location_id");
    return st;
  }
  Status check(lab_tour::leaf::IsListWithExhibit& m, const NodeInfo& n) {
    const btgen::Input<std::string_view> list = m.exhibits();
    return pepper_->isListWithExhibit(n, list ? *list : std::string_view());
  }

  // ---- The visitor -----------------------------------------------------------------------
  Status check(lab_tour::leaf::IsVisitorDiscovered&, const NodeInfo& n) { return pepper_->isVisitorDiscovered(n); }
  Status check(lab_tour::leaf::IsMutualGazeDiscovered&, const NodeInfo& n) {
    return pepper_->isMutualGazeDiscovered(n);
  }
  Status check(lab_tour::leaf::IsASREnabled&, const NodeInfo& n) { return pepper_->isASREnabled(n); }
  Status check(lab_tour::leaf::IsYesNoUttered& m, const NodeInfo& n) {
    const Status st = pepper_->isYesNoUttered(n, text_);
    return st == Status::SUCCESS && !m.set_response(std::string_view(text_)) ? pepper_->writeFailure(n, "response")
                                                                             : st;
  }
  Status onStart(lab_tour::leaf::PressYesNoDialogue& m, const NodeInfo& n) {
    const Status st = pepper_->pressYesNoDialogueStart(n, text_);
    return st == Status::SUCCESS && !m.set_response(std::string_view(text_)) ? pepper_->writeFailure(n, "response")
                                                                             : st;
  }
  Status onRunning(lab_tour::leaf::PressYesNoDialogue& m, const NodeInfo& n) {
    const Status st = pepper_->pressYesNoDialogueRunning(n, text_);
    return st == Status::SUCCESS && !m.set_response(std::string_view(text_)) ? pepper_->writeFailure(n, "response")
                                                                             : st;
  }
  void onHalted(lab_tour::leaf::PressYesNoDialogue&, const NodeInfo& n) { pepper_->pressYesNoDialogueHalted(n); }
  Status check(lab_tour::leaf::IsVisitorResponseYes& m, const NodeInfo& n) {
    const btgen::Input<std::string_view> response = m.response();
    return pepper_->isVisitorResponseYes(n, response.has_value(), response.value());
  }

 private:
  static LocationPort location(const btgen::Input<std::int32_t>& in) {
    return in ? LocationPort{true, *in, {}} : LocationPort{false, 0, btgen::describe(in.error())};
  }

  SimulatedPepper* pepper_ = nullptr;
  std::vector<std::string_view> failed_before_;  // by node index
  std::string text_;                             // an output being written
};

}  // namespace lab_tour_robot
