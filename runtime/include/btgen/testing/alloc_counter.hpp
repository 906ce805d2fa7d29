// Counts heap allocations: the global operator new/delete (all forms) are
// replaced, and so is malloc/calloc/realloc where the toolchain allows it
// (glibc, no AddressSanitizer, which owns malloc itself).
#pragma once

#include <cstddef>

namespace btgen_test {

// Allocations (operator new and, when counted, malloc-family calls) since
// the program started.
std::size_t allocation_count() noexcept;

// True when malloc/calloc/realloc are counted too, not only operator new.
bool counts_malloc() noexcept;

// Allocations made while an instance is alive.
class AllocationScope {
 public:
  AllocationScope() noexcept : start_(allocation_count()) {}
  [[nodiscard]] std::size_t count() const noexcept { return allocation_count() - start_; }

 private:
  std::size_t start_;
};

}  // namespace btgen_test
