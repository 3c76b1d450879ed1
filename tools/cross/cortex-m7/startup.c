/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The board's start (mps2-an500.ld): the vector table at 0, the FPU switched on, then newlib's
 * crt0 (_start: the stack, .bss, main, exit by semihosting). A fault ends the run with status
 * 70 rather than hanging QEMU. */
#include <stdint.h>
#include <unistd.h>

extern void _start(void);
extern char __stack[];

void m7_reset(void);

void m7_reset(void) {
  /* CPACR: full access to CP10 and CP11, the FPU; the compiler's first floating-point
   * instruction (in crt0's callees) must come after this */
  *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
  __asm volatile("dsb\n\tisb" ::: "memory");
  _start();
}

static void fault(void) { _exit(70); }

typedef void (*handler)(void);

/* initial stack pointer, reset, NMI, hard fault, memory management, bus and usage faults, four
 * reserved, SVCall, debug monitor, reserved, PendSV, SysTick */
__attribute__((section(".vectors"), used)) static const handler vectors[16] = {
    (handler)(uintptr_t)__stack,
    m7_reset,
    fault,
    fault,
    fault,
    fault,
    fault,
    0,
    0,
    0,
    0,
    fault,
    fault,
    0,
    fault,
    fault};
