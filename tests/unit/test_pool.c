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
    Pool *p = pool_new(false);
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
    Pool *p = pool_new(false), *q = pool_new(false);
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

/* pool_new(true) (fl_debug_options.no_pool): nothing is kept, every block is a real malloc/free. */
static void test_nopool(void **st)
{
    (void)st;
    Pool *p = pool_new(true);
    Pool *prev = pool_enter(p);
    for (int i = 0; i < 3; i++) pool_release(pool_alloc(24), 24);
    assert_int_equal(pool_stats(p).mallocs, 3);
    assert_int_equal(pool_stats(p).frees, 3);
    pool_leave(prev);
    pool_free(p);
}

/* pool_trim(p, keep): cached blocks are freed until at most [keep] bytes
 * stay, the smallest classes kept first and, within a class, the blocks
 * released last; the kept ones are handed out again without malloc. */
static void test_trim_keeps(void **st)
{
    (void)st;
    Pool *p = pool_new(false);
    Pool *prev = pool_enter(p);
    void *s16[4], *s64[3], *b1k[2];
    for (int i = 0; i < 4; i++) s16[i] = pool_alloc(16);
    for (int i = 0; i < 3; i++) s64[i] = pool_alloc(64);
    for (int i = 0; i < 2; i++) b1k[i] = pool_alloc(1000);       /* class 1024 */
    for (int i = 0; i < 4; i++) pool_release(s16[i], 16);
    for (int i = 0; i < 3; i++) pool_release(s64[i], 64);
    for (int i = 0; i < 2; i++) pool_release(b1k[i], 1000);
    assert_int_equal(pool_stats(p).mallocs, 9);
    assert_int_equal(pool_stats(p).frees, 0);
    pool_leave(prev);
    /* 4 * 16 = 64 bytes of the 16-byte class, then 2 of the 3 64-byte
     * blocks (128 bytes; 64 + 128 + 64 would pass 200), none of 1024 */
    pool_trim(p, 200);
    assert_int_equal(pool_stats(p).frees, 1 + 2);
    prev = pool_enter(p);
    /* the 64-byte blocks kept are the two released last, last out first */
    assert_ptr_equal(pool_alloc(64), s64[2]);
    assert_ptr_equal(pool_alloc(64), s64[1]);
    for (int i = 3; i >= 0; i--) assert_ptr_equal(pool_alloc(16), s16[i]);
    assert_int_equal(pool_stats(p).mallocs, 9);
    void *x = pool_alloc(64);                 /* the class is empty again */
    assert_int_equal(pool_stats(p).mallocs, 10);
    pool_release(x, 64);
    pool_release(s64[1], 64);
    pool_release(s64[2], 64);
    for (int i = 0; i < 4; i++) pool_release(s16[i], 16);
    pool_leave(prev);
    uint64_t f = pool_stats(p).frees;
    pool_trim(p, 0);                          /* everything goes */
    assert_int_equal(pool_stats(p).frees, f + 7);
    prev = pool_enter(p);
    void *y = pool_alloc(16);
    assert_int_equal(pool_stats(p).mallocs, 11);
    pool_release(y, 16);
    pool_leave(prev);
    pool_trim(NULL, 0);
    pool_free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_classes_and_reuse),
        cmocka_unit_test(test_inactive_and_nesting),
        cmocka_unit_test(test_nopool),
        cmocka_unit_test(test_trim_keeps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
