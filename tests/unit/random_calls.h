/* random_calls.h: the random expressions that the evaluation-route tests
 * (test_fastroute.c, test_kernel.c) run on every route: a small linear
 * congruential generator, and expressions with the calls compiled into
 * expressions of their own (numexpr.c). Header-only, static functions;
 * the test files include cmocka.h and runscript.h before it. */
#ifndef FL_TEST_RANDOM_CALLS_H
#define FL_TEST_RANDOM_CALLS_H

#include <stdint.h>

#include "buf.h"

/* A deterministic pseudo-random generator for the random expressions. */
static uint32_t lcg(uint32_t *st)
{
    *st = *st * 1664525u + 1013904223u;
    return *st >> 8;
}

/* Random arithmetic (as test_fastroute's random_vexpr) with the calls
 * that compile into an expression of their own (numexpr.c): hypot of one
 * argument, map and clamp of three, noise of a seed and one to three coordinates, and
 * draws of uniform, beta and normal streams made from numbers; their
 * operands are numbers, vectors (of one length, and of two), NaN, inf,
 * -0, huge numbers and a string. */
static void random_cexpr(Buf *b, uint32_t *st, int depth)
{
    static const char *const leaves[] = {"x", "p", "q", "w", "n", "i", "mz", "2", "0.5", "-1.75", "1e200", "s"};
    static const char *const binops[] = {"+", "-", "*", "/", "//", "%", "<", "+", "-", "*"};
    static const char *const streams[] = {"uniform", "beta", "normal"};
    uint32_t r = lcg(st) % 14;
    if (depth == 0 || r < 3) {
        buf_puts(b, leaves[lcg(st) % (sizeof leaves / sizeof leaves[0])]);
    } else if (r < 6) {
        buf_puts(b, "(");
        random_cexpr(b, st, depth - 1);
        buf_printf(b, ")%s(", binops[lcg(st) % (sizeof binops / sizeof binops[0])]);
        random_cexpr(b, st, depth - 1);
        buf_puts(b, ")");
    } else if (r < 7) {
        buf_puts(b, "hypot(");
        random_cexpr(b, st, depth - 1);
        buf_puts(b, ")");
    } else if (r < 9) {
        buf_puts(b, lcg(st) % 2 ? "map(" : "clamp(");
        for (int j = 0; j < 3; j++) {
            if (j) buf_puts(b, ", ");
            random_cexpr(b, st, depth - 1);
        }
        buf_puts(b, ")");
    } else if (r < 11) {
        uint32_t k = 1 + lcg(st) % 3;
        buf_puts(b, lcg(st) % 2 ? "noise(:s, " : "noise(:s;(");
        if (b->len && b->data[b->len - 1] == '(') {
            /* a seed of a symbol and an expression */
            random_cexpr(b, st, depth - 1);
            buf_puts(b, "), ");
        }
        for (uint32_t j = 0; j < k; j++) {
            if (j) buf_puts(b, ", ");
            random_cexpr(b, st, depth - 1);
        }
        buf_puts(b, ")");
    } else {
        buf_printf(b, "%s(:k;(", streams[lcg(st) % 3]);
        random_cexpr(b, st, depth - 1);
        buf_puts(b, "))[");
        random_cexpr(b, st, depth - 1);
        buf_puts(b, "]");
    }
}

#endif
