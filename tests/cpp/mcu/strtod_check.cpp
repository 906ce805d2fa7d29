// The bare-metal build's strtod (btgen::value_detail::exact_strtod, used under
// BTGEN_BARE_METAL where newlib's strtod allocates) against the host's strtod:
// halfway cases, subnormals, overflow, long mantissas, hexadecimal literals and
// random decimal literals. (Not hexadecimal literals whose value is subnormal:
// glibc 2.36 rounds some of them differently from Python's float.fromhex and
// from exact_strtod, e.g. 0xc12adf17599f94p-1079, and btgen never uses such a
// value: std::stod, the one reader of hexadecimal text, rejects subnormal
// results.) Built and run by tests/python/test_bare_metal_text.py:
//     strtod_check [N]   # N random literals of each form (default 100000)
// prints the mismatches (at most 10) and exits 1 when there is one.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "btgen/value.hpp"

int main(int argc, char** argv) {
  std::mt19937_64 rng(7);
  long bad = 0, n = 0;
  auto check = [&](const std::string& text) {
    const double want = std::strtod(text.c_str(), nullptr);
    const double got = btgen::value_detail::exact_strtod(text);
    const bool hex = text.find('x') != std::string::npos;
    if (hex && want != 0 && std::fabs(want) < 2.2250738585072014e-308) return;
    ++n;
    std::uint64_t a = 0, b = 0;
    std::memcpy(&a, &want, 8);
    std::memcpy(&b, &got, 8);
    if (a != b && bad++ < 10) std::printf("%s: %a vs %a\n", text.c_str(), want, got);
  };
  const char* fixed[] = {"0",
                         "-0",
                         "1",
                         "0.1",
                         "2.5",
                         "9007199254740993",
                         "9007199254740995",
                         "2.2250738585072011e-308",
                         "2.2250738585072014e-308",
                         "4.9406564584124654e-324",
                         "2.4703282292062327e-324",
                         "2.4703282292062328e-324",
                         "1e-400",
                         "1.7976931348623157e308",
                         "1.7976931348623158e308",
                         "1.7976931348623159e308",
                         "1e309",
                         "123456789012345678901234567890e-20",
                         "0.000000000000000000000000000000000000001e39",
                         "0x1p-1074",
                         "0x1.fffffffffffff8p0",
                         "0x1.fffffffffffff7p0",
                         "0x.8p1",
                         "0xAB.CDp-3",
                         "0x1p1024",
                         "inf",
                         "-Infinity",
                         ".5e1",
                         "5.",
                         "+7e+2"};
  for (const char* f : fixed) check(f);
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 100000;
  const char* hexd = "0123456789abcdef";
  for (int r = 0; r < rounds; ++r) {
    std::string s = (rng() & 1) ? "-" : "";
    const int digits = 1 + static_cast<int>(rng() % (r % 50 == 0 ? 500 : 25));
    const int point = static_cast<int>(rng() % (digits + 1));
    for (int d = 0; d < digits; ++d) {
      if (d == point) s += '.';
      s += static_cast<char>('0' + rng() % 10);
    }
    s += 'e' + std::to_string(static_cast<int>(rng() % 700) - 350);
    check(s);
    // A double's shortest text and its neighbours' halfway points.
    std::uint64_t bits = rng();
    double v = 0;
    std::memcpy(&v, &bits, 8);
    if (std::isfinite(v)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", v);
      check(buf);
      std::snprintf(buf, sizeof buf, "%.25e", v);
      check(buf);
    }
    std::string h = "0x";
    const int hd = 1 + static_cast<int>(rng() % 20);
    for (int d = 0; d < hd; ++d) h += hexd[rng() % 16];
    h += 'p' + std::to_string(static_cast<int>(rng() % 2200) - 1100);
    check(h);
  }
  std::printf("checked %ld bad %ld\n", n, bad);
  return bad != 0;
}
