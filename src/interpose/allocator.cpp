// The process's memory allocator settings (CMake target gridshell_allocator: jemalloc, linked
// into the gridshell executable, the tests and the benchmarks when Debian's libjemalloc-dev is
// found and no sanitizer is on; docs/performance.md, "The Aquadom LBA and the allocator").
//
// Why: the large analyses touch a few hundred MB of fresh memory (stiffness, factor, Lanczos
// basis). On the 2-core virtual machines we measure on, a page fault costs several µs, and with
// glibc's malloc a fifth of the Aquadom LBA went to faulting 4 KB pages in (62 000 faults for
// a 0.2 GB peak). jemalloc is told here to back its memory with transparent huge pages (2 MB:
// 500× fewer faults, fewer TLB misses in the memory-bound solves) and to keep freed pages for
// 30 s before giving them back, so what a step frees the next one reuses instead of faulting it
// in again. Trade-off measured (docs/performance.md): pages kept for the process's life made
// the 8188-beam non-linear path ~5 % faster still but raised the fine input's peak from 0.56 to
// 0.80 GB (freed pages kept in each thread's arena); with jemalloc's default (pages given back
// within seconds) that path ran 40 % slower in one unpaired sitting. Where the kernel offers no
// huge pages the setting does nothing. The environment's MALLOC_CONF is applied after these and
// overrides them.

extern "C" {
// Read by jemalloc at its initialisation (its documented compile-time configuration symbol).
extern const char* malloc_conf;
const char* malloc_conf = "thp:always,metadata_thp:auto,dirty_decay_ms:30000,muzzy_decay_ms:30000";
}
