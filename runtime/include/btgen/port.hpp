// btgen runtime: reading and writing blackboard slots through ports.
//
// A user leaf reads an input port with a generated getter and writes an
// output port with a generated setter (see the mission header). Both land
// here, with the conversions of BehaviorTree.CPP 4.6.2:
//
//   read<T>(slot)      TreeNode::getInput<T>: the entry must exist and hold
//                      a value; a string is converted with convertFromString<T>
//                      (unless T is a string), any other value with Any::cast<T>
//   write(slot, ...)   Blackboard::set<T> (what setOutput<T> calls): a value
//                      of the entry's type is stored; a string goes through
//                      the converter of the entry's declared type; a number
//                      of another type must fit it (isCastingSafe)
//
// T is the C++ type of the port: std::int32_t (int), std::uint32_t
// (unsigned), double, bool, btgen::Status, std::string_view (a string; the
// text of a number is written into a scratch buffer that the view points
// into). Nothing allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/convert.hpp"
#include "btgen/dynamic.hpp"
#include "btgen/fixed_string.hpp"
#include "btgen/status.hpp"
#include "btgen/value.hpp"

namespace btgen {

enum class PortError : std::uint8_t {
  kNone = 0,
  kNotSet,      // the port is not written on this node and has no default
  kNoEntry,     // the blackboard entry it names does not exist
  kNoValue,     // the entry exists but holds no value yet
  kConversion,  // the value does not convert to the port's type
};

[[nodiscard]] constexpr std::string_view describe(PortError e) noexcept {
  switch (e) {
    case PortError::kNone: return "no error";
    case PortError::kNotSet: return "the port is not set on this node and has no default";
    case PortError::kNoEntry: return "the blackboard entry does not exist";
    case PortError::kNoValue: return "the blackboard entry has no value yet";
    case PortError::kConversion: return "the value does not convert to the port's type";
  }
  return "error";
}

// The result of reading an input port (BT::Expected<T>).
template <class T>
class Input {
 public:
  constexpr Input(T value) noexcept : value_(std::move(value)), error_(PortError::kNone) {}  // NOLINT: implicit
  constexpr Input(PortError error) noexcept : value_{}, error_(error) {}                     // NOLINT

  [[nodiscard]] constexpr bool has_value() const noexcept { return error_ == PortError::kNone; }
  constexpr explicit operator bool() const noexcept { return has_value(); }
  // The value; T{} when there is none.
  [[nodiscard]] constexpr const T& value() const noexcept { return value_; }
  [[nodiscard]] constexpr const T& operator*() const noexcept { return value_; }
  [[nodiscard]] constexpr const T* operator->() const noexcept { return &value_; }  // (a user type's members)
  [[nodiscard]] constexpr T value_or(T fallback) const noexcept { return has_value() ? value_ : fallback; }
  [[nodiscard]] constexpr PortError error() const noexcept { return error_; }

 private:
  T value_;
  PortError error_;
};

// The declared type of a blackboard entry (the type 4.6.2 created it with):
// it decides how writes of other types convert.
enum class Declared : std::uint8_t { kAny, kInt, kUnsigned, kDouble, kBool, kString, kStatus, kQueue, kOpaque };

namespace port {

template <class T>
inline constexpr bool is_port_type =
    std::is_same_v<T, std::int32_t> || std::is_same_v<T, std::uint32_t> || std::is_same_v<T, double> ||
    std::is_same_v<T, bool> || std::is_same_v<T, Status> || std::is_same_v<T, std::string_view>;

template <class S>
struct is_fixed_string : std::false_type {};
template <std::size_t N>
struct is_fixed_string<FixedString<N>> : std::true_type {};

template <class S>
struct is_dyn : std::false_type {};
template <std::size_t N>
struct is_dyn<Dyn<N>> : std::true_type {};

template <class S>
struct is_fixed_queue : std::false_type {};
template <class E, std::size_t N>
struct is_fixed_queue<FixedQueue<E, N>> : std::true_type {};

// ---------------------------------------------------------------- reads

// convertFromString<T>(text), doubles by the release's rule (btgen/convert.hpp).
template <class T, bool kFromChars>
Input<T> parse(std::string_view text) noexcept {
  static_assert(is_port_type<T>, "a port is int, unsigned, double, bool, Status or a string");
  if constexpr (std::is_same_v<T, std::string_view>) {
    return text;
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    std::int64_t v = 0;
    if (convert_int(text, v) != Errc::kOk) return PortError::kConversion;
    return static_cast<std::int32_t>(v);
  } else if constexpr (std::is_same_v<T, std::uint32_t>) {
    std::int64_t v = 0;
    if (convert_unsigned(text, v) != Errc::kOk) return PortError::kConversion;
    return static_cast<std::uint32_t>(v);
  } else if constexpr (std::is_same_v<T, double>) {
    double v = 0.0;
    if (convert_double<kFromChars>(text, v) != Errc::kOk) return PortError::kConversion;
    return v;
  } else if constexpr (std::is_same_v<T, bool>) {
    bool v = false;
    if (parse_bool(text, v) != Errc::kOk) return PortError::kConversion;
    return v;
  } else {
    Status v = Status::IDLE;
    if (parse_status(text, v) != Errc::kOk) return PortError::kConversion;
    return v;
  }
}

// Any::cast<T>() of an integer (bool and Status values count as integers).
template <class T>
Input<T> from_integer(std::int64_t v, NumberText* scratch) noexcept {
  if constexpr (std::is_same_v<T, std::string_view>) {
    if (scratch == nullptr) return PortError::kConversion;
    return scratch->set(v);
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    if (int_in_range(v, INT32_MIN, INT32_MAX) != Errc::kOk) return PortError::kConversion;
    return static_cast<std::int32_t>(v);
  } else if constexpr (std::is_same_v<T, std::uint32_t>) {
    if (int_in_range(v, 0, UINT32_MAX) != Errc::kOk) return PortError::kConversion;
    return static_cast<std::uint32_t>(v);
  } else if constexpr (std::is_same_v<T, double>) {
    double d = 0.0;
    if (int_to_double(v, d) != Errc::kOk) return PortError::kConversion;
    return d;
  } else if constexpr (std::is_same_v<T, bool>) {
    bool b = false;
    if (int_to_bool(v, b) != Errc::kOk) return PortError::kConversion;
    return b;
  } else {
    Status s = Status::IDLE;
    if (v < INT32_MIN || v > INT32_MAX || int_to_status(v, s) != Errc::kOk) return PortError::kConversion;
    return s;
  }
}

// Any::cast<T>() of a double.
template <class T>
Input<T> from_double(double v, NumberText* scratch) noexcept {
  if constexpr (std::is_same_v<T, std::string_view>) {
    if (scratch == nullptr) return PortError::kConversion;
    return scratch->set(v);
  } else if constexpr (std::is_same_v<T, double>) {
    return v;
  } else if constexpr (std::is_same_v<T, bool>) {
    return v != 0.0;
  } else {
    std::int64_t i = 0;
    if constexpr (std::is_same_v<T, std::uint32_t>) {
      if (double_to_int_in(v, 0, UINT32_MAX, i) != Errc::kOk) return PortError::kConversion;
      return static_cast<std::uint32_t>(i);
    } else {
      if (double_to_int_in(v, INT32_MIN, INT32_MAX, i) != Errc::kOk) return PortError::kConversion;
      if constexpr (std::is_same_v<T, std::int32_t>) {
        return static_cast<std::int32_t>(i);
      } else {
        Status s = Status::IDLE;
        if (int_to_status(i, s) != Errc::kOk) return PortError::kConversion;
        return s;
      }
    }
  }
}

// TreeNode::getInput<T> of a port connected to `slot`. Reading a number as
// a string writes its text into `scratch` (the generator passes one where
// that can happen). A string converts by the release's rule (kFromChars).
template <class T, bool kFromChars, class S>
Input<T> read(const Slot<S>& slot, NumberText* scratch = nullptr) noexcept {
  static_assert(is_port_type<T>, "a port is int, unsigned, double, bool, Status or a string");
  if (!slot.exists) return PortError::kNoEntry;
  if (!slot.has_value) return PortError::kNoValue;
  if constexpr (std::is_same_v<S, NoValue>) {
    return PortError::kNoValue;
  } else if constexpr (is_fixed_string<S>::value) {
    return parse<T, kFromChars>(slot.value.view());
  } else if constexpr (std::is_same_v<S, std::int64_t>) {
    return from_integer<T>(slot.value, scratch);
  } else if constexpr (std::is_same_v<S, bool>) {
    return from_integer<T>(slot.value ? 1 : 0, scratch);
  } else if constexpr (std::is_same_v<S, Status>) {
    return from_integer<T>(static_cast<std::int64_t>(slot.value), scratch);
  } else if constexpr (std::is_same_v<S, double>) {
    return from_double<T>(slot.value, scratch);
  } else if constexpr (is_dyn<S>::value) {
    // A dynamic entry: whatever it holds now, converted as above.
    const dyn::Ref v = slot.value.ref();
    switch (v.tag) {
      case DynTag::kNone: return PortError::kNoValue;
      case DynTag::kString: return parse<T, kFromChars>(v.s);
      case DynTag::kDouble: return from_double<T>(v.d, scratch);
      default: return from_integer<T>(v.i, scratch);
    }
  } else {
    static_assert(is_fixed_queue<S>::value, "unknown slot type");
    return PortError::kConversion;  // a queue is no scalar
  }
}

// getInput<T> of an entry for an integer port narrower than its accessor (`uint16`,
// `int8_t`; the accessor is std::uint32_t or std::int32_t): 4.6.2 fails the read when
// the value does not fit the port's own type.
template <class T>
constexpr Input<T> within(Input<T> in, std::int64_t lo, std::int64_t hi) noexcept {
  static_assert(std::is_same_v<T, std::int32_t> || std::is_same_v<T, std::uint32_t>, "an integer port");
  if (in.has_value() && (static_cast<std::int64_t>(in.value()) < lo || static_cast<std::int64_t>(in.value()) > hi)) {
    return PortError::kConversion;
  }
  return in;
}

// ---------------------------------------------------------------- writes

// The 4.6.2 type name of what a port writes (the T of setOutput<T>).
enum class WriteType : std::uint8_t { kInt, kUnsigned, kDouble, kBool, kStatus, kString };

template <class V>
constexpr WriteType write_type() noexcept {
  if constexpr (std::is_same_v<V, std::uint32_t>) {
    return WriteType::kUnsigned;
  } else if constexpr (std::is_same_v<V, bool>) {
    return WriteType::kBool;
  } else if constexpr (std::is_same_v<V, Status>) {
    return WriteType::kStatus;
  } else if constexpr (std::is_floating_point_v<V>) {
    return WriteType::kDouble;
  } else if constexpr (std::is_integral_v<V>) {
    return WriteType::kInt;
  } else {
    return WriteType::kString;
  }
}

constexpr bool same_type(Declared d, WriteType t) noexcept {
  switch (t) {
    case WriteType::kInt: return d == Declared::kInt;
    case WriteType::kUnsigned: return d == Declared::kUnsigned;
    case WriteType::kDouble: return d == Declared::kDouble;
    case WriteType::kBool: return d == Declared::kBool;
    case WriteType::kStatus: return d == Declared::kStatus;
    case WriteType::kString: return d == Declared::kString;
  }
  return false;
}

// Stores `v` in the slot as it is: only when it is of the slot's own kind
// (anything else would change the entry's type, which btgen does not do).
template <class S, class V>
Errc store_as_is(Slot<S>& slot, const V& v) noexcept {
  if constexpr (is_fixed_string<S>::value) {
    if constexpr (std::is_convertible_v<V, std::string_view> && !std::is_arithmetic_v<V>) {
      if (!slot.value.assign(std::string_view(v))) return Errc::kTooLong;
      return Errc::kOk;
    } else {
      return Errc::kInvalid;
    }
  } else if constexpr (std::is_same_v<S, bool>) {
    if constexpr (std::is_same_v<V, bool>) {
      slot.value = v;
      return Errc::kOk;
    } else {
      return Errc::kInvalid;
    }
  } else if constexpr (std::is_same_v<S, Status>) {
    if constexpr (std::is_same_v<V, Status>) {
      slot.value = v;
      return Errc::kOk;
    } else {
      return Errc::kInvalid;
    }
  } else if constexpr (std::is_same_v<S, double>) {
    if constexpr (std::is_floating_point_v<V>) {
      slot.value = static_cast<double>(v);
      return Errc::kOk;
    } else {
      return Errc::kInvalid;
    }
  } else if constexpr (std::is_same_v<S, std::int64_t>) {
    // Integers, and bools as 0 and 1 (4.6.2's Any keeps bools as integers).
    if constexpr (std::is_integral_v<V>) {
      slot.value = static_cast<std::int64_t>(v);
      return Errc::kOk;
    } else {
      return Errc::kInvalid;
    }
  } else {
    return Errc::kInvalid;
  }
}

// A number as an int64 (bools as 0/1): Any::copyInto's integer path.
template <class V>
Errc number_as_int(const V& v, std::int64_t& out) noexcept {
  if constexpr (std::is_same_v<V, bool>) {
    out = v ? 1 : 0;
    return Errc::kOk;
  } else if constexpr (std::is_same_v<V, Status>) {
    out = static_cast<std::int64_t>(v);
    return Errc::kOk;
  } else if constexpr (std::is_floating_point_v<V>) {
    return double_to_int(static_cast<double>(v), out);
  } else {
    out = static_cast<std::int64_t>(v);
    return Errc::kOk;
  }
}

// isCastingSafe(declared, v): a number that fits an int, unsigned or double entry.
template <class V>
bool casting_safe(Declared d, const V& v) noexcept {
  if constexpr (std::is_arithmetic_v<V>) {
    if (d == Declared::kDouble) {
      if constexpr (std::is_floating_point_v<V>) {
        return true;
      } else {
        double out = 0.0;
        return int_to_double(static_cast<std::int64_t>(v), out) == Errc::kOk;
      }
    }
    if (d == Declared::kInt || d == Declared::kUnsigned) {
      std::int64_t i = 0;
      if constexpr (std::is_floating_point_v<V>) {
        if (double_to_int(static_cast<double>(v), i) != Errc::kOk) return false;
      } else {
        i = static_cast<std::int64_t>(v);
      }
      return d == Declared::kInt ? (i >= INT32_MIN && i <= INT32_MAX) : (i >= 0 && i <= UINT32_MAX);
    }
  }
  (void)d;
  (void)v;
  return false;
}

// Any::copyInto of a number into a slot that holds a number of another type.
template <class S, class V>
Errc copy_number(Slot<S>& slot, const V& v) noexcept {
  if constexpr (std::is_same_v<S, double>) {
    if constexpr (std::is_floating_point_v<V>) {
      slot.value = static_cast<double>(v);
      return Errc::kOk;
    } else {
      std::int64_t i = 0;
      (void)number_as_int(v, i);
      return int_to_double(i, slot.value);
    }
  } else if constexpr (std::is_same_v<S, std::int64_t> || std::is_same_v<S, bool> || std::is_same_v<S, Status>) {
    std::int64_t i = 0;
    if (const Errc e = number_as_int(v, i); e != Errc::kOk) return e;
    if constexpr (std::is_same_v<S, std::int64_t>) {
      slot.value = i;
      return Errc::kOk;
    } else if constexpr (std::is_same_v<S, bool>) {
      return int_to_bool(i, slot.value);
    } else {
      return int_to_status(i, slot.value);
    }
  } else {
    (void)slot;
    (void)v;
    return Errc::kInvalid;
  }
}

// convertFromString of a `;`-separated queue: no element for an empty text
// or after a final `;`.
template <bool kFromChars, class E, std::size_t N>
Errc parse_queue(std::string_view text, FixedQueue<E, N>& out) noexcept {
  FixedQueue<E, N> q;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find(';', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view part = text.substr(pos, end - pos);
    E* slot = q.emplace_slot();
    if (slot == nullptr) return Errc::kTooLong;
    if constexpr (std::is_same_v<E, std::int64_t>) {
      if (const Errc e = convert_int(part, *slot); e != Errc::kOk) return e;
    } else if constexpr (std::is_same_v<E, double>) {
      if (const Errc e = convert_double<kFromChars>(part, *slot); e != Errc::kOk) return e;
    } else if constexpr (std::is_same_v<E, bool>) {
      if (const Errc e = parse_bool(part, *slot); e != Errc::kOk) return e;
    } else {
      if (!slot->assign(part)) return Errc::kTooLong;
    }
    pos = end + 1;
  }
  out = q;
  return Errc::kOk;
}

// A Loop's `queue` read from an entry holding a string, from BehaviorTree.CPP 4.9.1
// (Semantics::loop_queue_untyped): the text is converted into a private queue
// when the loop starts (every element checked then), and the loop pops from
// that copy, whatever later happens to the entry. The copy is the text itself
// and a position: no room for the elements (4.6.2's convertFromString splitting:
// no element for an empty text or after a final `;`).
template <std::size_t N>
struct TextQueue {
  FixedString<N> text{};
  std::size_t pos = 0;
  bool loaded = false;  // converted since the loop last started

  [[nodiscard]] bool empty() const noexcept { return pos >= text.size(); }
  [[nodiscard]] std::string_view front() const noexcept {
    const std::string_view t = text.view();
    const std::size_t end = t.find(';', pos);
    return t.substr(pos, (end == std::string_view::npos ? t.size() : end) - pos);
  }
  void pop_front() noexcept { pos += front().size() + 1; }
};

// One element of a queue's text as convertFromString<E> reads it (doubles by the
// release's rule); on failure `m`, if given, gets the reference interpreter's
// reason ("`x` is not a valid int").
template <bool kFromChars, class E>
bool queue_element(std::string_view part, E& out, dyn::Msg* m = nullptr) noexcept {
  Errc e = Errc::kOk;
  std::string_view type;
  if constexpr (std::is_same_v<E, std::int64_t>) {
    type = "int";
    e = convert_int(part, out);
  } else if constexpr (std::is_same_v<E, double>) {
    type = "double";
    e = convert_double<kFromChars>(part, out);
  } else if constexpr (std::is_same_v<E, bool>) {
    type = "bool";
    e = parse_bool(part, out);
  } else {
    (void)type;
    out = part;
    return true;
  }
  if (e == Errc::kOk) return true;
  if (m != nullptr) dyn::add_conversion_error(*m, part, type, e);
  return false;
}

// Starts `q` over `text`, checking every element as E (false: `m` says why, as
// "`1;x` is not a valid queue<int>: element 2: `x` is not a valid int").
template <class E, bool kFromChars, std::size_t N>
bool load_queue(TextQueue<N>& q, std::string_view text, std::string_view elem_type, dyn::Msg& m) noexcept {
  std::size_t pos = 0;
  std::int64_t index = 0;
  while (pos < text.size()) {
    std::size_t end = text.find(';', pos);
    if (end == std::string_view::npos) end = text.size();
    ++index;
    E value{};
    dyn::Msg why;
    if (!queue_element<kFromChars>(text.substr(pos, end - pos), value, &why)) {
      m.add("`").add(text).add("` is not a valid queue<").add(elem_type).add(">: element ");
      m.add_int(index).add(": ").add(why.view());
      return false;
    }
    pos = end + 1;
  }
  (void)q.text.assign(text);  // (the text comes from an entry of the same capacity)
  q.pos = 0;
  q.loaded = true;
  return true;
}

// A string through the converter of the slot's declared type.
template <bool kFromChars, class S>
Errc convert_into(Slot<S>& slot, Declared d, std::string_view text) noexcept {
  if constexpr (std::is_same_v<S, std::int64_t>) {
    if (d == Declared::kInt) return convert_int(text, slot.value);
    if (d == Declared::kUnsigned) return convert_unsigned(text, slot.value);
    if (d == Declared::kBool) {  // a bool entry holds the integer 0 or 1 (ir/kinds.py kind_of_type)
      bool b = false;
      const Errc e = parse_bool(text, b);
      if (e == Errc::kOk) slot.value = b ? 1 : 0;
      return e;
    }
    return Errc::kInvalid;
  } else if constexpr (std::is_same_v<S, double>) {
    return d == Declared::kDouble ? convert_double<kFromChars>(text, slot.value) : Errc::kInvalid;
  } else if constexpr (std::is_same_v<S, bool>) {
    return d == Declared::kBool ? parse_bool(text, slot.value) : Errc::kInvalid;
  } else if constexpr (is_fixed_string<S>::value) {
    return slot.value.assign(text) ? Errc::kOk : Errc::kTooLong;
  } else if constexpr (is_fixed_queue<S>::value) {
    return parse_queue<kFromChars>(text, slot.value);
  } else {
    (void)slot;
    (void)d;
    (void)text;
    return Errc::kInvalid;
  }
}

// Blackboard::set<T>(key, v) of an entry declared `d` (T the type of `v`):
// the store 4.6.2 does when a port writes. Errc::kInvalid is a write 4.6.2
// rejects, or one that would change the entry's type.
template <bool kFromChars, class S, class V>
Errc write(Slot<S>& slot, Declared d, const V& v) noexcept {
  constexpr WriteType t = write_type<V>();
  const bool existed = slot.exists;
  Errc e = Errc::kOk;
  if (!slot.exists || d == Declared::kAny || d == Declared::kOpaque) {
    // A new entry, or one without a declared type: the value as it is.
    e = store_as_is(slot, v);
  } else if (!same_type(d, t)) {
    if constexpr (t == WriteType::kString) {
      if (d == Declared::kStatus) return Errc::kInvalid;  // no converter for NodeStatus
      e = convert_into<kFromChars>(slot, d, std::string_view(v));
    } else if constexpr (t == WriteType::kStatus) {
      return Errc::kInvalid;
    } else {
      if (!casting_safe(d, v)) return Errc::kInvalid;
      e = slot.has_value ? copy_number(slot, v) : store_as_is(slot, v);
    }
  } else {
    e = store_as_is(slot, v);
    if (e != Errc::kOk && slot.has_value) {
      if constexpr (t != WriteType::kString) e = copy_number(slot, v);
    }
  }
  if (e == Errc::kOk) {
    slot.mark_written();
    // Blackboard::set<T> gives an existing untyped entry the type T (a new one stays untyped).
    if (existed && d == Declared::kAny) slot.entry_type = EntryType::kTyped;
  }
  return e;
}

// The value a port writes, as a btgen::dyn::Ref.
template <class V>
dyn::Ref written_ref(const V& v) noexcept {
  if constexpr (std::is_arithmetic_v<V>) {
    return dyn::of_number(v);
  } else {
    return dyn::of_string(std::string_view(v));
  }
}

// Blackboard::set<T>(key, v) into a Dyn slot (lang/blackboard.py Blackboard.set is the
// reference; T the type of `v`: int, double, bool or a string). False when the library
// throws, `m` saying why after the writer's prefix.
//  - `d` int, unsigned, double or bool: an entry a port declared that a 4.6.2
//    SetBlackboard copy may have left holding a string: Any::copyInto of the value into
//    what the entry holds.
//  - `d` any (no port declared it): a missing entry is created with the type T (a string:
//    untyped) and the value; an entry that is not strongly typed (`any`, BT::Any) takes
//    the type T and the value; one typed (std::string, or the T of an earlier typed
//    write) converts a string with its converter and takes a number that fits it
//    (isCastingSafe), anything else throws; the value is then copied into what it holds.
//    `kFalseIntoIntUnsafe`: Semantics::false_into_int_unsafe (4.10.0 refuses `false` into an
//    int entry).
template <bool kFromChars, bool kFalseIntoIntUnsafe = false, std::size_t N = 0, class V = int>
bool write(Slot<Dyn<N>>& slot, Declared d, const V& v, std::string_view key, dyn::Msg& m) noexcept {
  constexpr WriteType t = write_type<V>();
  static_assert(t != WriteType::kStatus && (t != WriteType::kUnsigned || std::is_same_v<V, std::uint32_t>),
                "a typed write into a dynamic slot is of an int, a double, a bool or a string");
  dyn::Ref value = written_ref(v);
  const dyn::Ref held = dyn::ref(slot);
  dyn::Ref out;
  dyn::Msg why;
  if (d != Declared::kAny) {
    if (!dyn::copy_into(value, held, out, why) || !slot.value.set(out)) {
      dyn::add_write_failure(m, value, key, held);
      return false;
    }
    slot.mark_written();
    return true;
  }
  constexpr DynTag tag = t == WriteType::kString   ? DynTag::kString
                         : t == WriteType::kDouble ? DynTag::kDouble
                         : t == WriteType::kBool   ? DynTag::kBool
                                                   : DynTag::kInt;
  const DynTag type = dyn::declared(slot);
  if (!slot.exists || type == DynTag::kNone) {
    // A new entry takes the type T (a string: none); an untyped one, the type T.
    const bool created = !slot.exists;
    if (!dyn::put(slot, value, key, m)) return false;
    if (created && tag == DynTag::kString) {
      slot.value.typed_string = false;
      slot.value.typed = DynTag::kNone;
      slot.entry_type = EntryType::kUntyped;
    } else {
      slot.value.typed_string = tag == DynTag::kString;
      slot.value.typed = tag == DynTag::kString ? DynTag::kNone : tag;
      slot.entry_type = EntryType::kTyped;
    }
    return true;
  }
  const std::string_view type_name = dyn::type_name(dyn::Ref{type, 0, 0.0, {}});
  if (type != tag) {
    bool ok = false;
    if constexpr (t == WriteType::kString) {
      if (type != DynTag::kStatus) {  // (NodeStatus has no converter)
        const Errc e = dyn::convert_typed<kFromChars>(type, value.s, value);
        if (e != Errc::kOk) {
          m.add("cannot write ");
          dyn::add_string_repr(m, std::string_view(v));
          m.add(" to `").add(key).add("` (").add(type_name).add("): ");
          dyn::add_conversion_error(m, std::string_view(v), type_name, e);
          return false;
        }
        ok = true;
      }
    } else {
      const Declared as = type == DynTag::kInt      ? Declared::kInt
                          : type == DynTag::kDouble ? Declared::kDouble
                                                    : Declared::kAny;
      ok = casting_safe(as, v);
      if constexpr (kFalseIntoIntUnsafe && std::is_same_v<V, bool>) {
        if (type == DynTag::kInt && !v) ok = false;
      }
    }
    if (!ok) {
      m.add("blackboard entry `")
          .add(key)
          .add("` is declared as ")
          .add(type_name)
          .add("; it cannot be written with a ");
      m.add(t == WriteType::kUnsigned ? std::string_view("unsigned") : dyn::type_name(dyn::Ref{tag, 0, 0.0, {}}));
      return false;
    }
  }
  if (!dyn::copy_into(value, held, out, why)) {
    m.add("cannot write ");
    dyn::add_value(m, written_ref(v));
    m.add(" to `").add(key).add("`: ").add(why.view());
    return false;
  }
  return dyn::put(slot, out, key, m);
}

// The same without the message: Errc::kInvalid where the library throws.
template <bool kFromChars, std::size_t N, class V>
Errc write(Slot<Dyn<N>>& slot, Declared d, const V& v) noexcept {
  dyn::Msg m;
  return write<kFromChars>(slot, d, v, std::string_view(), m) ? Errc::kOk : Errc::kInvalid;
}

// A script's `key := value` (and `=`) into an entry declared `d` (int, unsigned, double,
// bool; `type` its name) that a 4.6.2 SetBlackboard copy may leave holding a string or
// another value, a Dyn slot (ir/data/types.py _mark_typed_copy_dynamic): the entry keeps its
// declared type, so a string goes through that type's converter unless the entry holds a
// string; any other value is Any::copyInto into what it holds, as it is into an empty entry
// (lang/script/evaluate.py _store is the reference).
template <bool kFromChars, std::size_t N>
bool store_declared(Slot<Dyn<N>>& slot, Declared d, std::string_view type, const dyn::Ref& value, std::string_view key,
                    dyn::Msg& m) noexcept {
  const dyn::Ref dst = dyn::ref(slot);
  dyn::Ref out = value;
  if (value.is_string() && !dst.is_string()) {
    Errc e = Errc::kInvalid;
    if (d == Declared::kInt || d == Declared::kUnsigned) {
      std::int64_t x = 0;
      e = d == Declared::kInt ? convert_int(value.s, x) : convert_unsigned(value.s, x);
      out = dyn::of_int(x);
    } else if (d == Declared::kDouble) {
      double x = 0.0;
      e = convert_double<kFromChars>(value.s, x);
      out = dyn::of_double(x);
    } else if (d == Declared::kBool) {
      bool x = false;
      e = parse_bool(value.s, x);
      out = dyn::of_bool(x);
    }
    if (!dyn::converted_text(e, value.s, key, type, m)) return false;
  } else if (!dst.none() && !dyn::store_into(value, dst, ":=", key, out, m)) {
    return false;
  }
  return dyn::put(slot, out, key, m);
}

// SetBlackboard value="{src}" from 4.7.0, the source a Dyn slot that scripts and literals
// write, into an entry declared `d` (int, unsigned, double, bool; `type` its name) that
// exists (ir/dataops.py SetCopyDynTyped410; lang/blackboard.py set_blackboard_410 is the
// reference): Blackboard::set<BT::Any>. Returns 1 (copied), 0 (the source is empty: the node
// fails), -1 (a string the entry's converter refuses) or -2 (a value of another type than
// the entry's, a script's integer being an int64_t: the library prints its blackboard and
// throws), `m` saying why.
template <bool kFromChars, class S>
int set_dyn_typed_410(Slot<S>& slot, Declared d, std::string_view type, const dyn::Ref& v, std::string_view raw,
                      std::string_view key, dyn::Msg& m) noexcept {
  if (v.none()) return 0;
  if (v.is_string()) {
    Slot<S> converted = slot;
    const Errc e = convert_into<kFromChars>(converted, d, v.s);
    if (e != Errc::kOk) {
      m.add("SetBlackboard: cannot convert ");
      dyn::add_string_repr(m, raw);
      m.add(": ");
      dyn::add_conversion_error(m, v.s, type, e);
      return -1;
    }
    slot.value = converted.value;
    slot.mark_written();
    return 1;
  }
  const bool same =
      (v.tag == DynTag::kDouble && d == Declared::kDouble) || (v.tag == DynTag::kBool && d == Declared::kBool);
  if (!same) {
    m.add("SetBlackboard: blackboard entry `").add(key).add("` is declared as ").add(type);
    m.add("; it cannot be written with a ").add(v.tag == DynTag::kInt ? std::string_view("int64") : dyn::type_name(v));
    return -2;
  }
  if constexpr (std::is_same_v<S, double>) {
    slot.value = v.d;
  } else {
    slot.value = static_cast<S>(v.i);
  }
  slot.mark_written();
  return 1;
}

// The same into a Dyn slot: an entry declared `d` that a script gave the other kind of number
// first (ir/data/types.py _mark_typed_number_dynamic). The check is on the declared type, as
// Blackboard::set's; the value is stored as it is.
template <bool kFromChars, std::size_t N>
int set_dyn_typed_410(Slot<Dyn<N>>& slot, Declared d, std::string_view type, const dyn::Ref& v, std::string_view raw,
                      std::string_view key, dyn::Msg& m) noexcept {
  if (v.none()) return 0;
  dyn::Ref out = v;
  if (v.is_string()) {
    if (d == Declared::kDouble) {
      Slot<double> converted;
      const Errc e = convert_into<kFromChars>(converted, d, v.s);
      out = dyn::of_double(converted.value);
      if (e != Errc::kOk) {
        m.add("SetBlackboard: cannot convert ");
        dyn::add_string_repr(m, raw);
        m.add(": ");
        dyn::add_conversion_error(m, v.s, type, e);
        return -1;
      }
    } else {
      Slot<std::int64_t> converted;
      const Errc e = convert_into<kFromChars>(converted, d, v.s);
      out = d == Declared::kBool ? dyn::of_bool(converted.value != 0) : dyn::of_int(converted.value);
      if (e != Errc::kOk) {
        m.add("SetBlackboard: cannot convert ");
        dyn::add_string_repr(m, raw);
        m.add(": ");
        dyn::add_conversion_error(m, v.s, type, e);
        return -1;
      }
    }
  } else if (!((v.tag == DynTag::kDouble && d == Declared::kDouble) ||
               (v.tag == DynTag::kBool && d == Declared::kBool))) {
    m.add("SetBlackboard: blackboard entry `").add(key).add("` is declared as ").add(type);
    m.add("; it cannot be written with a ").add(v.tag == DynTag::kInt ? std::string_view("int64") : dyn::type_name(v));
    return -2;
  }
  return dyn::put(slot, out, key, m) ? 1 : -1;
}

}  // namespace port
}  // namespace btgen
