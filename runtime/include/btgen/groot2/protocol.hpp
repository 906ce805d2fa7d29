// btgen runtime: BehaviorTree.CPP's Groot2 protocol 2 (groot2_protocol.h), without sockets:
// the protocol id, the request types, the bounds on what one client may send, the bytes a
// hook leaves for the tick thread, and a request decided from its frames alone. The
// publisher (btgen/groot2.hpp) answers requests over ZeroMQ; tests/fuzz runs parse_request
// on any bytes.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string_view>

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

// How long the server waits for a request before it disables every hook (4.6.2's
// Groot2Publisher: Groot2 asks for STATUS many times a second; a client that went away
// leaves no fault forced and no tick thread paused). Publisher::set_max_heartbeat_delay.
inline constexpr std::chrono::milliseconds kMaxHeartbeatDelay{5000};

// The byte a hook leaves in the table the tick thread reads (one per node): 0 none or
// disabled; else kHookSet, kHookOnce (removed at its first use), kHookBreak (a breakpoint:
// BTGEN_GROOT2_BREAKPOINTS builds only), and the desired status in the low three bits.
inline constexpr std::uint8_t kHookSet = 0x80;
inline constexpr std::uint8_t kHookOnce = 0x40;
inline constexpr std::uint8_t kHookBreak = 0x20;
inline constexpr std::uint8_t kHookStatus = 0x07;
// A breakpoint's release (its own byte per node): kReleased and the status to return.
inline constexpr std::uint8_t kReleased = 0x80;

#ifdef BTGEN_GROOT2_BREAKPOINTS
inline constexpr bool kBreakpoints = true;
#else
inline constexpr bool kBreakpoints = false;
#endif

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

namespace detail {

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
    kHookInsert,        // argument: a hook's JSON, or an array of them
    kHookRemove,        // argument: {"uid", "position"}
    kBreakpointUnlock,  // argument: {"uid", "position", "desired_status", "remove_when_done"}
    kRemoveAllHooks,
    kDisableAllHooks,
  };
  Kind kind = Kind::kError;
  std::string_view error;
  std::string_view argument;
};

inline Request parse_request(const std::string_view* parts, std::size_t n) noexcept {
  using K = Request::Kind;
  const auto fail = [](std::string_view message) { return Request{K::kError, message, {}}; };
  const auto two_parts = [&](K kind) { return n != 2 ? fail("must be 2 parts message") : Request{kind, {}, parts[1]}; };
  if (n == 0 || parts[0].size() != 6) return fail("wrong request header");
  const auto* h = reinterpret_cast<const unsigned char*>(parts[0].data());
  if (h[0] != kProtocolId) return fail("wrong protocol: btgen speaks Groot2 protocol 2");
  switch (h[1]) {
    case kFullTree: return {K::kFullTree, {}, {}};
    case kStatus: return {K::kStatus, {}, {}};
    case kBlackboard: return two_parts(K::kBlackboard);
    case kToggleRecording:
      if (n != 2) return fail("must be 2 parts message");
      if (parts[1] == "start") return {K::kRecordStart, {}, {}};
      if (parts[1] == "stop") return {K::kRecordStop, {}, {}};
      return {K::kRecordOther, {}, {}};
    case kGetTransitions: return {K::kTransitions, {}, {}};
    case kHooksDump: return {K::kHooksDump, {}, {}};
    case kRemoveAllHooks: return {K::kRemoveAllHooks, {}, {}};
    case kDisableAllHooks: return {K::kDisableAllHooks, {}, {}};
    case kHookInsert: return two_parts(K::kHookInsert);
    case kHookRemove: return two_parts(K::kHookRemove);
    case kBreakpointUnlock: return two_parts(K::kBreakpointUnlock);
    default: return fail("Request not recognized");
  }
}

}  // namespace detail
}  // namespace btgen::groot2
