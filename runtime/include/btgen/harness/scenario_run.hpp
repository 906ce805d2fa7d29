// btgen runtime: what the two scenario runners share.
//
// btgen/harness/driver.hpp (scenario files, stdio) and
// btgen/harness/static_scenario.hpp (scenarios compiled in, no heap) run a
// mission the same way: their leaves take every Action and Condition result
// from the scenario's lists (ScenarioHooks), and the ticks follow
// tests/conformance/FORMAT.md's Execution section (run_scenario_ticks). Each
// keeps its own storage of the lists and its own output. Nothing here
// allocates or does I/O.
#pragma once

#include <cstdint>

#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen {

// The leaf hooks of a scenario: generic, so one object serves every leaf
// model of any mission, and all of them take the next result of the node's
// list (`Derived::next(const NodeInfo&) noexcept`; Derived befriends this
// class). Every Action is a StatefulActionNode; onHalted does nothing.
template <class Derived>
class ScenarioHooks {
 public:
  template <class Leaf>
  Status onStart(Leaf& leaf, const NodeInfo& node) noexcept {
    self().fill(leaf, node);
    return self().next(node);
  }
  template <class Leaf>
  Status onRunning(Leaf& leaf, const NodeInfo& node) noexcept {
    self().fill(leaf, node);
    return self().next(node);
  }
  template <class Leaf>
  void onHalted(Leaf&, const NodeInfo&) noexcept {}
  template <class Leaf>
  Status check(Leaf& leaf, const NodeInfo& node) noexcept {
    self().fill(leaf, node);
    return self().next(node);
  }
  // A scenario's `queue` lines of the node (Derived may hide it): none here.
  template <class Leaf>
  void fill(Leaf&, const NodeInfo&) noexcept {}
  // The input of a Nav2 Decorator (btgen/nav2.hpp), scripted under its name as a Condition.
  Status nav2_input(const NodeInfo& node) noexcept { return self().next(node); }

 private:
  Derived& self() noexcept { return static_cast<Derived&>(*this); }
};

// Sends up to `ticks` ticks to the mission's root, `clock_ms` of its
// ManualClock between them: on_tick(n) before tick n, on_result(status)
// after it, ending at the first completed tick. A run-time error (the
// mission's observer reported it) ends the run after its tick, without a
// result, as the interpreter stops: false then, else true.
template <class Mission, class OnTick, class OnResult>
bool run_scenario_ticks(Mission& mission, long ticks, long clock_ms, OnTick&& on_tick, OnResult&& on_result) {
  for (long n = 1; n <= ticks; ++n) {
    if (n > 1) mission.clock().advance(static_cast<std::uint64_t>(clock_ms));
    on_tick(n);
    const Status s = mission.tick();
    if (mission.errors() != 0) return false;
    on_result(s);
    if (is_completed(s)) break;
  }
  return true;
}

}  // namespace btgen
