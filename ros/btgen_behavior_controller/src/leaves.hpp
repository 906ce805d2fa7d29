// The leaves of missions/labTour.xml on the CSSR4Africa robot: one overload
// per leaf model, as the btgen-generated mission (lab_tour.hpp) calls them.
//
// Parameters come from the node's `name` attribute, as in the production
// node (<SayText name="4"/>); main.cpp checks every one before the mission
// starts (check_mission_parameters). State the production node keeps in
// globals (the tour, the current stop, the visitor's answer) lives here.
//
// Actions that call a service start the call on the ServiceWorker and return
// RUNNING; onRunning() returns its result when it has one. Conditions never
// wait: they read the latest message of a topic, and the mission retries
// them once per tick.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <ros/ros.h>
#include <std_msgs/String.h>

#include <cssr_system/animateBehaviorSetActivation.h>
#include <cssr_system/gestureExecutionPerformGesture.h>
#include <cssr_system/overtAttentionMode.h>
#include <cssr_system/overtAttentionSetMode.h>
#include <cssr_system/robotLocalizationSetPose.h>
#include <cssr_system/robotNavigationSetGoal.h>
#include <cssr_system/speechEventSetLanguage.h>
#include <cssr_system/speechEventSetStatus.h>
#include <cssr_system/tabletEventPromptAndGetResponse.h>
#include <cssr_system/textToSpeechSayText.h>

#include "btgen/environment_knowledge_base.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "lab_tour.hpp"
#include "phrases.hpp"
#include "service_worker.hpp"

namespace btgen_behavior_controller {

namespace leaf = lab_tour::leaf;

/// The services and topics of the CSSR4Africa interfaces the mission uses.
struct Interfaces {
  static constexpr const char* kAnimate = "/animateBehaviour/setActivation";
  static constexpr const char* kGesture = "/gestureExecution/perform_gesture";
  static constexpr const char* kAttention = "/overtAttention/set_mode";
  static constexpr const char* kSetPose = "/robotLocalization/set_pose";
  static constexpr const char* kNavigate = "/robotNavigation/set_goal";
  static constexpr const char* kSetLanguage = "/speechEvent/set_language";
  static constexpr const char* kSetSpeech = "/speechEvent/set_enabled";
  static constexpr const char* kTablet = "/tabletEvent/prompt_and_get_response";
  static constexpr const char* kSay = "/textToSpeech/say_text";
  static constexpr const char* kAttentionTopic = "/overtAttention/mode";
  static constexpr const char* kSpeechTopic = "/speechEvent/text";

  static const std::vector<const char*>& services() {
    static const std::vector<const char*> all = {kAnimate,     kGesture,   kAttention, kSetPose, kNavigate,
                                                 kSetLanguage, kSetSpeech, kTablet,    kSay};
    return all;
  }
};

struct Settings {
  Language language = Language::kEnglish;
  bool asr_enabled = true;
  double response_timeout_s = 10.0;  // GetVisitorResponse: how long to listen
};

class Leaves {
 public:
  using Status = btgen::Status;
  using NodeInfo = btgen::NodeInfo;

  Leaves(ros::NodeHandle& nh, const btgen::EnvironmentKnowledgeBase& kb, const Settings& settings,
         const NodeInfo* nodes, std::size_t count)
      : kb_(kb), settings_(settings), worker_(count), nodes_(nodes, nodes + count) {
    animate_ = nh.serviceClient<cssr_system::animateBehaviorSetActivation>(Interfaces::kAnimate);
    gesture_ = nh.serviceClient<cssr_system::gestureExecutionPerformGesture>(Interfaces::kGesture);
    attention_ = nh.serviceClient<cssr_system::overtAttentionSetMode>(Interfaces::kAttention);
    set_pose_ = nh.serviceClient<cssr_system::robotLocalizationSetPose>(Interfaces::kSetPose);
    navigate_ = nh.serviceClient<cssr_system::robotNavigationSetGoal>(Interfaces::kNavigate);
    set_language_ = nh.serviceClient<cssr_system::speechEventSetLanguage>(Interfaces::kSetLanguage);
    set_speech_ = nh.serviceClient<cssr_system::speechEventSetStatus>(Interfaces::kSetSpeech);
    tablet_ = nh.serviceClient<cssr_system::tabletEventPromptAndGetResponse>(Interfaces::kTablet);
    say_ = nh.serviceClient<cssr_system::textToSpeechSayText>(Interfaces::kSay);
    attention_sub_ = nh.subscribe(Interfaces::kAttentionTopic, 10, &Leaves::on_attention, this);
    speech_sub_ = nh.subscribe(Interfaces::kSpeechTopic, 10, &Leaves::on_speech, this);
  }

  /// Both topics have a publisher connected to this node.
  [[nodiscard]] const ros::Subscriber& attention_subscriber() const { return attention_sub_; }
  [[nodiscard]] const ros::Subscriber& speech_subscriber() const { return speech_sub_; }

  /// No further service call; waits for the one in progress (after ros::shutdown() it returns at once).
  void stop() { worker_.stop(); }

  // ---- Mission bookkeeping, no service -------------------------------------------------
  Status onStart(leaf::StartOfTree&, const NodeInfo& n) {
    ROS_INFO("behaviorController: ==== START OF TREE ==== (language %s, ASR %s)", language_name(settings_.language),
             settings_.asr_enabled ? "enabled" : "disabled");
    response_.clear();
    visits_ = 0;
    current_ = nullptr;
    if (!settings_.asr_enabled) return Status::SUCCESS;
    cssr_system::speechEventSetLanguage srv;
    srv.request.language = language_name(settings_.language);
    return start(n, set_language_, srv, "language " + srv.request.language,
                 [](const cssr_system::speechEventSetLanguage::Response& r) { return r.response != 0; });
  }

  Status onStart(leaf::HandleFallBack&, const NodeInfo& n) {
    const NodeInfo* failed = previous_sibling(n);
    ROS_WARN("behaviorController: HandleFallBack: %s failed; carrying on (%.*s)",
             failed != nullptr ? label(*failed).c_str() : "the previous step", static_cast<int>(n.source.size()),
             n.source.data());
    return Status::SUCCESS;
  }

  Status onStart(leaf::RetrieveListOfExhibits&, const NodeInfo&) {
    visits_ = 0;
    if (kb_.tour().empty()) {
      ROS_ERROR("behaviorController: RetrieveListOfExhibits: the knowledge base's tour is empty");
      return Status::FAILURE;
    }
    std::string ids;
    for (std::int32_t id : kb_.tour()) ids += (ids.empty() ? "" : " ") + std::to_string(id);
    ROS_INFO("behaviorController: RetrieveListOfExhibits: tour %s", ids.c_str());
    return Status::SUCCESS;
  }

  Status onStart(leaf::SelectExhibit&, const NodeInfo&) {
    if (visits_ >= kb_.tour().size()) {
      ROS_WARN("behaviorController: SelectExhibit: no exhibit left");
      return Status::FAILURE;
    }
    current_ = kb_.find(kb_.tour()[visits_++]);  // taken off the list even if it were missing: no endless loop
    if (current_ == nullptr) return Status::FAILURE;
    ROS_INFO("behaviorController: SelectExhibit: %d (%s), stop %zu of %zu", current_->id, current_->description.c_str(),
             visits_, kb_.tour().size());
    return Status::SUCCESS;
  }

  Status onStart(leaf::RetrieveInitialLocation&, const NodeInfo&) {
    current_ = kb_.tour().empty() ? nullptr : kb_.find(kb_.tour().front());
    if (current_ == nullptr) return Status::FAILURE;
    ROS_INFO("behaviorController: RetrieveInitialLocation: %d (%s)", current_->id, current_->description.c_str());
    return Status::SUCCESS;
  }

  // ---- Speech ----------------------------------------------------------------------------
  Status onStart(leaf::SayText&, const NodeInfo& n) {
    const char* text = utility_phrase(n.name, settings_.language);
    if (text == nullptr) return Status::FAILURE;  // checked at start-up
    return say(n, text, settings_.language);
  }

  Status onStart(leaf::DescribeExhibitSpeech&, const NodeInfo& n) {
    if (current_ == nullptr) {
      ROS_ERROR("behaviorController: DescribeExhibitSpeech: no exhibit selected");
      return Status::FAILURE;
    }
    const bool pre = n.name == "1";
    const btgen::Language kb_language = static_cast<btgen::Language>(static_cast<int>(settings_.language));
    const std::string& text =
        pre ? current_->preGestureMessage(kb_language) : current_->postGestureMessage(kb_language);
    if (!has_translation(text) && settings_.language != Language::kEnglish) {
      ROS_WARN("behaviorController: location %d has no %s %s-gesture message: saying it in English", current_->id,
               language_name(settings_.language), pre ? "pre" : "post");
      return say(n,
                 pre ? current_->preGestureMessage(btgen::Language::kEnglish)
                     : current_->postGestureMessage(btgen::Language::kEnglish),
                 Language::kEnglish);
    }
    return say(n, text, settings_.language);
  }

  Status onStart(leaf::SetSpeechEvent&, const NodeInfo& n) {
    cssr_system::speechEventSetStatus srv;
    srv.request.status = std::string(n.name);
    const bool listen = n.name == "true";
    return start(n, set_speech_, srv, "status " + srv.request.status,
                 [this, listen](const cssr_system::speechEventSetStatus::Response& r) {
                   if (r.response == 0) return false;
                   // Worker thread, as soon as the call returns: only what is heard from now on is an answer.
                   if (listen) mark_speech_floor();
                   return true;
                 });
  }

  /// Listens for the visitor's answer on /speechEvent/text (heard since SetSpeechEvent "true").
  Status onStart(leaf::GetVisitorResponse&, const NodeInfo&) {
    listen_since_ = ros::WallTime::now();
    response_.clear();
    ROS_INFO("behaviorController: GetVisitorResponse: listening on %s", Interfaces::kSpeechTopic);
    return poll_response();
  }
  Status onRunning(leaf::GetVisitorResponse&, const NodeInfo&) { return poll_response(); }
  void onHalted(leaf::GetVisitorResponse&, const NodeInfo&) {}

  Status onStart(leaf::PressYesNoDialogue&, const NodeInfo& n) {
    cssr_system::tabletEventPromptAndGetResponse srv;
    srv.request.message = "'Yes'|'No'";
    response_.clear();
    std::string* answer = &tablet_answer_;
    return start(n, tablet_, srv, "message " + srv.request.message,
                 [answer](const cssr_system::tabletEventPromptAndGetResponse::Response& r) {
                   *answer = r.success ? "yes" : "no";  // the tablet's one bit: Yes pressed
                   return true;
                 });
  }

  // ---- Body ------------------------------------------------------------------------------
  Status onStart(leaf::SetAnimateBehavior&, const NodeInfo& n) {
    cssr_system::animateBehaviorSetActivation srv;
    srv.request.state = std::string(n.name);
    return start(n, animate_, srv, "state " + srv.request.state,
                 [](const cssr_system::animateBehaviorSetActivation::Response& r) { return r.success == "1"; });
  }

  Status onStart(leaf::SetOvertAttentionMode&, const NodeInfo& n) {
    cssr_system::overtAttentionSetMode srv;
    srv.request.state = std::string(n.name);
    if (n.name == "location") {
      if (current_ == nullptr) return Status::FAILURE;
      srv.request.location_x = current_->gesture_target.x();
      srv.request.location_y = current_->gesture_target.y();
      srv.request.location_z = current_->gesture_target.z();
    }
    return start(n, attention_, srv, "state " + srv.request.state,
                 [this](const cssr_system::overtAttentionSetMode::Response& r) {
                   if (r.mode_set_success == 0) return false;
                   mark_attention_floor();  // worker thread: only messages of the new mode count
                   return true;
                 });
  }

  Status onStart(leaf::PerformIconicGesture&, const NodeInfo& n) {
    cssr_system::gestureExecutionPerformGesture srv;
    srv.request.gesture_type = "iconic";
    srv.request.gesture_id = n.name == "welcome" ? 1 : 3;  // 1 welcome, 3 goodbye (checked at start-up)
    srv.request.gesture_duration = 3000;
    srv.request.bow_nod_angle = 0;
    return start(n, gesture_, srv, "iconic " + std::string(n.name),
                 [](const cssr_system::gestureExecutionPerformGesture::Response& r) { return r.gesture_success != 0; });
  }

  Status onStart(leaf::PerformDeicticGesture&, const NodeInfo& n) {
    if (current_ == nullptr) return Status::FAILURE;
    const Eigen::Vector3d& t = current_->gesture_target;
    if (t.isZero()) {  // as the production node: nothing to point at
      ROS_INFO("behaviorController: PerformDeicticGesture: location %d has no gesture target", current_->id);
      return Status::SUCCESS;
    }
    cssr_system::gestureExecutionPerformGesture srv;
    srv.request.gesture_type = "deictic";
    srv.request.gesture_id = 1;
    srv.request.gesture_duration = 3000;
    srv.request.bow_nod_angle = 0;
    srv.request.location_x = t.x();
    srv.request.location_y = t.y();
    srv.request.location_z = t.z();
    return start(n, gesture_, srv, "deictic at " + xyz(t),
                 [](const cssr_system::gestureExecutionPerformGesture::Response& r) { return r.gesture_success != 0; });
  }

  Status onStart(leaf::SetRobotPose&, const NodeInfo& n) {
    const btgen::KbLocation* start_at = kb_.tour().empty() ? nullptr : kb_.find(kb_.tour().front());
    if (start_at == nullptr) return Status::FAILURE;
    cssr_system::robotLocalizationSetPose srv;
    srv.request.x = start_at->pose.x();
    srv.request.y = start_at->pose.y();
    srv.request.theta = start_at->pose.z();
    return start(n, set_pose_, srv, "pose of " + std::to_string(start_at->id) + " " + xyz(start_at->pose),
                 [](const cssr_system::robotLocalizationSetPose::Response& r) { return r.success; });
  }

  Status onStart(leaf::Navigate&, const NodeInfo& n) {
    if (current_ == nullptr) {
      ROS_ERROR("behaviorController: Navigate: no location selected");
      return Status::FAILURE;
    }
    cssr_system::robotNavigationSetGoal srv;
    srv.request.goal_x = current_->pose.x();
    srv.request.goal_y = current_->pose.y();
    srv.request.goal_theta = current_->pose.z();
    return start(n, navigate_, srv, "to " + std::to_string(current_->id) + " " + xyz(current_->pose),
                 [](const cssr_system::robotNavigationSetGoal::Response& r) { return r.navigation_goal_success != 0; });
  }

  // ---- Every Action: the call's result, and halts --------------------------------------------
  template <class M>
  Status onRunning(M& m, const NodeInfo& n) {
    switch (worker_.poll(n.index)) {
      case ServiceWorker::Poll::kRunning: return Status::RUNNING;
      case ServiceWorker::Poll::kFailed: return Status::FAILURE;
      case ServiceWorker::Poll::kSucceeded: break;
    }
    completed(m, n);
    return Status::SUCCESS;
  }
  template <class M>
  void onHalted(M&, const NodeInfo& n) {
    worker_.abandon(n.index);
  }

  // ---- Conditions ----------------------------------------------------------------------------
  Status check(leaf::IsASREnabled&, const NodeInfo&) { return ok(settings_.asr_enabled); }
  Status check(leaf::IsListWithExhibit&, const NodeInfo&) { return ok(visits_ < kb_.tour().size()); }
  Status check(leaf::IsVisitorResponseYes&, const NodeInfo&) {
    ROS_INFO("behaviorController: IsVisitorResponseYes: the answer is \"%s\"", response_.c_str());
    return ok(response_ == "yes");
  }
  Status check(leaf::HasVisitorResponded&, const NodeInfo&) { return ok(!response_.empty()); }
  // overtAttention reports 2 when the mode found what it looks for (a visitor
  // when scanning, mutual gaze when seeking), 3 when seeking failed. Only
  // messages received after the last SetOvertAttentionMode count.
  Status check(leaf::IsVisitorDiscovered&, const NodeInfo&) { return ok(attention_is("scanning", 2)); }
  Status check(leaf::IsVisitorPresent&, const NodeInfo&) { return ok(attention_is("scanning", 2)); }
  Status check(leaf::IsMutualGazeDiscovered&, const NodeInfo&) { return ok(attention_is("seeking", 2)); }

 private:
  static Status ok(bool b) { return b ? Status::SUCCESS : Status::FAILURE; }

  static std::string label(const NodeInfo& n) {
    std::string s(n.id);
    if (n.name != n.id) s += " \"" + std::string(n.name) + "\"";
    return s;
  }

  static std::string xyz(const Eigen::Vector3d& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.2f, %.2f, %.2f)", v.x(), v.y(), v.z());
    return buf;
  }

  static bool has_translation(const std::string& text) {
    return !text.empty() && text.rfind("No message in", 0) != 0;  // the knowledge base's placeholder
  }

  const NodeInfo* previous_sibling(const NodeInfo& n) const {
    for (std::size_t j = n.index; j-- > 0;) {
      if (nodes_[j].parent == n.parent) return &nodes_[j];
    }
    return nullptr;
  }

  Status say(const NodeInfo& n, const std::string& text, Language language) {
    cssr_system::textToSpeechSayText srv;
    srv.request.message = text;
    srv.request.language = language_name(language);
    return start(n, say_, srv, "\"" + text + "\" in " + srv.request.language,
                 [](const cssr_system::textToSpeechSayText::Response& r) { return r.success; });
  }

  // Hands the call to the worker; RUNNING until onRunning() sees its result.
  template <class Srv, class Ok>
  Status start(const NodeInfo& n, ros::ServiceClient& client, const Srv& srv, const std::string& what, Ok ok) {
    const std::string who = label(n);
    ROS_INFO("behaviorController: %s: %s %s", who.c_str(), client.getService().c_str(), what.c_str());
    worker_.start(n.index, [&client, srv = Srv(srv), ok, who]() mutable {
      try {
        if (!client.call(srv)) {
          ROS_WARN("behaviorController: %s: calling %s failed", who.c_str(), client.getService().c_str());
          return false;
        }
      } catch (const std::exception& e) {
        ROS_WARN("behaviorController: %s: calling %s failed: %s", who.c_str(), client.getService().c_str(), e.what());
        return false;
      }
      if (!ok(srv.response)) {
        ROS_WARN("behaviorController: %s: %s reported failure", who.c_str(), client.getService().c_str());
        return false;
      }
      return true;
    });
    return Status::RUNNING;
  }

  // What a successful call changes besides the robot.
  template <class M>
  void completed(const M&, const NodeInfo&) {}
  void mark_attention_floor() {
    std::lock_guard<std::mutex> lock(mutex_);
    attention_floor_ = attention_seq_;
  }
  void mark_speech_floor() {
    std::lock_guard<std::mutex> lock(mutex_);
    speech_floor_ = speech_seq_;
  }
  void completed(const leaf::PressYesNoDialogue&, const NodeInfo&) {
    response_ = tablet_answer_;
    ROS_INFO("behaviorController: PressYesNoDialogue: the visitor pressed %s", response_.c_str());
  }

  Status poll_response() {
    std::string heard;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (speech_seq_ > speech_floor_) {
        heard = speech_text_;
        speech_floor_ = speech_seq_;  // consumed
      }
    }
    if (!heard.empty()) {
      ROS_INFO("behaviorController: GetVisitorResponse: heard \"%s\"", heard.c_str());
      if (heard.find("Error") != std::string::npos) return Status::FAILURE;  // speechEvent's error report
      const Answer a = classify_answer(heard, settings_.language);
      response_ = a == Answer::kYes ? "yes" : a == Answer::kNo ? "no" : "";
      return Status::SUCCESS;
    }
    if ((ros::WallTime::now() - listen_since_).toSec() > settings_.response_timeout_s) {
      ROS_WARN("behaviorController: GetVisitorResponse: no answer within %.1f s", settings_.response_timeout_s);
      response_.clear();
      return Status::SUCCESS;  // as the production node: HasVisitorResponded then fails
    }
    return Status::RUNNING;
  }

  bool attention_is(const char* state, std::int64_t value) {
    std::lock_guard<std::mutex> lock(mutex_);
    return attention_seq_ > attention_floor_ && attention_state_ == state && attention_value_ == value;
  }

  void on_attention(const cssr_system::overtAttentionMode::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    attention_state_ = msg->state;
    attention_value_ = msg->value;
    ++attention_seq_;
  }
  void on_speech(const std_msgs::String::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    speech_text_ = msg->data;
    ++speech_seq_;
  }

  const btgen::EnvironmentKnowledgeBase& kb_;
  Settings settings_;
  ros::ServiceClient animate_, gesture_, attention_, set_pose_, navigate_, set_language_, set_speech_, tablet_, say_;
  ros::Subscriber attention_sub_, speech_sub_;
  ServiceWorker worker_;
  std::vector<NodeInfo> nodes_;

  // Tick thread only.
  std::size_t visits_ = 0;                      // stops of the tour taken so far
  const btgen::KbLocation* current_ = nullptr;  // the exhibit or location selected
  std::string response_;                        // "yes", "no" or "" (none)
  std::string tablet_answer_;                   // written by the worker before it reports the call done
  ros::WallTime listen_since_;

  // Shared with the subscriber callbacks.
  std::mutex mutex_;
  std::string attention_state_;
  std::int64_t attention_value_ = 0;
  std::uint64_t attention_seq_ = 0, attention_floor_ = 0;
  std::string speech_text_;
  std::uint64_t speech_seq_ = 0, speech_floor_ = 0;
};

}  // namespace btgen_behavior_controller
