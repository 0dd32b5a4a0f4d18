// Memory accounting (exec/memory.h): the peak and what each buffer held at it.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "exec/host_exec.h"
#include "exec/memory.h"

namespace cdb::test {
namespace {

size_t bytes_of(const MemoryStats& m, const std::string& buffer) {
  for (const BufferBytes& b : m.at_peak)
    if (b.buffer == buffer) return b.bytes;
  return 0;
}

size_t sum_at_peak(const MemoryStats& m, const std::string& prefix = "") {
  size_t sum = 0;
  for (const BufferBytes& b : m.at_peak)
    if (b.buffer.compare(0, prefix.size(), prefix) == 0) sum += b.bytes;
  return sum;
}

}  // namespace

// The peak, the bytes each named buffer held at it (the sum is the peak), and a growth
// after a buffer's first reservation counted with its sizes.
TEST(MemoryStats, PeakBreakdownAndGrowths) {
  HostExec exec;
  MemoryStats m;
  {
    Array<uint32_t> a(exec.memory(), "a");
    Array<uint64_t> b(exec.memory(), "b");
    a.reserve(100);
    b.reserve(50);
    a.reserve(80);  // fits: no allocation, no growth
    EXPECT_EQ(exec.memory().stats().growths, 0u);
    a.reserve(400);  // the old 400 bytes go before the new 1600 come
    b.reserve(10);
    m = exec.memory().stats();
  }
  EXPECT_EQ(m.peak_bytes, 400 * 4 + 50 * 8);
  EXPECT_EQ(m.current_bytes, 400 * 4 + 50 * 8);
  EXPECT_EQ(sum_at_peak(m), m.peak_bytes);
  EXPECT_EQ(bytes_of(m, "a"), 1600u);
  EXPECT_EQ(bytes_of(m, "b"), 400u);
  EXPECT_EQ(m.allocations, 3u);
  EXPECT_EQ(m.growths, 1u);
  ASSERT_EQ(m.grown.size(), 1u);
  EXPECT_EQ(m.grown[0].buffer, "a");
  EXPECT_EQ(m.grown[0].first_count, 100u);
  EXPECT_EQ(m.grown[0].last_count, 400u);
  EXPECT_EQ(exec.memory().stats().current_bytes, 0u);
}

}  // namespace cdb::test
