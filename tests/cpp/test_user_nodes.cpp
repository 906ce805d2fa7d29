// The mission's own Controls and Decorators (missions/user_nodes.xml):
// Nav2's PipelineSequence, RecoveryNode and RateController written against
// the generated hooks (tick(control::X&), halt(control::X&)) with Nav2's
// documented semantics, and their status traces checked against what
// BehaviorTree.CPP 4.6.2 does around ControlNode/DecoratorNode (the
// engine's bookkeeping: statuses from tick(), a decorator's completed child
// reset, haltChild, halts from above).
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>

#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "user_nodes.hpp"
#include "user_nodes_sync.hpp"

namespace {

using btgen::Status;
namespace control = user_nodes::control;
namespace leaf = user_nodes::leaf;

constexpr std::size_t kNodes = user_nodes::detail::Spec::kNodeCount;

// What happened, in order, in a fixed buffer (no allocation on the tick path).
struct Log {
  std::array<char, 4096> text{};
  std::size_t size = 0;
  void add(std::string_view a, std::string_view b = {}, std::string_view c = {}, std::string_view d = {},
           std::string_view e = {}) {
    for (std::string_view part : {a, b, c, d, e}) {
      for (char ch : part) {
        if (size + 1 < text.size()) text[size++] = ch;
      }
    }
    if (size + 1 < text.size()) text[size++] = '\n';
  }
  std::string take() {
    std::string out(text.data(), size);
    size = 0;
    return out;
  }
};

struct Leaves {
  Log* log;
  // Step: the statuses each instance answers, in turn (the last one repeats).
  struct Script {
    std::array<Status, 8> answers{};
    std::size_t count = 0, next = 0;
    Status pop() {
      const Status s = answers[next < count ? next : count - 1];
      if (next < count) ++next;
      return s;
    }
  };
  std::array<Script, kNodes> steps{};
  void script(std::string_view name, std::initializer_list<Status> answers) {
    for (std::size_t i = 0; i < kNodes; ++i) {
      if (user_nodes::detail::Spec::kNodes[i].name != name) continue;
      steps[i].count = 0;
      steps[i].next = 0;
      for (Status s : answers) steps[i].answers[steps[i].count++] = s;
    }
  }

  std::string_view failing{};  // this Step reports a run-time error when it starts
  Status onStart(leaf::Step& m, const btgen::NodeInfo& n) {
    log->add(n.name, ".onStart");
    if (n.name == failing) {
      failing = {};
      return m.fail("no path");
    }
    return steps[n.index].pop();
  }
  Status onRunning(leaf::Step&, const btgen::NodeInfo& n) {
    log->add(n.name, ".onRunning");
    return steps[n.index].pop();
  }
  void onHalted(leaf::Step&, const btgen::NodeInfo& n) { log->add(n.name, ".onHalted"); }

  // ---- nav2_behavior_tree::PipelineSequence: ticks children in order; a
  // RUNNING child before the furthest one reached keeps the ones after it
  // running; any FAILURE halts all and fails; all SUCCESS succeeds.
  std::array<std::size_t, kNodes> last_child_ticked{};
  Status tick(control::PipelineSequence& m, const btgen::NodeInfo& n) {
    std::size_t& last = last_child_ticked[n.index];
    for (std::size_t i = 0; i < m.children_count(); ++i) {
      switch (m.tick_child(i)) {
        case Status::FAILURE:
          m.halt_children();
          last = 0;
          return Status::FAILURE;
        case Status::SUCCESS: break;
        case Status::RUNNING:
          if (i >= last) {
            last = i;
            return Status::RUNNING;
          }
          break;
        default: return m.fail("PipelineSequence: a child returned an invalid status");
      }
    }
    m.halt_children();
    last = 0;
    return Status::SUCCESS;
  }
  void halt(control::PipelineSequence&, const btgen::NodeInfo& n) {
    log->add(n.name, ".halt");
    last_child_ticked[n.index] = 0;
  }

  // ---- nav2_behavior_tree::RecoveryNode: the first child; on its FAILURE
  // the second (the recovery) and the first again, at most
  // number_of_retries times.
  struct Recovery {
    std::size_t current = 0;
    int retries = 0;
  };
  std::array<Recovery, kNodes> recovery{};
  void reset(control::RecoveryNode& m, Recovery& r) {  // RecoveryNode::halt() inside tick()
    m.halt_children();
    m.set_status(Status::IDLE);
    r = Recovery{};
  }
  Status tick(control::RecoveryNode& m, const btgen::NodeInfo& n) {
    if (m.children_count() != 2) return m.fail("RecoveryNode must have 2 children");
    const int number_of_retries = m.number_of_retries().value_or(1);  // a typed port
    Recovery& r = recovery[n.index];
    m.set_status(Status::RUNNING);
    while (r.current < 2 && r.retries <= number_of_retries) {
      const Status child = m.tick_child(r.current);
      if (r.current == 0) {
        switch (child) {
          case Status::SKIPPED: reset(m, r); return Status::SKIPPED;
          case Status::SUCCESS: reset(m, r); return Status::SUCCESS;
          case Status::RUNNING: return Status::RUNNING;
          case Status::FAILURE:
            if (r.retries < number_of_retries) {
              m.halt_child(0);
              ++r.current;
              break;
            }
            reset(m, r);
            return Status::FAILURE;
          default: return m.fail("RecoveryNode: invalid status");
        }
      } else {
        switch (child) {
          case Status::SKIPPED:
            r.current = 0;
            m.halt_child(1);
            return Status::FAILURE;
          case Status::RUNNING: return Status::RUNNING;
          case Status::SUCCESS:
            m.halt_child(1);
            ++r.retries;
            r.current = 0;
            break;
          case Status::FAILURE: reset(m, r); return Status::FAILURE;
          default: return m.fail("RecoveryNode: invalid status");
        }
      }
    }
    reset(m, r);
    return Status::FAILURE;
  }
  void halt(control::RecoveryNode&, const btgen::NodeInfo& n) {
    log->add(n.name, ".halt");
    recovery[n.index] = Recovery{};
  }

  // ---- nav2_behavior_tree::RateController: ticks its child at most at
  // `hz` (the first time at once, then when the period has passed, and on
  // every tick while the child is RUNNING); meanwhile it answers its status.
  struct Rate {
    std::uint64_t start = 0;
    bool first_time = false;
  };
  std::array<Rate, kNodes> rate{};
  Status tick(control::RateController& m, const btgen::NodeInfo& n) {
    Rate& r = rate[n.index];
    const double hz = m.hz().value_or(10.0);  // a typed port with a default
    const double period_ms = 1000.0 / hz;
    if (m.status() == Status::IDLE || m.status() == Status::SKIPPED) {
      r.start = m.now_ms();
      r.first_time = true;
    }
    m.set_status(Status::RUNNING);
    const std::uint64_t now = m.now_ms();
    if (r.first_time || m.child_status(0) == Status::RUNNING || static_cast<double>(now - r.start) >= period_ms) {
      r.first_time = false;
      switch (m.tick_child(0)) {
        case Status::RUNNING: return Status::RUNNING;
        case Status::SUCCESS: r.start = now; return Status::SUCCESS;
        default: return Status::FAILURE;
      }
    }
    return m.status();
  }
};

struct Trace {
  Log* log;
  void on_status_change(const btgen::NodeInfo& n, Status from, Status to) noexcept {
    log->add(n.name, " ", btgen::to_string(from), "->", btgen::to_string(to));
  }
};

using Mission = user_nodes::UserNodes<Leaves, btgen::ManualClock, Trace>;

struct Fixture {
  Log log;
  Leaves leaves{&log};
  Mission mission{leaves, btgen::ManualClock{}, Trace{&log}};
  Status tick_at(std::uint64_t ms) {
    mission.clock().set(ms);
    return mission.tick();
  }
};

TEST(UserNodes, PipelineKeepsFollowingWhileTheRateControllerReplans) {
  Fixture f;
  f.leaves.script("Plan", {Status::SUCCESS});
  f.leaves.script("Follow", {Status::RUNNING, Status::RUNNING, Status::SUCCESS});
  EXPECT_EQ(f.tick_at(0), Status::RUNNING);
  EXPECT_EQ(f.log.take(),
            "Recovery IDLE->RUNNING\n"
            "Rate IDLE->RUNNING\n"
            "Plan.onStart\n"
            "Plan IDLE->SUCCESS\n"
            "Rate RUNNING->SUCCESS\n"  // DecoratorNode::executeTick: status, then the completed child reset
            "Plan SUCCESS->IDLE\n"
            "Follow.onStart\n"
            "Follow IDLE->RUNNING\n"
            "Pipeline IDLE->RUNNING\n");
  // 100 ms later: the period (500 ms at 2 Hz) has not passed; Rate answers RUNNING, Pipeline goes on.
  EXPECT_EQ(f.tick_at(100), Status::RUNNING);
  EXPECT_EQ(f.log.take(),
            "Rate SUCCESS->RUNNING\n"
            "Follow.onRunning\n");
  // 600 ms: Plan again; Follow succeeds; all succeed; RecoveryNode halts itself and succeeds.
  EXPECT_EQ(f.tick_at(600), Status::SUCCESS);
  EXPECT_EQ(f.log.take(),
            "Plan.onStart\n"
            "Plan IDLE->SUCCESS\n"
            "Rate RUNNING->SUCCESS\n"
            "Plan SUCCESS->IDLE\n"
            "Follow.onRunning\n"
            "Follow RUNNING->SUCCESS\n"
            "Rate SUCCESS->IDLE\n"
            "Follow SUCCESS->IDLE\n"
            "Pipeline RUNNING->SUCCESS\n"
            "Pipeline SUCCESS->IDLE\n"
            "Recovery RUNNING->IDLE\n"
            "Recovery IDLE->SUCCESS\n"
            "Recovery SUCCESS->IDLE\n");
  EXPECT_EQ(f.mission.errors(), 0u);
}

TEST(UserNodes, RecoveryRunsTheRecoveryAndRetries) {
  Fixture f;
  f.leaves.script("Plan", {Status::SUCCESS});
  f.leaves.script("Follow", {Status::FAILURE, Status::SUCCESS});
  f.leaves.script("Clear", {Status::SUCCESS});
  EXPECT_EQ(f.tick_at(0), Status::SUCCESS);
  EXPECT_EQ(f.log.take(),
            "Recovery IDLE->RUNNING\n"
            "Rate IDLE->RUNNING\n"
            "Plan.onStart\n"
            "Plan IDLE->SUCCESS\n"
            "Rate RUNNING->SUCCESS\n"
            "Plan SUCCESS->IDLE\n"
            "Follow.onStart\n"
            "Follow IDLE->FAILURE\n"
            "Rate SUCCESS->IDLE\n"  // PipelineSequence: a FAILURE halts all children
            "Follow FAILURE->IDLE\n"
            "Pipeline IDLE->FAILURE\n"
            "Pipeline FAILURE->IDLE\n"  // RecoveryNode: haltChild(0), then the recovery
            "Clear.onStart\n"
            "Clear IDLE->SUCCESS\n"
            "Clear SUCCESS->IDLE\n"
            "Rate IDLE->RUNNING\n"  // the first child again (retry 1 of number_of_retries=1)
            "Plan.onStart\n"
            "Plan IDLE->SUCCESS\n"
            "Rate RUNNING->SUCCESS\n"
            "Plan SUCCESS->IDLE\n"
            "Follow.onStart\n"
            "Follow IDLE->SUCCESS\n"
            "Rate SUCCESS->IDLE\n"
            "Follow SUCCESS->IDLE\n"
            "Pipeline IDLE->SUCCESS\n"
            "Pipeline SUCCESS->IDLE\n"
            "Recovery RUNNING->IDLE\n"
            "Recovery IDLE->SUCCESS\n"
            "Recovery SUCCESS->IDLE\n");
}

TEST(UserNodes, RecoveryFailsWhenTheRetriesAreUsedUp) {
  Fixture f;
  f.leaves.script("Plan", {Status::SUCCESS});
  f.leaves.script("Follow", {Status::FAILURE});
  f.leaves.script("Clear", {Status::SUCCESS});
  EXPECT_EQ(f.tick_at(0), Status::FAILURE);
  const std::string log = f.log.take();
  std::size_t plans = 0, clears = 0;
  for (std::size_t p = log.find("Plan.onStart"); p != std::string::npos; p = log.find("Plan.onStart", p + 1)) ++plans;
  for (std::size_t p = log.find("Clear.onStart"); p != std::string::npos; p = log.find("Clear.onStart", p + 1)) {
    ++clears;
  }
  EXPECT_EQ(plans, 2u);   // the first child twice: number_of_retries="1"
  EXPECT_EQ(clears, 1u);  // one recovery
  EXPECT_NE(log.find("Pipeline IDLE->FAILURE\nPipeline FAILURE->IDLE\nRecovery RUNNING->IDLE\n"
                     "Recovery IDLE->FAILURE\nRecovery FAILURE->IDLE\n"),
            std::string::npos)
      << log;
}

TEST(UserNodes, AChildsRunTimeErrorFailsTheChildNotItsUserParent) {
  Fixture f;
  f.leaves.script("Plan", {Status::SUCCESS});
  f.leaves.script("Follow", {Status::SUCCESS});
  f.leaves.script("Clear", {Status::SUCCESS});
  f.leaves.failing = "Follow";  // first start: an error, FAILURE; the recovery then retries
  EXPECT_EQ(f.tick_at(0), Status::SUCCESS);
  EXPECT_EQ(f.mission.errors(), 1u);
  const std::string log = f.log.take();
  EXPECT_NE(log.find("Follow IDLE->FAILURE\n"), std::string::npos) << log;
  EXPECT_NE(log.find("Clear.onStart\n"), std::string::npos) << log;
}

TEST(UserNodes, HaltFromAboveHaltsRunningChildrenThenTheNodes) {
  Fixture f;
  f.leaves.script("Plan", {Status::SUCCESS});
  f.leaves.script("Follow", {Status::RUNNING});
  EXPECT_EQ(f.tick_at(0), Status::RUNNING);
  (void)f.log.take();
  f.leaves.last_child_ticked[1] = 1;  // Pipeline's own state (index 1) is cleared by its halt()
  f.mission.halt();
  const std::string log = f.log.take();
  EXPECT_EQ(log.substr(0, log.find("Recovery RUNNING->IDLE\n") + 23),
            "Rate SUCCESS->IDLE\n"  // not RUNNING: only reset (ControlNode::haltChild)
            "Follow.onHalted\n"
            "Follow RUNNING->IDLE\n"
            "Pipeline.halt\n"  // the user's halt() after its children
            "Pipeline RUNNING->IDLE\n"
            "Recovery.halt\n"
            "Recovery RUNNING->IDLE\n");
  EXPECT_EQ(f.leaves.last_child_ticked[1], 0u);
  EXPECT_EQ(f.mission.status(), Status::IDLE);
  // It starts again from scratch.
  f.leaves.script("Follow", {Status::SUCCESS});
  EXPECT_EQ(f.tick_at(1000), Status::SUCCESS);
}

// PipelineSequence over a SyncActionNode (missions/user_nodes_sync.xml).
struct SyncLeaves {
  int computed = 0, followed = 0;
  std::array<std::size_t, user_nodes_sync::detail::Spec::kNodeCount> last{};
  Status tick(user_nodes_sync::leaf::Compute&, const btgen::NodeInfo&) {
    ++computed;
    return Status::SUCCESS;
  }
  Status onStart(user_nodes_sync::leaf::Step&, const btgen::NodeInfo&) {
    ++followed;
    return Status::RUNNING;
  }
  Status onRunning(user_nodes_sync::leaf::Step&, const btgen::NodeInfo&) {
    ++followed;
    return followed < 3 ? Status::RUNNING : Status::SUCCESS;
  }
  void onHalted(user_nodes_sync::leaf::Step&, const btgen::NodeInfo&) {}
  Status tick(user_nodes_sync::control::PipelineSequence& m, const btgen::NodeInfo& n) {
    std::size_t& l = last[n.index];
    for (std::size_t i = 0; i < m.children_count(); ++i) {
      const Status s = m.tick_child(i);
      if (s == Status::FAILURE) {
        m.halt_children();
        l = 0;
        return s;
      }
      if (s == Status::RUNNING && i >= l) {
        l = i;
        return s;
      }
    }
    m.halt_children();
    l = 0;
    return Status::SUCCESS;
  }
};

TEST(UserNodes, ASyncActionTheParentDoesNotResetTicksAgain) {
  SyncLeaves leaves;
  user_nodes_sync::UserNodesSync<SyncLeaves, btgen::ManualClock> mission(leaves);
  EXPECT_EQ(mission.tick(), Status::RUNNING);
  EXPECT_EQ(mission.status(1), Status::SUCCESS);  // Compute is left SUCCESS by the pipeline
  EXPECT_EQ(mission.tick(), Status::RUNNING);
  EXPECT_EQ(mission.tick(), Status::SUCCESS);
  EXPECT_EQ(leaves.computed, 3);  // ticked on every tick, as SyncActionNode::executeTick does
  EXPECT_EQ(leaves.followed, 3);
}

TEST(UserNodes, NoAllocation) {
  Fixture f;
  f.leaves.script("Plan", {Status::SUCCESS});
  f.leaves.script("Follow", {Status::RUNNING, Status::RUNNING, Status::FAILURE, Status::RUNNING});
  f.leaves.script("Clear", {Status::SUCCESS});
  btgen_test::AllocationScope scope;
  for (int i = 0; i < 100; ++i) {
    (void)f.tick_at(static_cast<std::uint64_t>(i) * 150);
    f.log.size = 0;
  }
  f.mission.halt();
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
