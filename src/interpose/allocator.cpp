// The process's memory allocator settings (CMake target gridshell_allocator: jemalloc, linked
// into the gridshell executable, the tests and the benchmarks when Debian's libjemalloc-dev is
// found and no sanitizer is on; docs/performance.md "Memory allocator").
//
// Why: the large analyses touch a few hundred MB of fresh memory (stiffness, factor, Lanczos
// basis). On the 2-core virtual machines we measure on, a page fault costs several µs, and with
// glibc's malloc a quarter of the Aquadom LBA went to faulting 4 KB pages in (62 000 faults for
// a 0.2 GB peak). jemalloc is told here to back its memory with transparent huge pages (2 MB:
// 500× fewer faults, fewer TLB misses in the memory-bound solves) and to keep freed pages
// instead of returning them to the kernel, so a path that frees and reallocates its matrices
// every step reuses them instead of faulting them in again (with pages returned after 30 s the
// 8188-beam non-linear path ran 3–9 % slower; kept, it runs as fast as with glibc's malloc). A
// process therefore holds its high-water mark until it exits (`gridshell studio`: that of its
// largest request). Where the kernel offers no huge pages the setting does nothing. The
// environment's MALLOC_CONF is applied after these and overrides them.

extern "C" {
// Read by jemalloc at its initialisation (its documented compile-time configuration symbol).
extern const char* malloc_conf;
const char* malloc_conf = "thp:always,metadata_thp:auto,dirty_decay_ms:-1,muzzy_decay_ms:-1";
}
