// A mission's cost on the Cortex-M4 board (mcu/), run under QEMU with -icount.
//
// Compiled with -DBTGEN_MISSION_HEADER='"x.hpp"' -DBTGEN_MISSION_TEMPLATE=ns::X
// (bench/mcu/run_mcu_bench.py does it), or with -DBTGEN_MCU_BASELINE for the
// same program without a mission (what the board support and this main cost).
// The leaves answer at once with a status read from a volatile (so nothing is
// folded away), the clock is a counter, there is no observer. Prints
//   ticks N / counts N / calibration_counts N / calibration_instructions N /
//   state_bytes N / stack_bytes N
// `counts` are SysTick periods (core clock) summed over N ticks (the baseline's
// are the loop without them); with QEMU's
// -icount shift=0 an instruction takes 1 ns of virtual time, so SysTick counts
// instructions (25 MHz: one count per 40); the calibration loop of a known
// instruction count gives the exact ratio.
#include <cstdint>
#include <new>

#include "btgen_bsp.hpp"

#ifndef BTGEN_MCU_BASELINE
#include BTGEN_MISSION_HEADER
#endif

namespace {

constexpr std::uint32_t kTicks = 2000;
constexpr std::uint32_t kChunk = 100;
constexpr std::uint32_t kCalibrationLoops = 1000000;  // 2 instructions each (subs, bne)

volatile std::uint8_t g_answer = 2;  // btgen::Status::SUCCESS
volatile std::uint64_t g_now = 0;

void line(const char* key, std::uint64_t value) {
  btgen_bsp::write(key);
  btgen_bsp::write(" ");
  btgen_bsp::write_unsigned(value);
  btgen_bsp::write("\n");
}

#ifndef BTGEN_MCU_BASELINE
struct BenchLeaves {
  static btgen::Status answer() noexcept { return static_cast<btgen::Status>(g_answer); }
  template <class M>
  btgen::Status onStart(M&, const btgen::NodeInfo&) noexcept {
    return answer();
  }
  template <class M>
  btgen::Status onRunning(M&, const btgen::NodeInfo&) noexcept {
    return answer();
  }
  template <class M>
  void onHalted(M&, const btgen::NodeInfo&) noexcept {}
  template <class M>
  btgen::Status check(M&, const btgen::NodeInfo&) noexcept {
    return answer();
  }
  btgen::Status nav2_input(const btgen::NodeInfo&) noexcept { return answer(); }
};

struct CounterClock {
  [[nodiscard]] std::uint64_t now_ms() const noexcept { return g_now; }
};

using Mission = BTGEN_MISSION_TEMPLATE<BenchLeaves, CounterClock, btgen::NoObserver>;
BenchLeaves leaves;
// Built at start-up in zeroed RAM (.bss), as firmware does: a mission object defined with
// its constructor at namespace scope is constant-initialised into .data, whose initial
// image (mostly zeros) would take as much flash as the object takes RAM.
alignas(Mission) unsigned char storage[sizeof(Mission)];
#endif

__attribute__((noinline)) void calibration_loop(std::uint32_t n) {
  __asm volatile(
      "1: subs %0, %0, #1\n"
      "   bne 1b\n"
      : "+r"(n)
      :
      : "cc");
}

}  // namespace

int main() {
  btgen_bsp::init();
#ifndef BTGEN_MCU_BASELINE
  Mission& mission = *::new (static_cast<void*>(storage)) Mission(leaves);
#endif
  btgen_bsp::cycle_counter_start();
  std::uint32_t a = btgen_bsp::cycle_counter_read();
  calibration_loop(kCalibrationLoops);
  std::uint32_t b = btgen_bsp::cycle_counter_read();
  line("calibration_counts", btgen_bsp::cycle_counter_elapsed(a, b));
  line("calibration_instructions", 2ull * kCalibrationLoops);
  // Ticks in chunks of kChunk (so that a chunk stays well inside the 24-bit counter), less the
  // same loop without the tick.
  std::uint64_t counts = 0;
  std::uint64_t state = 0;
  for (std::uint32_t chunk = 0; chunk < kTicks / kChunk; ++chunk) {
    a = btgen_bsp::cycle_counter_read();
    for (std::uint32_t i = 0; i < kChunk; ++i) {
      g_now = g_now + 10;
#ifndef BTGEN_MCU_BASELINE
      (void)mission.tick();
#endif
      __asm volatile("" ::: "memory");
    }
    b = btgen_bsp::cycle_counter_read();
    counts += btgen_bsp::cycle_counter_elapsed(a, b);
  }
#ifndef BTGEN_MCU_BASELINE
  state = sizeof(Mission);
#endif
  line("ticks", kTicks);
  line("counts", counts);
  line("state_bytes", state);
  line("stack_bytes", btgen_bsp::stack_used());
  return 0;
}
