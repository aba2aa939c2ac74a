/* test_pool.c: the runtime's size-class free lists (lib/core/pool.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "pool.h"

/* A released block is handed out again for any request of its class
 * (16-byte steps up to 256, then powers of two), and only misses call
 * malloc. */
static void test_classes_and_reuse(void **st)
{
    (void)st;
    unsetenv("FLITTER_NOPOOL");
    Pool *p = pool_new();
    Pool *prev = pool_enter(p);
    void *a = pool_alloc(20);                 /* class 32 */
    memset(a, 0xab, 32);                      /* the whole class block is usable */
    assert_int_equal(pool_stats(p).mallocs, 1);
    pool_release(a, 20);
    assert_ptr_equal(pool_alloc(32), a);      /* same class: reused */
    assert_int_equal(pool_stats(p).mallocs, 1);
    void *b = pool_alloc(33);                 /* class 48: a miss */
    assert_ptr_not_equal(b, a);
    assert_int_equal(pool_stats(p).mallocs, 2);
    pool_release(a, 32);
    pool_release(b, 33);
    void *c = pool_alloc(300);                /* class 512 */
    pool_release(c, 300);
    assert_ptr_equal(pool_alloc(512), c);
    pool_release(c, 512);
    void *z = pool_alloc(0);                  /* smallest class */
    pool_release(z, 0);
    assert_ptr_equal(pool_alloc(16), z);
    pool_release(z, 16);
    uint64_t m = pool_stats(p).mallocs;
    void *big = pool_alloc((size_t)5 << 20); /* over 4 MiB: never kept */
    pool_release(big, (size_t)5 << 20);
    assert_int_equal(pool_stats(p).mallocs, m + 1);
    assert_int_equal(pool_stats(p).frees, 1);
    void *c2 = pool_calloc(100);
    for (int i = 0; i < 100; i++) assert_int_equal(((unsigned char *)c2)[i], 0);
    pool_release(c2, 100);
    pool_leave(prev);
    pool_free(p);
}

/* With no active pool the calls are plain malloc/free; pool_enter and
 * pool_leave nest. */
static void test_inactive_and_nesting(void **st)
{
    (void)st;
    Pool *p = pool_new(), *q = pool_new();
    void *x = pool_alloc(40);                 /* no pool: malloc */
    pool_release(x, 40);                      /* no pool: free */
    Pool *outer = pool_enter(p);
    assert_null(outer);
    Pool *inner = pool_enter(q);
    assert_ptr_equal(inner, p);
    void *y = pool_alloc(40);
    assert_int_equal(pool_stats(q).mallocs, 1);
    assert_int_equal(pool_stats(p).mallocs, 0);
    pool_leave(inner);                        /* p active again */
    pool_release(y, 40);                      /* any pool may take any block */
    assert_ptr_equal(pool_alloc(48), y);
    assert_int_equal(pool_stats(p).mallocs, 0);
    pool_release(y, 48);
    pool_leave(outer);
    pool_free(q);
    pool_free(p);
}

/* FLITTER_NOPOOL: nothing is kept, every block is a real malloc/free. */
static void test_nopool(void **st)
{
    (void)st;
    setenv("FLITTER_NOPOOL", "1", 1);
    Pool *p = pool_new();
    unsetenv("FLITTER_NOPOOL");
    Pool *prev = pool_enter(p);
    for (int i = 0; i < 3; i++) pool_release(pool_alloc(24), 24);
    assert_int_equal(pool_stats(p).mallocs, 3);
    assert_int_equal(pool_stats(p).frees, 3);
    pool_leave(prev);
    pool_free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_classes_and_reuse),
        cmocka_unit_test(test_inactive_and_nesting),
        cmocka_unit_test(test_nopool),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
