// btgen runtime: conversions between blackboard values, as BehaviorTree.CPP 4.6.2 does them.
//
// The generator knows the type of every blackboard entry and port, so it
// calls the one conversion a read or write needs; these functions are
// those conversions, with 4.6.2's rules (btgen/lang/values.py is the reference
// and documents each one):
//
//   text of a number     std::to_string: integers in decimal, doubles as
//                        printf("%f") ("2.500000", "-nan")
//   convertFromString    int/unsigned: std::from_chars then a range check;
//                        double: std::stod; bool: 1 0 true false TRUE FALSE
//                        True False; NodeStatus: its name
//   Any::cast            integer <-> double only when exact, double -> bool
//                        when non-zero, integer -> bool only 0 and 1
//
// Nothing allocates; every fallible function returns an Errc.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string_view>
#include <system_error>

#include "btgen/status.hpp"

namespace btgen {

enum class Errc : std::uint8_t {
  kOk = 0,
  kInvalid,     // not a number / bool / status at all
  kOutOfRange,  // too large or small for the type
  kNotWhole,    // a double with a fraction (or nan, inf) where an integer is needed
  kPrecision,   // an integer a double cannot hold exactly
  kNotBool,     // an integer other than 0 and 1 read as bool
  kNotStatus,   // a number that is no NodeStatus
  kTooLong,     // a text longer than its fixed capacity
};

[[nodiscard]] constexpr std::string_view describe(Errc e) noexcept {
  switch (e) {
    case Errc::kOk: return "no error";
    case Errc::kInvalid: return "not a valid value of the type";
    case Errc::kOutOfRange: return "out of range for the type";
    case Errc::kNotWhole: return "not a whole number";
    case Errc::kPrecision: return "precision would be lost";
    case Errc::kNotBool: return "only the integers 0 and 1 convert to bool";
    case Errc::kNotStatus: return "not a status number (0 to 4)";
    case Errc::kTooLong: return "longer than the capacity btgen gave it";
  }
  return "error";
}

// ------------------------------------------------------------ number -> text

// Longest text of an int64 ("-9223372036854775808") and of a double with
// "%f" ("-" then 309 digits of -DBL_MAX, "." and 6 decimals).
inline constexpr std::size_t kIntTextMax = 20;
inline constexpr std::size_t kDoubleTextMax = 317;

#ifdef BTGEN_BARE_METAL
namespace value_detail {

// printf("%f", v) for a finite or infinite v, without printf: the exact binary value times
// 10^6, rounded to nearest with ties to even (as glibc rounds), in decimal with six
// decimals. Writes at most kDoubleTextMax bytes to `out` (capacity `cap` > that) and
// returns how many. Fixed storage: a double is m * 2^e with m < 2^53 and e <= 971, so
// m * 10^6 * 2^e needs fewer than 1,050 bits.
inline std::size_t format_fixed6(double v, char* out, std::size_t cap) noexcept {
  constexpr std::size_t kWords = 36;  // 1,152 bits
  std::uint64_t bits = 0;
  static_assert(sizeof bits == sizeof v, "IEEE-754 binary64 doubles");
  std::memcpy(&bits, &v, sizeof bits);
  std::size_t n = 0;
  auto put = [&](char c) {
    if (n + 1 < cap) out[n++] = c;
  };
  if ((bits >> 63) != 0) put('-');
  const int biased = static_cast<int>((bits >> 52) & 0x7FFu);
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1u);
  if (biased == 0x7FF) {  // inf (nan is handled by the caller)
    put('i');
    put('n');
    put('f');
    return n;
  }
  int e = biased == 0 ? -1074 : biased - 1075;
  if (biased != 0) m |= std::uint64_t{1} << 52;
  // x = m * 10^6, as 32-bit words, least significant first.
  std::uint32_t x[kWords] = {};
  std::uint64_t lo = (m & 0xFFFFFFFFu) * 1000000u;
  std::uint64_t hi = (m >> 32) * 1000000u + (lo >> 32);
  x[0] = static_cast<std::uint32_t>(lo);
  x[1] = static_cast<std::uint32_t>(hi);
  x[2] = static_cast<std::uint32_t>(hi >> 32);
  if (e > 0) {
    // Exact: shift left by e.
    const int words = e / 32, shift = e % 32;
    for (int i = static_cast<int>(kWords) - 1; i >= 0; --i) {
      const int from = i - words;
      std::uint32_t w = 0;
      if (from >= 0) {
        w = x[from] << shift;
        if (shift != 0 && from >= 1) w |= x[from - 1] >> (32 - shift);
      }
      x[i] = w;
    }
  } else if (e < 0) {
    // q = x >> -e, rounded to nearest, ties to even, on the bits shifted out (x < 2^96 here).
    constexpr int kBits = 96;
    const int s = -e;
    auto bit = [&x](int k) { return k >= 0 && k < kBits && ((x[k / 32] >> (k % 32)) & 1u) != 0; };
    const bool half = bit(s - 1);
    bool below = false;
    for (int k = 0; k < s - 1 && k < kBits && !below; ++k) below = bit(k);
    std::uint32_t q[3] = {};
    for (int k = s; k < kBits; ++k) {
      if (bit(k)) q[(k - s) / 32] |= 1u << ((k - s) % 32);
    }
    if (half && (below || (q[0] & 1u) != 0)) {
      for (std::uint32_t& w : q) {
        if (++w != 0) break;
      }
    }
    x[0] = q[0];
    x[1] = q[1];
    x[2] = q[2];
  }
  // Decimal digits of x, least significant first, nine at a time.
  char digits[kDoubleTextMax + 16];
  std::size_t nd = 0;
  for (;;) {
    bool zero = true;
    std::uint64_t rem = 0;
    for (int i = static_cast<int>(kWords) - 1; i >= 0; --i) {
      const std::uint64_t cur = (rem << 32) | x[i];
      x[i] = static_cast<std::uint32_t>(cur / 1000000000u);
      rem = cur % 1000000000u;
      zero = zero && x[i] == 0;
    }
    for (int k = 0; k < 9 && nd < sizeof digits; ++k) {
      digits[nd++] = static_cast<char>('0' + static_cast<int>(rem % 10u));
      rem /= 10u;
    }
    if (zero) break;
  }
  while (nd > 7 && digits[nd - 1] == '0') --nd;  // leading zeros, keeping "0.dddddd"
  for (std::size_t i = nd; i-- > 6;) put(digits[i]);
  put('.');
  for (std::size_t i = 6; i-- > 0;) put(digits[i]);
  return n;
}

}  // namespace value_detail
#endif

// The text of a number, held in place (valid while the object lives):
//     const btgen::NumberText text(2.5);   // text.view() == "2.500000"
class NumberText {
 public:
  NumberText() noexcept { buf_[0] = '\0'; }
  explicit NumberText(std::int64_t v) noexcept { set(v); }
  explicit NumberText(double v) noexcept { set(v); }
  explicit NumberText(bool v) noexcept { set(static_cast<std::int64_t>(v ? 1 : 0)); }
  explicit NumberText(Status v) noexcept { set(static_cast<std::int64_t>(v)); }
  NumberText(const NumberText&) = delete;
  NumberText& operator=(const NumberText&) = delete;

  [[nodiscard]] std::string_view view() const noexcept { return std::string_view(buf_, size_); }

  std::string_view set(std::int64_t v) noexcept {
    char tmp[kIntTextMax];
    std::size_t n = 0;
    // Work on the magnitude as unsigned so that INT64_MIN is fine.
    std::uint64_t m = v < 0 ? (~static_cast<std::uint64_t>(v) + 1u) : static_cast<std::uint64_t>(v);
    do {
      tmp[n++] = static_cast<char>('0' + static_cast<int>(m % 10u));
      m /= 10u;
    } while (m != 0);
    size_ = 0;
    if (v < 0) buf_[size_++] = '-';
    while (n > 0) buf_[size_++] = tmp[--n];
    buf_[size_] = '\0';
    return view();
  }

  std::string_view set(double v) noexcept {
    if (std::isnan(v)) {
      const char* s = std::signbit(v) ? "-nan" : "nan";
      size_ = 0;
      while (*s != '\0') buf_[size_++] = *s++;
      buf_[size_] = '\0';
      return view();
    }
#ifdef BTGEN_BARE_METAL
    // newlib-nano's printf has no %f (and newlib's allocates for it): the exact digits, computed here.
    size_ = value_detail::format_fixed6(v, buf_, sizeof buf_);
    buf_[size_] = '\0';
#else
    const int n = std::snprintf(buf_, sizeof buf_, "%f", v);
    size_ = n < 0 ? 0 : (static_cast<std::size_t>(n) < sizeof buf_ ? static_cast<std::size_t>(n) : sizeof buf_ - 1);
#endif
    return view();
  }

  std::string_view set(bool v) noexcept { return set(static_cast<std::int64_t>(v ? 1 : 0)); }
  std::string_view set(Status v) noexcept { return set(static_cast<std::int64_t>(v)); }

 private:
  char buf_[kDoubleTextMax + 1];
  std::size_t size_ = 0;
};

// ------------------------------------------------------------ text -> number

namespace value_detail {

constexpr bool is_digit(char c) noexcept { return c >= '0' && c <= '9'; }
constexpr bool is_hex(char c) noexcept { return is_digit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }
constexpr char lower(char c) noexcept { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// Case-insensitive "does `text` continue with `word` at `i`".
constexpr bool starts_ci(std::string_view text, std::size_t i, std::string_view word) noexcept {
  if (text.size() - i < word.size()) return false;
  for (std::size_t k = 0; k < word.size(); ++k) {
    if (lower(text[i + k]) != word[k]) return false;
  }
  return true;
}

// Digits [i, end) of `text`: any of them not '0' (decimal or hex digits).
constexpr bool any_nonzero(std::string_view text, std::size_t i, std::size_t end, bool hex) noexcept {
  for (; i < end; ++i) {
    const char c = text[i];
    if ((hex ? is_hex(c) : is_digit(c)) && c != '0') return true;
  }
  return false;
}

// What a scan found: [start, end) is the number's literal.
struct Scan {
  bool ok = false;
  bool special = false;  // inf or nan
  bool is_nan = false;
  bool negative = false;
  bool hex = false;
  std::size_t start = 0, end = 0;
  std::size_t mant_begin = 0, mant_end = 0;
};

// `inf`, `infinity`, `nan`, `nan(chars)` at `i` (after the sign).
constexpr bool scan_special(std::string_view t, std::size_t i, Scan& s) noexcept {
  if (starts_ci(t, i, "inf")) {
    s.end = i + 3;
    if (starts_ci(t, s.end, "inity")) s.end += 5;
    s.special = true;
    return true;
  }
  if (starts_ci(t, i, "nan")) {
    s.end = i + 3;
    if (s.end < t.size() && t[s.end] == '(') {
      std::size_t k = s.end + 1;
      while (k < t.size() && (is_digit(t[k]) || (lower(t[k]) >= 'a' && lower(t[k]) <= 'z') || t[k] == '_')) ++k;
      if (k < t.size() && t[k] == ')') s.end = k + 1;
    }
    s.special = true;
    s.is_nan = true;
    return true;
  }
  return false;
}

// A mantissa at `k`, digits by `digit`: [d]+\.?[d]*|\.[d]+. Its end, or `k` when there is none.
constexpr std::size_t scan_mantissa(std::string_view t, std::size_t k, bool (*digit)(char) noexcept) noexcept {
  if (k < t.size() && digit(t[k])) {
    while (k < t.size() && digit(t[k])) ++k;
    if (k < t.size() && t[k] == '.') {
      ++k;
      while (k < t.size() && digit(t[k])) ++k;
    }
    return k;
  }
  if (k + 1 < t.size() && t[k] == '.' && digit(t[k + 1])) {
    k += 1;
    while (k < t.size() && digit(t[k])) ++k;
  }
  return k;
}

// An exponent at `k`, marked by `lower` or `upper`: [mM][+-]?[0-9]+. Its end, or `k` when
// there is none.
constexpr std::size_t scan_exponent(std::string_view t, std::size_t k, char lower, char upper) noexcept {
  if (k < t.size() && (t[k] == lower || t[k] == upper)) {
    std::size_t e = k + 1;
    if (e < t.size() && (t[e] == '+' || t[e] == '-')) ++e;
    if (e < t.size() && is_digit(t[e])) {
      while (e < t.size() && is_digit(t[e])) ++e;
      return e;
    }
  }
  return k;
}

// Decimal mantissa and optional exponent at `i`: ([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?
constexpr bool scan_decimal(std::string_view t, std::size_t i, Scan& s) noexcept {
  const std::size_t k = scan_mantissa(t, i, is_digit);
  if (k == i) return false;
  s.mant_begin = i;
  s.mant_end = k;
  s.end = scan_exponent(t, k, 'e', 'E');
  return true;
}

// Hexadecimal: 0[xX]([0-9a-f]+\.?[0-9a-f]*|\.[0-9a-f]+)([pP][+-]?[0-9]+)?
constexpr bool scan_hex(std::string_view t, std::size_t i, Scan& s) noexcept {
  if (!(i + 1 < t.size() && t[i] == '0' && (t[i + 1] == 'x' || t[i + 1] == 'X'))) return false;
  const std::size_t mb = i + 2;
  const std::size_t k = scan_mantissa(t, mb, is_hex);
  if (k == mb) return false;
  s.mant_begin = mb;
  s.mant_end = k;
  s.end = scan_exponent(t, k, 'p', 'P');
  s.hex = true;
  return true;
}

#ifdef BTGEN_BARE_METAL
// A fixed-size unsigned integer (32-bit words, least significant first) for exact_strtod.
struct BigNum {
  static constexpr int kWords = 112;  // 3,584 bits: a 511-character literal scaled to 54 bits
  std::uint32_t w[kWords] = {};
  int n = 0;  // words in use

  bool is_zero() const noexcept { return n == 0; }
  void trim() noexcept {
    while (n > 0 && w[n - 1] == 0) --n;
  }
  void mul_add(std::uint32_t m, std::uint32_t a) noexcept {
    std::uint64_t carry = a;
    for (int i = 0; i < n; ++i) {
      const std::uint64_t v = static_cast<std::uint64_t>(w[i]) * m + carry;
      w[i] = static_cast<std::uint32_t>(v);
      carry = v >> 32;
    }
    if (carry != 0 && n < kWords) w[n++] = static_cast<std::uint32_t>(carry);
  }
  int bits() const noexcept {
    if (n == 0) return 0;
    int b = 32 * (n - 1);
    for (std::uint32_t top = w[n - 1]; top != 0; top >>= 1) ++b;
    return b;
  }
  void shl(int k) noexcept {
    if (n == 0 || k <= 0) return;
    const int words = k / 32, sh = k % 32;
    int m = n + words + 1;
    if (m > kWords) m = kWords;
    for (int i = m - 1; i >= 0; --i) {
      const int from = i - words;
      std::uint32_t v = 0;
      if (from >= 0 && from < n) v = w[from] << sh;
      if (sh != 0 && from - 1 >= 0 && from - 1 < n) v |= w[from - 1] >> (32 - sh);
      w[i] = v;
    }
    n = m;
    trim();
  }
  void shr1() noexcept {
    for (int i = 0; i < n; ++i) w[i] = (w[i] >> 1) | (i + 1 < n ? w[i + 1] << 31 : 0u);
    trim();
  }
  int compare(const BigNum& o) const noexcept {
    if (n != o.n) return n < o.n ? -1 : 1;
    for (int i = n - 1; i >= 0; --i) {
      if (w[i] != o.w[i]) return w[i] < o.w[i] ? -1 : 1;
    }
    return 0;
  }
  void sub(const BigNum& o) noexcept {  // *this >= o
    std::int64_t borrow = 0;
    for (int i = 0; i < n; ++i) {
      std::int64_t v = static_cast<std::int64_t>(w[i]) - (i < o.n ? o.w[i] : 0u) - borrow;
      borrow = v < 0 ? 1 : 0;
      w[i] = static_cast<std::uint32_t>(v + (borrow << 32));
    }
    trim();
  }
};

// strtod, correctly rounded (to nearest, ties to even), without allocating: the value of a
// literal the scan accepted (decimal with an optional exponent, 0x hexadecimal with an optional
// binary exponent, inf, infinity; an optional sign), at most 511 characters. The literal is an
// integer times 10^e (or 2^e); that integer scaled by a power of two and divided by the
// power of ten gives the 54 leading bits and whether anything is left.
inline double exact_strtod(std::string_view t) noexcept {
  std::size_t i = 0;
  bool negative = false;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) negative = t[i++] == '-';
  const double sign = negative ? -1.0 : 1.0;
  if (i < t.size() && (t[i] == 'i' || t[i] == 'I')) return sign * std::numeric_limits<double>::infinity();
  const bool hex = i + 1 < t.size() && t[i] == '0' && (t[i + 1] == 'x' || t[i + 1] == 'X');
  if (hex) i += 2;
  const std::uint32_t base = hex ? 16u : 10u;
  BigNum num;
  long exp = 0;  // value = num * base^exp (decimal) or num * 2^exp (hex)
  bool seen_point = false;
  bool any = false;
  for (; i < t.size(); ++i) {
    const char c = t[i];
    if (c == '.') {
      seen_point = true;
      continue;
    }
    std::uint32_t d = 0;
    if (is_digit(c)) {
      d = static_cast<std::uint32_t>(c - '0');
    } else if (hex && is_hex(c)) {
      d = static_cast<std::uint32_t>(lower(c) - 'a' + 10);
    } else {
      break;
    }
    if (d != 0) any = true;
    if (any) num.mul_add(base, d);
    if (seen_point) exp -= hex ? 4 : 1;
  }
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E' || t[i] == 'p' || t[i] == 'P')) {
    ++i;
    bool eneg = false;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) eneg = t[i++] == '-';
    long e = 0;
    for (; i < t.size() && is_digit(t[i]); ++i) e = e < 100000 ? e * 10 + (t[i] - '0') : e;
    exp += eneg ? -e : e;
  }
  num.trim();
  if (num.is_zero()) return sign * 0.0;
  // Bounds, before any big arithmetic: log2 of the value lies in (lo, hi].
  const double log2_base = hex ? 1.0 : 3.321928094887362;
  const double hi = num.bits() + (hex ? static_cast<double>(exp) : exp * log2_base) + 1.0;
  const double lo = num.bits() - 1.0 + (hex ? static_cast<double>(exp) : exp * log2_base) - 1.0;
  if (lo > 1025.0) return sign * std::numeric_limits<double>::infinity();
  if (hi < -1077.0) return sign * 0.0;
  BigNum den;
  den.w[0] = 1;
  den.n = 1;
  int bin = 0;  // value = num / den * 2^bin
  if (hex) {
    bin = static_cast<int>(exp);
  } else if (exp > 0) {
    for (long k = 0; k < exp; ++k) num.mul_add(10u, 0u);
  } else {
    for (long k = 0; k < -exp; ++k) den.mul_add(10u, 0u);
  }
  // q = floor(num * 2^k / den) with 54 bits (53 and a rounding bit); k at most 1075, where
  // the rounding bit is 2^-1075 (subnormals keep fewer bits).
  int k = 54 - (num.bits() - den.bits()) - bin;
  if (k > 1075) k = 1075;
  for (int attempt = 0; attempt < 4; ++attempt) {
    BigNum a = num, b = den;
    const int sh = k + bin;
    if (sh >= 0) {
      a.shl(sh);
    } else {
      b.shl(-sh);
    }
    // Long division, 55 quotient bits at most.
    BigNum d = b;
    d.shl(55);
    std::uint64_t q = 0;
    for (int bit = 55; bit >= 0; --bit) {
      if (a.compare(d) >= 0) {
        a.sub(d);
        q |= std::uint64_t{1} << bit;
      }
      d.shr1();
    }
    if (q >= (std::uint64_t{1} << 54)) {  // one bit too many: scale down once
      --k;
      continue;
    }
    if (q < (std::uint64_t{1} << 53) && k < 1075) {  // one too few
      ++k;
      continue;
    }
    std::uint64_t mant = q >> 1;
    if ((q & 1u) != 0 && (!a.is_zero() || (mant & 1u) != 0)) ++mant;
    return sign * std::ldexp(static_cast<double>(mant), -(k - 1));
  }
  return sign * 0.0;  // not reached: the estimate of k is off by at most one
}
#endif

// strtod of exactly the scanned literal (copied: strtod reads more forms
// than the scan allows, and the text need not be NUL-terminated).
inline Errc strtod_literal(std::string_view t, const Scan& s, double& out) noexcept {
  char buf[512];
  const std::size_t n = s.end - s.start;
  if (n >= sizeof buf) return Errc::kOutOfRange;  // more digits than any double needs
  for (std::size_t k = 0; k < n; ++k) buf[k] = t[s.start + k];
  buf[n] = '\0';
#ifdef BTGEN_BARE_METAL
  // newlib's strtod allocates for long inputs: the correctly rounded value, computed here.
  out = exact_strtod(std::string_view(buf, n));
#else
  out = std::strtod(buf, nullptr);
#endif
  return Errc::kOk;
}

}  // namespace value_detail

// std::from_chars into an integer type: an optional '-', then digits; the
// text after the digits is ignored. The value must lie in [lo, hi].
inline Errc parse_integer(std::string_view text, std::int64_t lo, std::int64_t hi, std::int64_t& out) noexcept {
  std::size_t i = 0;
  if (i < text.size() && text[i] == '-') ++i;
  if (i >= text.size() || !value_detail::is_digit(text[i])) return Errc::kInvalid;
  std::int64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec == std::errc::result_out_of_range) return Errc::kOutOfRange;
  if (r.ec != std::errc()) return Errc::kInvalid;
  if (v < lo || v > hi) return Errc::kOutOfRange;
  out = v;
  return Errc::kOk;
}

// std::from_chars into a double (what Any::cast uses for strings): no
// leading blanks or '+', no hex; inf, infinity, nan, nan(...) in any case;
// the text after the number is ignored. A value too large (inf) or too
// small (zero from non-zero digits) is out of range; the latter only with
// `check_underflow` (SwitchNode reads it as 0).
inline Errc parse_double_from_chars(std::string_view text, double& out, bool check_underflow = true,
                                    std::size_t* consumed = nullptr) noexcept {
  using namespace value_detail;
  Scan s;
  std::size_t i = 0;
  if (i < text.size() && text[i] == '-') {
    s.negative = true;
    ++i;
  }
  if (!scan_special(text, i, s) && !scan_decimal(text, i, s)) return Errc::kInvalid;
  s.start = 0;
  if (consumed != nullptr) *consumed = s.end;
  if (s.is_nan) {
    out = std::copysign(std::numeric_limits<double>::quiet_NaN(), s.negative ? -1.0 : 1.0);
    return Errc::kOk;
  }
  double v = 0.0;
  if (const Errc e = strtod_literal(text, s, v); e != Errc::kOk) return e;
  if (!s.special) {
    if (std::isinf(v)) return Errc::kOutOfRange;
    if (check_underflow && v == 0.0 && any_nonzero(text, s.mant_begin, s.mant_end, false)) return Errc::kOutOfRange;
  }
  out = v;
  return Errc::kOk;
}

// std::stod (convertFromString<double>): leading blanks, an optional sign,
// decimal or 0x hex digits, inf, nan; the text after the number is ignored.
// Out of range: inf from finite digits, zero from non-zero digits, and
// subnormal results (std::stod throws for them).
inline Errc parse_double_stod(std::string_view text, double& out) noexcept {
  using namespace value_detail;
  Scan s;
  std::size_t i = 0;
  while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\v' ||
                             text[i] == '\f' || text[i] == '\r')) {
    ++i;
  }
  s.start = i;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
    s.negative = text[i] == '-';
    ++i;
  }
  if (!scan_hex(text, i, s) && !scan_special(text, i, s) && !scan_decimal(text, i, s)) return Errc::kInvalid;
  if (s.is_nan) {
    out = std::copysign(std::numeric_limits<double>::quiet_NaN(), s.negative ? -1.0 : 1.0);
    return Errc::kOk;
  }
  double v = 0.0;
  if (const Errc e = strtod_literal(text, s, v); e != Errc::kOk) return e;
  if (!s.special) {
    const bool nonzero = any_nonzero(text, s.mant_begin, s.mant_end, s.hex);
    if (std::isinf(v) || (nonzero && v == 0.0) || (v != 0.0 && std::fabs(v) < std::numeric_limits<double>::min())) {
      return Errc::kOutOfRange;
    }
  }
  out = v;
  return Errc::kOk;
}

// convertFromString<bool>: exactly 1 0 true false TRUE FALSE True False.
inline Errc parse_bool(std::string_view text, bool& out) noexcept {
  if (text == "1" || text == "true" || text == "TRUE" || text == "True") {
    out = true;
    return Errc::kOk;
  }
  if (text == "0" || text == "false" || text == "FALSE" || text == "False") {
    out = false;
    return Errc::kOk;
  }
  return Errc::kInvalid;
}

// convertFromString<NodeStatus>: exactly IDLE RUNNING SUCCESS FAILURE SKIPPED.
inline Errc parse_status(std::string_view text, Status& out) noexcept {
  constexpr Status all[] = {Status::IDLE, Status::RUNNING, Status::SUCCESS, Status::FAILURE, Status::SKIPPED};
  for (const Status s : all) {
    if (to_string(s) == text) {
      out = s;
      return Errc::kOk;
    }
  }
  return Errc::kInvalid;
}

// ------------------------------------------------------------ number -> number

// An integer as a double, only when the double holds it exactly.
inline Errc int_to_double(std::int64_t v, double& out) noexcept {
  const double d = static_cast<double>(v);
  if (d >= 9223372036854775808.0 || static_cast<std::int64_t>(d) != v) return Errc::kPrecision;
  out = d;
  return Errc::kOk;
}

// A double as an int64: only whole numbers in range.
inline Errc double_to_int(double v, std::int64_t& out) noexcept {
  if (std::isnan(v) || std::isinf(v) || v != std::floor(v)) return Errc::kNotWhole;
  if (!(v >= -9223372036854775808.0 && v < 9223372036854775808.0)) return Errc::kOutOfRange;
  out = static_cast<std::int64_t>(v);
  return Errc::kOk;
}

// An integer into [lo, hi] (the C++ type of a port: int, unsigned).
[[nodiscard]] constexpr Errc int_in_range(std::int64_t v, std::int64_t lo, std::int64_t hi) noexcept {
  return (v < lo || v > hi) ? Errc::kOutOfRange : Errc::kOk;
}

// A double into [lo, hi] as an integer (negative values never fit unsigned).
inline Errc double_to_int_in(double v, std::int64_t lo, std::int64_t hi, std::int64_t& out) noexcept {
  if (lo == 0 && v < 0) return Errc::kOutOfRange;
  if (std::isnan(v) || std::isinf(v) || v != std::floor(v)) return Errc::kNotWhole;
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi))) return Errc::kOutOfRange;
  out = static_cast<std::int64_t>(v);
  return Errc::kOk;
}

// An integer read as bool: only 0 and 1.
inline Errc int_to_bool(std::int64_t v, bool& out) noexcept {
  if (v != 0 && v != 1) return Errc::kNotBool;
  out = v == 1;
  return Errc::kOk;
}

// An integer read as a NodeStatus: 0 to 4.
inline Errc int_to_status(std::int64_t v, Status& out) noexcept {
  if (v < 0 || v > 4) return Errc::kNotStatus;
  out = static_cast<Status>(v);
  return Errc::kOk;
}

}  // namespace btgen

namespace btgen {

// SwitchNode's CheckStringEquality: equal as text, or as integers (an
// optional '-' and digits, in int range), or as reals (std::from_chars)
// within FLT_EPSILON. 4.6.2 reads the number at the start of the text and
// ignores the rest; from 4.10.0 (`whole`, Semantics::switch_whole_parse) the
// number must be the whole text.
inline bool switch_equal(std::string_view a, std::string_view b, bool whole = false) noexcept {
  if (a == b) return true;
  const auto integer = [whole](std::string_view t, std::int64_t& v) noexcept {
    if (parse_integer(t, INT32_MIN, INT32_MAX, v) != Errc::kOk) return false;
    if (!whole) return true;
    std::size_t i = (!t.empty() && t[0] == '-') ? 1 : 0;
    while (i < t.size() && value_detail::is_digit(t[i])) ++i;
    return i == t.size();
  };
  const auto real = [whole](std::string_view t, double& v) noexcept {
    std::size_t end = 0;
    return parse_double_from_chars(t, v, false, &end) == Errc::kOk && (!whole || end == t.size());
  };
  std::int64_t ia = 0, ib = 0;
  if (integer(a, ia) && integer(b, ib) && ia == ib) return true;
  double ra = 0.0, rb = 0.0;
  return real(a, ra) && real(b, rb) && std::fabs(ra - rb) <= 1.1920928955078125e-07;
}

}  // namespace btgen
