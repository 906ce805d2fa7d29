// btgen runtime: live monitoring of a compiled mission in Groot2.
//
//     using Tour = lab_tour::LabTour<Robot, btgen::SteadyClock, btgen::MonitorObserver<>>;
//     Tour mission(robot);
//     btgen::groot2::Publisher groot2(mission, 1667);  // REP on 1667, PUB on 1668
//     for (;;) { mission.tick(); groot2.sync(); ... }
//
// Speaks BehaviorTree.CPP 4.6's Groot2Publisher protocol (groot2_protocol.h:
// protocol 2, a ZeroMQ REP socket on `port` and a PUB socket on `port + 1`).
// Every request is a 6-byte header (protocol, request type, uint32 id) and
// every reply starts with that header and the tree's 16-byte UUID:
//
//   FULLTREE 'T'     the mission's tree XML, built by the generator (Groot2::kTreeXml)
//   STATUS 'S'       3 bytes per node, uint16 UID + status, in 4.6.2's order; IDLE
//                    reached from S is written 10 + S, as 4.6.2 does
//   BLACKBOARD 'B'   second part "name;name;...": MessagePack of a JSON object with
//                    each named blackboard's entries (integers, bools as integers,
//                    doubles, strings; other types null, as 4.6.2's JSON export);
//                    from 4.10.0 a SubTree's also brings the root blackboard as `ROOT`
//   TOGGLE_RECORDING 'r' "start" (reply: now in microseconds) / "stop"
//   GET_TRANSITIONS 't' the transitions since the last call, 9 bytes each
//   HOOKS_DUMP 'D'   "[]"; REMOVE_ALL_HOOKS 'A', DISABLE_ALL_HOOKS 'X': done (none exist)
//   HOOK_INSERT 'I', HOOK_REMOVE 'R', BREAKPOINT_UNLOCK 'U': error replies; btgen has no
//                    breakpoints (a compiled tick cannot be paused), so Groot2 shows the
//                    error and never waits for a breakpoint
//   anything else, a header that is not 6 bytes, a protocol other than 2: an error
//                    reply ("error", message), as 4.6.2 answers what it does not know.
//
// The tick path: each status change stores one byte in an array of atomics
// (and, while recording, one record in a fixed ring); the server thread reads
// them. The blackboard is copied by sync() (call it after each tick), and at
// a status change while a BLACKBOARD request waits for it, under a mutex the
// tick thread only try-locks: it never waits. Nothing on the tick path
// allocates. A BLACKBOARD request waits up to 200 ms for a fresh copy, then
// answers with the last one (the blackboard after the last sync()); all BLACKBOARD requests
// together wait at most 200 ms a second.
//
// What one client may make it hold: a request of at most kMaxRequestFrames frames and
// kMaxRequestBytes (a larger one drops its peer), no subscription (the PUB port is an XPUB
// that reads them and drops them).
#pragma once

#ifdef BTGEN_BARE_METAL
#error \
    "btgen/groot2.hpp needs an operating system (threads and ZeroMQ sockets): it is not built for bare-metal targets (mcu/README.md)"
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include <zmq.hpp>

#include "btgen/blackboard.hpp"
#include "btgen/btlog.hpp"
#include "btgen/dynamic.hpp"
#include "btgen/fixed_string.hpp"
#include "btgen/monitor.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen::groot2 {

inline constexpr std::uint8_t kProtocolId = 2;

// What one client may make the monitor hold. Groot2 sends at most two frames, a few bytes
// and a list of blackboard names; ZMQ_MAXMSGSIZE bounds each frame, not a message, so a
// request of more frames or bytes than these drops its peer as a larger frame does.
inline constexpr std::size_t kMaxRequestFrames = 4;
inline constexpr std::size_t kMaxRequestBytes = std::size_t{256} << 10;
// A subscription on the PUB port (btgen publishes nothing: they are read and dropped).
inline constexpr std::int64_t kMaxSubscriptionBytes = 256;
// The most a BLACKBOARD request waits for a fresh copy, and the most all of them wait in
// one second: requests left by clients that went away cannot hold the server for long.
inline constexpr std::chrono::milliseconds kBlackboardWait{200};
inline constexpr std::chrono::milliseconds kBlackboardWaitPerSecond{200};

enum RequestType : std::uint8_t {
  kFullTree = 'T',
  kStatus = 'S',
  kBlackboard = 'B',
  kHookInsert = 'I',
  kHookRemove = 'R',
  kBreakpointReached = 'N',
  kBreakpointUnlock = 'U',
  kHooksDump = 'D',
  kRemoveAllHooks = 'A',
  kDisableAllHooks = 'X',
  kToggleRecording = 'r',
  kGetTransitions = 't',
};

// MessagePack, as nlohmann::json::to_msgpack writes what the blackboard export holds.
class MsgPack {
 public:
  std::string out;

  void nil() { out.push_back(static_cast<char>(0xc0)); }
  void integer(std::int64_t v) {
    if (v >= 0) {
      const auto u = static_cast<std::uint64_t>(v);
      if (u < 128)
        byte(static_cast<std::uint8_t>(u));
      else if (u <= 0xFF) {
        byte(0xcc);
        be(u, 1);
      } else if (u <= 0xFFFF) {
        byte(0xcd);
        be(u, 2);
      } else if (u <= 0xFFFFFFFFu) {
        byte(0xce);
        be(u, 4);
      } else {
        byte(0xcf);
        be(u, 8);
      }
    } else if (v >= -32) {
      byte(static_cast<std::uint8_t>(static_cast<std::int8_t>(v)));
    } else if (v >= INT8_MIN) {
      byte(0xd0);
      be(static_cast<std::uint64_t>(v), 1);
    } else if (v >= INT16_MIN) {
      byte(0xd1);
      be(static_cast<std::uint64_t>(v), 2);
    } else if (v >= INT32_MIN) {
      byte(0xd2);
      be(static_cast<std::uint64_t>(v), 4);
    } else {
      byte(0xd3);
      be(static_cast<std::uint64_t>(v), 8);
    }
  }
  void real(double v) {
    const auto f = static_cast<float>(v);
    if (static_cast<double>(f) == v) {  // nlohmann writes a float32 when nothing is lost
      std::uint32_t bits;
      std::memcpy(&bits, &f, 4);
      byte(0xca);
      be(bits, 4);
    } else {
      std::uint64_t bits;
      std::memcpy(&bits, &v, 8);
      byte(0xcb);
      be(bits, 8);
    }
  }
  void str(std::string_view s) {
    const std::size_t n = s.size();
    if (n < 32)
      byte(static_cast<std::uint8_t>(0xa0 | n));
    else if (n <= 0xFF) {
      byte(0xd9);
      be(n, 1);
    } else if (n <= 0xFFFF) {
      byte(0xda);
      be(n, 2);
    } else {
      byte(0xdb);
      be(n, 4);
    }
    out.append(s.data(), n);
  }
  void map(std::size_t n) {
    if (n < 16)
      byte(static_cast<std::uint8_t>(0x80 | n));
    else if (n <= 0xFFFF) {
      byte(0xde);
      be(n, 2);
    } else {
      byte(0xdf);
      be(n, 4);
    }
  }

 private:
  void byte(std::uint8_t b) { out.push_back(static_cast<char>(b)); }
  void be(std::uint64_t v, int n) {
    for (int i = n - 1; i >= 0; --i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
  }
};

namespace detail {

template <class T>
struct is_fixed_string : std::false_type {};
template <std::size_t N>
struct is_fixed_string<FixedString<N>> : std::true_type {};
template <class T>
struct is_dyn : std::false_type {};
template <std::size_t N>
struct is_dyn<Dyn<N>> : std::true_type {};

// One entry's value as 4.6.2's ExportBlackboardToJSON writes it.
template <class T>
void write_value(MsgPack& mp, const Slot<T>& slot) {
  if (!slot.has_value) return mp.nil();
  const T& v = slot.value;
  if constexpr (std::is_same_v<T, bool> || std::is_integral_v<T>) {
    mp.integer(static_cast<std::int64_t>(v));  // 4.6.2's Any holds every integral as int64
  } else if constexpr (std::is_floating_point_v<T>) {
    mp.real(static_cast<double>(v));
  } else if constexpr (is_fixed_string<T>::value) {
    mp.str(v.view());
  } else if constexpr (is_dyn<T>::value) {
    switch (v.tag) {
      case DynTag::kInt:
      case DynTag::kBool: return mp.integer(v.i);
      case DynTag::kDouble: return mp.real(v.d);
      case DynTag::kString: return mp.str(v.s.view());
      default: return mp.nil();
    }
  } else {
    mp.nil();  // NodeStatus, queues: 4.6.2 has no JSON converter for them
  }
}

// What one request asks, decided from its frames alone (no socket, no mission): the
// server answers it, and tests/fuzz/fuzz_groot2_request.cpp runs it on any bytes.
struct Request {
  enum class Kind : std::uint8_t {
    kError,  // reply ("error", error)
    kFullTree,
    kStatus,
    kBlackboard,  // argument: the `;`-separated names
    kRecordStart,
    kRecordStop,
    kRecordOther,  // TOGGLE_RECORDING with neither word: the header alone, as 4.6.2
    kTransitions,
    kHooksDump,
    kDone,  // the header alone
  };
  Kind kind = Kind::kError;
  std::string_view error;
  std::string_view argument;
};

inline Request parse_request(const std::string_view* parts, std::size_t n) noexcept {
  using K = Request::Kind;
  const auto fail = [](std::string_view message) { return Request{K::kError, message, {}}; };
  if (n == 0 || parts[0].size() != 6) return fail("wrong request header");
  const auto* h = reinterpret_cast<const unsigned char*>(parts[0].data());
  if (h[0] != kProtocolId) return fail("wrong protocol: btgen speaks Groot2 protocol 2");
  switch (h[1]) {
    case kFullTree: return {K::kFullTree, {}, {}};
    case kStatus: return {K::kStatus, {}, {}};
    case kBlackboard:
      if (n != 2) return fail("must be 2 parts message");
      return {K::kBlackboard, {}, parts[1]};
    case kToggleRecording:
      if (n != 2) return fail("must be 2 parts message");
      if (parts[1] == "start") return {K::kRecordStart, {}, {}};
      if (parts[1] == "stop") return {K::kRecordStop, {}, {}};
      return {K::kRecordOther, {}, {}};
    case kGetTransitions: return {K::kTransitions, {}, {}};
    case kHooksDump: return {K::kHooksDump, {}, {}};
    case kRemoveAllHooks:
    case kDisableAllHooks: return {K::kDone, {}, {}};
    case kHookInsert: return fail("btgen: breakpoints and hooks are not supported by compiled missions");
    case kHookRemove:
    case kBreakpointUnlock: return fail("Node ID not found");
    default: return fail("Request not recognized");
  }
}

// Calls f(name) for each `;`-separated name of a BLACKBOARD request (empty ones too).
template <class F>
void for_each_name(std::string_view names, F&& f) {
  std::size_t start = 0;
  while (start <= names.size()) {
    std::size_t end = names.find(';', start);
    if (end == std::string_view::npos) end = names.size();
    f(names.substr(start, end - start));
    start = end + 1;
  }
}

inline std::array<char, 16> random_uuid() {
  std::random_device rd;
  std::array<char, 16> out{};
  for (std::size_t i = 0; i < 16; i += 4) {
    const std::uint32_t r = rd();
    std::memcpy(out.data() + i, &r, 4);
  }
  out[8] = static_cast<char>((out[8] & 0xBF) | 0x80);  // variant 10xxxxxx
  out[6] = static_cast<char>((out[6] & 0x4F) | 0x40);  // version 0100xxxx
  return out;
}

}  // namespace detail

// The publisher of one mission (a btgen mission whose observer is a
// btgen::MonitorObserver); destroy it before the mission (it detaches itself).
// Throws zmq::error_t when a port cannot be bound.
// `address` is the interface ("*": all, as BehaviorTree.CPP; "127.0.0.1").
template <class Mission>
class Publisher final : public StatusSink {
 public:
  using Groot2 = typename Mission::Groot2;
  using Blackboard = typename Mission::Blackboard;
  static constexpr std::size_t kNodes = Mission::node_count();

  Publisher(Mission& mission, unsigned port, const std::string& address = "*", std::size_t recording_capacity = 1000)
      : mission_(&mission),
        port_(port),
        recording_(recording_capacity),
        snapshot_(std::make_unique<Blackboard>()),
        server_(context_, zmq::socket_type::rep),
        publisher_(context_, zmq::socket_type::xpub),
        uuid_(detail::random_uuid()) {
    for (auto& s : status_) s.store(0, std::memory_order_relaxed);
    server_address_ = "tcp://" + address + ":" + std::to_string(port);
    configure(server_);
    server_.bind(server_address_);
    publisher_.set(zmq::sockopt::linger, 0);
    // Subscriptions are handed to serve(), which drops them: a PUB socket would keep every
    // distinct one (300 of 1 MiB each grew the process by 300 MiB).
    publisher_.set(zmq::sockopt::xpub_manual, 1);
    publisher_.set(zmq::sockopt::maxmsgsize, kMaxSubscriptionBytes);
    publisher_.bind("tcp://" + address + ":" + std::to_string(port + 1));
    if (!mission.observer().attach(this))
      throw std::runtime_error("groot2: the mission's observer has no room for another monitor");
    *snapshot_ = mission.blackboard();
    thread_ = std::thread([this] { serve(); });
  }

  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  ~Publisher() {
    mission_->observer().detach(this);
    active_.store(false);
    if (thread_.joinable()) thread_.join();
  }

  // Tick thread, inside tick(): one byte, and a record while recording.
  void on_status(const NodeInfo& node, Status from, Status to) noexcept override {
    const auto code =
        static_cast<std::uint8_t>(to == Status::IDLE ? 10 + static_cast<int>(from) : static_cast<int>(to));
    status_[node.index].store(code, std::memory_order_relaxed);
    if (recording_on_.load(std::memory_order_relaxed)) {
      const std::int64_t now = btgen::wall_clock_usec() - record_origin_.load(std::memory_order_relaxed);
      recording_.push(
          Transition{now > 0 ? static_cast<std::uint64_t>(now) : 0, node.uid, static_cast<std::uint8_t>(to)});
    }
    if (bb_wanted_.load(std::memory_order_acquire)) sync();
  }

  // Tick thread, between ticks (after each tick): copies the blackboard for
  // BLACKBOARD requests, unless the server thread is reading the last copy.
  void sync() noexcept {
    std::unique_lock<std::mutex> lock(bb_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    *snapshot_ = mission_->blackboard();
    bb_wanted_.store(false, std::memory_order_release);
    bb_version_.fetch_add(1, std::memory_order_release);
  }

  [[nodiscard]] unsigned port() const noexcept { return port_; }
  // Requests answered so far (tests, diagnostics).
  [[nodiscard]] std::uint64_t requests() const noexcept { return requests_.load(); }

 private:
  void serve() {
    while (active_.load()) {
      if (!bound_) {
        rebind();
        if (!bound_) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      std::vector<zmq::message_t> parts;
      try {
        zmq::pollitem_t items[] = {{server_.handle(), 0, ZMQ_POLLIN, 0}, {publisher_.handle(), 0, ZMQ_POLLIN, 0}};
        zmq::poll(items, 2, std::chrono::milliseconds(100));  // then look at active_ again
        if ((items[1].revents & ZMQ_POLLIN) != 0) drop_subscriptions();
        if ((items[0].revents & ZMQ_POLLIN) == 0) continue;
        zmq::message_t first;
        if (!server_.recv(first, zmq::recv_flags::dontwait)) continue;
        std::size_t bytes = first.size();
        parts.push_back(std::move(first));
        bool over = false;
        while (!over && parts.back().more()) {
          zmq::message_t next;
          if (!server_.recv(next, zmq::recv_flags::none)) break;
          bytes += next.size();
          parts.push_back(std::move(next));
          over = parts.size() > kMaxRequestFrames || bytes > kMaxRequestBytes;
        }
        if (over || parts.back().more()) {  // over a bound, or the rest never came: drop the peer
          parts.clear();
          reset_server();
          continue;
        }
        answer(parts);
      } catch (const zmq::error_t& e) {
        // A peer that went away mid-request, an interrupted call: keep serving. A REP
        // socket left waiting for a reply it could not send (EFSM) is made anew.
        if (e.num() == EFSM) reset_server();
      } catch (const std::exception&) {
        reset_server();  // out of memory while answering: the reply was not sent
      }
    }
  }

  void drop_subscriptions() {
    for (int i = 0; i < 1000; ++i) {  // (then serve requests; the rest at the next poll)
      zmq::message_t m;
      if (!publisher_.recv(m, zmq::recv_flags::dontwait)) return;
    }
  }

  static void configure(zmq::socket_t& s) {
    s.set(zmq::sockopt::linger, 0);
    s.set(zmq::sockopt::rcvtimeo, 100);
    s.set(zmq::sockopt::sndtimeo, 1000);
    s.set(zmq::sockopt::maxmsgsize, static_cast<std::int64_t>(kMaxRequestBytes));  // a larger frame drops its peer
  }
  void reset_server() {
    try {
      server_.close();
      server_ = zmq::socket_t(context_, zmq::socket_type::rep);
      configure(server_);
      bound_ = false;
      rebind();
    } catch (const zmq::error_t&) {
    }
  }
  // Binds the new socket; serve() tries again every 100 ms until the port is free.
  void rebind() {
    try {
      server_.bind(server_address_);
      bound_ = true;
    } catch (const zmq::error_t&) {
    }
  }

  void send(std::vector<std::string>& reply) {
    for (std::size_t i = 0; i < reply.size(); ++i) {
      const auto flags = i + 1 < reply.size() ? zmq::send_flags::sndmore : zmq::send_flags::none;
      if (!server_.send(zmq::buffer(reply[i]), flags)) {
        reset_server();  // the reply could not go out within a second: start afresh
        return;
      }
    }
    requests_.fetch_add(1);
  }
  void error(std::string_view message) {
    std::vector<std::string> reply{"error", std::string(message)};
    send(reply);
  }

  void answer(const std::vector<zmq::message_t>& parts) {
    std::array<std::string_view, kMaxRequestFrames> views{};
    for (std::size_t i = 0; i < parts.size(); ++i)
      views[i] = std::string_view(static_cast<const char*>(parts[i].data()), parts[i].size());
    const detail::Request request = detail::parse_request(views.data(), parts.size());
    using K = detail::Request::Kind;
    if (request.kind == K::kError) return error(request.error);
    std::string header(22, '\0');
    std::memcpy(header.data(), views[0].data(), 6);
    std::memcpy(header.data() + 6, uuid_.data(), 16);
    std::vector<std::string> reply{header};
    switch (request.kind) {
      case K::kFullTree: reply.emplace_back(Groot2::kTreeXml); break;
      case K::kStatus: {
        std::string buf(3 * kNodes, '\0');
        for (std::size_t i = 0; i < kNodes; ++i) {
          const std::uint16_t index = Groot2::kStatusOrder[i];
          const std::uint16_t uid = Mission::node(index).uid;
          buf[3 * i] = static_cast<char>(uid & 0xFF);
          buf[3 * i + 1] = static_cast<char>(uid >> 8);
          buf[3 * i + 2] = static_cast<char>(status_[index].load(std::memory_order_relaxed));
        }
        reply.push_back(std::move(buf));
        break;
      }
      case K::kBlackboard: {
        std::string dump;
        std::string_view why;
        if (!blackboards(request.argument, dump, why)) return error(why);
        reply.push_back(std::move(dump));
        break;
      }
      case K::kRecordStart:
        recording_.drain([](const Transition&) {});
        record_origin_.store(btgen::wall_clock_usec());
        recording_on_.store(true);
        reply.push_back(std::to_string(btgen::wall_clock_usec()));
        break;
      case K::kRecordStop: recording_on_.store(false); break;
      case K::kTransitions: {
        std::string buf;
        char rec[9];
        recording_.drain([&](const Transition& t) {
          pack_transition(t, rec);
          buf.append(rec, 9);
        });
        reply.push_back(std::move(buf));
        break;
      }
      case K::kHooksDump: reply.emplace_back("[]"); break;
      default: break;
    }
    send(reply);
  }

  // The blackboards named in `names` (`;`-separated) that exist, as 4.6.2 dumps them;
  // from 4.10.0 (Sem::groot2_root_blackboard) a SubTree's comes with the root blackboard
  // (the main tree's, index 0) under the name `ROOT`. False: `err` says why there is no dump.
  bool blackboards(std::string_view names, std::string& out, std::string_view& err) {
    wait_for_a_fresh_copy();
    static constexpr std::string_view kRoot = "ROOT";
    std::vector<std::pair<std::string_view, std::size_t>> wanted;  // name, blackboard index
    bool root_exported = false;
    err = {};
    detail::for_each_name(names, [&](std::string_view name) {
      for (std::size_t b = 0; b < Groot2::kBlackboards.size(); ++b) {
        if (Groot2::kBlackboards[b] != name || !err.empty()) continue;
        const auto has = [&](std::string_view n) {
          return std::any_of(wanted.begin(), wanted.end(), [&](const auto& w) { return w.first == n; });
        };
        const bool needs_root = Mission::Sem::groot2_root_blackboard && b != 0;
        if (Mission::Sem::groot2_root_blackboard && name == kRoot && (needs_root || root_exported)) {
          err = "blackboard dump request uses reserved name [ROOT] together with an external root blackboard export";
          return;
        }
        if (!has(name)) wanted.emplace_back(name, b);
        if (!needs_root || root_exported) continue;
        if (has(kRoot)) {
          err = "blackboard dump request would overwrite subtree [ROOT] with an external root blackboard export";
          return;
        }
        wanted.emplace_back(kRoot, 0);
        root_exported = true;
      }
    });
    if (!err.empty()) return false;
    // nlohmann's object is a std::map: names in byte order.
    std::sort(wanted.begin(), wanted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    MsgPack mp;
    if (wanted.empty()) {
      mp.nil();
      out = std::move(mp.out);
      return true;
    }
    std::lock_guard<std::mutex> lock(bb_mutex_);
    mp.map(wanted.size());
    for (const auto& [bb_name, b] : wanted) {
      mp.str(bb_name);
      std::size_t n = 0;
      Groot2::visit_blackboard(*snapshot_, [&](std::size_t bb, std::string_view, const auto& slot) {
        if (bb == b && slot.exists) ++n;
      });
      if (n == 0) {
        mp.nil();
        continue;
      }
      mp.map(n);
      Groot2::visit_blackboard(*snapshot_, [&](std::size_t bb, std::string_view key, const auto& slot) {
        if (bb != b || !slot.exists) return;
        mp.str(key);
        detail::write_value(mp, slot);
      });
    }
    out = std::move(mp.out);
    return true;
  }

  // Asks the tick thread for a copy at its next status change and waits for it, within
  // kBlackboardWait and what is left of kBlackboardWaitPerSecond (the server thread cannot
  // tell whether the client is still there: 300 requests of clients that left took 60 s).
  void wait_for_a_fresh_copy() {
    const auto now = std::chrono::steady_clock::now();
    if (now - wait_window_ >= std::chrono::seconds(1)) {
      wait_window_ = now;
      waited_ = std::chrono::steady_clock::duration::zero();
    }
    const auto budget =
        std::min<std::chrono::steady_clock::duration>(kBlackboardWait, kBlackboardWaitPerSecond - waited_);
    if (budget <= std::chrono::steady_clock::duration::zero()) return;
    const std::uint64_t version = bb_version_.load(std::memory_order_acquire);
    bb_wanted_.store(true, std::memory_order_release);
    const auto deadline = now + budget;
    while (bb_version_.load(std::memory_order_acquire) == version && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    waited_ += std::chrono::steady_clock::now() - now;
  }

  Mission* mission_;
  unsigned port_;
  std::chrono::steady_clock::time_point wait_window_{};  // server thread only
  std::chrono::steady_clock::duration waited_{};
  std::array<std::atomic<std::uint8_t>, kNodes> status_{};
  TransitionRing recording_;
  std::atomic<bool> recording_on_{false};
  std::atomic<std::int64_t> record_origin_{0};
  std::mutex bb_mutex_;
  std::unique_ptr<Blackboard> snapshot_;
  std::atomic<bool> bb_wanted_{false};
  std::atomic<std::uint64_t> bb_version_{0};
  std::atomic<std::uint64_t> requests_{0};
  std::atomic<bool> active_{true};
  std::string server_address_;
  bool bound_ = true;  // server thread only, after construction
  zmq::context_t context_;
  zmq::socket_t server_;
  zmq::socket_t publisher_;
  std::array<char, 16> uuid_;
  std::thread thread_;
};

template <class Mission>
Publisher(Mission&, unsigned) -> Publisher<Mission>;
template <class Mission>
Publisher(Mission&, unsigned, const std::string&) -> Publisher<Mission>;

}  // namespace btgen::groot2
