// The benchmark executable of one generated mission, built by `btgen bench`
// (generator/btgen/tools/bench.py) with
//   -DBTGEN_MISSION_HEADER='"x.hpp"' -DBTGEN_MISSION_TEMPLATE=x::X
// and linked with runtime/src/testing/alloc_counter.cpp, which replaces the
// global operator new/delete and malloc/calloc/realloc to count allocations.
//
//   BINARY N            constructs the mission and ticks it N times; prints nothing,
//                       so `valgrind --tool=callgrind BINARY N` counts instructions
//                       (start-up + N ticks: difference two values of N for one tick)
//   BINARY N --report   the same, then prints `key value` lines:
//     nodes             nodes of the mission (SubTrees expanded)
//     ticks             N
//     ns_per_tick       wall-clock time of the N ticks / N (steady_clock)
//     allocs_create     heap allocations while constructing the mission object
//     allocs_per_tick   heap allocations during the N ticks / N
//     state_bytes       sizeof the mission object (all of its run-time state)
//     node_state_bytes  the part of it that is the nodes' state (Engine::node_state_bytes)
//     blackboard_bytes  the part of it that is the blackboard (Engine::blackboard_bytes)
//     visited_per_tick  nodes ticked per tick, counted on a second instance
//                       (see VisitCounter), averaged over the first min(N, 64) ticks
//     result            status the last tick returned
//     alloc_counter     what is counted: `new+malloc`, or `new` where malloc cannot
//                       be replaced (sanitizers). Before printing, the binary checks
//                       that the counter sees an allocation (exit 3 if not).
//
// The leaves finish at once (Actions SUCCESS from onStart, Conditions
// SUCCESS) and the clock is a ManualClock that never moves, so every run of
// the same binary executes the same instructions.
#ifndef BTGEN_MISSION_HEADER
#error "define BTGEN_MISSION_HEADER as the generated header, e.g. -DBTGEN_MISSION_HEADER='\"lab_tour.hpp\"'"
#endif
#ifndef BTGEN_MISSION_TEMPLATE
#error "define BTGEN_MISSION_TEMPLATE as the mission class template, e.g. -DBTGEN_MISSION_TEMPLATE=lab_tour::LabTour"
#endif

#include BTGEN_MISSION_HEADER

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "btgen/clock.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "btgen/testing/alloc_counter.hpp"

namespace {

// Leaves that finish at once. The hooks take any trailing arguments, so the
// benchmark keeps building when hooks gain parameters (ports, blackboard).
struct InstantLeaves {
  template <class Model, class... Rest>
  btgen::Status onStart(Model&, Rest&&...) noexcept {
    return btgen::Status::SUCCESS;
  }
  template <class Model, class... Rest>
  btgen::Status onRunning(Model&, Rest&&...) noexcept {
    return btgen::Status::SUCCESS;
  }
  template <class Model, class... Rest>
  void onHalted(Model&, Rest&&...) noexcept {}
  template <class Model, class... Rest>
  btgen::Status check(Model&, Rest&&...) noexcept {
    return btgen::Status::SUCCESS;
  }
  // Nav2's Decorators that read ROS 2 (btgen/nav2.hpp): always yes, so their child runs.
  btgen::Status nav2_input(const btgen::NodeInfo&) noexcept { return btgen::Status::SUCCESS; }
};

using Mission = BTGEN_MISSION_TEMPLATE<InstantLeaves, btgen::ManualClock, btgen::NoObserver>;
constexpr std::size_t kNodes = Mission::node_count();

// A node is counted as visited in a tick when its status moves to RUNNING,
// SUCCESS or FAILURE during that tick: every node the engine ticks does so,
// except one that was RUNNING and stays RUNNING, or one that returns SKIPPED
// (neither happens in the benchmark missions, whose leaves finish at once).
// Resets to IDLE are not visits.
struct VisitCounter {
  std::array<unsigned char, kNodes>* touched;
  std::size_t* visits;
  void on_status_change(const btgen::NodeInfo& node, btgen::Status, btgen::Status to) noexcept {
    if (to != btgen::Status::IDLE && (*touched)[node.index] == 0) {
      (*touched)[node.index] = 1;
      ++*visits;
    }
  }
};
// Counted on the table interpreter (the same statuses as the straight-line
// ticks of Mission): compiling the straight-line code once is enough.
struct CountedSpec : Mission::MissionSpec {
  static constexpr std::size_t kStraightLineBudget = 0;
};
using CountedMission = btgen::Engine<CountedSpec, InstantLeaves, btgen::ManualClock, VisitCounter>;

InstantLeaves g_leaves;
// Static storage (a 10,000-node mission is too big for some stacks); constructed
// in main() so that the construction's allocations, if any, are counted.
std::optional<Mission> g_mission;
std::optional<CountedMission> g_counted;
std::array<unsigned char, kNodes> g_touched{};
volatile unsigned g_sink;

double visited_per_tick(long ticks) {
  std::size_t visits = 0;
  g_counted.emplace(g_leaves, btgen::ManualClock{}, VisitCounter{&g_touched, &visits});
  const long n = ticks < 64 ? ticks : 64;
  for (long i = 0; i < n; ++i) {
    g_touched.fill(0);
    g_sink = static_cast<unsigned>(g_counted->tick());
  }
  return n > 0 ? static_cast<double>(visits) / static_cast<double>(n) : 0.0;
}

// The counter really is in this binary and sees operator new (and malloc
// where it is replaced): a 0 reported below is a measurement, not a counter
// that was never linked. The pointers escape to volatiles, so the compiler
// cannot elide the allocations.
bool counter_works() {
  static int* volatile escaped = nullptr;
  const btgen_test::AllocationScope scope;
  escaped = new int(7);
  bool ok = scope.count() >= 1;
  delete escaped;
  if (btgen_test::counts_malloc()) {
    const btgen_test::AllocationScope m;
    void* volatile raw = std::malloc(32);
    std::free(raw);
    ok = ok && m.count() == 1;
  }
  return ok;
}

int usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s TICKS [--report]\n", argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) return usage(argv[0]);
  char* end = nullptr;
  const long ticks = std::strtol(argv[1], &end, 10);
  if (end == argv[1] || *end != '\0' || ticks < 0) return usage(argv[0]);
  const bool report = argc == 3;
  if (report && std::strcmp(argv[2], "--report") != 0) return usage(argv[0]);

  const btgen_test::AllocationScope create_scope;
  g_mission.emplace(g_leaves);
  const std::size_t allocs_create = create_scope.count();

  btgen::Status last = btgen::Status::IDLE;
  const btgen_test::AllocationScope tick_scope;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < ticks; ++i) last = g_mission->tick();
  const auto t1 = std::chrono::steady_clock::now();
  const std::size_t allocs_ticks = tick_scope.count();
  g_sink = static_cast<unsigned>(last);
  if (!report) return 0;

  if (!counter_works()) {
    std::fprintf(stderr, "%s: the allocation counter does not count: no numbers\n", argv[0]);
    return 3;
  }
  const double ns = std::chrono::duration<double, std::nano>(t1 - t0).count();
  const double visited = visited_per_tick(ticks);
  std::printf("nodes %zu\n", kNodes);
  std::printf("ticks %ld\n", ticks);
  std::printf("ns_per_tick %.3f\n", ticks > 0 ? ns / static_cast<double>(ticks) : 0.0);
  std::printf("allocs_create %zu\n", allocs_create);
  std::printf("allocs_per_tick %.6g\n",
              ticks > 0 ? static_cast<double>(allocs_ticks) / static_cast<double>(ticks) : 0.0);
  std::printf("state_bytes %zu\n", sizeof(Mission));
  std::printf("node_state_bytes %zu\n", Mission::node_state_bytes());
  std::printf("blackboard_bytes %zu\n", Mission::blackboard_bytes());
  std::printf("visited_per_tick %.2f\n", visited);
  std::printf("result %.*s\n", static_cast<int>(btgen::to_string(last).size()), btgen::to_string(last).data());
  std::printf("alloc_counter %s\n", btgen_test::counts_malloc() ? "new+malloc" : "new");
  return 0;
}
