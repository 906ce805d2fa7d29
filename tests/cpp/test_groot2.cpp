// Groot2 monitors attached to a compiled mission: the tick path allocates
// nothing with a publisher and a .btlog logger attached, the publisher
// answers STATUS with what the tick published, the .btlog holds every change.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <zmq.hpp>

#include "btgen/btlog.hpp"
#include "btgen/clock.hpp"
#include "btgen/groot2.hpp"
#include "btgen/monitor.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "control_flow.hpp"
#include "test_leaves.hpp"

namespace {

using btgen_test::RandomLeaves;
using Mission = control_flow::ControlFlow<RandomLeaves, btgen::ManualClock, btgen::MonitorObserver<>>;

// Counts the changes it sees, to compare with the .btlog.
struct Counter final : btgen::StatusSink {
  std::size_t changes = 0;
  void on_status(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept override { ++changes; }
};

unsigned free_port_pair() {
  // Bind a publisher-like pair on ephemeral ports until two consecutive ones are free.
  for (int attempt = 0; attempt < 50; ++attempt) {
    zmq::context_t ctx;
    zmq::socket_t a(ctx, zmq::socket_type::rep);
    a.bind("tcp://127.0.0.1:*");
    const std::string ep = a.get(zmq::sockopt::last_endpoint);
    const unsigned port = static_cast<unsigned>(std::stoul(ep.substr(ep.rfind(':') + 1)));
    a.close();
    if (port >= 65534) continue;
    zmq::socket_t b(ctx, zmq::socket_type::rep);
    try {
      b.bind("tcp://127.0.0.1:" + std::to_string(port + 1));
      return port;
    } catch (const zmq::error_t&) {
    }
  }
  return 0;
}

std::vector<std::string> request(zmq::socket_t& s, char type, const std::string& extra = {}) {
  const char head[6] = {2, type, 1, 2, 3, 4};
  s.send(zmq::buffer(head, 6), extra.empty() ? zmq::send_flags::none : zmq::send_flags::sndmore);
  if (!extra.empty()) s.send(zmq::buffer(extra), zmq::send_flags::none);
  std::vector<std::string> parts;
  for (;;) {
    zmq::message_t m;
    if (!s.recv(m)) break;
    parts.push_back(m.to_string());
    if (!m.more()) break;
  }
  return parts;
}

TEST(Groot2, TicksAllocateNothingWithAPublisherAndALoggerAttached) {
  RandomLeaves leaves(0x6e007);
  const unsigned port = free_port_pair();
  ASSERT_NE(port, 0u);
  const std::string log_path = ::testing::TempDir() + "btgen_groot2_test.btlog";
  auto mission = std::make_unique<Mission>(leaves);
  Counter counter;
  long changes_before = 0;
  {
    btgen::groot2::Publisher publisher(*mission, port, "127.0.0.1");
    btgen::btlog::FileLogger logger(*mission, log_path, 1 << 20);
    ASSERT_TRUE(mission->observer().attach(&counter));
    EXPECT_EQ(mission->observer().attached(), 3u);
    for (int i = 0; i < 10; ++i) (void)mission->tick();
    // The counter counts every thread: let the server, writer and ZeroMQ threads
    // finish starting (their first allocations) before the ticks are measured.
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    changes_before = static_cast<long>(counter.changes);
    {
      btgen_test::AllocationScope scope;
      for (int i = 0; i < 20000; ++i) {
        mission->clock().advance(7);
        (void)mission->tick();
        publisher.sync();
        if (i % 1009 == 1008) mission->halt();
      }
      EXPECT_EQ(scope.count(), 0u);
    }
    EXPECT_GT(counter.changes, 20000u);

    // STATUS is what the tick published: every node, 4.6.2's codes.
    zmq::context_t ctx;
    zmq::socket_t client(ctx, zmq::socket_type::req);
    client.set(zmq::sockopt::rcvtimeo, 3000);
    client.set(zmq::sockopt::linger, 0);
    client.connect("tcp://127.0.0.1:" + std::to_string(port));
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
  (void)changes_before;
  std::remove(log_path.c_str());
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
