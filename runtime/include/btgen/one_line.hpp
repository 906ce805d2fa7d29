// btgen runtime: diagnostics on one line.
//
// The interpreter escapes the control characters of every diagnostic
// (btgen/diagnostics.py one_line); the C++ side prints run-time errors
// (trace.hpp) and scenario diagnostics (scenario.hpp) the same way.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string_view>

namespace btgen {

// A diagnostic's text on one line, as the interpreter's diagnostics have it
// (btgen/diagnostics.py one_line): newline and carriage return become `\n`
// and `\r`, U+2028 and U+2029 `\u2028` and `\u2029`, the other control
// characters (C0 but tab, DEL, C1) `\xHH`; the rest, UTF-8 included, stays as
// it is. A message that quotes a node name or a string with a line break stays
// one `path:line:col: error:` line. `put` gets the text in pieces
// (std::string_view).
//
// A text longer than kMaxDiagnosticBytes (a scenario line of megabytes quoted
// whole) keeps its first bytes up to a character boundary and ends in
// `... (cut: N bytes in all)`, as the interpreter's.
inline constexpr std::size_t kMaxDiagnosticBytes = 4096;

template <class Put>
void one_line(std::string_view text, Put&& put) noexcept(noexcept(put(std::string_view()))) {
  static constexpr char kHex[] = "0123456789abcdef";
  const std::size_t whole = text.size();
  if (whole > kMaxDiagnosticBytes) {
    std::size_t cut = kMaxDiagnosticBytes;
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xc0u) == 0x80u) --cut;
    text = text.substr(0, cut);
  }
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
  if (whole > n) {
    char digits[24];
    std::size_t k = sizeof digits;
    std::size_t v = whole;
    do {
      digits[--k] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    put(std::string_view("... (cut: "));
    put(std::string_view(digits + k, sizeof digits - k));
    put(std::string_view(" bytes in all)"));
  }
}

// Writes one_line(text) to `f`.
inline void write_one_line(std::FILE* f, std::string_view text) noexcept {
  one_line(text, [f](std::string_view part) { std::fwrite(part.data(), 1, part.size(), f); });
}

}  // namespace btgen
