// Groot2 POST hooks of a mission compiled with --btcpp 4.10.0 (Sem::groot2_post_hooks):
// a POST hook replaces the result of the node's tick (which runs), PRE and POST hooks on
// one node are kept apart, and the tick path still allocates nothing. (What 4.10.0's
// Groot2Publisher answers is tests/groot2/*.hooks410.json, replayed by
// tests/python/test_groot2.py.)
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <zmq.hpp>

#include "btgen/clock.hpp"
#include "btgen/groot2.hpp"
#include "btgen/monitor.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "control_flow.hpp"
#include "groot2_client.hpp"
#include "test_leaves.hpp"

namespace {

using btgen_test::RandomLeaves;
using Mission = control_flow_410::ControlFlow<RandomLeaves, btgen::ManualClock, btgen::MonitorObserver<>>;
static_assert(Mission::Sem::groot2_post_hooks, "this test is built from a --btcpp 4.10.0 mission");

using btgen_test::free_port_pair;
using btgen_test::request;

std::string hook_json(unsigned uid, const char* status, int position) {
  return std::string("{\"enabled\":true,\"uid\":") + std::to_string(uid) + ",\"mode\":1,\"once\":false," +
         "\"desired_status\":\"" + status + "\",\"position\":" + std::to_string(position) + "}";
}

struct Seen final : btgen::StatusSink {
  std::array<std::array<std::size_t, 5>, Mission::node_count()> to{};
  void on_status(const btgen::NodeInfo& n, btgen::Status, btgen::Status s) noexcept override {
    ++to[n.index][static_cast<std::size_t>(s)];
  }
};

TEST(Groot2PostHooks, ReplaceTheTickResultAndTicksAllocateNothing) {
  RandomLeaves leaves(0x4107);
  const unsigned port = free_port_pair();
  ASSERT_NE(port, 0u);
  auto mission = std::make_unique<Mission>(leaves);
  std::size_t condition = 1, control = 0;  // the root's IsBatteryOk, the Sequence "Cycle"
  for (std::size_t i = 0; i < Mission::node_count(); ++i)
    if (Mission::node(i).name == "Cycle") control = i;
  ASSERT_NE(control, 0u);
  ASSERT_EQ(Mission::node(condition).kind, btgen::NodeKind::Condition);
  Seen seen;
  btgen::groot2::Publisher publisher(*mission, port, "127.0.0.1");
  ASSERT_TRUE(mission->observer().attach(&seen));
  zmq::context_t ctx;
  zmq::socket_t client = btgen_test::connect_client(ctx, port);
  const auto uid = [](std::size_t i) { return static_cast<unsigned>(Mission::node(i).uid); };
  // The condition: PRE forces FAILURE, POST then SUCCESS (4.10.0 runs both); the Sequence:
  // POST FAILURE after its children ran.
  const std::string hooks = "[" + hook_json(uid(condition), "FAILURE", 0) + "," +
                            hook_json(uid(condition), "SUCCESS", 1) + "," + hook_json(uid(control), "FAILURE", 1) + "]";
  ASSERT_EQ(request(client, 'I', hooks).size(), 1u);
  const std::string dump = request(client, 'D').at(1);
  EXPECT_NE(dump.find("\"position\":0"), std::string::npos) << dump;
  EXPECT_NE(dump.find("\"position\":1"), std::string::npos) << dump;
  btgen_test::settle(*mission);
  seen.to = {};
  EXPECT_EQ(btgen_test::allocations_of_20000_ticks(*mission, publisher), 0u);
  using S = btgen::Status;
  const auto n = [&](std::size_t node, S s) { return seen.to[node][static_cast<std::size_t>(s)]; };
  EXPECT_GT(n(condition, S::SUCCESS), 100u);
  EXPECT_EQ(n(condition, S::FAILURE), 0u);
  EXPECT_GT(n(control, S::FAILURE), 0u);
  EXPECT_EQ(n(control, S::SUCCESS), 0u);
  // Without its PRE hook the condition is checked, and its POST hook still gives SUCCESS.
  ASSERT_EQ(request(client, 'R', "{\"uid\":" + std::to_string(uid(condition)) + ",\"position\":0}").size(), 1u);
  ASSERT_EQ(request(client, 'R', "{\"uid\":" + std::to_string(uid(condition)) + ",\"position\":0}").at(1),
            "Node ID not found");
  seen.to = {};
  for (int i = 0; i < 2000; ++i) (void)mission->tick();
  EXPECT_GT(n(condition, S::SUCCESS), 0u);
  EXPECT_EQ(n(condition, S::FAILURE), 0u);
  // Removed, the leaves answer again.
  ASSERT_EQ(request(client, 'A').size(), 1u);
  EXPECT_EQ(request(client, 'D').at(1), "[]");
  seen.to = {};
  for (int i = 0; i < 2000; ++i) (void)mission->tick();
  EXPECT_GT(n(condition, S::FAILURE), 0u);
  mission->observer().detach(&seen);
}

}  // namespace
