#include "uav/shared/process_memory.hpp"

#include <malloc.h>

namespace uav {

bool KeepFreedMemory() {
  // Blocks below 32 MiB (glibc's largest allowed threshold) come from the heap, not from their
  // own mmap; the heap is never trimmed. The peak stays resident, as it would anyway at the next
  // frame.
  constexpr int kMmapThreshold = 32 << 20;
  const bool threshold = mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1;
  const bool trim = mallopt(M_TRIM_THRESHOLD, -1) == 1;
  return threshold && trim;
}

}  // namespace uav
