// Force-included (g++ -include) before a Nav2 plugin source by record.py: the plugin's
// std::chrono::high_resolution_clock becomes a clock the harness moves, so a case with
// `clock_ms N` is recorded without sleeping and without timing noise (btgen's executors
// take time from the same kind of injectable clock).
#pragma once
#include <chrono>

extern "C" long long btgen_nav2_clock_ns;  // defined and advanced by the harness

namespace btgen_nav2 {
struct Clock {
  using duration = std::chrono::nanoseconds;
  using rep = duration::rep;
  using period = duration::period;
  using time_point = std::chrono::time_point<Clock>;
  static constexpr bool is_steady = true;
  static time_point now() noexcept { return time_point(duration(btgen_nav2_clock_ns)); }
};
}  // namespace btgen_nav2

namespace std::chrono {
using btgen_nav2_clock = ::btgen_nav2::Clock;
}

#define high_resolution_clock btgen_nav2_clock
