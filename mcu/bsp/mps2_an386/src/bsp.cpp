// btgen board support, MPS2+ AN386: UART0, SysTick, semihosting exit, stack use.
#include <cstddef>
#include <cstdint>

#include "btgen_bsp.hpp"

extern "C" {
extern std::uint32_t __stack_limit[], __stack_top[];
void SysTick_Handler();
}

namespace {

template <class T = std::uint32_t>
volatile T& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile T*>(address);
}

// CMSDK APB UART0 (QEMU connects it to the first -serial).
constexpr std::uintptr_t kUart0 = 0x40004000u;
constexpr std::uintptr_t kUartData = kUart0 + 0x000u;
constexpr std::uintptr_t kUartState = kUart0 + 0x004u;  // bit 0: transmit buffer full
constexpr std::uintptr_t kUartCtrl = kUart0 + 0x008u;   // bit 0: transmit enable
constexpr std::uintptr_t kUartBaudDiv = kUart0 + 0x010u;

// SysTick (ARMv7-M system control space).
constexpr std::uintptr_t kSystCsr = 0xE000E010u;  // bit 0 enable, 1 interrupt, 2 core clock
constexpr std::uintptr_t kSystRvr = 0xE000E014u;
constexpr std::uintptr_t kSystCvr = 0xE000E018u;

constexpr std::uint32_t kPaint = 0x5AA5C33Cu;  // as startup.c paints

volatile std::uint32_t g_millis_lo = 0;
volatile std::uint32_t g_millis_hi = 0;

}  // namespace

extern "C" void SysTick_Handler() {
  const std::uint32_t lo = g_millis_lo + 1u;
  g_millis_lo = lo;
  if (lo == 0) g_millis_hi = g_millis_hi + 1u;
}

namespace btgen_bsp {

void init() noexcept {
  reg(kUartBaudDiv) = kCoreClockHz / 115200u;
  reg(kUartCtrl) = 1u;
  reg(kSystCsr) = 0;
  reg(kSystRvr) = kCoreClockHz / 1000u - 1u;
  reg(kSystCvr) = 0;
  reg(kSystCsr) = 0x7u;
}

void write(const char* data, std::size_t size) noexcept {
  for (std::size_t i = 0; i < size; ++i) {
    while ((reg(kUartState) & 1u) != 0) {
    }
    reg(kUartData) = static_cast<unsigned char>(data[i]);
  }
}

void write_unsigned(std::uint64_t value) noexcept {
  char buf[20];
  std::size_t n = 0;
  do {
    buf[n++] = static_cast<char>('0' + static_cast<int>(value % 10u));
    value /= 10u;
  } while (value != 0);
  char out[20];
  for (std::size_t i = 0; i < n; ++i) out[i] = buf[n - 1 - i];
  write(out, n);
}

[[noreturn]] void exit(int status) noexcept {
  // SYS_EXIT_EXTENDED (0x20): {ADP_Stopped_ApplicationExit, status}.
  static std::uint32_t block[2];
  block[0] = 0x20026u;
  block[1] = static_cast<std::uint32_t>(status);
  register std::uint32_t r0 __asm("r0") = 0x20u;
  register std::uint32_t* r1 __asm("r1") = block;
  __asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  for (;;) {
    __asm volatile("wfi");
  }
}

std::uint64_t millis() noexcept {
  for (;;) {
    const std::uint32_t hi = g_millis_hi;
    const std::uint32_t lo = g_millis_lo;
    if (hi == g_millis_hi) return (static_cast<std::uint64_t>(hi) << 32) | lo;
  }
}

void cycle_counter_start() noexcept {
  reg(kSystCsr) = 0;
  reg(kSystRvr) = 0x00FFFFFFu;
  reg(kSystCvr) = 0;
  reg(kSystCsr) = 0x5u;  // core clock, no interrupt
}

std::uint32_t cycle_counter_read() noexcept { return reg(kSystCvr) & 0x00FFFFFFu; }

std::size_t stack_used() noexcept {
  const std::uint32_t* p = __stack_limit;
  while (p < __stack_top && *p == kPaint) ++p;
  return static_cast<std::size_t>(reinterpret_cast<std::uintptr_t>(__stack_top) - reinterpret_cast<std::uintptr_t>(p));
}

std::size_t stack_size() noexcept {
  return static_cast<std::size_t>(reinterpret_cast<std::uintptr_t>(__stack_top) -
                                  reinterpret_cast<std::uintptr_t>(__stack_limit));
}

}  // namespace btgen_bsp

// For the C startup code.
extern "C" [[noreturn]] void btgen_bsp_exit(int status) { btgen_bsp::exit(status); }
extern "C" void btgen_bsp_write(const char* data, unsigned size) { btgen_bsp::write(data, size); }
