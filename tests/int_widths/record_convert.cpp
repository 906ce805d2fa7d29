// Records what BehaviorTree.CPP's convertFromString<T> gives for integer types of every width
// (issue 37: `uint16` error codes, `int64_t` ports). Built against the oracle library:
//
//   g++ -std=c++17 record_convert.cpp -I PREFIX/include -L PREFIX/lib -lbehaviortree_cpp \
//       -Wl,-rpath,PREFIX/lib -o record && ./record > convert-VERSION.txt
//
// One line per (type, input): `TYPE <TAB> INPUT <TAB> value` or `TYPE <TAB> INPUT <TAB> error`
// (the text is written as a C string literal would be; test_int_widths.py reads this file).
#include <behaviortree_cpp/basic_types.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace {

const std::vector<std::string> kInputs = {"0",
                                          "1",
                                          "-1",
                                          "+1",
                                          " 1",
                                          "1 ",
                                          "1.5",
                                          "0x10",
                                          "abc",
                                          "",
                                          "127",
                                          "128",
                                          "-128",
                                          "-129",
                                          "255",
                                          "256",
                                          "32767",
                                          "32768",
                                          "-32768",
                                          "-32769",
                                          "65535",
                                          "65536",
                                          "2147483647",
                                          "2147483648",
                                          "-2147483648",
                                          "-2147483649",
                                          "4294967295",
                                          "4294967296",
                                          "9223372036854775807",
                                          "9223372036854775808",
                                          "-9223372036854775808",
                                          "-9223372036854775809",
                                          "18446744073709551615",
                                          "18446744073709551616"};

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

template <class T>
void record(const char* name) {
  for (const std::string& input : kInputs) {
    std::string result;
    try {
      const T v = BT::convertFromString<T>(input);
      if constexpr (std::is_signed_v<T>) {
        result = std::to_string(static_cast<long long>(v));
      } else {
        result = std::to_string(static_cast<unsigned long long>(v));
      }
    } catch (const std::exception&) {
      result = "error";
    }
    std::printf("%s\t%s\t%s\n", name, quoted(input).c_str(), result.c_str());
  }
}

}  // namespace

int main() {
  record<int8_t>("int8_t");
  record<int16_t>("int16_t");
  record<int32_t>("int32_t");
  record<int64_t>("int64_t");
  record<uint8_t>("uint8_t");
  record<uint16_t>("uint16_t");
  record<uint32_t>("uint32_t");
  record<uint64_t>("uint64_t");
  return 0;
}
