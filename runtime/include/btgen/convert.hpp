// btgen runtime: every text-to-number conversion of the generated code, by the rules of
// the BehaviorTree.CPP release the mission follows.
//
// Two conversions exist in the library, and each release picks its own rule for one:
//
//   convertFromString<T>  a port literal, a string an input port reads, the elements of a
//                         queue's text, a string that SetBlackboard or a script stores into
//                         an entry through its declared type's converter. Integers:
//                         std::from_chars (an optional '-', digits, the rest ignored) in
//                         every release. Doubles: std::stod in 4.6.2 (leading blanks, '+',
//                         0x hex floats, inf, nan); std::from_chars from 4.9.0 (none of
//                         those but inf and nan; `0x1p3` reads 0.0, stopping at `x`).
//   Any::cast<T>          a string used as a number by a script's comparison or arithmetic,
//                         Switch: std::from_chars in every release.
//
// `kFromChars` is the mission header's `detail::Semantics::double_from_chars` (btgen's
// lang/versions.py); the reference interpreter reads the same switch (lang/values.py
// convert_from_string), and tests/conformance/conversions/ records both releases' table.
#pragma once

#include <cstdint>
#include <string_view>

#include "btgen/value.hpp"

namespace btgen {

// convertFromString<double> of the release.
template <bool kFromChars>
[[nodiscard]] inline Errc convert_double(std::string_view text, double& out) noexcept {
  if constexpr (kFromChars) {
    return parse_double_from_chars(text, out);
  } else {
    return parse_double_stod(text, out);
  }
}

// convertFromString<int> / <unsigned> (every release): from_chars into 64 bits, then the range.
[[nodiscard]] inline Errc convert_int(std::string_view text, std::int64_t& out) noexcept {
  return parse_integer(text, INT32_MIN, INT32_MAX, out);
}
[[nodiscard]] inline Errc convert_unsigned(std::string_view text, std::int64_t& out) noexcept {
  return parse_integer(text, 0, UINT32_MAX, out);
}

// Any::cast<double> of a string (every release): std::from_chars.
[[nodiscard]] inline Errc cast_double(std::string_view text, double& out) noexcept {
  return parse_double_from_chars(text, out);
}

}  // namespace btgen
