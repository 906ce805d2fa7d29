// btgen runtime: user port types (`btgen compile --type NAME=CPP_TYPE@HEADER`).
//
// A port type of TreeNodesModel that btgen does not know (Pose2D, ...) may be
// mapped to a C++ type T. An entry of that type is a btgen::Slot<T>: the
// value itself, held in place in the mission object (constructed once, with
// the mission, and assigned on writes), so T must be default constructible
// and copyable (the generated header checks both). Leaves read it with
// btgen::Input<T> getters (a copy, as getInput<T>) and write it with
// `bool set_x(const T&)` setters; nothing converts it on the tick path.
//
// btgen's own code allocates nothing for such an entry. T may own memory
// (std::string, std::vector, a ROS message): its copy constructor and copy
// assignment then may allocate, on writes and reads, and an exception they
// throw ends the program (the accessors are noexcept). A trivially copyable
// T (fixed-size members) keeps the mission free of heap allocation.
//
// Literals of such ports (and TreeNodesModel defaults) are converted once,
// when the mission object is constructed, by the user's conversion, which
// follows BehaviorTree.CPP's convertFromString<T> without allocating or
// throwing. Provide either
//
//   bool convertFromString(std::string_view text, T& out);   // found by ADL
//
// in T's namespace (true: `out` holds the value), or a specialisation
//
//   template <> struct btgen::StringConverter<T> {
//     static bool from_string(std::string_view text, T& out) noexcept;
//   };
//
// (for types whose namespace you cannot add to, such as std::array). A
// literal that does not convert is reported through the Observer's
// on_error() while the mission is constructed (mission.errors() is then
// not 0), and its getter returns btgen::PortError::kConversion.
#pragma once

#include <string_view>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/port.hpp"

namespace btgen {

namespace user_type_detail {

template <class T, class = void>
struct has_adl_converter : std::false_type {};
template <class T>
struct has_adl_converter<T, std::void_t<decltype(static_cast<bool>(convertFromString(
                                std::declval<std::string_view>(), std::declval<T&>())))>> : std::true_type {};

}  // namespace user_type_detail

// The conversion of a user port type's literals: by default the
// convertFromString(std::string_view, T&) that argument-dependent lookup finds.
template <class T>
struct StringConverter {
  static bool from_string(std::string_view text, T& out) {
    static_assert(user_type_detail::has_adl_converter<T>::value,
                  "btgen: a user port type (btgen compile --type) with literals needs "
                  "`bool convertFromString(std::string_view text, T& out)` in T's namespace, "
                  "or a specialisation of btgen::StringConverter<T> (see btgen/user_type.hpp)");
    if constexpr (user_type_detail::has_adl_converter<T>::value) {
      return static_cast<bool>(convertFromString(text, out));
    } else {
      (void)text;
      (void)out;
      return false;
    }
  }
};

// A literal of a user-typed port, converted when the mission is constructed.
template <class T>
struct UserLiteral {
  T value{};
  bool ok = false;
};

// Converts `text` into `lit` (once, at construction); false when it does not convert.
template <class T>
bool convert_literal(UserLiteral<T>& lit, std::string_view text) {
  T out{};
  lit.ok = StringConverter<T>::from_string(text, out);
  if (lit.ok) {
    lit.value = std::move(out);
  } else {
    lit.value = T{};
  }
  return lit.ok;
}

namespace port {

// The getter of a user-typed port given a literal.
template <class T>
Input<T> read_literal(const UserLiteral<T>& lit) noexcept {
  if (!lit.ok) return PortError::kConversion;
  return lit.value;
}

// The getter of a user-typed port reading its entry (getInput<T>: the entry must
// exist and hold a value).
template <class T>
Input<T> read_user(const Slot<T>& slot) noexcept {
  if (!slot.exists) return PortError::kNoEntry;
  if (!slot.has_value) return PortError::kNoValue;
  return slot.value;
}

// The template getter of an untyped port reading a user-typed entry: only as its own type.
template <class T, class S>
Input<T> read_user_as(const Slot<S>& slot) noexcept {
  if constexpr (std::is_same_v<T, S>) {
    return read_user(slot);
  } else {
    (void)slot;
    return PortError::kConversion;
  }
}

// The setter of a user-typed port: the value is copied into the entry.
template <class T>
void write_user(Slot<T>& slot, const T& value) noexcept {
  slot.value = value;
  slot.mark_written();
}

}  // namespace port
}  // namespace btgen
