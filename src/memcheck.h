/* memcheck.h: whether a memory checker watches this process. */
#ifndef FLITTER_MEMCHECK_H
#define FLITTER_MEMCHECK_H

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#if defined(__has_include)
#if __has_include(<valgrind/valgrind.h>)
#include <valgrind/valgrind.h>
#define HAVE_VALGRIND_H 1
#endif
#endif

/* Whether a memory checker watches this process: valgrind (its client
 * request, or its preloaded library when the header was missing at build
 * time) or a sanitizer compiled in. Such a checker expects every block
 * back at exit, and its allocator is not glibc's heap. */
static inline bool memory_checked(void)
{
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    return true;
#else
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
    return true;
#endif
#endif
#ifdef HAVE_VALGRIND_H
    if (RUNNING_ON_VALGRIND) return true;
#endif
    const char *pre = getenv("LD_PRELOAD");
    return pre && strstr(pre, "vgpreload");
#endif
}

#endif
