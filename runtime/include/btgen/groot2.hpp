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
//   HOOK_INSERT 'I'  a hook's JSON or an array of them (uid, position, enabled, once, mode,
//                    desired_status): live fault injection, below
//   HOOK_REMOVE 'R', BREAKPOINT_UNLOCK 'U' (desired_status, remove_when_done), HOOKS_DUMP 'D'
//                    (the hooks as 4.6.2's JSON), REMOVE_ALL_HOOKS 'A', DISABLE_ALL_HOOKS 'X'
//   anything else, a header that is not 6 bytes, a protocol other than 2: an error
//                    reply ("error", message), as 4.6.2 answers what it does not know.
//
// Hooks (4.6.2's Groot2Publisher: one pre-tick hook per node). A REPLACE hook (mode 1) is
// one atomic byte per node (hook_bytes_) that the engine reads on each visit of the node,
// after its pre-conditions and only when the node is not completed: SUCCESS or FAILURE is
// returned instead of ticking the node (its tick is not called, nothing is halted, the
// post-conditions run); RUNNING, SKIPPED and IDLE tick it as usual; `once` hooks are taken
// out of the table by the tick thread at their first use. A BREAKPOINT hook (mode 0) needs
// a build with BTGEN_GROOT2_BREAKPOINTS (else an error reply): the tick thread waits at the
// node, sleeping 1 ms at a time, until BREAKPOINT_UNLOCK (its desired_status: SUCCESS or
// FAILURE is returned, any other word ticks the node), or until the hook is disabled,
// removed or made REPLACE; BREAKPOINT_REACHED (header, UID) goes out on the PUB port. After
// kMaxHeartbeatDelay without a request every hook is disabled (a paused tick goes on) and
// the next request enables them again, as 4.6.2's heartbeat does. Differences from 4.6.2:
// an unknown UID and malformed JSON get error replies (4.6.2 ignores the first and
// terminates on the second); REPLACE hooks publish no BREAKPOINT_REACHED (4.6.2 sends one
// at each visit, from the tick thread); HOOKS_DUMP lists the hooks by UID.
//
// The tick path: each visit of a node tests its hook byte (a relaxed load); each status
// change stores one byte in an array of atomics
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
#include <cctype>
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
// In this order, the order of their functions when they were one header (g++'s inlining
// follows it): the MessagePack of the replies, the protocol, the JSON of the hook requests.
#include "btgen/groot2/msgpack.hpp"

#include "btgen/groot2/protocol.hpp"

#include "btgen/groot2/json.hpp"
#include "btgen/monitor.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen::groot2 {

namespace detail {

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
class Publisher final : public StatusSink, public HookSink {
 public:
  using Groot2 = typename Mission::Groot2;
  using Blackboard = typename Mission::Blackboard;
  static constexpr std::size_t kNodes = Mission::node_count();
  // 4.10.0 (Sem::groot2_post_hooks): a POST hook per node besides the PRE one, in slots
  // kNodes + index of the tables below; 4.6.2 files every hook as PRE (one slot a node).
  static constexpr bool kPostHooks = Mission::Sem::groot2_post_hooks;
  static constexpr std::size_t kSlots = kPostHooks ? 2 * kNodes : kNodes;
  // 4.10.0 (Sem::groot2_insert_until_error): a HOOK_INSERT array keeps the hooks before a
  // bad one; 4.6.2 (whose server thread terminates then) is modelled as all or none.
  static constexpr bool kInsertUntilError = Mission::Sem::groot2_insert_until_error;

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
    for (auto& b : hook_bytes_) b.store(0, std::memory_order_relaxed);
    for (auto& b : release_) b.store(0, std::memory_order_relaxed);
    if (!mission.observer().attach(this))
      throw std::runtime_error("groot2: the mission's observer has no room for another monitor");
    hooks_attached_ =
        mission.observer().attach_hooks(this, hook_bytes_.data(), kPostHooks ? hook_bytes_.data() + kNodes : nullptr);
    *snapshot_ = mission.blackboard();
    thread_ = std::thread([this] { serve(); });
  }

  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  ~Publisher() {
    mission_->observer().detach_hooks(this);
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

  // Tick thread, inside tick(): node `node` has a hook (byte `b`) and is about to be
  // ticked. REPLACE: its desired status (the engine ticks the node unless it is SUCCESS or
  // FAILURE); a `once` hook is taken out of the table first, so it is used once.
  // BREAKPOINT (BTGEN_GROOT2_BREAKPOINTS builds): waits for BREAKPOINT_UNLOCK, or for the
  // hook to be disabled, removed or made REPLACE. Nothing allocates or locks.
  Status on_hook(const NodeInfo& node, std::uint8_t b) noexcept override { return use_hook(node.index, b); }
  // The same for a POST hook (4.10.0 missions), after the node's tick.
  Status on_post_hook(const NodeInfo& node, std::uint8_t b) noexcept override {
    if constexpr (kPostHooks) return use_hook(kNodes + node.index, b);
    (void)node;
    (void)b;
    return Status::IDLE;
  }

  // The heartbeat: after this long without a request every hook is disabled, and enabled
  // again at the next request (4.6.2's setMaxHeartbeatDelay; default kMaxHeartbeatDelay).
  void set_max_heartbeat_delay(std::chrono::milliseconds delay) noexcept { heartbeat_ms_.store(delay.count()); }

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
  // Tick thread: the hook of slot `i` (node index, or kNodes + index for POST) with byte `b`.
  Status use_hook(std::size_t i, std::uint8_t b) noexcept {
    auto& slot = hook_bytes_[i];
    Status result = static_cast<Status>(b & kHookStatus);
    if constexpr (kBreakpoints) {
      if ((b & kHookBreak) != 0) {
        result = wait_at_breakpoint(i);
        b = slot.load(std::memory_order_acquire);
      }
    } else if ((b & kHookBreak) != 0) {
      return Status::IDLE;  // (never stored without breakpoints)
    }
    while ((b & kHookOnce) != 0) {  // remove_when_done: the server sees the byte gone
      if (slot.compare_exchange_weak(b, 0, std::memory_order_acq_rel, std::memory_order_acquire)) break;
      if (b == 0) return Status::IDLE;  // removed meanwhile
    }
    return result;
  }

  void serve() {
    last_request_ = std::chrono::steady_clock::now();
    while (active_.load()) {
      heartbeat();
      if constexpr (kBreakpoints) announce_breakpoint();
      if (!bound_) {
        rebind();
        if (!bound_) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      std::vector<zmq::message_t> parts;
      try {
        zmq::pollitem_t items[] = {{server_.handle(), 0, ZMQ_POLLIN, 0}, {publisher_.handle(), 0, ZMQ_POLLIN, 0}};
        zmq::poll(items, 2, std::chrono::milliseconds(kBreakpoints ? 10 : 100));  // then look at active_ again
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
        last_request_ = std::chrono::steady_clock::now();
        heartbeat();
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
      // Breakpoint builds publish BREAKPOINT_REACHED: a subscription to everything (the
      // empty topic, one per peer) is kept for it; every other one is still dropped.
      if (kBreakpoints && m.size() == 1 && *static_cast<const unsigned char*>(m.data()) == 1)
        publisher_.set(zmq::sockopt::subscribe, "");
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
      case K::kHooksDump: {
        collect_used_hooks();
        std::string json = "[";
        for (std::size_t i = 0; i < kSlots; ++i)  // (4.10.0: the PRE hooks, then the POST ones)
          if (hooks_[i].present) detail::dump_hook(json, hooks_[i].spec);
        json += "]";
        reply.push_back(std::move(json));
        break;
      }
      case K::kHookInsert:
      case K::kHookRemove:
      case K::kBreakpointUnlock: {
        const std::string_view failed = hook_request(request);
        if (!failed.empty()) return error(failed);
        break;
      }
      case K::kRemoveAllHooks:
        for (std::size_t i = 0; i < kSlots; ++i) remove_hook(i);
        break;
      case K::kDisableAllHooks: enable_all_hooks(false); break;
      default: break;
    }
    send(reply);
  }

  // ---------------------------------------------------------------- hooks
  // Server thread only: the hooks (4.6.2 keeps one pre-tick hook per node), and the byte
  // last stored for each, to see the `once` hooks the tick thread used up.
  struct HookEntry {
    bool present = false;
    detail::HookSpec spec;
  };

  static std::uint8_t byte_of(const HookEntry& h) noexcept {
    if (!h.present || !h.spec.enabled) return 0;
    return static_cast<std::uint8_t>(kHookSet | (h.spec.once ? kHookOnce : 0) | (h.spec.breakpoint ? kHookBreak : 0) |
                                     static_cast<std::uint8_t>(h.spec.desired));
  }
  // A new hook (or none) replaces whatever the byte holds.
  void publish_hook(std::size_t i) noexcept {
    armed_[i] = byte_of(hooks_[i]);
    hook_bytes_[i].store(armed_[i], std::memory_order_release);
  }
  // A change to a hook the tick thread may be using up: unless it took it meanwhile (a
  // `once` hook), which then stays gone.
  void republish_hook(std::size_t i) noexcept {
    std::uint8_t expected = armed_[i];
    const std::uint8_t want = byte_of(hooks_[i]);
    if (hook_bytes_[i].compare_exchange_strong(expected, want, std::memory_order_acq_rel)) {
      armed_[i] = want;
    } else {  // (only the tick thread writes it besides: it took the hook)
      hooks_[i] = HookEntry{};
      armed_[i] = 0;
    }
  }
  // A `once` hook whose byte the tick thread took is gone (4.6.2 erases it after its use).
  void collect_used_hooks() noexcept {
    for (std::size_t i = 0; i < kSlots; ++i) {
      if ((armed_[i] & kHookOnce) != 0 && hook_bytes_[i].load(std::memory_order_acquire) == 0) {
        hooks_[i] = HookEntry{};
        armed_[i] = 0;
      }
    }
  }
  void remove_hook(std::size_t i) noexcept {
    hooks_[i] = HookEntry{};
    publish_hook(i);  // a breakpoint waiting there goes on: its node is ticked
  }
  void enable_all_hooks(bool enable) noexcept {
    collect_used_hooks();
    for (std::size_t i = 0; i < kSlots; ++i) {
      if (!hooks_[i].present) continue;
      hooks_[i].spec.enabled = enable;
      republish_hook(i);
    }
  }
  // The slot of a hook on node `i` at `position` (0 PRE, 1 POST): 4.6.2 has PRE ones only.
  static std::size_t slot_of(std::size_t i, std::uint8_t position) noexcept {
    return kPostHooks && position == 1 ? kNodes + i : i;
  }
  // The node of a UID, or kNodes.
  static std::size_t node_of(std::uint16_t uid) noexcept {
    for (std::size_t i = 0; i < kNodes; ++i)
      if (Mission::node(i).uid == uid) return i;
    return kNodes;
  }

  // HOOK_INSERT, HOOK_REMOVE, BREAKPOINT_UNLOCK: an error message, or empty when done.
  std::string_view hook_request(const detail::Request& request) {
    using K = detail::Request::Kind;
    if (!hooks_attached_)
      return MonitorObserver<>::kHooks ? "btgen: another monitor of this mission forces statuses already"
                                       : "btgen: this build has no hooks (BTGEN_NO_GROOT2_HOOKS)";
    collect_used_hooks();
    std::string_view failed;
    if (request.kind == K::kHookInsert) {
      std::vector<detail::HookSpec> specs;
      const bool parsed = detail::parse_hooks(request.argument, specs, failed);
      if (!parsed && !kInsertUntilError) return failed;
      std::size_t good = 0;  // all of them, or none (4.10.0: those before the first bad one)
      for (const detail::HookSpec& h : specs) {
        if (h.breakpoint && !kBreakpoints) {
          failed =
              "btgen: breakpoints need a build with BTGEN_GROOT2_BREAKPOINTS (REPLACE hooks work in every "
              "build)";
          break;
        }
        if (node_of(h.uid) == kNodes) {
          failed = "Node ID not found";
          break;
        }
        ++good;
      }
      if (good < specs.size() && !kInsertUntilError) return failed;
      for (std::size_t k = 0; k < good; ++k) insert_hook(slot_of(node_of(specs[k].uid), specs[k].position), specs[k]);
      return failed;
    }
    detail::HookSpec ref;
    if (!detail::parse_hook_ref(request.argument, request.kind == K::kBreakpointUnlock, ref, failed)) return failed;
    const std::size_t node = node_of(ref.uid);
    // (4.6.2 files every hook as a PRE hook and looks POST ones up in a table it never fills)
    if (node == kNodes || (!kPostHooks && ref.position != 0)) return "Node ID not found";
    const std::size_t i = slot_of(node, ref.position);
    if (!hooks_[i].present) return "Node ID not found";
    if (request.kind == K::kHookRemove) {
      remove_hook(i);
      return {};
    }
    // BREAKPOINT_UNLOCK: the hook's desired status, `once` if asked, and a waiting
    // breakpoint released with them (4.6.2's unlockBreakpoint; a REPLACE hook only
    // changes).
    HookEntry& h = hooks_[i];
    h.spec.desired = ref.desired;
    h.spec.once = h.spec.once || ref.once;
    const bool breakpoint = h.spec.breakpoint;
    republish_hook(i);
    if (!hooks_[i].present) return "Node ID not found";  // used up meanwhile
    if (breakpoint) release(i, ref.desired);
    return {};
  }

  void insert_hook(std::size_t i, const detail::HookSpec& spec) noexcept {
    HookEntry& h = hooks_[i];
    const bool was_breakpoint = h.present && h.spec.breakpoint;
    if (!h.present) release_[i].store(0, std::memory_order_relaxed);  // a new hook: not unlocked yet
    h.present = true;
    h.spec = spec;
    // A breakpoint made REPLACE is released with the new desired status (4.6.2 sets `ready`).
    if (was_breakpoint && !spec.breakpoint) release(i, spec.desired);
    publish_hook(i);
  }
  void release(std::size_t i, Status desired) noexcept {
    release_[i].store(static_cast<std::uint8_t>(kReleased | static_cast<std::uint8_t>(desired)),
                      std::memory_order_release);
  }

  // Every hook disabled when no request came for the heartbeat delay, enabled again at the
  // next one (4.6.2's heartbeatLoop).
  void heartbeat() noexcept {
    const bool alive = std::chrono::steady_clock::now() - last_request_ <
                       std::chrono::milliseconds(heartbeat_ms_.load(std::memory_order_relaxed));
    if (alive != has_heartbeat_) {
      has_heartbeat_ = alive;
      enable_all_hooks(alive);
    }
  }

  // Tick thread, breakpoint builds: the node waits here until the server releases it
  // (BREAKPOINT_UNLOCK, or the breakpoint made REPLACE) or the hook is no longer a
  // breakpoint (disabled, removed: the node is ticked). Meanwhile the server answers
  // requests, and BLACKBOARD requests get fresh copies from here.
  Status wait_at_breakpoint(std::size_t i) noexcept {  // i: the hook's slot
    paused_.store(static_cast<std::uint32_t>(i % kNodes + 1), std::memory_order_release);
    pauses_.fetch_add(1, std::memory_order_acq_rel);
    Status result = Status::IDLE;
    for (;;) {
      std::uint8_t r = release_[i].exchange(0, std::memory_order_acq_rel);
      if ((r & kReleased) != 0) {
        result = static_cast<Status>(r & kHookStatus);
        break;
      }
      if ((hook_bytes_[i].load(std::memory_order_acquire) & kHookBreak) == 0) {
        r = release_[i].exchange(0, std::memory_order_acq_rel);  // (released as it changed)
        if ((r & kReleased) != 0) result = static_cast<Status>(r & kHookStatus);
        break;
      }
      if (bb_wanted_.load(std::memory_order_acquire)) sync();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    paused_.store(0, std::memory_order_release);
    return result;
  }
  // Server thread: BREAKPOINT_REACHED on the PUB port, once per pause (header, UID).
  void announce_breakpoint() {
    const std::uint32_t count = pauses_.load(std::memory_order_acquire);
    const std::uint32_t node = paused_.load(std::memory_order_acquire);
    if (node == 0 || count == announced_) return;
    announced_ = count;
    const std::uint32_t id = static_cast<std::uint32_t>(std::random_device{}());
    std::string header(6, '\0');
    header[0] = static_cast<char>(kProtocolId);
    header[1] = static_cast<char>(kBreakpointReached);
    std::memcpy(header.data() + 2, &id, 4);
    const std::string uid = std::to_string(Mission::node(node - 1).uid);
    try {
      publisher_.send(zmq::buffer(header), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
      publisher_.send(zmq::buffer(uid), zmq::send_flags::dontwait);
    } catch (const zmq::error_t&) {
    }
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
    for (const auto& entry : wanted) {
      // (a structured binding cannot be captured by a lambda in C++17: clang refuses it)
      const std::size_t b = entry.second;
      mp.str(entry.first);
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
  std::array<std::atomic<std::uint8_t>, kSlots> hook_bytes_{};  // the tick thread reads them
  std::array<std::atomic<std::uint8_t>, kSlots> release_{};     // breakpoints released
  // Server thread only, on the heap (some 11 bytes a node: a large mission's publisher may
  // live on a stack).
  std::vector<HookEntry> hooks_ = std::vector<HookEntry>(kSlots);
  std::vector<std::uint8_t> armed_ = std::vector<std::uint8_t>(kSlots);
  bool hooks_attached_ = false;
  std::atomic<std::int64_t> heartbeat_ms_{kMaxHeartbeatDelay.count()};
  std::chrono::steady_clock::time_point last_request_{};  // server thread only
  bool has_heartbeat_ = true;                             // server thread only
  std::atomic<std::uint32_t> paused_{0};                  // breakpoint builds: the paused node + 1, or 0
  std::atomic<std::uint32_t> pauses_{0};
  std::uint32_t announced_ = 0;  // server thread only
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
