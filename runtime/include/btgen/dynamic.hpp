// btgen runtime: dynamic blackboard slots, for entries whose type changes at run time.
//
// The generator gives most blackboard entries one static type. BehaviorTree.CPP
// 4.6.2 lets an entry that no typed port declared change its type while the
// tree runs: `SetBlackboard value="7"` replaces the integer a script stored
// with the string "7", `x := 5; x := '7'` turns it into the double 7.0. Such
// an entry gets a Dyn<N> slot instead: a tag (no value, integer, double, bool,
// NodeStatus, string), the number, and a FixedString<N> for text; no heap.
// The entry's own type as 4.6.2 keeps it (`any`, or `string` after a
// SetBlackboard literal) is kept too, since it decides how later writes go.
//
// The operations here are 4.6.2's for values whose kinds are only known at
// run time (btgen/lang/script.py, values.py and blackboard.py are the reference):
// arithmetic, `..`, comparisons, logic, `?:` conditions, truthiness, the
// script store (`:=` and `+=` ...), SetBlackboard literals and copies. Each
// fallible one returns false after writing the reference interpreter's
// message into a Msg (a fixed buffer, so that errors can name the values
// involved: "cannot assign 5 to `x`: a int cannot be stored where a string is").
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <system_error>
#include <type_traits>

#include "btgen/blackboard.hpp"
#include "btgen/convert.hpp"
#include "btgen/fixed_string.hpp"
#include "btgen/status.hpp"
#include "btgen/value.hpp"

namespace btgen {

enum class DynTag : std::uint8_t { kNone, kInt, kDouble, kBool, kStatus, kString };

namespace dyn {

// A value of a dynamic slot or expression (a view: the text is not owned).
struct Ref {
  DynTag tag = DynTag::kNone;
  std::int64_t i = 0;    // kInt, kBool (0/1), kStatus
  double d = 0.0;        // kDouble
  std::string_view s{};  // kString

  [[nodiscard]] constexpr bool none() const noexcept { return tag == DynTag::kNone; }
  [[nodiscard]] constexpr bool is_string() const noexcept { return tag == DynTag::kString; }
  [[nodiscard]] constexpr bool is_number() const noexcept {
    return tag == DynTag::kInt || tag == DynTag::kDouble || tag == DynTag::kBool || tag == DynTag::kStatus;
  }
};

[[nodiscard]] constexpr Ref of_int(std::int64_t v) noexcept { return Ref{DynTag::kInt, v, 0.0, {}}; }
[[nodiscard]] constexpr Ref of_double(double v) noexcept { return Ref{DynTag::kDouble, 0, v, {}}; }
[[nodiscard]] constexpr Ref of_bool(bool v) noexcept { return Ref{DynTag::kBool, v ? 1 : 0, 0.0, {}}; }
[[nodiscard]] constexpr Ref of_status(Status v) noexcept {
  return Ref{DynTag::kStatus, static_cast<std::int64_t>(v), 0.0, {}};
}
[[nodiscard]] constexpr Ref of_string(std::string_view v) noexcept { return Ref{DynTag::kString, 0, 0.0, v}; }
inline Ref of(std::int64_t v) noexcept { return of_int(v); }
inline Ref of(double v) noexcept { return of_double(v); }
inline Ref of(bool v) noexcept { return of_bool(v); }
inline Ref of(Status v) noexcept { return of_status(v); }
inline Ref of(std::string_view v) noexcept { return of_string(v); }

// A mission's scripting enums (registerScriptingEnum): value names and values.
struct ScriptingEnum {
  std::string_view name;
  double value;
};

// A message under construction (truncated, never overflowing). The prefix is
// copied in only when the message is written to or read: a compiled script
// builds one before every fallible dynamic operation, and most never fail.
class Msg {
 public:
  explicit Msg(std::string_view prefix = {}) noexcept : prefix_(prefix) {}
  // With the scripting enums a string read as a number may name (StringToDouble).
  Msg(std::string_view prefix, const ScriptingEnum* enums, std::size_t enum_count) noexcept
      : prefix_(prefix), enums_(enums), enum_count_(enum_count) {}
  Msg(const Msg&) = delete;
  Msg& operator=(const Msg&) = delete;

  Msg& add(std::string_view t) noexcept {
    flush();
    for (const char c : t) push(c);
    return *this;
  }
  Msg& add_int(std::int64_t v) noexcept {
    NumberText t(v);
    return add(t.view());
  }
  void put(char c) noexcept {
    flush();
    push(c);
  }
  [[nodiscard]] std::string_view view() const noexcept {
    flush();
    return std::string_view(buf_, size_);
  }
  // The value of scripting enum `name`, if the mission registered it.
  [[nodiscard]] bool enum_value(std::string_view name, double& out) const noexcept {
    for (std::size_t i = 0; i < enum_count_; ++i) {
      if (enums_[i].name == name) {
        out = enums_[i].value;
        return true;
      }
    }
    return false;
  }

 private:
  void push(char c) const noexcept {
    if (size_ < sizeof buf_) buf_[size_++] = c;
  }
  void flush() const noexcept {
    if (prefix_.empty()) return;
    const std::string_view p = prefix_;
    prefix_ = {};
    for (const char c : p) push(c);
  }

  mutable char buf_[1024];
  mutable std::size_t size_ = 0;
  mutable std::string_view prefix_;
  const ScriptingEnum* enums_ = nullptr;
  std::size_t enum_count_ = 0;
};

// values.type_of: the type name 4.6.2 gives a value ("int", "string", ...).
[[nodiscard]] constexpr std::string_view type_name(const Ref& v) noexcept {
  switch (v.tag) {
    case DynTag::kNone: return "none";
    case DynTag::kInt: return "int";
    case DynTag::kDouble: return "double";
    case DynTag::kBool: return "bool";
    case DynTag::kStatus: return "NodeStatus";
    case DynTag::kString: return "string";
  }
  return "none";
}

// Python's repr() of a float (the shortest text that reads back the same).
inline void add_double_repr(Msg& m, double v) noexcept {
  if (std::isnan(v)) {
    m.add("nan");
    return;
  }
  if (std::isinf(v)) {
    m.add(v < 0 ? "-inf" : "inf");
    return;
  }
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific);
  const std::string_view sci(buf, static_cast<std::size_t>(r.ptr - buf));  // e.g. "-2.5e+00"
  std::size_t i = 0;
  bool neg = false;
  if (!sci.empty() && sci[0] == '-') {
    neg = true;
    i = 1;
  }
  char digits[32];
  std::size_t nd = 0;
  std::size_t k = i;
  for (; k < sci.size() && sci[k] != 'e'; ++k) {
    if (sci[k] != '.' && nd < sizeof digits) digits[nd++] = sci[k];
  }
  int exp = 0;
  if (k < sci.size()) {
    std::from_chars(sci.data() + k + (sci[k + 1] == '+' ? 2 : 1), sci.data() + sci.size(), exp);
  }
  if (neg) m.put('-');
  if (exp >= -4 && exp < 16) {
    if (exp < 0) {
      m.add("0.");
      for (int z = -1; z > exp; --z) m.put('0');
      for (std::size_t d = 0; d < nd; ++d) m.put(digits[d]);
      return;
    }
    const std::size_t int_digits = static_cast<std::size_t>(exp) + 1;
    for (std::size_t d = 0; d < int_digits; ++d) m.put(d < nd ? digits[d] : '0');
    m.put('.');
    if (nd > int_digits) {
      for (std::size_t d = int_digits; d < nd; ++d) m.put(digits[d]);
    } else {
      m.put('0');
    }
    return;
  }
  m.put(digits[0]);
  if (nd > 1) {
    m.put('.');
    for (std::size_t d = 1; d < nd; ++d) m.put(digits[d]);
  }
  m.put('e');
  m.put(exp < 0 ? '-' : '+');
  const int a = exp < 0 ? -exp : exp;
  if (a < 10) m.put('0');
  m.add_int(a);
}

// Python's repr() of a str (ASCII rules; other UTF-8 is copied as is).
inline void add_string_repr(Msg& m, std::string_view s) noexcept {
  static constexpr char kHex[] = "0123456789abcdef";
  const bool has_single = s.find('\'') != std::string_view::npos;
  const bool has_double = s.find('"') != std::string_view::npos;
  const char q = (has_single && !has_double) ? '"' : '\'';
  m.put(q);
  for (std::size_t k = 0; k < s.size(); ++k) {
    const auto c = static_cast<unsigned char>(s[k]);
    if (c == '\\') {
      m.add("\\\\");
    } else if (c == static_cast<unsigned char>(q)) {
      m.put('\\');
      m.put(q);
    } else if (c == '\n') {
      m.add("\\n");
    } else if (c == '\r') {
      m.add("\\r");
    } else if (c == '\t') {
      m.add("\\t");
    } else if (c < 0x20 || c == 0x7f) {
      m.add("\\x");
      m.put(kHex[c >> 4]);
      m.put(kHex[c & 15]);
    } else if (c == 0xc2 && k + 1 < s.size() && static_cast<unsigned char>(s[k + 1]) >= 0x80 &&
               static_cast<unsigned char>(s[k + 1]) <= 0xa0) {
      // U+0080..U+00A0 are not printable for Python: \x80 ... \xa0
      const auto c2 = static_cast<unsigned char>(s[k + 1]);
      m.add("\\x");
      m.put(kHex[c2 >> 4]);
      m.put(kHex[c2 & 15]);
      ++k;
    } else {
      m.put(static_cast<char>(c));
    }
  }
  m.put(q);
}

// values.describe: a value for messages (3, 2.5, 'text', true, SUCCESS).
inline void add_value(Msg& m, const Ref& v) noexcept {
  switch (v.tag) {
    case DynTag::kNone: m.add("(no value)"); return;
    case DynTag::kInt: m.add_int(v.i); return;
    case DynTag::kDouble: add_double_repr(m, v.d); return;
    case DynTag::kBool: m.add(v.i != 0 ? "true" : "false"); return;
    case DynTag::kStatus: m.add(to_string(static_cast<Status>(v.i))); return;
    case DynTag::kString: add_string_repr(m, v.s); return;
  }
}

// script.py's kind(): "an empty value", "a int", "a string", ...
inline void add_kind(Msg& m, const Ref& v) noexcept {
  if (v.none()) {
    m.add("an empty value");
    return;
  }
  m.add("a ").add(type_name(v));
}

// values._cast_error: "cannot convert V (T) to TYPE: WHY".
inline void add_cast_error(Msg& m, const Ref& v, std::string_view type, std::string_view why) noexcept {
  m.add("cannot convert ");
  add_value(m, v);
  m.add(" (").add(type_name(v)).add(") to ").add(type).add(": ").add(why);
}

// values.to_double of a number (cast<double>): integers only when exact.
inline bool number_to_double(const Ref& v, double& out, Msg& m, std::string_view what) noexcept {
  if (v.tag == DynTag::kDouble) {
    out = v.d;
    return true;
  }
  if (int_to_double(v.i, out) != Errc::kOk) {
    m.add(what).add(": ");
    add_cast_error(m, v, "double", "precision would be lost");
    return false;
  }
  return true;
}

// values.to_int64 of a number.
inline bool number_to_int64(const Ref& v, std::int64_t& out, Msg& m) noexcept {
  if (v.tag != DynTag::kDouble) {
    out = v.i;
    return true;
  }
  const double x = v.d;
  if (std::isnan(x) || std::isinf(x) || x != std::floor(x)) {
    add_cast_error(m, v, "integer", "the value is not a whole number");
    return false;
  }
  if (!(x >= -9223372036854775808.0 && x <= 9223372036854775807.0) || x >= 9223372036854775808.0) {
    add_cast_error(m, v, "integer", "the value is out of range");
    return false;
  }
  out = static_cast<std::int64_t>(x);
  return true;
}

// values.convert_from_string's reason for a text that does not convert to `type` (int,
// unsigned, double, bool): "`x` is not a valid int", "`9e9` is out of range for int (...)".
inline void add_conversion_error(Msg& m, std::string_view text, std::string_view type, Errc e) noexcept {
  m.add("`").add(text).add("` is ");
  if (e == Errc::kOutOfRange) {
    m.add("out of range for ").add(type);
    if (type == "int") m.add(" (-2147483648 to 2147483647)");
    if (type == "unsigned") m.add(" (0 to 4294967295)");
  } else {
    m.add("not a valid ").add(type);
    if (type == "bool") m.add(" (use true or false, 1 or 0)");
  }
}

// getInput<int> (`is_unsigned`: getInput<unsigned>) of a loop count or duration given as
// `{key}`: a string is parsed (convertFromString), a number cast (values._to_integer);
// false with the reference interpreter's reason in `m`.
inline bool read_count(const Ref& v, bool is_unsigned, std::int64_t& out, Msg& m) noexcept {
  const std::string_view type = is_unsigned ? "unsigned" : "int";
  const std::int64_t lo = is_unsigned ? 0 : INT32_MIN;
  const std::int64_t hi = is_unsigned ? std::int64_t{UINT32_MAX} : INT32_MAX;
  if (v.tag == DynTag::kString) {
    const Errc e = parse_integer(v.s, lo, hi, out);
    if (e == Errc::kOk) return true;
    add_conversion_error(m, v.s, type, e);
    return false;
  }
  if (v.tag == DynTag::kDouble) {
    const double x = v.d;
    if (is_unsigned && x < 0.0) {
      add_cast_error(m, v, type, "the value is negative");
      return false;
    }
    if (std::isnan(x) || std::isinf(x) || x != std::floor(x)) {
      add_cast_error(m, v, type, "the value is not a whole number");
      return false;
    }
    if (!(x >= static_cast<double>(lo) && x <= static_cast<double>(hi))) {
      add_cast_error(m, v, type, "the value is out of range");
      return false;
    }
    out = static_cast<std::int64_t>(x);
    return true;
  }
  if (is_unsigned && v.i < 0) {
    add_cast_error(m, v, type, "the value is negative");
    return false;
  }
  if (v.i < lo || v.i > hi) {
    add_cast_error(m, v, type, "the value is out of range");
    return false;
  }
  out = v.i;
  return true;
}

// evaluate.script_bool: cast<bool>() of a number in a script (a condition's result, an
// operand of `&&`/`||`): never negative, then a double is true when non-zero and an integer
// is 0 or 1.
inline bool number_to_bool(const Ref& v, bool& out, Msg& m) noexcept {
  if (v.tag == DynTag::kBool) {
    out = v.i != 0;
    return true;
  }
  if (v.tag == DynTag::kDouble ? v.d < 0.0 : v.i < 0) {
    add_cast_error(m, v, "bool", "the value is negative");
    return false;
  }
  if (v.tag == DynTag::kDouble) {
    out = v.d != 0.0;
    return true;
  }
  if (v.i != 0 && v.i != 1) {
    add_cast_error(m, v, "bool", "only the integers 0 and 1 convert to bool");
    return false;
  }
  out = v.i == 1;
  return true;
}

// StringToDouble (comparisons): `true`, `false`, a scripting enum, else from_chars.
inline bool string_to_double(std::string_view s, double& out, Msg& m) noexcept {
  if (s == "true") {
    out = 1.0;
    return true;
  }
  if (s == "false") {
    out = 0.0;
    return true;
  }
  if (m.enum_value(s, out)) return true;
  if (parse_double_from_chars(s, out) != Errc::kOk) {
    m.add("the string ");
    add_string_repr(m, s);
    m.add(" is not a number");
    return false;
  }
  return true;
}

// values.to_text (Any::cast<std::string>): the text of a string or number.
// `scratch` holds a number's text.
inline std::string_view to_text(const Ref& v, NumberText& scratch) noexcept {
  switch (v.tag) {
    case DynTag::kString: return v.s;
    case DynTag::kDouble: return scratch.set(v.d);
    case DynTag::kNone: return {};
    default: return scratch.set(v.i);
  }
}

inline double arith(char op, double a, double b) noexcept {
  switch (op) {
    case '+': return a + b;
    case '-': return a - b;
    case '*': return a * b;
    default: break;
  }
  if (b == 0.0) {
    if (a == 0.0 || std::isnan(a)) return std::numeric_limits<double>::quiet_NaN();
    return std::copysign(std::numeric_limits<double>::infinity(), a) * std::copysign(1.0, b);
  }
  return a / b;
}

// ------------------------------------------------------------ operators

// Unary `-`, `!`, `~`.
inline bool unary(char op, const Ref& v, double& out, Msg& m) noexcept {
  const char opname[2] = {op, '\0'};
  const std::string_view o(opname, 1);
  if (v.is_number()) {
    double x = 0.0;
    Msg what;
    what.add("operand of `").add(o).add("`");
    if (!number_to_double(v, x, m, what.view())) return false;
    if (op == '-') {
      out = -x;
    } else if (op == '!') {
      out = x == 0.0 ? 1.0 : 0.0;
    } else {
      if (std::isnan(x) || !(x >= -9223372036854775808.0 && x < 9223372036854775808.0)) {
        add_value(m, v);
        m.add(" is out of range for `~`");
        return false;
      }
      out = static_cast<double>(~static_cast<std::int64_t>(x));
    }
    return true;
  }
  if (v.none()) {
    m.add("the operand of `").add(o).add("` has no value");
    return false;
  }
  m.add("`").add(o).add("` cannot be applied to ");
  add_kind(m, v);
  return false;
}

// Binary operators: + - * / & | ^ && || and `..` (op "..": 'c', "&&": 'a', "||": 'o').
// A text result goes into `buf`; `out` may be empty (`..` of two numbers).
template <std::size_t B>
bool binary(char op, const Ref& l, const Ref& r, Ref& out, FixedString<B>& buf, Msg& m) noexcept {
  const std::string_view o = op == 'c'   ? std::string_view("..")
                             : op == 'a' ? std::string_view("&&")
                             : op == 'o' ? std::string_view("||")
                                         : std::string_view(&op, 1);
  if (l.none()) {
    m.add("the left operand of `").add(o).add("` has no value");
    return false;
  }
  if (r.none()) {
    m.add("the right operand of `").add(o).add("` has no value");
    return false;
  }
  if (l.is_number() && r.is_number()) {
    if (op == '+' || op == '-' || op == '*' || op == '/') {
      double a = 0.0, b = 0.0;
      Msg w;
      w.add("left operand of `").add(o).add("`");
      if (!number_to_double(l, a, m, w.view())) return false;
      Msg w2;
      w2.add("right operand of `").add(o).add("`");
      if (!number_to_double(r, b, m, w2.view())) return false;
      out = of_double(arith(op, a, b));
      return true;
    }
    if (op == '&' || op == '|' || op == '^') {
      std::int64_t a = 0, b = 0;
      Msg why;
      if (!number_to_int64(l, a, why) || !number_to_int64(r, b, why)) {
        m.add("`").add(o).add("` needs whole-number operands: ").add(why.view());
        return false;
      }
      const std::int64_t x = op == '&' ? (a & b) : op == '|' ? (a | b) : (a ^ b);
      out = of_double(static_cast<double>(x));
      return true;
    }
    if (op == 'a' || op == 'o') {
      bool a = false, b = false;
      Msg why;
      if (!number_to_bool(l, a, why) || !number_to_bool(r, b, why)) {
        m.add("`").add(o).add("` needs operands that convert to bool: ").add(why.view());
        return false;
      }
      out = of_double((op == 'a' ? (a && b) : (a || b)) ? 1.0 : 0.0);
      return true;
    }
    out = Ref{};  // `..` of two numbers: an empty value
    return true;
  }
  if ((op == '+' || op == 'c') && (l.is_string() || r.is_string()) && (op == 'c' || (l.is_string() && r.is_string())) &&
      (l.is_string() || l.is_number()) && (r.is_string() || r.is_number())) {
    NumberText lt, rt;
    const std::string_view a = to_text(l, lt);
    const std::string_view b = to_text(r, rt);
    if (a.size() + b.size() > B) {
      m.add("the text would be longer than ").add_int(static_cast<std::int64_t>(B)).add(" bytes");
      return false;
    }
    (void)buf.assign(a);
    (void)buf.append(b);
    out = of_string(buf.view());
    return true;
  }
  m.add("`").add(o).add("` cannot be applied to ");
  add_kind(m, l);
  m.add(" and ");
  add_kind(m, r);
  return false;
}

// `a op b` for op one of "==" "!=" "<" ">" "<=" ">=", given `equal`, the operands' equality
// (within FLT_EPSILON for numbers): 4.6.2's ExprComparison::SwitchImpl (lang/script/evaluate.py's
// _compare), whose orderings are negations (`<` is !(a >= b)).
template <class T>
bool compared(std::string_view op, bool equal, const T& a, const T& b) noexcept {
  if (op == "==") return equal;
  if (op == "!=") return !equal;
  if (op == "<") return !(a >= b);
  if (op == ">") return !(a <= b);
  if (op == "<=") return !(a > b);
  return !(a < b);
}

// Comparisons: op one of "==" "!=" "<" ">" "<=" ">=".
inline bool compare(std::string_view op, const Ref& l, const Ref& r, bool& res, Msg& m) noexcept {
  if (l.none()) {
    m.add("the left operand of `").add(op).add("` has no value");
    return false;
  }
  if (r.none()) {
    m.add("the right operand of `").add(op).add("` has no value");
    return false;
  }
  Msg lw, rw;
  lw.add("left operand of `").add(op).add("`");
  rw.add("right operand of `").add(op).add("`");
  if (l.is_string() && r.is_string()) {
    const std::string_view a = l.s, b = r.s;
    res = compared(op, a == b, a, b);
    return true;
  }
  double a = 0.0, b = 0.0;
  if (l.is_string() && r.is_number()) {
    if (!string_to_double(l.s, a, m) || !number_to_double(r, b, m, rw.view())) return false;
  } else if (l.is_number() && r.is_string()) {
    if (!number_to_double(l, a, m, lw.view()) || !string_to_double(r.s, b, m)) return false;
  } else {
    if (!number_to_double(l, a, m, lw.view()) || !number_to_double(r, b, m, rw.view())) return false;
  }
  res = compared(op, std::fabs(a - b) <= 1.1920928955078125e-07, a, b);
  return true;
}

// The condition of `?:` as a double.
inline bool condition(const Ref& v, double& x, Msg& m) noexcept {
  if (v.none()) {
    m.add("the condition of `?:` has no value");
    return false;
  }
  if (v.is_string()) {
    if (parse_double_from_chars(v.s, x) != Errc::kOk) {
      m.add("the condition of `?:` is the string ");
      add_string_repr(m, v.s);
      m.add(", which is not a number");
      return false;
    }
    return true;
  }
  return number_to_double(v, x, m, "condition of `?:`");
}

// An operand of `&&` / `||` as a bool.
inline bool logic_operand(std::string_view op, const Ref& v, bool& out, Msg& m) noexcept {
  Msg why;
  if (!number_to_bool(v, out, why)) {
    m.add("`").add(op).add("` needs operands that convert to bool: ").add(why.view());
    return false;
  }
  return true;
}

// script_truth: the last value of a condition script. Returns 1, 0 or -1 (m says why).
inline int truth(const Ref& v, Msg& m) noexcept {
  if (v.none()) {
    m.add("the script gives no value, so it cannot be used as a condition");
    return -1;
  }
  if (v.is_string()) {
    m.add("the script gives ");
    add_value(m, v);
    m.add(" (string), which is not a condition");
    return -1;
  }
  bool b = false;
  Msg why;
  if (!number_to_bool(v, b, why)) {
    m.add("the script's result cannot be used as a condition: ").add(why.view());
    return -1;
  }
  return b ? 1 : 0;
}

}  // namespace dyn

namespace dyn {

// The message of a script's `key := text` into an entry typed BT::Any (store_text_bt_any).
inline void add_bt_any_assign(Msg& m, std::string_view text, std::string_view key) noexcept {
  m.add("cannot assign ");
  add_string_repr(m, text);
  m.add(" to `").add(key).add("` (BT::Any): cannot convert ");
  add_string_repr(m, text);
  m.add(" to BT::Any: the library has no convertFromString for BT::Any");
}

}  // namespace dyn

// The value of a dynamic slot: what the entry holds, and its 4.6.2 type (`any`,
// `string` once a SetBlackboard literal typed it, or the T of a Blackboard::set<T>
// that found it untyped: a Loop's `value`, a port).
template <std::size_t N>
struct Dyn {
  DynTag tag = DynTag::kNone;
  bool typed_string = false;
  DynTag typed = DynTag::kNone;  // int, double, bool (NodeStatus): the type a typed write or copy gave it
  std::int64_t i = 0;
  double d = 0.0;
  FixedString<N> s{};

  [[nodiscard]] dyn::Ref ref() const noexcept {
    return dyn::Ref{tag, i, d, tag == DynTag::kString ? s.view() : std::string_view()};
  }
  // Holds `v` (false: a text longer than N, nothing changed).
  [[nodiscard]] bool set(const dyn::Ref& v) noexcept {
    if (v.tag == DynTag::kString && !s.assign(v.s)) return false;
    tag = v.tag;
    i = v.i;
    d = v.d;
    return true;
  }
};

namespace dyn {

template <std::size_t N>
Ref ref(const Slot<Dyn<N>>& slot) noexcept {
  if (!slot.exists || !slot.has_value) return Ref{};
  return slot.value.ref();
}

// The entry's declared type: kNone (`any`, or BT::Any: not strongly typed), kString,
// or the kInt, kDouble, kBool a typed write gave it (btgen::port::write), or the kInt,
// kDouble, kBool, kStatus of the source a copy created it with.
template <std::size_t N>
constexpr DynTag declared(const Slot<Dyn<N>>& slot) noexcept {
  return slot.value.typed_string ? DynTag::kString : slot.value.typed;
}

// The converter of an entry declared `type` (kInt, kDouble, kBool) applied to `text`.
template <bool kFromChars>
Errc convert_typed(DynTag type, std::string_view text, Ref& out) noexcept {
  Errc e = Errc::kInvalid;
  if (type == DynTag::kInt) {
    std::int64_t v = 0;
    e = convert_int(text, v);
    out = of_int(v);
  } else if (type == DynTag::kDouble) {
    double v = 0.0;
    e = convert_double<kFromChars>(text, v);
    out = of_double(v);
  } else if (type == DynTag::kBool) {
    bool v = false;
    e = parse_bool(text, v);
    out = of_bool(v);
  }
  return e;
}

// Whether the entry holds a string now (a script's text then replaces it as it is).
template <class T>
constexpr bool holds_text(const Slot<T>&) noexcept {
  return false;  // a number, a bool, a status, a queue
}
template <std::size_t N>
constexpr bool holds_text(const Slot<FixedString<N>>& slot) noexcept {
  return slot.has_value;
}
template <std::size_t N>
constexpr bool holds_text(const Slot<Dyn<N>>& slot) noexcept {
  return slot.has_value && slot.value.tag == DynTag::kString;
}

// A script's `key := text` (and `=`) into an entry typed BT::Any: one an `entry` port
// (WasEntryUpdated & co., InputPort<BT::Any>) created at load, or one 4.7.0's
// SetBlackboard string left empty. Unless it holds a string, the text goes through
// the entry's converter, convertFromString<BT::Any>, which throws.
template <class T>
bool store_text_bt_any(const Slot<T>& slot, std::string_view text, std::string_view key, Msg& m) noexcept {
  if (slot.entry_type != EntryType::kBtAny || holds_text(slot)) return true;
  add_bt_any_assign(m, text, key);
  return false;
}

// values.copy_into(value, destination): the value an entry holding `dst` gets.
// On failure `m` holds the reason ("a int cannot be stored where a string is").
inline bool copy_into(const Ref& value, const Ref& dst, Ref& out, Msg& m) noexcept {
  if (dst.none() || (value.is_string() && dst.is_string())) {
    out = value;
    return true;
  }
  if (value.is_number() && dst.is_number()) {
    if (dst.tag == DynTag::kDouble) {
      if (value.tag == DynTag::kDouble) {
        out = value;
        return true;
      }
      double x = 0.0;
      if (int_to_double(value.i, x) != Errc::kOk) {
        add_cast_error(m, value, "double", "precision would be lost");
        return false;
      }
      out = of_double(x);
      return true;
    }
    std::int64_t n = 0;
    if (value.tag == DynTag::kDouble) {
      if (!number_to_int64(value, n, m)) return false;
    } else {
      n = value.i;
    }
    if (dst.tag == DynTag::kBool && (n == 0 || n == 1)) {
      out = of_bool(n == 1);
    } else if (dst.tag == DynTag::kStatus && n >= 0 && n <= 4) {
      out = Ref{DynTag::kStatus, n, 0.0, {}};
    } else {
      out = of_int(n);
    }
    return true;
  }
  m.add("a ").add(type_name(value)).add(" cannot be stored where a ").add(type_name(dst)).add(" is");
  return false;
}

// The message of a script store that copy_into refused (`why`): "cannot assign
// V to `key`: why" after `:=` and `=`, "cannot store the result of `+=` in
// `key`: why" after an update.
inline void add_store_failure(Msg& m, std::string_view op, const Ref& v, std::string_view key,
                              const Msg& why) noexcept {
  if (op == ":=" || op == "=") {
    m.add("cannot assign ");
    add_value(m, v);
    m.add(" to `").add(key).add("`: ");
  } else {
    m.add("cannot store the result of `").add(op).add("` in `").add(key).add("`: ");
  }
  m.add(why.view());
}

// A script's string stored through the converter of the entry's declared type `type`
// (int, unsigned, double, bool), which gave `e` (parse_integer & co.): false, with the
// interpreter's message (script.py `_store`, values.convert_from_string), when it failed:
// "cannot assign 'x' to `k` (int): `x` is not a valid int".
inline bool converted_text(Errc e, std::string_view text, std::string_view key, std::string_view type,
                           Msg& m) noexcept {
  if (e == Errc::kOk) return true;
  m.add("cannot assign ");
  add_string_repr(m, text);
  m.add(" to `").add(key).add("` (").add(type).add("): ");
  add_conversion_error(m, text, type, e);
  return false;
}

// A number or bool of any C++ arithmetic type as a Ref.
template <class V>
Ref of_number(V v) noexcept {
  static_assert(std::is_arithmetic_v<V>, "a number or a bool");
  if constexpr (std::is_same_v<V, bool>) {
    return of_bool(v);
  } else if constexpr (std::is_integral_v<V>) {
    return of_int(static_cast<std::int64_t>(v));
  } else {
    return of_double(static_cast<double>(v));
  }
}

// Why Blackboard::set<T> of `value` failed on an entry declared T that held `held` (a
// 4.6.2 SetBlackboard copy left a string there; btgen::port::write of a Dyn slot):
// "cannot write 1.0 to `x`: a double cannot be stored where a string is".
inline void add_write_failure(Msg& m, const Ref& value, std::string_view key, const Ref& held) noexcept {
  Ref out;
  Msg why;
  (void)copy_into(value, held, out, why);
  m.add("cannot write ");
  add_value(m, value);
  m.add(" to `").add(key).add("`: ").add(why.view());
}

// A script store (`op`) of `value` into a statically typed entry whose kind `dst`
// stands for: copy_into, with the interpreter's message on failure.
inline bool store_into(const Ref& value, const Ref& dst, std::string_view op, std::string_view key, Ref& out,
                       Msg& m) noexcept {
  Msg why;
  if (copy_into(value, dst, out, why)) return true;
  add_store_failure(m, op, value, key, why);
  return false;
}

template <std::size_t N>
bool put(Slot<Dyn<N>>& slot, const Ref& v, std::string_view key, Msg& m) noexcept {
  if (!slot.value.set(v)) {
    m.add("the text does not fit `").add(key).add("` (capacity ").add_int(static_cast<std::int64_t>(N)).add(" bytes)");
    return false;
  }
  slot.mark_written();
  return true;
}

// A script's `key := value` (and `=`): the entry exists (`:=` created it).
template <bool kFromChars = false, std::size_t N = 0>
bool store(Slot<Dyn<N>>& slot, const Ref& value, std::string_view key, Msg& m) noexcept {
  // Typed BT::Any (an `entry` port's entry, or one a 4.7.0+ SetBlackboard string left so):
  // unless it holds a string, a string goes through BT::Any's converter, which throws.
  if (value.is_string() && !store_text_bt_any(slot, value.s, key, m)) return false;
  const Ref dst = ref(slot);
  Ref out = value;
  const DynTag type = declared(slot);
  if (dst.none() && type == DynTag::kNone) {
    return put(slot, out, key, m);
  }
  if (value.is_string() && !dst.is_string()) {
    if (type == DynTag::kString) {
      out = value;                                                  // the string converter gives the text itself
    } else if (type != DynTag::kNone && type != DynTag::kStatus) {  // int, double or bool: its converter
      const Errc e = convert_typed<kFromChars>(type, value.s, out);
      if (!converted_text(e, value.s, key, type_name(Ref{type, 0, 0.0, {}}), m)) return false;
    } else if (dst.is_number()) {
      double x = 0.0;
      if (!string_to_double(value.s, x, m)) return false;
      out = of_double(x);
    } else {
      m.add("cannot assign the string ");
      add_value(m, value);
      m.add(" to `").add(key).add("`, which holds ");
      add_kind(m, dst);
      return false;
    }
    return put(slot, out, key, m);
  }
  if (!store_into(value, dst, ":=", key, out, m)) return false;
  return put(slot, out, key, m);
}

// `+= -= *= /=` (op the first character) on an entry holding `current`; the result,
// to be stored into an entry holding `current`, is `out` (text in `buf`).
template <std::size_t B>
bool compound(char op, const Ref& current, const Ref& value, std::string_view key, Ref& out, FixedString<B>& buf,
              Msg& m) noexcept {
  const char opname[3] = {op, '=', '\0'};
  const std::string_view o(opname, 2);
  if (current.none()) {
    m.add("`").add(key).add("` has no value yet, so `").add(o).add("` cannot update it");
    return false;
  }
  Ref result = current;
  if (value.is_number()) {
    if (!current.is_number()) {
      m.add("`").add(o).add("` with a number needs a numeric `").add(key).add("`, but it holds ");
      add_kind(m, current);
      return false;
    }
    double a = 0.0, b = 0.0;
    Msg w;
    w.add("`").add(key).add("`");
    if (!number_to_double(current, a, m, w.view())) return false;
    Msg w2;
    w2.add("right operand of `").add(o).add("`");
    if (!number_to_double(value, b, m, w2.view())) return false;
    result = of_double(arith(op, a, b));
  } else if (value.is_string()) {
    if (op != '+') {
      m.add("`").add(o).add("` cannot be used with a string");
      return false;
    }
    NumberText t;
    const std::string_view a = to_text(current, t);
    if (a.size() + value.s.size() > B) {
      m.add("the text of `")
          .add(key)
          .add("` would be longer than its capacity (")
          .add_int(static_cast<std::int64_t>(B))
          .add(" bytes)");
      return false;
    }
    (void)buf.assign(a);
    (void)buf.append(value.s);
    result = of_string(buf.view());
  }
  return store_into(result, current, o, key, out, m);
}

// SetBlackboard value="text" (Blackboard::set<std::string>). The entry exists afterwards.
template <bool kFromChars = false, std::size_t N = 0>
bool set_literal(Slot<Dyn<N>>& slot, std::string_view text, std::string_view key, Msg& m) noexcept {
  Ref v = of_string(text);
  const DynTag type = declared(slot);
  if (!slot.exists) {
    slot.value.typed_string = false;  // a new entry of type `any`
    slot.value.typed = DynTag::kNone;
  } else if (type == DynTag::kStatus) {  // (NodeStatus has no converter)
    m.add("blackboard entry `").add(key).add("` is declared as NodeStatus; it cannot be written with a string");
    return false;
  } else if (type != DynTag::kNone && type != DynTag::kString) {
    // typed int, double or bool (a typed write): the entry's converter, then copyInto
    const Errc e = convert_typed<kFromChars>(type, text, v);
    if (e != Errc::kOk) {
      m.add("cannot write ");
      add_string_repr(m, text);
      m.add(" to `").add(key).add("` (").add(type_name(Ref{type, 0, 0.0, {}})).add("): ");
      add_conversion_error(m, text, type_name(Ref{type, 0, 0.0, {}}), e);
      return false;
    }
    Ref out;
    Msg why;
    if (!copy_into(v, ref(slot), out, why)) {
      m.add("cannot write ");
      add_string_repr(m, text);
      m.add(" to `").add(key).add("`: ").add(why.view());
      return false;
    }
    v = out;
  } else if (!slot.value.typed_string) {
    slot.value.typed_string = true;  // an `any` (or BT::Any) entry takes the type std::string
    if (slot.entry_type == EntryType::kBtAny) slot.entry_type = EntryType::kTyped;
  } else {
    Ref out;
    Msg why;
    if (!copy_into(v, ref(slot), out, why)) {
      m.add("cannot write ");
      add_value(m, v);
      m.add(" to `").add(key).add("`: ").add(why.view());
      return false;
    }
  }
  return put(slot, v, key, m);
}

// SetBlackboard value="{src}" into a dynamic entry, once the source exists: `src_string`
// says the source's type is std::string, `src_tag` that it is int, double, bool or
// NodeStatus (a new destination takes it). Returns 1 (copied), 0 (the source has no value:
// the node fails) or -1 (m says why).
template <std::size_t N>
int set_copy(Slot<Dyn<N>>& slot, const Ref& value, bool src_string, std::string_view key, Msg& m,
             DynTag src_tag = DynTag::kNone) noexcept {
  if (!slot.exists) {
    slot.exists = true;
    slot.has_value = false;
    slot.value.typed_string = src_string;
    slot.value.typed = src_string || src_tag == DynTag::kString ? DynTag::kNone : src_tag;
  }
  if (value.none()) return 0;
  // 4.6.2 copies the value as it is (`dst_entry->value = src_entry->value`), into an entry
  // declared std::string too: the entry keeps its type (typed_string) and holds the value.
  return put(slot, value, key, m) ? 1 : -1;
}

}  // namespace dyn
}  // namespace btgen

// SetBlackboard into a dynamic entry, 4.7.0 and later
#include "btgen/dynamic/set410.hpp"  // IWYU pragma: export
