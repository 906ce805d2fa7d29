#include "pepper.hpp"

#include <cmath>
#include <cstdarg>

namespace lab_tour_robot {

using btgen::Status;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string_view attention_name(Attention a) noexcept {
  switch (a) {
    case Attention::kDisabled: return "disabled";
    case Attention::kScanning: return "scanning";
    case Attention::kSocial: return "social";
  }
  return "?";
}

// The difference of two headings in degrees, in (-180, 180].
double heading_change(double from_deg, double to_deg) noexcept {
  double d = std::fmod(to_deg - from_deg, 360.0);
  if (d <= -180.0) d += 360.0;
  if (d > 180.0) d -= 360.0;
  return d;
}

}  // namespace

SimulatedPepper::SimulatedPepper(const btgen::EnvironmentKnowledgeBase& kb, const SpeechBook& speech,
                                 const TourPlan& plan, Settings settings, std::size_t node_count,
                                 btgen::ScenarioLeaves* scenario, std::FILE* out)
    : kb_(kb),
      speech_(speech),
      plan_(plan),
      settings_(settings),
      scenario_(scenario),
      out_(out),
      activity_(node_count) {
  // Pepper starts the day at home.
  if (const btgen::KbLocation* home = kb_.find(plan_.home)) {
    pose_ = home->pose;
    at_ = home->id;
  }
}

void SimulatedPepper::say(const char* format, ...) {
  std::fprintf(out_, "[tick %3ld] ", tick_);
  va_list args;
  va_start(args, format);
  std::vfprintf(out_, format, args);
  va_end(args);
  std::fputc('\n', out_);
}

Status SimulatedPepper::decide(const btgen::NodeInfo& node, Status simulated) {
  if (scenario_ == nullptr) return simulated;
  int any_model = 0;  // ScenarioLeaves only looks at the node
  return scenario_->check(any_model, node);
}

std::string SimulatedPepper::place(std::int32_t id) const {
  const btgen::KbLocation* loc = kb_.find(id);
  return std::to_string(id) + " (" + (loc != nullptr ? loc->description : std::string("not in the knowledge base")) +
         ")";
}

std::string SimulatedPepper::cultural(std::int32_t id) const {
  const btgen::KbLocation* loc = kb_.find(id);
  std::string keys;
  if (loc == nullptr) return keys;
  for (const std::string& k : loc->cultural_knowledge) keys += (keys.empty() ? "" : " ") + k;
  return keys;
}

void SimulatedPepper::speak(const Utterance& u) { say("says: \"%s\"", u.text.c_str()); }

Status SimulatedPepper::fail(const btgen::NodeInfo& node, const char* why) {
  const Status st = decide(node, Status::FAILURE);
  say("%.*s: %s%s", static_cast<int>(node.name.size()), node.name.data(), why,
      st == Status::FAILURE ? "" : " (the scenario says it succeeds)");
  return st;
}

// ---- actions without ports -------------------------------------------------

Status SimulatedPepper::startOfTree(const btgen::NodeInfo& node) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::FAILURE) {
    say("mission start failed");
  } else {
    say("mission starts; Pepper stands at %s", place(at_).c_str());
  }
  return st;
}

Status SimulatedPepper::setAnimate(const btgen::NodeInfo& node, bool on) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    animate_ = on;
    say("animate behaviour %s", on ? "on" : "off");
  } else {
    say("could not switch animate behaviour %s (%s)", on ? "on" : "off", std::string(btgen::to_string(st)).c_str());
  }
  return st;
}

Status SimulatedPepper::setAttention(const btgen::NodeInfo& node, Attention mode) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    attention_ = mode;
    say("overt attention: %.*s", static_cast<int>(attention_name(mode).size()), attention_name(mode).data());
  } else {
    say("could not set overt attention to %.*s (%s)", static_cast<int>(attention_name(mode).size()),
        attention_name(mode).data(), std::string(btgen::to_string(st)).c_str());
  }
  return st;
}

Status SimulatedPepper::gestureStart(const btgen::NodeInfo& node, std::string_view what) {
  const Status st = decide(node, Status::RUNNING);
  const std::string keys = cultural(at_);
  say("%.*s%s%s%s", static_cast<int>(what.size()), what.data(),
      keys.empty() ? "" : " (cultural knowledge: ", keys.c_str(), keys.empty() ? "" : ")");
  if (st == Status::FAILURE) say("the gesture failed");
  return st;
}

Status SimulatedPepper::gestureRunning(const btgen::NodeInfo& node) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::FAILURE) say("the gesture failed");
  return st;
}

void SimulatedPepper::gestureHalted(const btgen::NodeInfo& node) {
  say("%.*s stopped", static_cast<int>(node.name.size()), node.name.data());
}

Status SimulatedPepper::handleFallBack(const btgen::NodeInfo& node, std::string_view failed) {
  const Status st = decide(node, Status::SUCCESS);
  say("HandleFallBack: %.*s failed; %s", static_cast<int>(failed.size()), failed.data(),
      st == Status::SUCCESS ? "carrying on" : "giving up");
  return st;
}

// ---- speech --------------------------------------------------------------------

Status SimulatedPepper::speechStart(const btgen::NodeInfo& node, std::string_view key) {
  const std::vector<Utterance>* utterances = speech_.phrase(key);
  if (utterances == nullptr) {
    const std::string why = "no phrase `" + std::string(key) + "` in the phrase table";
    return fail(node, why.c_str());
  }
  const Status st = decide(node, Status::RUNNING);
  if (st != Status::FAILURE) {
    for (const Utterance& u : *utterances) speak(u);
  } else {
    say("%.*s: the speech failed", static_cast<int>(node.name.size()), node.name.data());
  }
  return st;
}

Status SimulatedPepper::describeStart(const btgen::NodeInfo& node, LocationPort location, bool post_gesture) {
  if (!location.known) return fail(node, ("no location_id to describe: " + std::string(location.why)).c_str());
  const Utterance* u = speech_.location_message(location.id, post_gesture);
  if (u == nullptr) {
    const std::string why = "location " + std::to_string(location.id) + " is not in the knowledge base";
    return fail(node, why.c_str());
  }
  const Status st = decide(node, Status::RUNNING);
  if (st != Status::FAILURE) {
    speak(*u);
  } else {
    say("%.*s: the speech failed", static_cast<int>(node.name.size()), node.name.data());
  }
  return st;
}

Status SimulatedPepper::speechRunning(const btgen::NodeInfo& node) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::FAILURE) say("%.*s: the speech failed", static_cast<int>(node.name.size()), node.name.data());
  return st;
}

void SimulatedPepper::speechHalted(const btgen::NodeInfo& node) {
  say("%.*s: stops talking", static_cast<int>(node.name.size()), node.name.data());
}

// ---- moving and pointing ---------------------------------------------------------

Status SimulatedPepper::navigateStart(const btgen::NodeInfo& node, LocationPort location) {
  if (!location.known) return fail(node, ("no location_id to navigate to: " + std::string(location.why)).c_str());
  const btgen::KbLocation* target = kb_.find(location.id);
  if (target == nullptr) {
    const std::string why = "location " + std::to_string(location.id) + " is not in the knowledge base";
    return fail(node, why.c_str());
  }
  Activity& a = activity_[node.index];
  a.target = target->id;
  a.step = 0;
  a.from = pose_;
  const double distance = (target->pose.head<2>() - pose_.head<2>()).norm();
  a.steps = std::max(1, static_cast<int>(std::ceil(distance / kMetresPerTick - 1e-9)));
  ++navigations_;
  say("navigating to %s: x %.2f m, y %.2f m, theta %.1f deg (%.1f m away)", place(target->id).c_str(), target->pose.x(),
      target->pose.y(), target->pose.z(), distance);
  const Status st = decide(node, Status::RUNNING);
  if (st == Status::SUCCESS) {
    pose_ = target->pose;
    at_ = target->id;
    say("arrived at %s", place(at_).c_str());
  } else if (st == Status::FAILURE) {
    say("navigation to %s failed; still at x %.2f, y %.2f", place(target->id).c_str(), pose_.x(), pose_.y());
  } else {
    at_ = 0;
  }
  return st;
}

Status SimulatedPepper::navigateRunning(const btgen::NodeInfo& node) {
  Activity& a = activity_[node.index];
  const btgen::KbLocation* target = kb_.find(a.target);
  if (target == nullptr) return fail(node, "lost the navigation target");
  ++a.step;
  const Status st = decide(node, a.step >= a.steps ? Status::SUCCESS : Status::RUNNING);
  if (st == Status::SUCCESS) {
    pose_ = target->pose;
    at_ = target->id;
    say("arrived at %s: x %.2f, y %.2f, theta %.1f", place(at_).c_str(), pose_.x(), pose_.y(), pose_.z());
  } else if (st == Status::RUNNING) {
    const double f = std::min(1.0, static_cast<double>(a.step) / a.steps);
    pose_.head<2>() = a.from.head<2>() + f * (target->pose.head<2>() - a.from.head<2>());
    const Eigen::Vector2d to_go = target->pose.head<2>() - pose_.head<2>();
    if (to_go.norm() > 1e-9) pose_.z() = std::atan2(to_go.y(), to_go.x()) * 180.0 / kPi;
    const double turn = heading_change(pose_.z(), target->pose.z());
    say("on the way to %d: x %.2f, y %.2f, %.1f m to go%s", a.target, pose_.x(), pose_.y(), to_go.norm(),
        to_go.norm() > 1e-9 ? "" : (std::fabs(turn) > 1e-9 ? ", turning" : ", settling"));
  } else {
    say("navigation to %s failed at x %.2f, y %.2f", place(a.target).c_str(), pose_.x(), pose_.y());
  }
  return st;
}

void SimulatedPepper::navigateHalted(const btgen::NodeInfo& node) {
  const Activity& a = activity_[node.index];
  at_ = 0;
  say("navigation to %s halted at x %.2f, y %.2f", place(a.target).c_str(), pose_.x(), pose_.y());
}

Status SimulatedPepper::pointStart(const btgen::NodeInfo& node, LocationPort location) {
  if (!location.known) return fail(node, ("no location_id to point at: " + std::string(location.why)).c_str());
  const btgen::KbLocation* target = kb_.find(location.id);
  if (target == nullptr) {
    const std::string why = "location " + std::to_string(location.id) + " is not in the knowledge base";
    return fail(node, why.c_str());
  }
  activity_[node.index].target = target->id;
  const std::string keys = cultural(target->id);
  say("points at %s: x %.2f, y %.2f, z %.2f (cultural knowledge: %s)", place(target->id).c_str(),
      target->gesture_target.x(), target->gesture_target.y(), target->gesture_target.z(),
      keys.empty() ? "none" : keys.c_str());
  const Status st = decide(node, Status::RUNNING);
  if (st == Status::FAILURE) say("pointing at %s failed", place(target->id).c_str());
  return st;
}

Status SimulatedPepper::pointRunning(const btgen::NodeInfo& node) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::FAILURE) say("pointing at %s failed", place(activity_[node.index].target).c_str());
  return st;
}

void SimulatedPepper::pointHalted(const btgen::NodeInfo& node) {
  say("pointing at %s halted", place(activity_[node.index].target).c_str());
}

// ---- the knowledge base's tour ----------------------------------------------------

Status SimulatedPepper::lookUpHome(const btgen::NodeInfo& node, std::int32_t& location_id) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    location_id = plan_.home;
    say("home: %s, the tour's first stop", place(plan_.home).c_str());
  } else {
    say("LookUpHome failed");
  }
  return st;
}

Status SimulatedPepper::lookUpEntrance(const btgen::NodeInfo& node, std::int32_t& location_id) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    location_id = plan_.exit;
    say("entrance: %s, the tour's last stop", place(plan_.exit).c_str());
  } else {
    say("LookUpEntrance failed");
  }
  return st;
}

Status SimulatedPepper::retrieveListOfExhibits(const btgen::NodeInfo& node, std::string& exhibits) {
  const Status st = decide(node, Status::SUCCESS);
  if (st != Status::SUCCESS) {
    say("could not retrieve the list of exhibits");
    return st;
  }
  exhibits = exhibit_list_text(plan_.exhibits);
  std::string tour;
  for (std::int32_t id : kb_.tour()) tour += (tour.empty() ? "" : " ") + std::to_string(id);
  say("tour of the knowledge base: %s; exhibits to visit: %s", tour.c_str(),
      exhibits.empty() ? "none" : exhibits.c_str());
  return st;
}

Status SimulatedPepper::selectExhibit(const btgen::NodeInfo& node, std::string_view exhibits, std::string& rest,
                                      std::int32_t& location_id) {
  std::int32_t id = 0;
  std::string_view remaining;
  switch (take_first_exhibit(exhibits, id, remaining)) {
    case ListRead::kEmpty: return fail(node, "no exhibit left to select");
    case ListRead::kMalformed: {
      const std::string why = "the exhibit list `" + std::string(exhibits) + "` is not location ids separated by `;`";
      return fail(node, why.c_str());
    }
    case ListRead::kTaken: break;
  }
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    location_id = id;
    rest.assign(remaining.data(), remaining.size());
    say("next exhibit: %s; still to visit: %s", place(id).c_str(), rest.empty() ? "none" : rest.c_str());
  } else {
    say("SelectExhibit failed");
  }
  return st;
}

Status SimulatedPepper::isListWithExhibit(const btgen::NodeInfo& node, std::string_view exhibits) {
  std::int32_t id = 0;
  std::string_view rest;
  const bool any = take_first_exhibit(exhibits, id, rest) != ListRead::kEmpty;
  const Status st = decide(node, any ? Status::SUCCESS : Status::FAILURE);
  if (!any || st != Status::SUCCESS) say("no more exhibits%s", any ? " (as the scenario says)" : "");
  return st;
}

// ---- the visitor ----------------------------------------------------------------

Status SimulatedPepper::isVisitorDiscovered(const btgen::NodeInfo& node) {
  ++visitor_checks_;
  const Status st = decide(node, visitor_checks_ >= settings_.visitor_check ? Status::SUCCESS : Status::FAILURE);
  say(st == Status::SUCCESS ? "looking for a visitor: found one" : "looking for a visitor: nobody yet");
  return st;
}

Status SimulatedPepper::isMutualGazeDiscovered(const btgen::NodeInfo& node) {
  const Status st = decide(node, Status::SUCCESS);
  say(st == Status::SUCCESS ? "mutual gaze with the visitor" : "no mutual gaze with the visitor");
  return st;
}

Status SimulatedPepper::isASREnabled(const btgen::NodeInfo& node) {
  const Status st = decide(node, Status::SUCCESS);
  say(st == Status::SUCCESS ? "speech recognition is on" : "speech recognition is off");
  return st;
}

Status SimulatedPepper::isYesNoUttered(const btgen::NodeInfo& node, std::string& response) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    response = settings_.answer_yes ? "yes" : "no";
    say("hears the visitor say \"%s\"", response.c_str());
  } else {
    say("hears no clear yes or no");
  }
  return st;
}

Status SimulatedPepper::pressYesNoDialogueStart(const btgen::NodeInfo& node, std::string& response) {
  const Status st = decide(node, Status::RUNNING);
  say("shows Yes and No on the tablet");
  if (st == Status::SUCCESS) {
    response = settings_.answer_yes ? "yes" : "no";
    say("the visitor presses %s on the tablet", settings_.answer_yes ? "Yes" : "No");
  } else if (st == Status::FAILURE) {
    say("the tablet dialogue failed");
  }
  return st;
}

Status SimulatedPepper::pressYesNoDialogueRunning(const btgen::NodeInfo& node, std::string& response) {
  const Status st = decide(node, Status::SUCCESS);
  if (st == Status::SUCCESS) {
    response = settings_.answer_yes ? "yes" : "no";
    say("the visitor presses %s on the tablet", settings_.answer_yes ? "Yes" : "No");
  } else if (st == Status::FAILURE) {
    say("nobody pressed Yes or No in time");
  }
  return st;
}

void SimulatedPepper::pressYesNoDialogueHalted(const btgen::NodeInfo&) { say("the tablet dialogue is closed"); }

Status SimulatedPepper::isVisitorResponseYes(const btgen::NodeInfo& node, bool known, std::string_view response) {
  const bool yes = known && response == "yes";
  const Status st = decide(node, yes ? Status::SUCCESS : Status::FAILURE);
  say("the visitor's answer is %s%.*s%s: %s", known ? "\"" : "", static_cast<int>(known ? response.size() : 7),
      known ? response.data() : "unknown", known ? "\"" : "", st == Status::SUCCESS ? "the tour goes on" : "no tour");
  return st;
}

Status SimulatedPepper::portFailure(const btgen::NodeInfo& node, std::string_view port, std::string_view why) {
  const std::string text = "port `" + std::string(port) + "`: " + std::string(why);
  return fail(node, text.c_str());
}

Status SimulatedPepper::writeFailure(const btgen::NodeInfo& node, std::string_view port) {
  say("%.*s: could not write port `%.*s`; the node fails", static_cast<int>(node.name.size()), node.name.data(),
      static_cast<int>(port.size()), port.data());
  return Status::FAILURE;
}

void SimulatedPepper::halted(const btgen::NodeInfo& node) {
  say("%.*s halted", static_cast<int>(node.name.size()), node.name.data());
}

}  // namespace lab_tour_robot
