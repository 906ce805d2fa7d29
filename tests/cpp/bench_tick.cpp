// Speed of generated missions with instant leaves: prints numbers, asserts nothing.
//   bench_tick [ticks]
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "btgen/clock.hpp"
#include "control_flow.hpp"
#include "test_leaves.hpp"
#ifdef BTGEN_TEST_HAVE_PICK_PLACE_BALL
#include "pick_place_ball.hpp"
#endif
#ifdef BTGEN_TEST_HAVE_LAB_TOUR
#include "lab_tour.hpp"
#endif

namespace {

// Counts status changes, to report the work done per tick.
struct CountingObserver {
  unsigned long long* changes;
  void on_status_change(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept { ++*changes; }
};

template <template <class, class, class> class Mission>
void bench(const char* name, long ticks) {
  btgen_test::InstantLeaves leaves;
  unsigned long long changes = 0;
  {
    Mission<btgen_test::InstantLeaves, btgen::ManualClock, CountingObserver> counted(leaves, btgen::ManualClock{},
                                                                                     CountingObserver{&changes});
    for (int i = 0; i < 1000; ++i) (void)counted.tick();
  }
  static Mission<btgen_test::InstantLeaves, btgen::ManualClock, btgen::NoObserver> mission(leaves);
  unsigned sink = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < ticks; ++i) sink += static_cast<unsigned>(mission.tick());
  const auto t1 = std::chrono::steady_clock::now();
  const double secs = std::chrono::duration<double>(t1 - t0).count();
  std::printf("%-16s nodes %4zu  sizeof %6zu B  %12.0f ticks/s  %8.1f ns/tick  %6.2f ns/status change  (%u)\n", name,
              mission.node_count(), sizeof(mission), ticks / secs, secs * 1e9 / ticks,
              secs * 1e9 / (ticks * (changes / 1000.0)), sink % 10);
}

}  // namespace

int main(int argc, char** argv) {
  const long ticks = argc > 1 ? std::atol(argv[1]) : 2000000;
  bench<control_flow::ControlFlow>("control_flow", ticks);
#ifdef BTGEN_TEST_HAVE_PICK_PLACE_BALL
  bench<pick_place_ball::PickPlaceBall>("PickPlaceBall", ticks);
#endif
#ifdef BTGEN_TEST_HAVE_LAB_TOUR
  bench<lab_tour::LabTour>("LabTour", ticks);
#endif
  return 0;
}
