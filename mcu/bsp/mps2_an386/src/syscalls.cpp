// btgen board support, MPS2+ AN386: the newlib system calls, and no heap.
//
// A generated mission allocates nothing; this file makes sure of it on the
// target. malloc (and so operator new, and any library routine that
// allocates) gets its memory from _sbrk, which here reports the attempt on
// the UART and ends the program with btgen_bsp::kHeapExit: an allocation
// anywhere is a failed run, not a silent success. The other calls newlib may
// reference have no operating system behind them and fail (without touching
// errno, whose newlib module would link free()).
//
// abort() and __assert_func() are here too: the C++ library calls it where it would throw (built
// with -fno-exceptions: std::string_view::at out of range, ...), and
// newlib's abort() goes through raise(), whose signal table is allocated.
#include <cstddef>
#include <cstdint>

#include "btgen_bsp.hpp"

extern "C" {

void* _sbrk(std::ptrdiff_t increment) {
  btgen_bsp::write("btgen bsp: heap allocation of ");
  btgen_bsp::write_unsigned(static_cast<std::uint64_t>(increment < 0 ? 0 : increment));
  btgen_bsp::write(" bytes attempted; this image has no heap\n");
  btgen_bsp::exit(btgen_bsp::kHeapExit);
}

[[noreturn]] void _exit(int status) { btgen_bsp::exit(status); }

[[noreturn]] void abort() {
  btgen_bsp::write("btgen bsp: abort() (a C++ library check failed; with exceptions it would have thrown)\n");
  btgen_bsp::exit(btgen_bsp::kFaultExit);
}

// A failed assert() in the C or C++ library (newlib's prints with fprintf,
// whose stdio buffers are allocated).
[[noreturn]] void __assert_func(const char* file, int line, const char*, const char* expr) {
  btgen_bsp::write("btgen bsp: assertion failed: ");
  btgen_bsp::write(expr != nullptr ? expr : "?");
  btgen_bsp::write(" at ");
  btgen_bsp::write(file != nullptr ? file : "?");
  btgen_bsp::write(":");
  btgen_bsp::write_unsigned(static_cast<std::uint64_t>(line < 0 ? 0 : line));
  btgen_bsp::write("\n");
  btgen_bsp::exit(btgen_bsp::kFaultExit);
}

int _kill(int, int) { return -1; }

int _getpid() { return 1; }

int _write(int fd, const char* data, int size) {
  if (fd != 1 && fd != 2) return -1;
  btgen_bsp::write(data, static_cast<std::size_t>(size));
  return size;
}

int _read(int, char*, int) { return -1; }

int _close(int) { return -1; }

int _lseek(int, int, int) { return -1; }

int _isatty(int fd) { return fd <= 2 ? 1 : 0; }

struct stat;
int _fstat(int, struct stat*) { return -1; }

// A pure virtual function called: a bug, reported like a fault.
[[noreturn]] void __cxa_pure_virtual() {
  btgen_bsp::write("btgen bsp: pure virtual function called\n");
  btgen_bsp::exit(btgen_bsp::kFaultExit);
}

}  // extern "C"
