// The runtime's dynamic values (btgen/dynamic.hpp): 4.6.2's operations on values whose type is
// known at run time only, with the reference interpreter's messages (btgen/lang/script.py, values.py).
#include <gtest/gtest.h>

#include <string>

#include "btgen/dynamic.hpp"
#include "btgen/port.hpp"

namespace {

using btgen::Dyn;
using btgen::Slot;
namespace dyn = btgen::dyn;

std::string text(const dyn::Msg& m) { return std::string(m.view()); }

TEST(Dynamic, ValuesAreDescribedAsPythonReprDoes) {
  dyn::Msg m;
  dyn::add_value(m, dyn::of_double(2.5));
  m.add(" ");
  dyn::add_value(m, dyn::of_double(1e16));
  m.add(" ");
  dyn::add_value(m, dyn::of_double(7.0));
  m.add(" ");
  dyn::add_value(m, dyn::of_string("it's"));
  m.add(" ");
  dyn::add_value(m, dyn::of_int(-3));
  EXPECT_EQ(text(m), "2.5 1e+16 7.0 \"it's\" -3");
}

TEST(Dynamic, AssigningAStringToANumberReadsItAsANumber) {
  Slot<Dyn<8>> x;
  dyn::Msg m;
  ASSERT_TRUE(dyn::store(x, dyn::of_int(5), "x", m));
  ASSERT_TRUE(dyn::store(x, dyn::of_string("7"), "x", m));
  EXPECT_EQ(x.value.tag, btgen::DynTag::kDouble);
  EXPECT_EQ(x.value.d, 7.0);
  dyn::Msg e("P: ");
  EXPECT_FALSE(dyn::store(x, dyn::of_string("abc"), "x", e));
  EXPECT_EQ(text(e), "P: the string 'abc' is not a number");
}

TEST(Dynamic, SetBlackboardTypesAnEntryAsAString) {
  Slot<Dyn<8>> x;
  dyn::Msg m;
  ASSERT_TRUE(dyn::store(x, dyn::of_int(5), "x", m));
  ASSERT_TRUE(dyn::set_literal(x, "7", "x", m));
  EXPECT_EQ(x.value.tag, btgen::DynTag::kString);
  EXPECT_TRUE(x.value.typed_string);
  EXPECT_EQ(x.seq, 2u);
  dyn::Msg e;
  EXPECT_FALSE(dyn::store(x, dyn::of_int(2), "x", e));
  EXPECT_EQ(text(e), "cannot assign 2 to `x`: a int cannot be stored where a string is");
  // A typed port reads the text with convertFromString.
  const btgen::Input<std::int32_t> n = btgen::port::read<std::int32_t, false>(x);
  ASSERT_TRUE(n.has_value());
  EXPECT_EQ(n.value(), 7);
  x.unset();
  EXPECT_FALSE(x.value.typed_string);
}

TEST(Dynamic, OperatorsFollowTheKindsFoundAtRunTime) {
  btgen::FixedString<16> buf;
  dyn::Ref out;
  dyn::Msg m;
  ASSERT_TRUE(dyn::binary('c', dyn::of_string("a"), dyn::of_double(2.5), out, buf, m));
  EXPECT_EQ(out.s, "a2.500000");
  ASSERT_TRUE(dyn::binary('c', dyn::of_int(1), dyn::of_int(2), out, buf, m));
  EXPECT_TRUE(out.none());  // `..` of two numbers gives no value
  dyn::Msg e;
  EXPECT_FALSE(dyn::binary('+', dyn::of_string("a"), dyn::of_int(1), out, buf, e));
  EXPECT_EQ(text(e), "`+` cannot be applied to a string and a int");
  bool res = false;
  ASSERT_TRUE(dyn::compare("==", dyn::of_string("7"), dyn::of_int(7), res, m));
  EXPECT_TRUE(res);
  dyn::Msg e2;
  EXPECT_FALSE(dyn::logic_operand("&&", dyn::of_int(3), res, e2));
  EXPECT_EQ(text(e2),
            "`&&` needs operands that convert to bool: cannot convert 3 (int) to bool: only the "
            "integers 0 and 1 convert to bool");
  dyn::Msg e3;
  EXPECT_EQ(dyn::truth(dyn::of_string("x"), e3), -1);
  EXPECT_EQ(text(e3), "the script gives 'x' (string), which is not a condition");
}

}  // namespace

// BehaviorTree.CPP 4.10.0's SetBlackboard of a string into an entry no port declared
// (btgen::set_string_410): the entry's run-time type decides, as blackboard.set_blackboard_410.
namespace v410 {

TEST(EntryType410, AnUntypedEntryIsLeftEmptyThenTypedBtAnyThenThrows) {
  Slot<btgen::FixedString<8>> s;
  s.exists = true;  // created untyped (a Script, an untyped port)
  s.has_value = true;
  (void)s.value.assign("old");
  s.seq = 3;
  EXPECT_EQ(btgen::set_string_410(s, btgen::EntryType::kTyped, true), 0);
  EXPECT_FALSE(s.has_value);
  EXPECT_EQ(s.seq, 4u);  // an update all the same
  EXPECT_EQ(s.entry_type, btgen::EntryType::kBtAny);
  EXPECT_EQ(btgen::set_string_410(s, btgen::EntryType::kTyped, true), -1);
  dyn::Msg m("script error: ");
  EXPECT_FALSE(dyn::store_text_bt_any(s, "c", "mode", m));
  EXPECT_EQ(text(m),
            "script error: cannot assign 'c' to `mode` (BT::Any): cannot convert 'c' to BT::Any: the library has no "
            "convertFromString for BT::Any");
  // Holding a string, a BT::Any entry takes a script's text as it is (Any::copyInto).
  s.has_value = true;
  dyn::Msg ok;
  EXPECT_TRUE(dyn::store_text_bt_any(s, "d", "mode", ok));
  s.unset();  // UnsetBlackboard: a new entry starts untyped
  EXPECT_EQ(s.entry_type, btgen::EntryType::kUntyped);
}

TEST(EntryTypeBtAny, AnEntryPortsEntryRefusesTextUnlessItHoldsText) {
  // WasEntryUpdated's `entry` port creates its entry typed BT::Any (row E1): a number stored
  // there keeps that type, and a script's text then goes through convertFromString<BT::Any>.
  Slot<std::int64_t> n{{}, 0, true, false, btgen::EntryType::kBtAny};
  dyn::Msg m;
  EXPECT_FALSE(dyn::store_text_bt_any(n, "x", "state", m));
  n.value = 3;
  n.mark_written();
  dyn::Msg m2;
  EXPECT_FALSE(dyn::store_text_bt_any(n, "x", "state", m2));
  Slot<btgen::Dyn<8>> d{{}, 0, true, false, btgen::EntryType::kBtAny};
  ASSERT_TRUE(d.value.set(dyn::of_string("a")));
  d.mark_written();
  dyn::Msg m3;
  EXPECT_TRUE(dyn::store_text_bt_any(d, "b", "state", m3));  // it holds a string
  ASSERT_TRUE(d.value.set(dyn::of_int(1)));
  EXPECT_FALSE(dyn::store_text_bt_any(d, "b", "state", m3));
  n.entry_type = btgen::EntryType::kUntyped;
  dyn::Msg m4;
  EXPECT_TRUE(dyn::store_text_bt_any(n, "x", "state", m4));  // not BT::Any: other rules apply
}

TEST(EntryType410, ANewEntryIsTypedAndARemappedOneStaysUntyped) {
  Slot<btgen::FixedString<8>> fresh;
  EXPECT_EQ(btgen::set_string_410(fresh, btgen::EntryType::kTyped, true), 1);
  EXPECT_TRUE(fresh.exists);
  EXPECT_EQ(btgen::set_string_410(fresh, btgen::EntryType::kTyped, true), 1);
  Slot<btgen::FixedString<8>> remapped;
  remapped.exists = true;
  EXPECT_EQ(btgen::set_string_410(remapped, btgen::EntryType::kTyped, false), 0);
  EXPECT_EQ(btgen::set_string_410(remapped, btgen::EntryType::kTyped, false), 0);
  EXPECT_EQ(remapped.entry_type, btgen::EntryType::kUntyped);
}

TEST(EntryType410, APortWriteTypesAnExistingUntypedEntryOnly) {
  Slot<btgen::FixedString<8>> s;
  ASSERT_EQ(btgen::port::write<true>(s, btgen::Declared::kAny, std::string_view("a")), btgen::Errc::kOk);
  EXPECT_EQ(s.entry_type, btgen::EntryType::kUntyped);  // Blackboard::set<std::string> creates it untyped
  ASSERT_EQ(btgen::port::write<true>(s, btgen::Declared::kAny, std::string_view("b")), btgen::Errc::kOk);
  EXPECT_EQ(s.entry_type, btgen::EntryType::kTyped);
  EXPECT_EQ(btgen::set_string_410(s, btgen::EntryType::kTyped, true), 1);
}

TEST(EntryType410, ALoopQueueIsTheTextConvertedWhenItStarts) {
  btgen::port::TextQueue<16> q;
  dyn::Msg m;
  ASSERT_TRUE((btgen::port::load_queue<std::int64_t, true>(q, "3;4;", "int", m)));
  std::int64_t v = 0;
  ASSERT_TRUE(btgen::port::queue_element<true>(q.front(), v));
  EXPECT_EQ(v, 3);
  q.pop_front();
  ASSERT_TRUE(btgen::port::queue_element<true>(q.front(), v));
  EXPECT_EQ(v, 4);
  q.pop_front();
  EXPECT_TRUE(q.empty());  // no element after a final `;`
  ASSERT_TRUE((btgen::port::load_queue<std::int64_t, true>(q, "", "int", m)));
  EXPECT_TRUE(q.empty());
  dyn::Msg bad("p: ");
  EXPECT_FALSE((btgen::port::load_queue<double, true>(q, "0.5;+1.5", "double", bad)));
  EXPECT_EQ(text(bad), "p: `0.5;+1.5` is not a valid queue<double>: element 2: `+1.5` is not a valid double");
  dyn::Msg range;
  EXPECT_FALSE((btgen::port::load_queue<std::int64_t, true>(q, "1;3000000000", "int", range)));
  EXPECT_EQ(text(range),
            "`1;3000000000` is not a valid queue<int>: element 2: `3000000000` is out of range for int (-2147483648 to "
            "2147483647)");
}

}  // namespace v410

namespace copied_string {

using btgen::Dyn;
using btgen::Slot;
namespace dyn = btgen::dyn;

// A typed entry a 4.6.2 SetBlackboard copy may leave holding a string (a Dyn slot): a port's
// Blackboard::set<T> is Any::copyInto into what it holds (values.copy_into).
TEST(CopiedString, ATypedWriteCopiesIntoWhatTheEntryHolds) {
  Slot<Dyn<8>> x{{}, 0, true, false};  // created at load by the port, no value
  ASSERT_EQ(btgen::port::write<true>(x, btgen::Declared::kDouble, 1.5), btgen::Errc::kOk);
  EXPECT_EQ(x.value.tag, btgen::DynTag::kDouble);
  EXPECT_EQ(x.value.d, 1.5);
  EXPECT_EQ(x.seq, 1u);
  ASSERT_TRUE(x.value.set(dyn::of_int(3)));  // an integer there: a double converts to it when whole
  ASSERT_EQ(btgen::port::write<true>(x, btgen::Declared::kDouble, 4.0), btgen::Errc::kOk);
  EXPECT_EQ(x.value.tag, btgen::DynTag::kInt);
  EXPECT_EQ(x.value.i, 4);
  ASSERT_TRUE(x.value.set(dyn::of_string("8.5")));  // what the copy left
  const dyn::Ref held = dyn::ref(x);
  EXPECT_EQ(btgen::port::write<true>(x, btgen::Declared::kDouble, 1.0), btgen::Errc::kInvalid);
  EXPECT_EQ(dyn::ref(x).s, "8.5");  // unchanged
  EXPECT_EQ(x.seq, 2u);
  dyn::Msg m("`LoopDouble` \"L\": ");
  dyn::add_write_failure(m, dyn::of_number(1.0), "x", held);
  EXPECT_EQ(std::string(m.view()),
            "`LoopDouble` \"L\": cannot write 1.0 to `x`: a double cannot be stored where a string is");
  Slot<Dyn<8>> n{{}, 0, true, false};
  ASSERT_EQ(btgen::port::write<true>(n, btgen::Declared::kInt, std::int32_t{7}), btgen::Errc::kOk);
  EXPECT_EQ(n.value.tag, btgen::DynTag::kInt);
  EXPECT_EQ(n.value.i, 7);
}

}  // namespace copied_string

namespace typed_write {

using btgen::Dyn;
using btgen::Slot;
namespace dyn = btgen::dyn;

// Blackboard::set<T> into an entry of changing type (lang/blackboard.py Blackboard.set; the
// table of tests/python/test_typed_writes.py runs both engines over more cases).
TEST(TypedWrite, AnUntypedEntryTakesTheTypeThenConvertsOrRefuses) {
  Slot<Dyn<8>> v;
  dyn::Msg m;
  ASSERT_TRUE(dyn::store(v, dyn::of_string("abc"), "v", m));  // a script: untyped, a string
  ASSERT_TRUE(btgen::port::write<false>(v, btgen::Declared::kAny, std::int32_t{5}, "v", m));
  EXPECT_EQ(dyn::declared(v), btgen::DynTag::kInt);
  EXPECT_EQ(v.entry_type, btgen::EntryType::kTyped);
  EXPECT_EQ(v.value.i, 5);
  ASSERT_TRUE(btgen::port::write<false>(v, btgen::Declared::kAny, 2.0, "v", m));  // fits: stored as 2
  EXPECT_EQ(v.value.tag, btgen::DynTag::kInt);
  EXPECT_EQ(v.value.i, 2);
  ASSERT_TRUE(btgen::port::write<false>(v, btgen::Declared::kAny, std::string_view("8"), "v", m));
  EXPECT_EQ(v.value.i, 8);
  dyn::Msg e("P: ");
  EXPECT_FALSE(btgen::port::write<false>(v, btgen::Declared::kAny, 2.5, "v", e));
  EXPECT_EQ(std::string(e.view()), "P: blackboard entry `v` is declared as int; it cannot be written with a double");
  dyn::Msg t;
  EXPECT_FALSE(btgen::port::write<false>(v, btgen::Declared::kAny, std::string_view("x"), "v", t));
  EXPECT_EQ(std::string(t.view()), "cannot write 'x' to `v` (int): `x` is not a valid int");
  EXPECT_TRUE(btgen::port::write<false>(v, btgen::Declared::kAny, false, "v", m));  // 4.6.2: 0
  dyn::Msg f;
  EXPECT_FALSE((btgen::port::write<false, true>(v, btgen::Declared::kAny, false, "v", f)));  // 4.10.0
  EXPECT_EQ(v.seq, 5u);
}

TEST(TypedWrite, ScriptsAndLiteralsThenGoThroughTheConverter) {
  Slot<Dyn<8>> v;
  dyn::Msg m;
  ASSERT_TRUE(btgen::port::write<false>(v, btgen::Declared::kAny, 1.5, "v", m));  // a new entry: double
  ASSERT_TRUE(dyn::store<false>(v, dyn::of_string("2.5"), "v", m));
  EXPECT_EQ(v.value.tag, btgen::DynTag::kDouble);
  EXPECT_EQ(v.value.d, 2.5);
  dyn::Msg e;
  EXPECT_FALSE(dyn::store<false>(v, dyn::of_string("x"), "v", e));
  EXPECT_EQ(std::string(e.view()), "cannot assign 'x' to `v` (double): `x` is not a valid double");
  ASSERT_TRUE(dyn::set_literal<false>(v, "7", "v", m));
  EXPECT_EQ(v.value.d, 7.0);
  dyn::Msg l;
  EXPECT_FALSE(dyn::set_literal<false>(v, "abc", "v", l));
  EXPECT_EQ(std::string(l.view()), "cannot write 'abc' to `v` (double): `abc` is not a valid double");
  // 4.10.0's SetBlackboard converts with the same converter
  dyn::Msg s("SB: ");
  const dyn::SetNames410 names{"abc", "v", "v"};
  EXPECT_EQ(dyn::set_text_410<false>(v, "abc", true, names, s), -1);
  EXPECT_EQ(std::string(s.view()), "SB: SetBlackboard: cannot convert 'abc': `abc` is not a valid double");
}

TEST(TypedWrite, ACopyCreatesAMissingEntryWithTheSourcesType) {
  Slot<Dyn<8>> v;
  dyn::Msg m;
  ASSERT_EQ(dyn::set_copy(v, dyn::of_int(5), false, "v", m, btgen::DynTag::kInt), 1);
  EXPECT_EQ(dyn::declared(v), btgen::DynTag::kInt);
  dyn::Msg e;
  EXPECT_FALSE(dyn::store(v, dyn::of_string("x"), "v", e));
  EXPECT_EQ(std::string(e.view()), "cannot assign 'x' to `v` (int): `x` is not a valid int");
  v.unset();
  EXPECT_EQ(dyn::declared(v), btgen::DynTag::kNone);
}

}  // namespace typed_write
