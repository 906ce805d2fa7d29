/* btgen board support, MPS2+ AN386: vector table and reset handler.
 *
 * The Cortex-M4 reads its initial stack pointer and reset vector from the
 * table at address 0 (the linker script puts .isr_vector first). The reset
 * handler paints the whole stack (for btgen_bsp::stack_used()), copies .data,
 * clears .bss, turns the FPU on, runs the static constructors and main(), and
 * exits with main()'s status. (C, not C++: C++ may not call main().)
 */
#include <stdint.h>

extern uint32_t __data_load[], __data_start[], __data_end[];
extern uint32_t __bss_start[], __bss_end[];
extern uint32_t __stack_limit[], __stack_top[];
extern void (*__preinit_array_start[])(void);
extern void (*__preinit_array_end[])(void);
extern void (*__init_array_start[])(void);
extern void (*__init_array_end[])(void);

int main(void);
void btgen_bsp_exit(int status) __attribute__((noreturn));
void btgen_bsp_write(const char* data, unsigned size);
void SysTick_Handler(void);
void Reset_Handler(void) __attribute__((noreturn));
void btgen_bsp_start(void) __attribute__((noreturn, used));
void Fault_Handler(void) __attribute__((noreturn));
void Default_Handler(void) __attribute__((noreturn));

/* What the stack is painted with (bsp.cpp's stack_used() looks for it). */
#define BTGEN_BSP_PAINT 0x5AA5C33Cu

/* Paints the whole stack before anything uses it (so stack_used() sees every byte ever
 * used), then goes on in C. */
__attribute__((naked)) void Reset_Handler(void) {
  __asm volatile(
      "ldr r0, =__stack_limit\n"
      "ldr r1, =__stack_top\n"
      "ldr r2, =0x5AA5C33C\n" /* BTGEN_BSP_PAINT */
      "1: cmp r0, r1\n"
      "bhs 2f\n"
      "str r2, [r0], #4\n"
      "b 1b\n"
      "2: b btgen_bsp_start\n");
}

void btgen_bsp_start(void) {
  for (uint32_t *src = __data_load, *dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (uint32_t* dst = __bss_start; dst < __bss_end;) *dst++ = 0;
  /* CPACR: full access to the coprocessors CP10 and CP11 (the FPU). */
  *(volatile uint32_t*)0xE000ED88u |= (0xFu << 20);
  __asm volatile("dsb\n\tisb" ::: "memory");
  for (void (**f)(void) = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (void (**f)(void) = __init_array_start; f < __init_array_end; ++f) (*f)();
  btgen_bsp_exit(main());
}

static const char kFault[] = "btgen bsp: fault (HardFault, MemManage, BusFault or UsageFault)\n";
static const char kUnexpected[] = "btgen bsp: unexpected interrupt\n";

void Fault_Handler(void) {
  btgen_bsp_write(kFault, sizeof kFault - 1);
  btgen_bsp_exit(87); /* btgen_bsp::kFaultExit */
}

void Default_Handler(void) {
  btgen_bsp_write(kUnexpected, sizeof kUnexpected - 1);
  btgen_bsp_exit(87);
}

/* A vector: the initial stack pointer, then handlers. */
typedef union {
  uint32_t* stack;
  void (*handler)(void);
} Vector;

#define H(f) \
  { .handler = f }
#define NONE \
  { .handler = 0 }

/* 16 system exceptions, then the board's 32 external interrupts (none used). */
__attribute__((section(".isr_vector"), used)) const Vector btgen_bsp_vectors[16 + 32] = {
    {.stack = __stack_top},
    H(Reset_Handler),
    H(Default_Handler), /* NMI */
    H(Fault_Handler),   /* HardFault */
    H(Fault_Handler),   /* MemManage */
    H(Fault_Handler),   /* BusFault */
    H(Fault_Handler),   /* UsageFault */
    NONE,
    NONE,
    NONE,
    NONE,
    H(Default_Handler), /* SVCall */
    H(Default_Handler), /* DebugMonitor */
    NONE,
    H(Default_Handler), /* PendSV */
    H(SysTick_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
    H(Default_Handler),
};
