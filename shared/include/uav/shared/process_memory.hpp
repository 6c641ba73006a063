#pragma once
// How a long-running process (the flight stack, the GCS, the benchmarks, the test runners) keeps
// the memory it frees.

namespace uav {

// Freed blocks stay with the process for the next allocation instead of going back to the
// kernel. Each camera frame allocates and frees image-sized buffers (renderer, matcher,
// point cloud: hundreds of kB to MB each) at camera rate; glibc's defaults return blocks that
// big with munmap or a heap trim, so every frame page-faults its buffers back in. Measured on
// one avoidance benchmark flight (1/49, 3 m/s, seed 3, this 2-core machine): 59.6 s of wall time
// with the defaults, 28.6-32.5 s with this, the flight itself identical. Page faults are also
// latency on the control path; the PREEMPT_RT guides give the same advice (no trimming).
// Call first thing in main(), before threads start. Returns false where the allocator is not
// glibc's own (a sanitizer's refuses the settings): the process then runs as with the defaults.
bool KeepFreedMemory();

}  // namespace uav
