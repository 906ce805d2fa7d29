// What the Groot2 C++ tests share: a free pair of ports, one request as Groot2 sends it, and
// the measured ticking with a publisher attached.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <thread>
#include <vector>

#include <zmq.hpp>

#include "btgen/testing/alloc_counter.hpp"

namespace btgen_test {

// Binds a publisher-like pair on ephemeral ports until two consecutive ones are free.
inline unsigned free_port_pair() {
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

// A REQ socket connected to the publisher's request port on 127.0.0.1, waiting 3 s at most.
inline zmq::socket_t connect_client(zmq::context_t& ctx, unsigned port) {
  zmq::socket_t client(ctx, zmq::socket_type::req);
  client.set(zmq::sockopt::rcvtimeo, 3000);
  client.set(zmq::sockopt::linger, 0);
  client.connect("tcp://127.0.0.1:" + std::to_string(port));
  return client;
}

// One Groot2 request (protocol 2, header then an optional body) and every frame of its reply.
inline std::vector<std::string> request(zmq::socket_t& s, char type, const std::string& extra = {}) {
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

// 10 ticks, then a pause: the allocation counter counts every thread, so the server, writer
// and ZeroMQ threads finish starting (their first allocations) before ticks are measured.
template <class Mission>
void settle(Mission& mission) {
  for (int i = 0; i < 10; ++i) (void)mission.tick();
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
}

// 20,000 ticks with the publisher synchronised after each and a halt now and then: the
// allocations they made.
template <class Mission, class Publisher>
std::size_t allocations_of_20000_ticks(Mission& mission, Publisher& publisher) {
  AllocationScope scope;
  for (int i = 0; i < 20000; ++i) {
    mission.clock().advance(7);
    (void)mission.tick();
    publisher.sync();
    if (i % 1009 == 1008) mission.halt();
  }
  return scope.count();
}

}  // namespace btgen_test
