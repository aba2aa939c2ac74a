/* prefault.h: the heap's new pages faulted in on another core while a
 * headless run loads its script and steps its first frames.
 *
 * A large script's load and first two frames build megabytes of values in
 * fresh memory: discs20k (20,000 particles) faults in about 8,000 pages, a
 * microsecond and more each in a virtual machine, all on the thread that
 * loads. A prefaulter makes glibc's malloc grow the heap (brk) 2 MiB ahead
 * of what it needs and blocks of up to 32 MiB come from it (mallopt
 * M_TOP_PAD, M_MMAP_THRESHOLD: process-wide, so only the `flitter run`
 * whose end ends the process starts one), and a thread of its own faults
 * in each new stretch of the heap (madvise MADV_POPULATE_WRITE, Linux 5.14;
 * it never changes what the memory holds) before the loading thread gets
 * there, on a core that is mostly idle while a script loads. It starts
 * once the heap has grown 6 MiB: a smaller script (most) pays for no
 * faulting on the core its physics and loop kernels share.
 *
 * Nothing but time changes: on another allocator (a memory checker's, a
 * preloaded one) or an older kernel the thread finds nothing to do or
 * stops at its first refusal. Under a limit on the address space or the
 * data segment (`ulimit -v`, `ulimit -d`) none starts: the padding and the
 * larger heap blocks would reach the limit sooner. */
#ifndef FLITTER_PREFAULT_H
#define FLITTER_PREFAULT_H

typedef struct Prefault Prefault;

/* Set malloc's policy and start the thread; NULL (nothing started) when
 * it cannot start, under an address-space or data limit, or when the
 * environment variable FLITTER_PREFAULT is 0. */
Prefault *prefault_start(void);
/* Stop and join the thread, and free [p] (NULL is a no-op). Malloc's
 * policy stays. */
void prefault_stop(Prefault *p);

/* Keep memory freed at the heap's top for the next frame instead of
 * giving it back to the kernel (mallopt M_TRIM_THRESHOLD 512 MiB,
 * process-wide: for the `flitter` command's own runs, not the library's).
 * A frame that draws with Mesa's llvmpipe frees megabytes at the top of
 * the heap (its vertex and binning buffers) and takes them again in the
 * next frame: trimmed, each frame faulted them in afresh, most of the
 * time a frame took to submit (bench/PROFILE.md, "src/prefault.h: freed
 * memory kept at the heap's top"). Nothing but time and the process's
 * resident size change. None under an address-space or data limit. */
void prefault_keep_freed(void);

#endif
