// btgen runtime: status-change observers.
//
// A mission takes its observer as a template parameter. The default,
// NoObserver, has an empty inline hook, so an unobserved mission pays
// nothing. TraceWriter prints every change in the conformance trace format
// (tests/conformance/FORMAT.md):
//
//     <uid> <ID> "<name>" <FROM> -> <TO>
//
// An observer is any type with
//     void on_status_change(const btgen::NodeInfo& node, btgen::Status from, btgen::Status to);
#pragma once

#include <cstddef>
#include <cstdio>
#include <string_view>

#include "btgen/blackboard.hpp"
#include "btgen/node.hpp"
#include "btgen/one_line.hpp"
#include "btgen/status.hpp"

namespace btgen {

// Observers may also have
//     void on_error(const btgen::RuntimeError& error);
// which the mission calls for every run-time error (the node failed).
struct NoObserver {
  constexpr void on_status_change(const NodeInfo&, Status, Status) const noexcept {}
};

// Writes `name` with the trace format's escaping into `out` (capacity `cap`)
// and returns the number of bytes the escaped text needs (which may exceed
// `cap`; nothing is written past it). `"` and `\` become `\"` and `\\`;
// newline, carriage return and tab become `\n`, `\r`, `\t`; other control
// bytes (below 0x20, and 0x7f) become `\xHH`, upper-case digits as the library's
// recordings show (`\x7F`); everything else, UTF-8 included, is copied as is.
inline std::size_t escape_name(std::string_view name, char* out, std::size_t cap) noexcept {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::size_t n = 0;
  auto put = [&](char c) {
    if (n < cap) out[n] = c;
    ++n;
  };
  for (const char ch : name) {
    const auto b = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"':
        put('\\');
        put('"');
        break;
      case '\\':
        put('\\');
        put('\\');
        break;
      case '\n':
        put('\\');
        put('n');
        break;
      case '\r':
        put('\\');
        put('r');
        break;
      case '\t':
        put('\\');
        put('t');
        break;
      default:
        if (b < 0x20 || b == 0x7f) {
          put('\\');
          put('x');
          put(kHex[b >> 4]);
          put(kHex[b & 0xF]);
        } else {
          put(ch);
        }
    }
  }
  return n;
}

// Prints each status change as one trace line to a stdio stream.
class TraceWriter {
 public:
  constexpr explicit TraceWriter(std::FILE* out) noexcept : out_(out) {}

  void on_status_change(const NodeInfo& node, Status from, Status to) const noexcept {
    std::fprintf(out_, "%u ", static_cast<unsigned>(node.uid));
    write(node.id);
    std::fputs(" \"", out_);
    char buf[256];
    std::string_view rest = node.name;
    // Escape in chunks so that long names need no allocation.
    while (!rest.empty()) {
      std::size_t take = rest.size() < 64 ? rest.size() : 64;
      const std::size_t len = escape_name(rest.substr(0, take), buf, sizeof buf);
      std::fwrite(buf, 1, len, out_);
      rest.remove_prefix(take);
    }
    std::fputs("\" ", out_);
    write(to_string(from));
    std::fputs(" -> ", out_);
    write(to_string(to));
    std::fputc('\n', out_);
  }

  // A run-time error, on stderr: `path:line:col: error: message` (after what the library
  // prints on stdout before it throws, RuntimeError::printed).
  void on_error(const RuntimeError& e) const noexcept {
    if (!e.printed.empty()) write(e.printed);  // (an empty view's data() may be null)
    std::fflush(out_);
    std::fprintf(stderr, "%.*s: error: ", static_cast<int>(e.where.size()), e.where.data());
    write_one_line(stderr, e.message);
    if (!e.detail.empty()) {
      std::fputs(": ", stderr);
      write_one_line(stderr, e.detail);
    }
    std::fputc('\n', stderr);
  }

  [[nodiscard]] std::FILE* stream() const noexcept { return out_; }

 private:
  void write(std::string_view s) const noexcept { std::fwrite(s.data(), 1, s.size(), out_); }

  std::FILE* out_;
};

}  // namespace btgen
