// The Lab Tour's leaves on the board, simulated: what a firmware engineer
// replaces with drivers. Actions take time (speech, gestures, journeys run
// for some milliseconds of the SysTick clock, returning RUNNING meanwhile);
// conditions answer at once; the data leaves move exhibit ids through the
// blackboard with the generated typed port accessors. Nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "btgen_bsp.hpp"
#include "lab_tour.hpp"

namespace robot {

using btgen::NodeInfo;
using btgen::Status;
namespace leaf = lab_tour::leaf;

// How long a simulated action runs (milliseconds), by its model.
template <class M>
constexpr std::uint32_t duration_ms() noexcept {
  constexpr std::string_view id = M::kId;
  if constexpr (id == "Navigate") {
    return 400;
  } else if constexpr (id.size() > 6 && id.substr(id.size() - 6) == "Speech") {
    return 120;
  } else if constexpr (id.size() > 7 && id.substr(id.size() - 7) == "Gesture") {
    return 200;
  } else {
    return 0;
  }
}

class SimulatedRobot {
 public:
  static constexpr std::size_t kNodes = lab_tour::detail::Spec::kNodeCount;

  // Every Action: start a job of duration_ms<M>() (none: done at once).
  template <class M>
  Status onStart(M&, const NodeInfo& n) noexcept {
    if constexpr (duration_ms<M>() == 0) {
      return Status::SUCCESS;
    } else {
      deadline_[n.index] = btgen_bsp::millis() + duration_ms<M>();
      return Status::RUNNING;
    }
  }
  template <class M>
  Status onRunning(M&, const NodeInfo& n) noexcept {
    return btgen_bsp::millis() >= deadline_[n.index] ? Status::SUCCESS : Status::RUNNING;
  }
  template <class M>
  void onHalted(M&, const NodeInfo& n) noexcept {
    deadline_[n.index] = 0;  // stop the motors, cut the speech
  }
  // Every Condition not below: true.
  template <class C>
  Status check(C&, const NodeInfo&) noexcept {
    return Status::SUCCESS;
  }

  // A visitor walks in 300 ms after power-on.
  Status check(leaf::IsVisitorDiscovered&, const NodeInfo&) noexcept {
    return btgen_bsp::millis() >= 300 ? Status::SUCCESS : Status::FAILURE;
  }
  // The visitor says "yes".
  Status check(leaf::IsYesNoUttered& m, const NodeInfo&) noexcept {
    return m.set_response("yes") ? Status::SUCCESS : Status::FAILURE;
  }
  Status onStart(leaf::PressYesNoDialogue& m, const NodeInfo&) noexcept {
    return m.set_response("yes") ? Status::SUCCESS : Status::FAILURE;
  }
  Status check(leaf::IsVisitorResponseYes& m, const NodeInfo&) noexcept {
    return m.response().value_or("") == "yes" ? Status::SUCCESS : Status::FAILURE;
  }
  // Three exhibits (knowledge-base location ids), visited in order.
  Status onStart(leaf::RetrieveListOfExhibits& m, const NodeInfo&) noexcept {
    return m.set_exhibits("4;7;9") ? Status::SUCCESS : Status::FAILURE;
  }
  Status check(leaf::IsListWithExhibit& m, const NodeInfo&) noexcept {
    return m.exhibits().value_or("").empty() ? Status::FAILURE : Status::SUCCESS;
  }
  Status onStart(leaf::SelectExhibit& m, const NodeInfo&) noexcept {
    const std::string_view list = m.exhibits().value_or("");
    const std::size_t semi = list.find(';');
    const std::string_view first = list.substr(0, semi);
    std::int32_t id = 0;
    for (const char c : first) id = id * 10 + (c - '0');
    const std::string_view rest = semi == std::string_view::npos ? std::string_view() : list.substr(semi + 1);
    return m.set_location_id(id) && m.set_exhibits(rest) ? Status::SUCCESS : Status::FAILURE;
  }
  Status onStart(leaf::LookUpEntrance& m, const NodeInfo&) noexcept {
    return m.set_location_id(1) ? Status::SUCCESS : Status::FAILURE;
  }
  Status onStart(leaf::LookUpHome& m, const NodeInfo&) noexcept {
    return m.set_location_id(0) ? Status::SUCCESS : Status::FAILURE;
  }

 private:
  std::array<std::uint64_t, kNodes> deadline_{};
};

}  // namespace robot
