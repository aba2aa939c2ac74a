/* bench/fresh_memory.c: what writing fresh memory costs on this machine,
 * the floor under any load that builds a large tree (issue 24).
 *
 * Usage: fresh_memory MODE COUNT BYTES
 *   malloc  COUNT blocks of BYTES bytes, each from malloc() and filled
 *   reuse   the same, after as many blocks were taken, filled and freed
 *           (untimed): memory the process has touched before, as a live
 *           reload finds it
 *   pages   one anonymous mapping of COUNT*BYTES bytes in 4 KB pages
 *           (MADV_NOHUGEPAGE), filled block by block
 *   huge    the same mapping with MADV_HUGEPAGE (transparent huge pages
 *           where the kernel allows a program to ask for them)
 * Prints the milliseconds the allocation and filling took and the page
 * faults they caused. Each run must be a process of its own: memory freed
 * and taken again is no longer fresh. bench/floor.sh runs it.
 */
#define _DEFAULT_SOURCE
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static long minor_faults(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt;
}

/* malloc([n]), or the end of the run when there is no memory. */
static void *take(size_t n)
{
    void *p = malloc(n);
    if (!p) {
        fprintf(stderr, "fresh_memory: out of memory\n");
        exit(1);
    }
    return p;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: fresh_memory malloc|reuse|pages|huge COUNT BYTES\n");
        return 2;
    }
    const char *mode = argv[1];
    const size_t count = strtoull(argv[2], NULL, 10), bytes = strtoull(argv[3], NULL, 10);
    if (!count || !bytes || count > (1u << 24) || bytes > (1u << 16)) {
        fprintf(stderr, "fresh_memory: COUNT in 1..16M, BYTES in 1..64K\n");
        return 2;
    }
    const int reuse = strcmp(mode, "reuse") == 0, blocks = reuse || strcmp(mode, "malloc") == 0;
    if (!blocks && strcmp(mode, "pages") != 0 && strcmp(mode, "huge") != 0) {
        fprintf(stderr, "fresh_memory: unknown mode %s\n", mode);
        return 2;
    }
    if (reuse) {
        unsigned char **held = take(count * sizeof *held);
        for (size_t i = 0; i < count; i++) {
            held[i] = take(bytes);
            memset(held[i], 1, bytes);
        }
        for (size_t i = count; i-- > 0;)
            free(held[i]);
        free(held);
    }
    uintptr_t sum = 0;   /* stored to [sink] at the end, so the writes stay */
    const long f0 = minor_faults();
    const double t0 = now_ms();
    if (blocks) {
        for (size_t i = 0; i < count; i++) {
            unsigned char *p = take(bytes);   /* the blocks stay allocated */
            memset(p, (int)(i & 0xff), bytes);
            sum += (uintptr_t)p;
        }
    } else {
        const size_t align = (size_t)2 << 20, len = count * bytes + align;
        unsigned char *map = mmap(NULL, len, PROT_READ | PROT_WRITE,
                                  MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (map == MAP_FAILED) {
            perror("fresh_memory: mmap");
            return 1;
        }
        /* a huge page needs a 2 MB aligned start */
        unsigned char *base = (unsigned char *)(((uintptr_t)map + align - 1) & ~(uintptr_t)(align - 1));
        madvise(base, count * bytes, mode[0] == 'h' ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
        for (size_t i = 0; i < count; i++) {
            memset(base + i * bytes, (int)(i & 0xff), bytes);
            sum += base[i * bytes];
        }
    }
    const double ms = now_ms() - t0;
    volatile uintptr_t sink = sum;
    (void)sink;
    printf("%.3f ms %ld faults\n", ms, minor_faults() - f0);
    return 0;
}
