// btgen runtime: SetBlackboard into a dynamic blackboard slot under BehaviorTree.CPP 4.7.0
// and later (a part of btgen/dynamic.hpp, which includes it at its end; including this
// header alone includes the rest).
#pragma once

#include "btgen/dynamic.hpp"

namespace btgen {
namespace dyn {

// ------------------------------------------------------------ SetBlackboard, 4.7.0 and later
//
// SetBlackboard into a dynamic entry no port declared, from BehaviorTree.CPP 4.7.0
// (Semantics::setblackboard_converts_to_entry_type; lang/blackboard.py set_blackboard_410
// is the reference). The entry's own type is Slot::entry_type: kUntyped (created by a
// Script, an untyped port, a SubTree text literal), kTyped (std::string: created by a
// SetBlackboard literal, or copied from such an entry, as Dyn::typed_string says; or the
// int, double or bool of Dyn::typed, given by a typed write or a copy from an entry a port
// typed), kBtAny (left so by a string below). A string is converted with the entry's converter:
// an untyped entry has none and receives an empty value; BT::Any's throws. The write is
// Blackboard::set<BT::Any>: an entry on the node's own blackboard (`local`) that is not
// strongly typed becomes BT::Any; a std::string one refuses another type; one reached
// through a SubTree remapping keeps its type. Each returns 1 (SUCCESS), 0 (FAILURE: the
// value to copy is empty) or -1 (m says why, after the node's prefix).

// `raw`: the `value` port as written, for the conversion message; `key`: the output_key
// as written; `entry_key`: the entry's key on the blackboard that holds it.
struct SetNames410 {
  std::string_view raw;
  std::string_view key;
  std::string_view entry_key;
};

template <bool kFromChars, std::size_t N>
int set_value_410(Slot<Dyn<N>>& slot, Ref out, bool local, const SetNames410& names, Msg& m) noexcept {
  // The entry's own type: a typed write's int, double or bool, or std::string (kTyped).
  DynTag type = declared(slot);
  if (type == DynTag::kNone && slot.entry_type == EntryType::kTyped) type = DynTag::kString;
  if (type != DynTag::kString && out.is_string()) {
    if (type != DynTag::kNone && type != DynTag::kStatus) {  // TypeInfo::parseString: its converter
      const std::string_view text = out.s;
      const Errc e = convert_typed<kFromChars>(type, text, out);
      if (e != Errc::kOk) {
        m.add("SetBlackboard: cannot convert ");
        add_string_repr(m, names.raw);
        m.add(": ");
        add_conversion_error(m, text, type_name(Ref{type, 0, 0.0, {}}), e);
        return -1;
      }
    } else if (slot.entry_type == EntryType::kBtAny) {
      m.add("SetBlackboard: cannot convert ");
      add_string_repr(m, names.raw);
      m.add(": cannot convert ");
      add_string_repr(m, out.s);
      m.add(" to BT::Any: the library has no convertFromString for BT::Any");
      return -1;
    } else {
      out = Ref{};  // TypeInfo::parseString without a converter (untyped, NodeStatus): empty
    }
  }
  if (type != DynTag::kNone && !out.none() && out.tag != type) {
    const std::string_view declared_name = type_name(Ref{type, 0, 0.0, {}});
    if (local) {
      m.add("SetBlackboard: blackboard entry `")
          .add(names.key)
          .add("` is declared as ")
          .add(declared_name)
          .add("; it cannot be written with a ");
    } else {
      m.add("blackboard entry `")
          .add(names.entry_key)
          .add("` is declared as ")
          .add(declared_name)
          .add("; it cannot be used as ");
    }
    m.add(type_name(out));
    return -1;
  }
  if (local && type == DynTag::kNone) {
    slot.entry_type = EntryType::kBtAny;
    slot.value.typed_string = false;
  }
  if (out.none()) {
    slot.value.tag = DynTag::kNone;
    slot.exists = true;
    slot.has_value = false;
    ++slot.seq;
    return 1;
  }
  return put(slot, out, names.key, m) ? 1 : -1;
}

// SetBlackboard value="text".
template <bool kFromChars = false, std::size_t N = 0>
int set_text_410(Slot<Dyn<N>>& slot, std::string_view text, bool local, const SetNames410& names, Msg& m) noexcept {
  if (!slot.exists) {  // a new entry takes the value's type, std::string
    slot.exists = true;
    slot.has_value = false;
    slot.entry_type = EntryType::kTyped;
    slot.value.typed_string = true;
    slot.value.typed = DynTag::kNone;
  }
  return set_value_410<kFromChars>(slot, of_string(text), local, names, m);
}

// SetBlackboard value="{src}" once the source exists: `value` is what it holds, `src_type`
// its own type (a missing destination is created with it): kTyped is std::string, unless
// `src_tag` names the int, double or bool of a source a port or a typed write declared.
template <bool kFromChars = false, std::size_t N = 0>
int set_copy_410(Slot<Dyn<N>>& slot, const Ref& value, EntryType src_type, bool local, const SetNames410& names, Msg& m,
                 DynTag src_tag = DynTag::kNone) noexcept {
  if (!slot.exists) {
    const bool number = src_type == EntryType::kTyped && src_tag != DynTag::kNone && src_tag != DynTag::kString;
    slot.exists = true;
    slot.has_value = false;
    slot.value.tag = DynTag::kNone;
    slot.entry_type = src_type;
    slot.value.typed_string = src_type == EntryType::kTyped && !number;
    slot.value.typed = number ? src_tag : DynTag::kNone;
  }
  if (value.none()) return 0;
  return set_value_410<kFromChars>(slot, value, local, names, m);
}

}  // namespace dyn
}  // namespace btgen
