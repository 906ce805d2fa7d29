// btgen runtime: the MessagePack Groot2's BLACKBOARD replies carry, as nlohmann::json's
// to_msgpack writes BehaviorTree.CPP's blackboard export, and one slot's value in it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "btgen/blackboard.hpp"
#include "btgen/dynamic.hpp"
#include "btgen/fixed_string.hpp"

namespace btgen::groot2 {

// MessagePack, as nlohmann::json::to_msgpack writes what the blackboard export holds.
class MsgPack {
 public:
  std::string out;

  void nil() { out.push_back(static_cast<char>(0xc0)); }
  void integer(std::int64_t v) {
    if (v >= 0) {
      const auto u = static_cast<std::uint64_t>(v);
      if (u < 128)
        byte(static_cast<std::uint8_t>(u));
      else if (u <= 0xFF) {
        byte(0xcc);
        be(u, 1);
      } else if (u <= 0xFFFF) {
        byte(0xcd);
        be(u, 2);
      } else if (u <= 0xFFFFFFFFu) {
        byte(0xce);
        be(u, 4);
      } else {
        byte(0xcf);
        be(u, 8);
      }
    } else if (v >= -32) {
      byte(static_cast<std::uint8_t>(static_cast<std::int8_t>(v)));
    } else if (v >= INT8_MIN) {
      byte(0xd0);
      be(static_cast<std::uint64_t>(v), 1);
    } else if (v >= INT16_MIN) {
      byte(0xd1);
      be(static_cast<std::uint64_t>(v), 2);
    } else if (v >= INT32_MIN) {
      byte(0xd2);
      be(static_cast<std::uint64_t>(v), 4);
    } else {
      byte(0xd3);
      be(static_cast<std::uint64_t>(v), 8);
    }
  }
  void real(double v) {
    const auto f = static_cast<float>(v);
    if (static_cast<double>(f) == v) {  // nlohmann writes a float32 when nothing is lost
      std::uint32_t bits;
      std::memcpy(&bits, &f, 4);
      byte(0xca);
      be(bits, 4);
    } else {
      std::uint64_t bits;
      std::memcpy(&bits, &v, 8);
      byte(0xcb);
      be(bits, 8);
    }
  }
  void str(std::string_view s) {
    const std::size_t n = s.size();
    if (n < 32)
      byte(static_cast<std::uint8_t>(0xa0 | n));
    else if (n <= 0xFF) {
      byte(0xd9);
      be(n, 1);
    } else if (n <= 0xFFFF) {
      byte(0xda);
      be(n, 2);
    } else {
      byte(0xdb);
      be(n, 4);
    }
    out.append(s.data(), n);
  }
  void map(std::size_t n) {
    if (n < 16)
      byte(static_cast<std::uint8_t>(0x80 | n));
    else if (n <= 0xFFFF) {
      byte(0xde);
      be(n, 2);
    } else {
      byte(0xdf);
      be(n, 4);
    }
  }

 private:
  void byte(std::uint8_t b) { out.push_back(static_cast<char>(b)); }
  void be(std::uint64_t v, int n) {
    for (int i = n - 1; i >= 0; --i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
  }
};

namespace detail {

template <class T>
struct is_fixed_string : std::false_type {};
template <std::size_t N>
struct is_fixed_string<FixedString<N>> : std::true_type {};
template <class T>
struct is_dyn : std::false_type {};
template <std::size_t N>
struct is_dyn<Dyn<N>> : std::true_type {};

// One entry's value as 4.6.2's ExportBlackboardToJSON writes it.
template <class T>
void write_value(MsgPack& mp, const Slot<T>& slot) {
  if (!slot.has_value) return mp.nil();
  const T& v = slot.value;
  if constexpr (std::is_same_v<T, bool> || std::is_integral_v<T>) {
    mp.integer(static_cast<std::int64_t>(v));  // 4.6.2's Any holds every integral as int64
  } else if constexpr (std::is_floating_point_v<T>) {
    mp.real(static_cast<double>(v));
  } else if constexpr (is_fixed_string<T>::value) {
    mp.str(v.view());
  } else if constexpr (is_dyn<T>::value) {
    switch (v.tag) {
      case DynTag::kInt:
      case DynTag::kBool: return mp.integer(v.i);
      case DynTag::kDouble: return mp.real(v.d);
      case DynTag::kString: return mp.str(v.s.view());
      default: return mp.nil();
    }
  } else {
    mp.nil();  // NodeStatus, queues: 4.6.2 has no JSON converter for them
  }
}

}  // namespace detail
}  // namespace btgen::groot2
