// The allocator of the programs (radiosity, radiosity-view, the benchmarks): jemalloc, linked
// where CMake finds it (RADIOSITY_WITH_JEMALLOC; Debian's libjemalloc-dev), with the settings
// below. The library itself is header-only and leaves its user's allocator alone.
//
// Why: a hierarchical solve fills lists it did not have a moment before (every refinement
// round's links, each pass's per-node values), and under the C library's allocator every 4 KiB
// page of them costs a page fault on its first write, several microseconds each in a virtual
// machine: room3 took 18,000 of them, many in the serial parts of the solve, where the other
// core waits. jemalloc reuses what was freed and, set up so, maps its memory in 2 MiB
// transparent huge pages (512 times fewer faults where the kernel offers them: its "madvise"
// and "always" modes; elsewhere ordinary pages). The README's "Under a second" has the
// measurements.

#include <jemalloc/jemalloc.h>

/// jemalloc's settings, read as it starts, before main: its extents and its own metadata in
/// transparent huge pages (thp, metadata_thp), and large requests served like the others
/// (oversize_threshold 0: by default those past 8 MiB get an arena of their own that hands
/// freed memory back to the kernel at once, so that the next pass's 11 MB list of links came
/// in fresh pages again; room3's last sort of links took 7 to 11 ms this way, 7 to 25 ms
/// that way, five runs each). The environment's MALLOC_CONF overrides them.
const char* malloc_conf = "thp:always,metadata_thp:always,oversize_threshold:0";
