#include <malloc.h>

#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

#include "uav/shared/process_memory.hpp"

// A camera frame's buffer comes from the heap, not its own mmap, and stays with the process when
// freed, so the next frame reuses it without page faults. glibc's defaults fail both checks for a
// block this size.
TEST(ProcessMemory, AFrameSizedBlockComesFromTheHeapAndIsKeptWhenFreed) {
  // The test main has called it; a second call changes nothing.
  if (!uav::KeepFreedMemory()) GTEST_SKIP() << "the allocator is not glibc's (a sanitizer's): nothing to test";
  constexpr std::size_t kBlock = 8u << 20;  // a 1920 x 1080 RGBA frame
  const struct mallinfo2 before = mallinfo2();
  auto* volatile block = static_cast<unsigned char*>(std::malloc(kBlock));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlock);
  const struct mallinfo2 held = mallinfo2();
  EXPECT_EQ(held.hblks, before.hblks) << "the block was given its own mmap";
  EXPECT_EQ(block[kBlock - 1], 1);
  std::free(block);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_GE(after.arena, held.arena) << "the heap was trimmed";
  EXPECT_GE(after.fordblks, kBlock) << "the freed block did not stay as free heap";
}
