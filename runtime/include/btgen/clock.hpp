// btgen runtime: injectable clocks for the time-based nodes (Sleep, Delay, Timeout).
//
// A clock is any type with `std::uint64_t now_ms()` returning milliseconds
// from an arbitrary, fixed origin that never goes backwards. The mission
// object owns its clock (a template parameter), so a clock with no state
// costs nothing.
#pragma once

#include <chrono>
#include <cstdint>

namespace btgen {

// The default: std::chrono::steady_clock, a monotonic clock.
struct SteadyClock {
  [[nodiscard]] std::uint64_t now_ms() const noexcept {
    const auto since = std::chrono::steady_clock::now().time_since_epoch();
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(since).count());
  }
};

// A clock that moves only when told to: for tests, simulation and scenarios
// (`clock_ms N` advances it by N before each tick after the first).
class ManualClock {
 public:
  constexpr ManualClock() noexcept = default;
  constexpr explicit ManualClock(std::uint64_t start_ms) noexcept : now_(start_ms) {}

  [[nodiscard]] constexpr std::uint64_t now_ms() const noexcept { return now_; }
  constexpr void advance(std::uint64_t ms) noexcept { now_ += ms; }
  constexpr void set(std::uint64_t ms) noexcept { now_ = ms; }

 private:
  std::uint64_t now_ = 0;
};

}  // namespace btgen
