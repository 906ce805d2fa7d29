// btgen board support for ARM's MPS2+ AN386 (Cortex-M4), as QEMU's
// `qemu-system-arm -M mps2-an386` emulates it. Small on purpose: what a
// generated mission needs on a microcontroller and nothing else.
//
//   output     UART0 (CMSDK APB UART at 0x40004000; QEMU's -serial), polled
//   time       SysTick at the 25 MHz core clock: a millisecond interrupt
//              (millis(), SysTickClock for the mission) or, for benchmarks,
//              a free-running 24-bit counter (cycle_counter_*)
//   exit       ARM semihosting SYS_EXIT_EXTENDED: QEMU exits with the status
//              (run it with `-semihosting-config enable=on,target=native`)
//   no heap    _sbrk reports the allocation and exits with kHeapExit
//   stack      painted by the reset handler; stack_used() is its high-water mark
//
// The startup code (startup.c) sets up .data/.bss, the FPU and the stack
// paint, runs the static constructors, calls main() and exits with its
// status. main() calls btgen_bsp::init() first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace btgen_bsp {

// The exit status when something allocates (the image links no heap).
inline constexpr int kHeapExit = 86;
// The exit status of a fault (HardFault and the other fault handlers).
inline constexpr int kFaultExit = 87;

// Core clock of the AN386 image (QEMU's sysclk for the board).
inline constexpr std::uint32_t kCoreClockHz = 25000000u;

// UART0 on, SysTick's millisecond interrupt on.
void init() noexcept;

// Bytes to UART0, waiting while its transmit buffer is full.
void write(const char* data, std::size_t size) noexcept;
inline void write(std::string_view s) noexcept { write(s.data(), s.size()); }
void write_unsigned(std::uint64_t value) noexcept;

// Ends the program (and QEMU) with `status`.
[[noreturn]] void exit(int status) noexcept;

// Milliseconds since init(), from the SysTick interrupt.
std::uint64_t millis() noexcept;

// The mission clock (btgen/clock.hpp's contract) on SysTick.
struct SysTickClock {
  [[nodiscard]] std::uint64_t now_ms() const noexcept { return millis(); }
};

// SysTick as a free-running down-counter at the core clock, interrupt off
// (for measurements: millis() stops). elapsed(a, b) is the number of core
// clock periods from reading `a` to reading `b` (less than 2^24 apart).
void cycle_counter_start() noexcept;
std::uint32_t cycle_counter_read() noexcept;
constexpr std::uint32_t cycle_counter_elapsed(std::uint32_t a, std::uint32_t b) noexcept {
  return (a - b) & 0x00FFFFFFu;
}

// The deepest the stack has been since reset, in bytes (the painted words
// that are no longer paint), and its size.
std::size_t stack_used() noexcept;
std::size_t stack_size() noexcept;

}  // namespace btgen_bsp
