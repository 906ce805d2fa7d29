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

// ------------------------------------------------------------------ hooks' JSON
// A JSON reader for the hook requests (what nlohmann::json::parse accepts there), bounded:
// at most kMaxJsonDepth levels, numbers of at most 18 digits; any other input is an error
// with a message, never an exception or a read past the text.
inline constexpr int kMaxJsonDepth = 8;

struct JsonValue {
  enum class Type : std::uint8_t { kNull, kBool, kInt, kReal, kString, kObject, kArray };
  Type type = Type::kNull;
  bool boolean = false;
  std::int64_t integer = 0;
  std::string text;
  std::vector<std::string> keys;  // kObject: keys[i] names items[i]
  std::vector<JsonValue> items;   // kObject, kArray

  [[nodiscard]] const JsonValue* at(std::string_view key) const noexcept {
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (keys[i] == key) return &items[i];
    return nullptr;
  }
};

class JsonReader {
 public:
  explicit JsonReader(std::string_view text) noexcept : s_(text) {}
  // False (and error()) when the text is not one JSON value.
  bool read(JsonValue& out) {
    if (!value(out, 0)) return false;
    space();
    if (i_ != s_.size()) return fail("hook JSON: text after the value");
    return true;
  }
  [[nodiscard]] std::string_view error() const noexcept { return error_; }

 private:
  bool fail(std::string_view message) noexcept {
    error_ = message;
    return false;
  }
  void space() noexcept {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  bool word(std::string_view w) noexcept {
    if (s_.substr(i_, w.size()) != w) return fail("hook JSON: not a JSON value");
    i_ += w.size();
    return true;
  }
  bool value(JsonValue& v, int depth) {
    if (depth >= kMaxJsonDepth) return fail("hook JSON: nested too deep");
    space();
    if (i_ >= s_.size()) return fail("hook JSON: the text ends before a value");
    const char c = s_[i_];
    if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      v.type = c == '{' ? JsonValue::Type::kObject : JsonValue::Type::kArray;
      ++i_;
      space();
      if (i_ < s_.size() && s_[i_] == close) {
        ++i_;
        return true;
      }
      for (;;) {
        if (v.type == JsonValue::Type::kObject) {
          space();
          if (i_ >= s_.size() || s_[i_] != '"') return fail("hook JSON: an object key must be a string");
          std::string key;
          if (!string(key)) return false;
          space();
          if (i_ >= s_.size() || s_[i_] != ':') return fail("hook JSON: `:` expected after a key");
          ++i_;
          v.keys.push_back(std::move(key));
        }
        v.items.emplace_back();
        if (!value(v.items.back(), depth + 1)) return false;
        space();
        if (i_ < s_.size() && s_[i_] == ',') {
          ++i_;
          continue;
        }
        if (i_ < s_.size() && s_[i_] == close) {
          ++i_;
          return true;
        }
        return fail("hook JSON: `,` or the end of the object or array expected");
      }
    }
    if (c == '"') {
      v.type = JsonValue::Type::kString;
      return string(v.text);
    }
    if (c == 't') {
      v.type = JsonValue::Type::kBool;
      v.boolean = true;
      return word("true");
    }
    if (c == 'f') {
      v.type = JsonValue::Type::kBool;
      return word("false");
    }
    if (c == 'n') return word("null");
    return number(v);
  }
  bool number(JsonValue& v) noexcept {
    const std::size_t start = i_;
    bool negative = false;
    if (s_[i_] == '-') {
      negative = true;
      ++i_;
    }
    std::size_t digits = 0;
    std::int64_t n = 0;
    while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') {
      if (++digits > 18) return fail("hook JSON: a number too long");
      n = n * 10 + (s_[i_] - '0');
      ++i_;
    }
    if (digits == 0) return fail("hook JSON: not a JSON value");
    if (digits > 1 && s_[start + (negative ? 1 : 0)] == '0') return fail("hook JSON: a number with a leading zero");
    v.type = JsonValue::Type::kInt;
    v.integer = negative ? -n : n;
    if (i_ < s_.size() && s_[i_] == '.') {
      ++i_;
      std::size_t frac = 0;
      while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_, ++frac;
      if (frac == 0) return fail("hook JSON: a number without digits after `.`");
      v.type = JsonValue::Type::kReal;
    }
    if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      ++i_;
      if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) ++i_;
      std::size_t exp = 0;
      while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_, ++exp;
      if (exp == 0) return fail("hook JSON: a number without an exponent");
      v.type = JsonValue::Type::kReal;
    }
    return true;
  }
  // A string at s_[i_] == '"'; escapes decoded (\u as `?`: only ASCII names matter here).
  bool string(std::string& out) {
    ++i_;
    while (i_ < s_.size()) {
      const char c = s_[i_++];
      if (c == '"') return true;
      if (static_cast<unsigned char>(c) < 0x20) return fail("hook JSON: a control character in a string");
      if (c != '\\') {
        out.push_back(c);
        continue;
      }
      if (i_ >= s_.size()) break;
      const char e = s_[i_++];
      switch (e) {
        case '"':
        case '\\':
        case '/': out.push_back(e); break;
        case 'b': out.push_back('\b'); break;
        case 'f': out.push_back('\f'); break;
        case 'n': out.push_back('\n'); break;
        case 'r': out.push_back('\r'); break;
        case 't': out.push_back('\t'); break;
        case 'u':
          for (int k = 0; k < 4; ++k, ++i_) {
            if (i_ >= s_.size() || !std::isxdigit(static_cast<unsigned char>(s_[i_])))
              return fail("hook JSON: a bad \\u escape");
          }
          out.push_back('?');
          break;
        default: return fail("hook JSON: a bad escape");
      }
    }
    return fail("hook JSON: a string without its closing quote");
  }

  std::string_view s_;
  std::size_t i_ = 0;
  std::string_view error_;
};

// One hook as HOOK_INSERT gives it (groot2_protocol.h's Hook, from_json).
struct HookSpec {
  std::uint16_t uid = 0;
  std::uint8_t position = 0;  // 0 PRE, 1 POST
  bool enabled = true;
  bool once = false;        // remove_when_done
  bool breakpoint = false;  // mode 0 BREAKPOINT, 1 REPLACE
  Status desired = Status::SKIPPED;
};

// A status by its name (BT::convertFromString<NodeStatus>): false for any other word.
inline bool status_named(std::string_view name, Status& out) noexcept {
  for (const Status s : {Status::IDLE, Status::RUNNING, Status::SUCCESS, Status::FAILURE, Status::SKIPPED}) {
    if (to_string(s) == name) {
      out = s;
      return true;
    }
  }
  return false;
}

// The fields of a hook request; each a message when it is missing or of another type.
class HookFields {
 public:
  explicit HookFields(const JsonValue& v) noexcept : v_(v) {}
  std::string_view error;

  bool boolean(std::string_view key, bool& out) noexcept {
    const JsonValue* f = field(key);
    if (f == nullptr) return false;
    if (f->type != JsonValue::Type::kBool) return wrong(key);
    out = f->boolean;
    return true;
  }
  bool integer(std::string_view key, std::int64_t lo, std::int64_t hi, std::int64_t& out) noexcept {
    const JsonValue* f = field(key);
    if (f == nullptr) return false;
    if (f->type != JsonValue::Type::kInt || f->integer < lo || f->integer > hi) return wrong(key);
    out = f->integer;
    return true;
  }
  const std::string* text(std::string_view key) noexcept {
    const JsonValue* f = field(key);
    if (f == nullptr) return nullptr;
    if (f->type != JsonValue::Type::kString) {
      wrong(key);
      return nullptr;
    }
    return &f->text;
  }
  // uid (1..65535) and position (0 or 1), which every hook request has.
  bool where(std::uint16_t& uid, std::uint8_t& position) noexcept {
    std::int64_t u = 0, p = 0;
    if (!integer("uid", 0, 0xFFFF, u) || !integer("position", 0, 1, p)) return false;
    uid = static_cast<std::uint16_t>(u);
    position = static_cast<std::uint8_t>(p);
    return true;
  }

 private:
  const JsonValue* field(std::string_view key) noexcept {
    if (v_.type != JsonValue::Type::kObject) {
      error = "hook JSON: a hook must be an object";
      return nullptr;
    }
    const JsonValue* f = v_.at(key);
    if (f == nullptr) error = missing(key);
    return f;
  }
  bool wrong(std::string_view key) noexcept {
    error = key == "uid"              ? "hook JSON: `uid` must be a node UID (an integer from 0 to 65535)"
            : key == "position"       ? "hook JSON: `position` must be 0 (PRE) or 1 (POST)"
            : key == "mode"           ? "hook JSON: `mode` must be 0 (BREAKPOINT) or 1 (REPLACE)"
            : key == "desired_status" ? "hook JSON: `desired_status` must be IDLE, RUNNING, SUCCESS, FAILURE or SKIPPED"
                                      : "hook JSON: `enabled`, `once` and `remove_when_done` must be true or false";
    return false;
  }
  static std::string_view missing(std::string_view key) noexcept {
    if (key == "uid") return "hook JSON: `uid` is missing";
    if (key == "position") return "hook JSON: `position` is missing";
    if (key == "mode") return "hook JSON: `mode` is missing";
    if (key == "enabled") return "hook JSON: `enabled` is missing";
    if (key == "once") return "hook JSON: `once` is missing";
    if (key == "desired_status") return "hook JSON: `desired_status` is missing";
    return "hook JSON: `remove_when_done` is missing";
  }
  const JsonValue& v_;
};

// HOOK_INSERT's argument: one hook object or an array of them (4.6.2 takes both). False
// and `error` when one is not a hook; `out` then holds the hooks before it.
inline bool parse_hooks(std::string_view text, std::vector<HookSpec>& out, std::string_view& error) {
  JsonValue root;
  JsonReader reader(text);
  if (!reader.read(root)) {
    error = reader.error();
    return false;
  }
  const bool many = root.type == JsonValue::Type::kArray;
  const std::size_t n = many ? root.items.size() : 1;
  for (std::size_t k = 0; k < n; ++k) {
    HookFields f(many ? root.items[k] : root);
    HookSpec h;
    std::int64_t mode = 0;
    const std::string* desired = nullptr;
    if (!f.boolean("enabled", h.enabled) || !f.where(h.uid, h.position) || !f.boolean("once", h.once) ||
        !f.integer("mode", 0, 1, mode) || (desired = f.text("desired_status")) == nullptr) {
      error = f.error;
      return false;
    }
    if (!status_named(*desired, h.desired)) {
      error = "hook JSON: `desired_status` must be IDLE, RUNNING, SUCCESS, FAILURE or SKIPPED";
      return false;
    }
    h.breakpoint = mode == 0;
    out.push_back(h);
  }
  return true;
}

// HOOK_REMOVE's and BREAKPOINT_UNLOCK's argument (`unlock`: also desired_status, as 4.6.2
// reads it: SUCCESS, FAILURE, any other word SKIPPED; and remove_when_done).
inline bool parse_hook_ref(std::string_view text, bool unlock, HookSpec& out, std::string_view& error) {
  JsonValue root;
  JsonReader reader(text);
  if (!reader.read(root)) {
    error = reader.error();
    return false;
  }
  HookFields f(root);
  if (!f.where(out.uid, out.position)) {
    error = f.error;
    return false;
  }
  if (unlock) {
    const std::string* desired = f.text("desired_status");
    if (desired == nullptr || !f.boolean("remove_when_done", out.once)) {
      error = f.error;
      return false;
    }
    out.desired = *desired == "SUCCESS" ? Status::SUCCESS : *desired == "FAILURE" ? Status::FAILURE : Status::SKIPPED;
  }
  return true;
}

// HOOKS_DUMP: the hooks as nlohmann::json dumps them (keys in byte order, no spaces).
inline void dump_hook(std::string& out, const HookSpec& h) {
  out += out.size() > 1 ? ",{" : "{";
  out += "\"desired_status\":\"";
  out += to_string(h.desired);
  out += "\",\"enabled\":";
  out += h.enabled ? "true" : "false";
  out += ",\"mode\":";
  out += h.breakpoint ? "0" : "1";
  out += ",\"once\":";
  out += h.once ? "true" : "false";
  out += ",\"position\":";
  out += std::to_string(h.position);
  out += ",\"uid\":";
  out += std::to_string(h.uid);
  out += "}";
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
