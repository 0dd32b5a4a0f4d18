// operator new and delete replaced by malloc and free with a count of the allocations. The
// count lives in one process-wide atomic because operator new is itself process-wide: every
// thread's allocations (the CPU executor's OpenMP workers too) must land in it.
#include "allocation_count.h"

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {

std::atomic<uint64_t>& counter() {
  static std::atomic<uint64_t> count{0};
  return count;
}

void* counted(std::size_t bytes, std::size_t alignment) {
  counter().fetch_add(1, std::memory_order_relaxed);
  if (bytes == 0) bytes = 1;
  // aligned_alloc wants a size that is a multiple of the alignment.
  void* p = alignment > alignof(std::max_align_t)
                ? std::aligned_alloc(alignment, (bytes + alignment - 1) / alignment * alignment)
                : std::malloc(bytes);
  if (!p) throw std::bad_alloc();
  return p;
}

}  // namespace

uint64_t heap_allocations() { return counter().load(std::memory_order_relaxed); }

void* operator new(std::size_t bytes) { return counted(bytes, 0); }
void* operator new[](std::size_t bytes) { return counted(bytes, 0); }
void* operator new(std::size_t bytes, std::align_val_t a) { return counted(bytes, std::size_t(a)); }
void* operator new[](std::size_t bytes, std::align_val_t a) { return counted(bytes, std::size_t(a)); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
