// btgen runtime: a scenario runner that allocates nothing, for microcontrollers.
//
// The same run as btgen/harness/driver.hpp's (shared/conformance/FORMAT.md's
// Execution section), with the scenario compiled in as constant data instead
// of read from a file, and the trace written to any byte sink instead of a
// FILE*: no heap, no stdio, no file system, so it runs on a bare-metal target
// (mcu/: the MPS2 AN386 board in QEMU) and prints the trace the host runner
// prints, byte for byte.
//
//     static constexpr btgen::Status kFind[] = {btgen::Status::FAILURE, btgen::Status::SUCCESS};
//     static constexpr btgen::LeafScript kLeaves[] = {{"FindBall", kFind, 2}};
//     static constexpr btgen::StaticScenario kScenario{20, 0, btgen::Status::SUCCESS, kLeaves, 1};
//     alignas(8) static unsigned char storage[btgen::static_run_storage<pick_place_ball::PickPlaceBall>()];
//     btgen::run_static_scenario<pick_place_ball::PickPlaceBall>(kScenario, sink, storage);
//
// A sink is any type with
//     void write(const char* data, std::size_t size);   // the trace
//     void error(const char* data, std::size_t size);   // a run-time error's line (the host prints it on stderr)
//
// The scenario is checked where it is compiled in (the Python reference's
// load_scenario does it, with its path:line:col diagnostics): here it is
// taken as valid.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string_view>

#include "btgen/blackboard.hpp"
#include "btgen/clock.hpp"
#include "btgen/harness/scenario_run.hpp"
#include "btgen/node.hpp"
#include "btgen/one_line.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"

namespace btgen {

// `leaf NAME S1 S2 ...`: the successive results of every Action and Condition named NAME.
struct LeafScript {
  std::string_view name;
  const Status* statuses;
  std::size_t count;  // at least 1
};

inline constexpr std::uint16_t kNoLeafScript = 0xFFFF;

// A scenario file's content (`ticks`, `clock_ms`, `default`, the `leaf` lines).
// `node_scripts`, when given, says which leaf line drives each node (by node
// index; kNoLeafScript: none, the default), as the host matched them by name;
// without it the runner matches names itself, which a build without node
// text (BTGEN_NODE_TEXT=0, btgen/node.hpp) cannot.
struct StaticScenario {
  long ticks;
  long clock_ms;
  Status default_status;
  const LeafScript* leaves;
  std::size_t leaf_count;
  const std::uint16_t* node_scripts = nullptr;
};

namespace static_scenario_detail {

inline std::size_t unsigned_text(unsigned long long v, char* out) noexcept {
  char tmp[20];
  std::size_t n = 0;
  do {
    tmp[n++] = static_cast<char>('0' + static_cast<int>(v % 10u));
    v /= 10u;
  } while (v != 0);
  for (std::size_t i = 0; i < n; ++i) out[i] = tmp[n - 1 - i];
  return n;
}

}  // namespace static_scenario_detail

// ScenarioLeaves (btgen/harness/scenario.hpp) in fixed storage: every
// instance of a name shares one list; a used-up list repeats its last status.
template <std::size_t NodeCount>
class StaticScenarioLeaves : public ScenarioHooks<StaticScenarioLeaves<NodeCount>> {
 public:
  StaticScenarioLeaves(const StaticScenario& sc, const NodeInfo* nodes) noexcept : sc_(&sc) {
    for (std::size_t i = 0; i < NodeCount; ++i) {
      script_[i] = kNone;
      owner_[i] = static_cast<std::uint16_t>(i);
      cursor_[i] = 0;
      if (!is_scripted(nodes[i].kind)) continue;
      if (sc.node_scripts != nullptr) {
        script_[i] = sc.node_scripts[i];
      } else {
        // The last line naming it wins, as in ScenarioLeaves (names are unique in a valid scenario).
        for (std::size_t k = 0; k < sc.leaf_count; ++k) {
          if (sc.leaves[k].name == nodes[i].name) script_[i] = static_cast<std::uint16_t>(k);
        }
      }
      if (script_[i] == kNone) continue;
      // The cursor of a list lives with the first node that uses it.
      for (std::size_t j = 0; j < i; ++j) {
        if (script_[j] == script_[i]) {
          owner_[i] = owner_[j];
          break;
        }
      }
    }
  }

 private:
  friend class ScenarioHooks<StaticScenarioLeaves>;

  static constexpr std::uint16_t kNone = kNoLeafScript;

  Status next(const NodeInfo& node) noexcept {
    const std::uint16_t k = script_[node.index];
    if (k == kNone) return sc_->default_status;
    const LeafScript& list = sc_->leaves[k];
    std::uint16_t& cursor = cursor_[owner_[node.index]];
    const Status s = list.statuses[cursor < list.count ? cursor : list.count - 1];
    if (cursor < list.count) ++cursor;
    return s;
  }

  const StaticScenario* sc_;
  std::array<std::uint16_t, NodeCount> script_{};
  std::array<std::uint16_t, NodeCount> owner_{};
  std::array<std::uint16_t, NodeCount> cursor_{};
};

// The trace format of TraceWriter (btgen/trace.hpp), to a sink, up to the
// first run-time error (as TraceUntilError in btgen/harness/driver.hpp).
template <class Sink>
class SinkTrace {
 public:
  explicit SinkTrace(Sink& sink) noexcept : sink_(&sink) {}

  void on_status_change(const NodeInfo& node, Status from, Status to) const noexcept {
    if (stopped_) return;
    char num[20];
    sink_->write(num, static_scenario_detail::unsigned_text(node.uid, num));
    put(" ");
    put(node.id);
    put(" \"");
    char buf[256];
    std::string_view rest = node.name;
    while (!rest.empty()) {
      const std::size_t take = rest.size() < 64 ? rest.size() : 64;
      sink_->write(buf, escape_name(rest.substr(0, take), buf, sizeof buf));
      rest.remove_prefix(take);
    }
    put("\" ");
    put(to_string(from));
    put(" -> ");
    put(to_string(to));
    put("\n");
  }

  // `path:line:col: error: message[: detail]`, one line, as TraceWriter prints it on stderr.
  void on_error(const RuntimeError& e) const noexcept {
    if (stopped_) return;
    stopped_ = true;
    if (!e.printed.empty()) put(e.printed);  // (what the library prints before it throws)
    Sink* sink = sink_;
    auto err = [sink](std::string_view s) { sink->error(s.data(), s.size()); };
    err(e.where);
    err(": error: ");
    one_line(e.message, err);
    if (!e.detail.empty()) {
      err(": ");
      one_line(e.detail, err);
    }
    err("\n");
  }

 private:
  void put(std::string_view s) const noexcept { sink_->write(s.data(), s.size()); }

  Sink* sink_;
  mutable bool stopped_ = false;
};

template <template <class, class, class> class Mission, class Sink>
using StaticRunner =
    Mission<StaticScenarioLeaves<Mission<StaticScenarioLeaves<1>, ManualClock, NoObserver>::kNodeCount>, ManualClock,
            SinkTrace<Sink>>;

// Bytes (and alignment) the run's objects need: the leaves and the mission.
template <template <class, class, class> class Mission, class Sink>
constexpr std::size_t static_run_storage() noexcept {
  using Runner = StaticRunner<Mission, Sink>;
  using Leaves = StaticScenarioLeaves<Runner::kNodeCount>;
  return (sizeof(Leaves) + alignof(Runner) - 1) / alignof(Runner) * alignof(Runner) + sizeof(Runner);
}

// Runs the mission on the scenario, as btgen::run_scenario_main does: up to
// `ticks` ticks, `clock_ms` between them, `tick <n>` / the status changes /
// `result <STATUS>`, ending at the first completed tick. The objects are built
// in `storage` (static_run_storage() bytes, aligned for the mission), so that
// one buffer serves missions run one after another. Returns 0, or 1 after a
// run-time error (its line went to the sink's error(), and no result line
// follows), as the host runner's exit status.
template <template <class, class, class> class Mission, class Sink>
int run_static_scenario(const StaticScenario& sc, Sink& sink, void* storage) noexcept {
  using Runner = StaticRunner<Mission, Sink>;
  using Leaves = StaticScenarioLeaves<Runner::kNodeCount>;
  constexpr std::size_t kRunnerOffset = (sizeof(Leaves) + alignof(Runner) - 1) / alignof(Runner) * alignof(Runner);
  auto* bytes = static_cast<unsigned char*>(storage);
  auto* leaves = ::new (static_cast<void*>(bytes)) Leaves(sc, Runner::nodes().data());
  auto* mission =
      ::new (static_cast<void*>(bytes + kRunnerOffset)) Runner(*leaves, ManualClock{}, SinkTrace<Sink>(sink));
  const bool ok = run_scenario_ticks(
      *mission, sc.ticks, sc.clock_ms,
      [&sink](long n) noexcept {
        char num[20];
        sink.write("tick ", 5);
        sink.write(num, static_scenario_detail::unsigned_text(static_cast<unsigned long long>(n), num));
        sink.write("\n", 1);
      },
      [&sink](Status s) noexcept {
        const std::string_view text = to_string(s);
        sink.write("result ", 7);
        sink.write(text.data(), text.size());
        sink.write("\n", 1);
      });
  mission->~Runner();
  leaves->~Leaves();
  return ok ? 0 : 1;
}

}  // namespace btgen
