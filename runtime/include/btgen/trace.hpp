// btgen runtime: status-change observers.
//
// A mission takes its observer as a template parameter. The default,
// NoObserver, has an empty inline hook, so an unobserved mission pays
// nothing. TraceWriter prints every change in the conformance trace format
// (shared/conformance/FORMAT.md):
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
#include "btgen/status.hpp"

namespace btgen {

// Observers may also have
//     void on_error(const btgen::RuntimeError& error);
// which the mission calls for every run-time error (the node failed).
struct NoObserver {
  constexpr void on_status_change(const NodeInfo&, Status, Status) const noexcept {}
};

// A diagnostic's text on one line, as the interpreter's diagnostics have it
// (btgen/diagnostics.py one_line): newline and carriage return become `\n`
// and `\r`, U+2028 and U+2029 `\u2028` and `\u2029`, the other control
// characters (C0 but tab, DEL, C1) `\xHH`; the rest, UTF-8 included, stays as
// it is. A message that quotes a node name or a string with a line break stays
// one `path:line:col: error:` line. `put` gets the text in pieces
// (std::string_view).
template <class Put>
void one_line(std::string_view text, Put&& put) noexcept(noexcept(put(std::string_view()))) {
  static constexpr char kHex[] = "0123456789abcdef";
  const auto* p = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  std::size_t plain = 0;  // start of the bytes not yet written
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned c = p[i];
    std::size_t len = 1;
    unsigned code = 0x100;
    std::string_view esc;
    if (c == '\n') {
      esc = "\\n";
    } else if (c == '\r') {
      esc = "\\r";
    } else if ((c < 0x20 && c != '\t') || c == 0x7f) {
      code = c;
    } else if (c == 0xc2 && i + 1 < n && p[i + 1] >= 0x80 && p[i + 1] <= 0x9f) {
      code = p[i + 1];  // U+0080..U+009F
      len = 2;
    } else if (c == 0xe2 && i + 2 < n && p[i + 1] == 0x80 && (p[i + 2] == 0xa8 || p[i + 2] == 0xa9)) {
      esc = p[i + 2] == 0xa8 ? "\\u2028" : "\\u2029";
      len = 3;
    } else {
      continue;
    }
    if (i > plain) put(text.substr(plain, i - plain));
    if (code != 0x100) {
      const char hex[4] = {'\\', 'x', kHex[code >> 4], kHex[code & 15]};
      put(std::string_view(hex, sizeof hex));
    } else {
      put(esc);
    }
    i += len - 1;
    plain = i + 1;
  }
  if (n > plain) put(text.substr(plain));
}

// Writes one_line(text) to `f`.
inline void write_one_line(std::FILE* f, std::string_view text) noexcept {
  one_line(text, [f](std::string_view part) { std::fwrite(part.data(), 1, part.size(), f); });
}

// Writes `name` with the trace format's escaping into `out` (capacity `cap`)
// and returns the number of bytes the escaped text needs (which may exceed
// `cap`; nothing is written past it). `"` and `\` become `\"` and `\\`;
// newline, carriage return and tab become `\n`, `\r`, `\t`; other control
// bytes (below 0x20, and 0x7f) become `\xHH`; everything else, UTF-8
// included, is copied as is.
inline std::size_t escape_name(std::string_view name, char* out, std::size_t cap) noexcept {
  static constexpr char kHex[] = "0123456789abcdef";
  std::size_t n = 0;
  auto put = [&](char c) {
    if (n < cap) out[n] = c;
    ++n;
  };
  for (const char ch : name) {
    const auto b = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"': put('\\'); put('"'); break;
      case '\\': put('\\'); put('\\'); break;
      case '\n': put('\\'); put('n'); break;
      case '\r': put('\\'); put('r'); break;
      case '\t': put('\\'); put('t'); break;
      default:
        if (b < 0x20 || b == 0x7f) {
          put('\\'); put('x'); put(kHex[b >> 4]); put(kHex[b & 0xF]);
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

  // A run-time error, on stderr: `path:line:col: error: message`.
  void on_error(const RuntimeError& e) const noexcept {
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
