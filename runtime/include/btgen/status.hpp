// btgen runtime: node status, as BehaviorTree.CPP 4.6.2's BT::NodeStatus.
#pragma once

#include <cstdint>
#include <string_view>

namespace btgen {

// Same enumerators and values as BT::NodeStatus.
enum class Status : std::uint8_t {
  IDLE = 0,
  RUNNING = 1,
  SUCCESS = 2,
  FAILURE = 3,
  SKIPPED = 4,
};

[[nodiscard]] constexpr std::string_view to_string(Status s) noexcept {
  switch (s) {
    case Status::IDLE: return "IDLE";
    case Status::RUNNING: return "RUNNING";
    case Status::SUCCESS: return "SUCCESS";
    case Status::FAILURE: return "FAILURE";
    case Status::SKIPPED: return "SKIPPED";
  }
  return "INVALID";
}

// SUCCESS or FAILURE (BT::isStatusCompleted).
[[nodiscard]] constexpr bool is_completed(Status s) noexcept { return s == Status::SUCCESS || s == Status::FAILURE; }

// Neither IDLE nor SKIPPED (BT::isStatusActive).
[[nodiscard]] constexpr bool is_active(Status s) noexcept { return s != Status::IDLE && s != Status::SKIPPED; }

}  // namespace btgen
