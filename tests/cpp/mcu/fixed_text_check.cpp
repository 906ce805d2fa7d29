// The bare-metal build's "%f" (btgen::value_detail::format_fixed6, used under
// BTGEN_BARE_METAL where newlib-nano's printf has no %f) against the host's
// printf: special values, ties, subnormals, extremes and random bit patterns.
// Built and run by tests/python/test_mcu.py with the host compiler:
//     fixed_text_check [N]   # N rounds of random values (default 200000)
// prints the mismatches (at most 10) and exits 1 when there is one.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include "btgen/value.hpp"
int main(int argc, char** argv) {
  std::mt19937_64 rng(42);
  long bad = 0, n = 0;
  auto check = [&](double v) {
    if (std::isnan(v)) return;
    char a[400], b[400];
    std::snprintf(a, sizeof a, "%f", v);
    std::size_t k = btgen::value_detail::format_fixed6(v, b, sizeof b);
    b[k] = 0;
    ++n;
    if (std::strcmp(a, b) != 0) {
      if (bad++ < 10) std::printf("%a: %s vs %s\n", v, a, b);
    }
  };
  double specials[] = {0.0,        -0.0,
                       0.5,        2.5,
                       0.0078125,  1e-7,
                       5e-7,       4.999999e-7,
                       1.0000005,  0.0000015,
                       1e300,      -1.7976931348623157e308,
                       4.9e-324,   2.2250738585072014e-308,
                       123456.789, 1e15,
                       1e16,       9007199254740993.0,
                       INFINITY,   -INFINITY};
  for (double v : specials) check(v);
  for (int i = 0; i < (argc > 1 ? std::atoi(argv[1]) : 200000); ++i) {
    std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, 8);
    check(v);
    double w = std::ldexp(static_cast<double>(rng() >> 11), -static_cast<int>(rng() % 90));
    check(w);
    double z = static_cast<double>(static_cast<std::int64_t>(rng() % 20000000)) / (1 << (rng() % 24));
    check(z);
  }
  std::printf("checked %ld bad %ld\n", n, bad);
  return bad != 0;
}
