// btgen runtime: the operations compiled scripts are made of.
//
// The generator turns every script of a mission (Script, ScriptCondition,
// Precondition `if`, `_skipIf`, `_while`, `_onSuccess`, ...) into C++ with
// the types of its operands known; what is left for run time is here, with
// BehaviorTree.CPP 4.6.2's meaning (btgen/lang/script.py is the reference):
// arithmetic, comparison and logic work on doubles; `==` and `!=` compare
// within FLT_EPSILON; a string compared with a number is read as a number.
// There is no parser and no interpreter here, and nothing allocates.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <type_traits>

#include "btgen/status.hpp"
#include "btgen/value.hpp"

namespace btgen::script {

inline constexpr double kFltEpsilon = 1.1920928955078125e-07;

// An operand as a double (4.6.2 converts every number to double first).
inline Errc num(std::int64_t v, double& out) noexcept { return int_to_double(v, out); }
inline Errc num(double v, double& out) noexcept {
  out = v;
  return Errc::kOk;
}
inline Errc num(bool v, double& out) noexcept {
  out = v ? 1.0 : 0.0;
  return Errc::kOk;
}
inline Errc num(Status v, double& out) noexcept {
  out = static_cast<double>(static_cast<int>(v));
  return Errc::kOk;
}

// An operand as a double as the mission's release converts it: from 4.7.0
// (Semantics::int_to_double_53_bits) an integer beyond 2^53-1 fails, exact or not.
template <bool k53, class T>
inline Errc num_v(T v, double& out) noexcept {
  if constexpr (k53 && std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    constexpr std::int64_t kMaxExact = (std::int64_t{1} << 53) - 1;
    const auto w = static_cast<std::int64_t>(v);
    if (w > kMaxExact || w < -kMaxExact) return Errc::kPrecision;
  }
  return num(v, out);
}

// An operand as an int64 (bitwise operators, and storing into an integer).
inline Errc whole(std::int64_t v, std::int64_t& out) noexcept {
  out = v;
  return Errc::kOk;
}
inline Errc whole(double v, std::int64_t& out) noexcept { return double_to_int(v, out); }
inline Errc whole(bool v, std::int64_t& out) noexcept {
  out = v ? 1 : 0;
  return Errc::kOk;
}
inline Errc whole(Status v, std::int64_t& out) noexcept {
  out = static_cast<std::int64_t>(v);
  return Errc::kOk;
}

// Comparisons of numbers (ExprComparison): `==`/`!=` within FLT_EPSILON;
// the others as `not (a >= b)` and so on, so that NaN compares as 4.6.2 does.
inline bool eq(double a, double b) noexcept { return std::fabs(a - b) <= kFltEpsilon; }
inline bool ne(double a, double b) noexcept { return !eq(a, b); }
inline bool lt(double a, double b) noexcept { return !(a >= b); }
inline bool gt(double a, double b) noexcept { return !(a <= b); }
inline bool le(double a, double b) noexcept { return !(a > b); }
inline bool ge(double a, double b) noexcept { return !(a < b); }

// Comparisons of strings: byte by byte.
inline bool eq(std::string_view a, std::string_view b) noexcept { return a == b; }
inline bool ne(std::string_view a, std::string_view b) noexcept { return a != b; }
inline bool lt(std::string_view a, std::string_view b) noexcept { return !(a >= b); }
inline bool gt(std::string_view a, std::string_view b) noexcept { return !(a <= b); }
inline bool le(std::string_view a, std::string_view b) noexcept { return !(a > b); }
inline bool ge(std::string_view a, std::string_view b) noexcept { return !(a < b); }

// Division as 4.6.2's double arithmetic on x86-64, with division by zero
// spelled out: 0/0 is the processor's default NaN, whose sign bit is set
// (std::to_string writes `-nan`; edges table N1), nan/0 that NaN as it is,
// x/0 an infinity with the signs' product.
inline double div(double a, double b) noexcept {
  if (b == 0.0) {
    if (std::isnan(a)) return a;
    if (a == 0.0) return -std::numeric_limits<double>::quiet_NaN();
    return std::copysign(std::numeric_limits<double>::infinity(), a) * std::copysign(1.0, b);
  }
  return a / b;
}

// `!x`: 1 when x is zero, else 0.
inline double logical_not(double x) noexcept { return x == 0.0 ? 1.0 : 0.0; }

// `~x`: the complement of x truncated to int64 (x must be in range).
inline Errc complement(double x, double& out) noexcept {
  if (std::isnan(x) || !(x >= -9223372036854775808.0 && x < 9223372036854775808.0)) return Errc::kOutOfRange;
  out = static_cast<double>(~static_cast<std::int64_t>(x));
  return Errc::kOk;
}

// A number read as a condition (Any::cast<bool>): doubles are true when
// non-zero; integers must be 0 or 1. Returns 1, 0, or -1 (not a condition).
inline int truth(double v) noexcept { return v != 0.0 ? 1 : 0; }
inline int truth(std::int64_t v) noexcept { return v == 0 ? 0 : (v == 1 ? 1 : -1); }
inline int truth(bool v) noexcept { return v ? 1 : 0; }
inline int truth(Status v) noexcept { return truth(static_cast<std::int64_t>(v)); }

// A string read as a number in a comparison (StringToDouble): `true` 1,
// `false` 0, else std::from_chars.
inline Errc text_to_double(std::string_view s, double& out) noexcept {
  if (s == "true") {
    out = 1.0;
    return Errc::kOk;
  }
  if (s == "false") {
    out = 0.0;
    return Errc::kOk;
  }
  return parse_double_from_chars(s, out);
}

// An integer result kept as the type of the value it replaces (Any::copyInto
// keeps a bool a bool and a status a status when the number allows it).
inline Errc as_bool(std::int64_t v, bool& out) noexcept { return int_to_bool(v, out); }
inline Errc as_status(std::int64_t v, Status& out) noexcept { return int_to_status(v, out); }

}  // namespace btgen::script
