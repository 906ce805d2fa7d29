// Groot2 monitors attached to a compiled mission: the tick path allocates
// nothing with a publisher and a .btlog logger attached, the publisher
// answers STATUS with what the tick published, the .btlog holds every change.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <unistd.h>

#include <zmq.hpp>

#include "btgen/btlog.hpp"
#include "btgen/clock.hpp"
#include "btgen/groot2.hpp"
#include "btgen/monitor.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "control_flow.hpp"
#include "groot2_client.hpp"
#include "test_leaves.hpp"

namespace {

using btgen_test::RandomLeaves;
using Mission = control_flow::ControlFlow<RandomLeaves, btgen::ManualClock, btgen::MonitorObserver<>>;

// Counts the changes it sees, to compare with the .btlog.
struct Counter final : btgen::StatusSink {
  std::size_t changes = 0;
  void on_status(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept override { ++changes; }
};

using btgen_test::free_port_pair;
using btgen_test::request;

TEST(Groot2, TicksAllocateNothingWithAPublisherAndALoggerAttached) {
  RandomLeaves leaves(0x6e007);
  const unsigned port = free_port_pair();
  ASSERT_NE(port, 0u);
  // One file per process: this source is built twice (with and without breakpoints) and
  // ctest runs the two binaries at once.
  const std::string log_path = ::testing::TempDir() + "btgen_groot2_test_" + std::to_string(::getpid()) + ".btlog";
  auto mission = std::make_unique<Mission>(leaves);
  Counter counter;
  {
    btgen::groot2::Publisher publisher(*mission, port, "127.0.0.1");
    btgen::btlog::FileLogger logger(*mission, log_path, 1 << 20);
    ASSERT_TRUE(mission->observer().attach(&counter));
    EXPECT_EQ(mission->observer().attached(), 3u);
    btgen_test::settle(*mission);
    EXPECT_EQ(btgen_test::allocations_of_20000_ticks(*mission, publisher), 0u);
    EXPECT_GT(counter.changes, 20000u);

    // STATUS is what the tick published: every node, 4.6.2's codes.
    zmq::context_t ctx;
    zmq::socket_t client = btgen_test::connect_client(ctx, port);
    const auto status = request(client, 'S');
    ASSERT_EQ(status.size(), 2u);
    ASSERT_EQ(status[1].size(), 3 * Mission::node_count());
    for (std::size_t k = 0; k < Mission::node_count(); ++k) {
      const auto uid = static_cast<std::uint16_t>(static_cast<unsigned char>(status[1][3 * k]) |
                                                  (static_cast<unsigned char>(status[1][3 * k + 1]) << 8));
      ASSERT_GE(uid, 1u);
      const btgen::Status now = mission->status(uid - 1u);
      const auto code = static_cast<unsigned char>(status[1][3 * k + 2]);
      if (now == btgen::Status::IDLE) {
        EXPECT_TRUE(code == 0 || (code >= 11 && code <= 14)) << "uid " << uid << " code " << int(code);
      } else {
        EXPECT_EQ(code, static_cast<unsigned char>(now)) << "uid " << uid;
      }
    }
    const auto tree = request(client, 'T');
    ASSERT_EQ(tree.size(), 2u);
    EXPECT_EQ(tree[1], std::string(Mission::Groot2::kTreeXml));
    mission->observer().detach(&counter);
  }
  EXPECT_EQ(mission->observer().attached(), 0u);  // the monitors detached themselves

  // The .btlog: header, XML, first timestamp, one 9-byte record per change.
  std::ifstream in(log_path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(data.size(), 31u);
  EXPECT_EQ(data.substr(0, 18), "BTCPP4-FileLogger2");
  EXPECT_EQ(data[18], 1);
  std::uint32_t n = 0;
  for (int i = 0; i < 4; ++i) n |= static_cast<std::uint32_t>(static_cast<unsigned char>(data[19 + i])) << (8 * i);
  ASSERT_EQ(n, Mission::Groot2::kTreeXml.size());
  EXPECT_EQ(data.substr(23, n), std::string(Mission::Groot2::kTreeXml));
  const std::size_t records = (data.size() - 31 - n) / 9;
  EXPECT_EQ((data.size() - 31 - n) % 9, 0u);
  EXPECT_EQ(records, counter.changes);
  std::remove(log_path.c_str());
}

// Records the statuses each node takes.
struct Seen final : btgen::StatusSink {
  std::array<std::array<std::uint64_t, 5>, Mission::node_count()> to{};
  void on_status(const btgen::NodeInfo& n, btgen::Status, btgen::Status s) noexcept override {
    ++to[n.index][static_cast<std::size_t>(s)];
  }
};

std::string hook_json(unsigned uid, const char* status, bool once = false) {
  return std::string("{\"enabled\":true,\"uid\":") + std::to_string(uid) +
         ",\"mode\":1,\"once\":" + (once ? "true" : "false") + ",\"desired_status\":\"" + status + "\",\"position\":0}";
}

// Groot2's REPLACE hooks (live fault injection): a forced node takes only the forced
// status, its leaf hooks are not called, and the tick still allocates nothing.
TEST(Groot2, ReplaceHooksForceStatusesAndTicksAllocateNothing) {
  RandomLeaves leaves(0x4007);
  const unsigned port = free_port_pair();
  ASSERT_NE(port, 0u);
  auto mission = std::make_unique<Mission>(leaves);
  // FetchA's GiveUp (an Action), the root's IsBatteryOk, the Sequence "Cycle".
  std::size_t action = 0, condition = 1, control = 0;
  for (std::size_t i = 0; i < Mission::node_count(); ++i) {
    const std::string_view name = Mission::node(i).name;
    if (name == "GiveUp" && action == 0) action = i;
    if (name == "Cycle") control = i;
  }
  ASSERT_TRUE(action != 0 && control != 0);
  ASSERT_EQ(Mission::node(condition).kind, btgen::NodeKind::Condition);
  Seen seen;
  {
    btgen::groot2::Publisher publisher(*mission, port, "127.0.0.1");
    ASSERT_TRUE(mission->observer().attach(&seen));
    zmq::context_t ctx;
    zmq::socket_t client = btgen_test::connect_client(ctx, port);
    const auto uid = [](std::size_t i) { return static_cast<unsigned>(Mission::node(i).uid); };
    const std::string hooks = "[" + hook_json(uid(action), "FAILURE") + "," + hook_json(uid(condition), "SUCCESS") +
                              "," + hook_json(uid(control), "RUNNING") + "]";
    ASSERT_EQ(request(client, 'I', hooks).size(), 1u);
    btgen_test::settle(*mission);
    seen.to = {};
    EXPECT_EQ(btgen_test::allocations_of_20000_ticks(*mission, publisher), 0u);
    using S = btgen::Status;
    const auto n = [&](std::size_t node, S s) { return seen.to[node][static_cast<std::size_t>(s)]; };
    EXPECT_GT(n(action, S::FAILURE), 100u);
    EXPECT_EQ(n(action, S::SUCCESS) + n(action, S::RUNNING), 0u);
    EXPECT_GT(n(condition, S::SUCCESS), 100u);
    EXPECT_EQ(n(condition, S::FAILURE), 0u);
    EXPECT_GT(n(control, S::RUNNING) + n(control, S::SUCCESS) + n(control, S::FAILURE), 0u);  // ticked as usual
    // A `once` hook: used at the first visit, then gone from HOOKS_DUMP.
    ASSERT_EQ(request(client, 'I', hook_json(uid(action), "SUCCESS", true)).size(), 1u);
    EXPECT_NE(request(client, 'D')[1].find("\"once\":true"), std::string::npos);
    seen.to = {};
    for (int i = 0; i < 200; ++i) (void)mission->tick();
    EXPECT_GE(n(action, S::SUCCESS), 1u);
    EXPECT_EQ(request(client, 'D')[1].find("\"uid\":" + std::to_string(uid(action)) + "}"), std::string::npos);
    // Removed, the leaves answer again.
    ASSERT_EQ(request(client, 'A').size(), 1u);
    EXPECT_EQ(request(client, 'D')[1], "[]");
    seen.to = {};
    const auto checks = leaves.checks;
    for (int i = 0; i < 2000; ++i) (void)mission->tick();
    EXPECT_GT(n(condition, S::FAILURE), 0u);
    EXPECT_GT(leaves.checks, checks);
    mission->observer().detach(&seen);
  }
  // The publisher took its table with it: the next one may force statuses.
  EXPECT_EQ(mission->observer().forced_status(Mission::node(action)), btgen::Status::IDLE);
  const unsigned port2 = free_port_pair();
  ASSERT_NE(port2, 0u);
  btgen::groot2::Publisher again(*mission, port2, "127.0.0.1");
  (void)mission->tick();
}

TEST(Groot2, HookRequestsParse) {
  namespace d = btgen::groot2::detail;
  std::vector<d::HookSpec> specs;
  std::string_view error;
  ASSERT_TRUE(d::parse_hooks(" [ " + hook_json(3, "SKIPPED", true) + " ] ", specs, error)) << error;
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].uid, 3u);
  EXPECT_TRUE(specs[0].once);
  EXPECT_FALSE(specs[0].breakpoint);
  EXPECT_EQ(specs[0].desired, btgen::Status::SKIPPED);
  std::string dump = "[";
  d::dump_hook(dump, specs[0]);
  EXPECT_EQ(dump,
            "[{\"desired_status\":\"SKIPPED\",\"enabled\":true,\"mode\":1,\"once\":true,\"position\":0,"
            "\"uid\":3}");
  specs.clear();
  EXPECT_FALSE(d::parse_hooks("[1, 2]", specs, error));
  EXPECT_EQ(error, "hook JSON: a hook must be an object");
  EXPECT_FALSE(d::parse_hooks(std::string(20, '{'), specs, error));
  EXPECT_FALSE(d::parse_hooks("{\"a\": \"\\q\"}", specs, error));
  EXPECT_EQ(error, "hook JSON: a bad escape");
  d::HookSpec ref;
  ASSERT_TRUE(d::parse_hook_ref(R"({"uid":7,"position":0,"desired_status":"RUNNING","remove_when_done":true})", true,
                                ref, error));
  EXPECT_EQ(ref.desired, btgen::Status::SKIPPED);  // 4.6.2: neither SUCCESS nor FAILURE
  EXPECT_TRUE(ref.once);
}

TEST(Groot2, RingDropsInsteadOfWaitingWhenFull) {
  btgen::TransitionRing ring(4);
  for (std::uint16_t i = 0; i < 10; ++i) ring.push(btgen::Transition{i, i, 1});
  EXPECT_EQ(ring.dropped(), 7u);
  std::vector<std::uint16_t> got;
  ring.drain([&](const btgen::Transition& t) { got.push_back(t.uid); });
  EXPECT_EQ(got, (std::vector<std::uint16_t>{0, 1, 2}));
}

TEST(Groot2, MsgPackAsNlohmannWritesIt) {
  btgen::groot2::MsgPack mp;
  mp.map(1);
  mp.str("a");
  mp.integer(-33);
  EXPECT_EQ(mp.out, std::string("\x81\xa1"
                                "a\xd0\xdf",
                                5));
  btgen::groot2::MsgPack f;
  f.real(0.25);  // exact in float32
  f.real(0.1);   // not
  EXPECT_EQ(f.out.size(), 5u + 9u);
  EXPECT_EQ(static_cast<unsigned char>(f.out[0]), 0xca);
  EXPECT_EQ(static_cast<unsigned char>(f.out[5]), 0xcb);
}

TEST(Groot2, LoggerRefusesAnotherExtension) {
  RandomLeaves leaves(1);
  auto mission = std::make_unique<Mission>(leaves);
  EXPECT_THROW(btgen::btlog::FileLogger(*mission, ::testing::TempDir() + "x.log"), std::runtime_error);
  EXPECT_EQ(mission->observer().attached(), 0u);
}

}  // namespace
