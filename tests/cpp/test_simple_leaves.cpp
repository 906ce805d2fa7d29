// Simple and asynchronous leaves (missions/simple_leaves.xml): an Action
// implemented with tick() alone (BehaviorTree.CPP's SyncActionNode), and one
// that runs a blocking call on btgen::AsyncCall's worker thread and polls it
// (ThreadedAction), cancelled cleanly when a ReactiveSequence halts it.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "btgen/async_call.hpp"
#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "simple_leaves.hpp"

namespace {

using btgen::Status;
namespace leaf = simple_leaves::leaf;

// A blocking call: waits until `release` or a cancellation, returns goal * 2.
struct Planner {
  std::atomic<bool> release{false};
  std::atomic<int> started{0}, cancelled{0};
  double compute(double goal, const btgen::CancelToken& token) {
    started.fetch_add(1);
    while (!release.load()) {
      if (token.cancelled()) {
        cancelled.fetch_add(1);
        return -1.0;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    return goal * 2.0;
  }
};

struct Leaves {
  bool ready = true;
  int counted = 0;
  Status count_answer = Status::SUCCESS;
  Planner planner;
  btgen::AsyncCall<double> plan;
  double planned = 0.0;
  int halted = 0;

  Status check(leaf::Ready&, const btgen::NodeInfo&) { return ready ? Status::SUCCESS : Status::FAILURE; }

  // SyncActionNode: one function; no onStart/onRunning/onHalted.
  Status tick(leaf::Count&, const btgen::NodeInfo&) {
    ++counted;
    return count_answer;
  }

  // ThreadedAction through AsyncCall.
  Status onStart(leaf::Plan& m, const btgen::NodeInfo&) {
    const double goal = m.goal().value_or(0.0);
    Planner* p = &planner;
    if (!plan.start([p, goal](const btgen::CancelToken& t) { return p->compute(goal, t); })) return Status::FAILURE;
    return Status::RUNNING;
  }
  Status onRunning(leaf::Plan&, const btgen::NodeInfo&) {
    if (plan.running()) return Status::RUNNING;
    if (!plan.succeeded() || !plan.result()) return Status::FAILURE;
    planned = *plan.result();
    return Status::SUCCESS;
  }
  void onHalted(leaf::Plan&, const btgen::NodeInfo&) {
    ++halted;
    plan.cancel();
  }
};

static_assert(btgen::is_sync_action<Leaves, leaf::Count>);
static_assert(!btgen::is_sync_action<Leaves, leaf::Plan>);

using Mission = simple_leaves::SimpleLeaves<Leaves, btgen::ManualClock>;

// Ticks until the mission is not RUNNING (at most `limit` ticks).
Status run(Mission& mission, int limit = 20000) {
  Status s = Status::RUNNING;
  for (int i = 0; i < limit && s == Status::RUNNING; ++i) {
    s = mission.tick();
    if (s == Status::RUNNING) std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  return s;
}

TEST(SimpleLeaves, SyncActionTicksOncePerTickAndTheThreadedCallCompletes) {
  Leaves leaves;
  Mission mission(leaves);
  EXPECT_EQ(mission.tick(), Status::RUNNING);  // Plan's call started
  EXPECT_EQ(mission.tick(), Status::RUNNING);
  // The ReactiveSequence ticks Count on every tick: a SyncActionNode ticks again each time.
  EXPECT_EQ(leaves.counted, 2);
  leaves.planner.release = true;
  EXPECT_EQ(run(mission), Status::SUCCESS);
  EXPECT_DOUBLE_EQ(leaves.planned, 5.0);
  EXPECT_EQ(leaves.planner.started.load(), 1);
  EXPECT_EQ(leaves.planner.cancelled.load(), 0);
  EXPECT_EQ(leaves.halted, 0);
  EXPECT_EQ(mission.errors(), 0u);
}

TEST(SimpleLeaves, HaltCancelsTheCallAndWaitsForIt) {
  Leaves leaves;
  Mission mission(leaves);
  EXPECT_EQ(mission.tick(), Status::RUNNING);
  while (leaves.planner.started.load() == 0) std::this_thread::yield();
  leaves.ready = false;  // the ReactiveSequence halts Plan
  EXPECT_EQ(mission.tick(), Status::FAILURE);
  EXPECT_EQ(leaves.halted, 1);
  EXPECT_EQ(leaves.planner.cancelled.load(), 1);  // the call saw its token and returned before halt did
  EXPECT_EQ(leaves.plan.poll(), btgen::CallState::kIdle);
  EXPECT_TRUE(mission.blackboard().halted.value);  // _onHalted ran after onHalted

  // It can start again.
  leaves.ready = true;
  leaves.planner.release = true;
  EXPECT_EQ(run(mission), Status::SUCCESS);
  EXPECT_EQ(leaves.planner.started.load(), 2);
}

TEST(SimpleLeaves, SyncActionReturningRunningIsAnError) {
  struct Observer {
    std::string message;
    void on_status_change(const btgen::NodeInfo&, Status, Status) noexcept {}
    void on_error(const btgen::RuntimeError& e) noexcept {
      message = std::string(e.where) + ": " + std::string(e.message);
    }
  };
  Leaves leaves;
  leaves.count_answer = Status::RUNNING;
  simple_leaves::SimpleLeaves<Leaves, btgen::ManualClock, Observer> mission(leaves);
  EXPECT_EQ(mission.tick(), Status::FAILURE);
  EXPECT_EQ(mission.errors(), 1u);
  EXPECT_EQ(mission.observer().message,
            "tests/cpp/missions/simple_leaves.xml:9:7: SyncActionNode MUST never return RUNNING");
  EXPECT_EQ(leaves.planner.started.load(), 0);
}

// The virtual adapter: Count overrides tick() only, Plan the three hooks.
struct VirtualLeaves : simple_leaves::SimpleLeavesLeaves {
  int counted = 0;
  Status check(leaf::Ready&, const btgen::NodeInfo&) override { return Status::SUCCESS; }
  Status tick(leaf::Count&, const btgen::NodeInfo&) override {
    ++counted;
    return Status::SUCCESS;
  }
  Status onStart(leaf::Plan&, const btgen::NodeInfo&) override { return Status::RUNNING; }
  Status onRunning(leaf::Plan&, const btgen::NodeInfo&) override { return Status::SUCCESS; }
  void onHalted(leaf::Plan&, const btgen::NodeInfo&) override {}
};

TEST(SimpleLeaves, VirtualAdapterTakesTickAlone) {
  VirtualLeaves leaves;
  simple_leaves::SimpleLeavesVirtual mission(leaves);
  EXPECT_EQ(mission.tick(), Status::RUNNING);
  EXPECT_EQ(mission.tick(), Status::SUCCESS);
  EXPECT_EQ(leaves.counted, 2);
  EXPECT_EQ(mission.errors(), 0u);
}

TEST(SimpleLeaves, VirtualAdapterReportsAModelWithNoImplementation) {
  struct Observer {
    std::string message;
    void on_status_change(const btgen::NodeInfo&, Status, Status) noexcept {}
    void on_error(const btgen::RuntimeError& e) noexcept {
      message = std::string(e.where) + ": " + std::string(e.message);
    }
  };
  struct Partial : simple_leaves::SimpleLeavesLeaves {
    Status check(leaf::Ready&, const btgen::NodeInfo&) override { return Status::SUCCESS; }
  } leaves;
  simple_leaves::SimpleLeaves<simple_leaves::SimpleLeavesLeaves, btgen::ManualClock, Observer> mission(leaves);
  EXPECT_EQ(mission.tick(), Status::FAILURE);  // Count: no tick(), no onStart
  EXPECT_EQ(mission.errors(), 1u);
  // (btgen::no_implementation: the message put together from the model's ID when compiling)
  EXPECT_EQ(mission.observer().message,
            "tests/cpp/missions/simple_leaves.xml:9:7: Action Count has no implementation: override tick() or "
            "onStart/onRunning/onHalted");
}

}  // namespace
