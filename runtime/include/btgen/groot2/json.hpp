// btgen runtime: the JSON of Groot2's hook requests (HOOK_INSERT, HOOK_REMOVE,
// BREAKPOINT_UNLOCK) read with a bounded reader, and the hooks written back as
// BehaviorTree.CPP 4.6.2's HOOKS_DUMP writes them.
#pragma once

#include <cctype>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "btgen/groot2/protocol.hpp"
#include "btgen/status.hpp"

namespace btgen::groot2::detail {

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

}  // namespace btgen::groot2::detail
