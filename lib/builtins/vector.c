/* vector.c: the vector utilities (LANGUAGE.md §5.3): len, sum, product,
 * accumulate, mean, min, max, minindex, maxindex, sort, count, zip.
 *
 * Arguments are borrowed; results are new vectors or NULL (null). Lane
 * functions (sum, product, accumulate, mean) take their lane count with the
 * reference's C `(int)` cast, emulated without undefined behaviour (NaN and
 * out-of-range values give INT_MIN, as on x86). Where the reference
 * compares host objects (min/max of an object vector, sort), only
 * number/number and string/string pairs are ordered; anything else is the
 * reference's TypeError, reported through bi_error with its message text.
 * sort is a stable merge sort, which equals the reference's (stable) sort
 * for every input without NaN.
 */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "builtins.h"
#include "mem.h"
#include "node.h"

/* {====================================================================
 * Helpers
 * ===================================================================== */

/* C `(int)x` as on x86: truncation, INT_MIN when out of range or NaN. */
static int to_int(double x)
{
    if (x > -2147483649.0 && x < 2147483648.0)
        return (int)x;
    return INT_MIN;
}

/* Element [i] of a numeric or object vector, as an element (borrowed). */
static Elem elem_at(const Vec *v, uint32_t i)
{
    if (v->kind == VEC_NUM) {
        Elem e = {.kind = EL_NUM};
        e.num = vec_cnums(v)[i];
        return e;
    }
    return vec_celems(v)[i];
}

/* Store a new reference to [src] in [dst] (an initialised element). */
static void elem_set(Elem *dst, const Elem *src)
{
    *dst = *src;
    switch (src->kind) {
    case EL_STR: str_retain(src->str); break;
    case EL_NODE: node_retain(src->node); break;
    case EL_FUNC: func_retain(src->func); break;
    default: break;
    }
}

/* The reference's host type name of an element, for TypeError texts. */
static const char *type_name(const Elem *e)
{
    switch (e->kind) {
    case EL_NUM: return "float";
    case EL_STR: return "str";
    case EL_NODE: return "flitter.model.Node";
    default: return e->func->bi ? "builtin_function_or_method" : "flitter.language.vm.Function";
    }
}

/* Host ordering `a OP b` (OP '<' or '>'): numbers and strings only; any
 * other pair sets *bad (a TypeError in the reference). */
static bool host_order(const Elem *a, const Elem *b, char op, bool *bad)
{
    if (a->kind == EL_NUM && b->kind == EL_NUM)
        return op == '<' ? a->num < b->num : a->num > b->num;
    if (a->kind == EL_STR && b->kind == EL_STR) {
        int c = str_cmp(a->str, b->str);
        return op == '<' ? c < 0 : c > 0;
    }
    *bad = true;
    return false;
}

static Vec *type_error(Eval *ev, const Builtin *bi, char op, const Elem *a, const Elem *b)
{
    return bi_error(ev, bi, "'%c' not supported between instances of '%s' and '%s'", op,
                    type_name(a), type_name(b));
}

/* }==================================================================== */

/* {====================================================================
 * len, sum, product, accumulate, mean
 * ===================================================================== */

static Vec *bi_lenv(BI_PARAMS)
{
    return vec_num1((double)vec_len(args[0]));
}

/* The lane count argument (position 1, default 1) of the lane functions;
 * 0 when it is missing the required shape or below 1. */
static int lanes(int nargs, Vec *const *args)
{
    if (nargs < 2)
        return 1;
    if (!vec_is_scalar(args[1]))
        return 0;
    int m = to_int(vec_scalar(args[1]));
    return m < 1 ? 0 : m;
}

/* sum (product when [mul]): m lanes, lane j accumulating xs[i], i ≡ j. */
static Vec *fold_lanes(Eval *ev, const Builtin *bi, int nargs, Vec *const *args, bool mul)
{
    const Vec *xs = args[0];
    if (vec_is_obj(xs))
        return NULL;
    int m = lanes(nargs, args);
    if (m == 0)
        return NULL;
    if ((uint64_t)m > MAX_RESULT)
        return bi_error(ev, bi, "too many lanes");
    if (!mem_fits(sizeof(Vec) + (size_t)m * sizeof(double)) && mem_take_refusal())
        return bi_error(ev, bi, "out of memory");   /* the budget, mem.h */
    Vec *r = vec_new_num((uint32_t)m);
    double *y = vec_nums(r);
    for (int j = 0; j < m; j++)
        y[j] = mul ? 1 : 0;
    uint32_t n = vec_is_num(xs) ? xs->len : 0;
    /* (the lane counted, not divided) */
    for (uint32_t i = 0, j = 0; i < n; i++) {
        if (mul)
            y[j] *= vec_cnums(xs)[i];
        else
            y[j] += vec_cnums(xs)[i];
        if (++j == (uint32_t)m) j = 0;
    }
    return r;
}

static Vec *bi_sumv(BI_PARAMS) { return fold_lanes(ev, bi, nargs, args, false); }
static Vec *bi_product(BI_PARAMS) { return fold_lanes(ev, bi, nargs, args, true); }

static Vec *bi_accumulate(BI_PARAMS)
{
    const Vec *xs = args[0];
    if (!vec_is_num(xs))
        return NULL;
    int m = lanes(nargs, args);
    if (m == 0)
        return NULL;
    uint32_t n = xs->len, um = (uint32_t)m;
    const double *x = vec_cnums(xs);
    Vec *r = vec_new_num(n);
    double *y = vec_nums(r);
    for (uint32_t k = 0; k < n; k++)
        y[k] = k < um ? x[k] : y[k - um] + x[k];
    return r;
}

/* mean(xs, zs=1): lane sums divided by lane counts; empty lanes stay 0. */
static Vec *bi_mean(BI_PARAMS)
{
    const Vec *xs = args[0];
    if (vec_is_obj(xs))
        return NULL;
    int m = lanes(nargs, args);
    if (m == 0)
        return NULL;
    if ((uint64_t)m > MAX_RESULT)
        return bi_error(ev, bi, "too many lanes");
    if (!mem_fits(sizeof(Vec) + (size_t)m * sizeof(double)) && mem_take_refusal())
        return bi_error(ev, bi, "out of memory");   /* the budget, mem.h */
    uint32_t um = (uint32_t)m, n = vec_is_num(xs) ? xs->len : 0;
    Vec *r = vec_new_num(um);
    double *y = vec_nums(r);
    for (uint32_t j = 0; j < um; j++)
        y[j] = 0;
    for (uint32_t i = 0, j = 0; i < n; i++) {   /* (the lane counted, not divided) */
        y[j] = y[j] + vec_cnums(xs)[i];
        if (++j == um) j = 0;
    }
    for (uint32_t j = 0; j < um; j++) {
        /* lane j holds the elements j, j+m, ... below n */
        double d = j < n ? (double)((n - j - 1) / um + 1) : 0;
        if (d != 0)
            y[j] = y[j] / d;
    }
    return r;
}

/* }==================================================================== */

/* {====================================================================
 * min, max, minindex, maxindex
 * ===================================================================== */

/* The scans behind min/max/minindex/maxindex. [op] is '<' (min) or '>'
 * (max); [index] asks for the winner's position instead of its value. */
static Vec *extreme(Eval *ev, const Builtin *bi, int nargs, Vec *const *args, char op, bool index)
{
    if (nargs > 1) {
        /* whole vectors by cmp (§3.7); incomparable gives null silently */
        int want = op == '<' ? -1 : 1, best = 0;
        for (int k = 1; k < nargs; k++) {
            int c = vec_cmp(args[k], args[best]);
            if (c == want)
                best = k;
            else if (c == CMP_INCOMPARABLE)
                return NULL;
        }
        return index ? vec_num1(best) : vec_retain(args[best]);
    }
    const Vec *xs = args[0];
    uint32_t n = vec_len(xs), best = 0;
    if (n == 0)
        return NULL;
    if (xs->kind == VEC_NUM) {
        const double *x = vec_cnums(xs);
        double f = x[0];
        for (uint32_t i = 1; i < n; i++)
            if (op == '<' ? x[i] < f : x[i] > f) {
                f = x[i];
                best = i;
            }
        return index ? vec_num1(best) : vec_num1(f);
    }
    const Elem *e = vec_celems(xs);
    for (uint32_t i = 1; i < n; i++) {
        bool bad = false;
        bool better = host_order(&e[i], &e[best], op, &bad);
        if (bad)
            return type_error(ev, bi, op, &e[i], &e[best]);
        if (better)
            best = i;
    }
    if (index)
        return vec_num1(best);
    Vec *r = vec_new_obj(1);
    elem_set(&vec_elems(r)[0], &e[best]);
    return vec_normalize_take(r);
}

static Vec *bi_minv(BI_PARAMS) { return extreme(ev, bi, nargs, args, '<', false); }
static Vec *bi_maxv(BI_PARAMS) { return extreme(ev, bi, nargs, args, '>', false); }
static Vec *bi_minindex(BI_PARAMS) { return extreme(ev, bi, nargs, args, '<', true); }
static Vec *bi_maxindex(BI_PARAMS) { return extreme(ev, bi, nargs, args, '>', true); }

/* }==================================================================== */

/* {====================================================================
 * sort, count, zip
 * ===================================================================== */

/* Stable bottom-up merge sort of [n] elements with host '<'. On an
 * unorderable pair, stores it in bad[0..1] and returns false. The merge
 * asks "right < left" like the reference's sort, so a later element is
 * taken only when strictly smaller. */
static bool merge_sort(Elem *a, uint32_t n, Elem bad[2])
{
    Elem *tmp = malloc(sizeof *tmp * (n ? n : 1));
    if (!tmp)
        mem_oom();
    bool ok = true;
    for (uint64_t width = 1; width < n && ok; width *= 2) {
        for (uint64_t lo = 0; lo + width < n && ok; lo += 2 * width) {
            uint64_t mid = lo + width, hi = mid + width < n ? mid + width : n;
            uint64_t i = lo, j = mid, k = lo;
            while (i < mid && j < hi) {
                bool wrong = false;
                bool take_right = host_order(&a[j], &a[i], '<', &wrong);
                if (wrong) {
                    bad[0] = a[j];
                    bad[1] = a[i];
                    ok = false;
                    break;
                }
                tmp[k++] = take_right ? a[j++] : a[i++];
            }
            if (!ok)
                break;
            while (i < mid)
                tmp[k++] = a[i++];
            while (j < hi)
                tmp[k++] = a[j++];
            memcpy(a + lo, tmp + lo, sizeof *a * (size_t)(hi - lo));
        }
    }
    free(tmp);
    return ok;
}

static Vec *bi_sort(BI_PARAMS)
{
    const Vec *xs = args[0];
    uint32_t n = vec_len(xs);
    if (n == 0)
        return NULL;
    Elem *tmp = malloc(sizeof *tmp * n);
    if (!tmp)
        mem_oom();
    for (uint32_t i = 0; i < n; i++)
        tmp[i] = elem_at(xs, i); /* borrowed */
    Elem bad[2];
    if (!merge_sort(tmp, n, bad)) {
        free(tmp);
        return type_error(ev, bi, '<', &bad[0], &bad[1]);
    }
    Vec *r;
    if (xs->kind == VEC_NUM) {
        r = vec_new_num(n);
        for (uint32_t i = 0; i < n; i++)
            vec_nums(r)[i] = tmp[i].num;
    } else {
        r = vec_new_obj(n);
        for (uint32_t i = 0; i < n; i++)
            elem_set(&vec_elems(r)[i], &tmp[i]);
        r = vec_normalize_take(r);
    }
    free(tmp);
    return r;
}

/* count(xs, ys): for each element of xs, how many elements of ys equal it
 * (elem_equal: numbers by value, strings by bytes, nodes structurally,
 * functions by identity, different kinds unequal). */
static Vec *bi_count(BI_PARAMS)
{
    const Vec *xs = args[0], *ys = args[1];
    uint32_t n = vec_len(xs), m = vec_len(ys);
    if (n == 0)
        return NULL;
    Vec *r = vec_new_num(n);
    for (uint32_t i = 0; i < n; i++) {
        Elem x = elem_at(xs, i);
        uint32_t k = 0;
        for (uint32_t j = 0; j < m; j++) {
            Elem y = elem_at(ys, j);
            if (elem_equal(&y, &x))
                k++;
        }
        vec_nums(r)[i] = (double)k;
    }
    return r;
}

/* zip(v1, v2, ...): empty arguments dropped; element i*m + j of the result
 * is v_j[i mod len_j] for i below the longest length n. */
static Vec *bi_zipv(BI_PARAMS)
{
    int m = 0;
    uint32_t n = 0;
    bool numeric = true;
    for (int k = 0; k < nargs; k++)
        if (vec_len(args[k])) {
            m++;
            if (args[k]->len > n)
                n = args[k]->len;
            numeric = numeric && args[k]->kind == VEC_NUM;
        }
    if (m == 0)
        return NULL;
    const Vec **vs = malloc(sizeof *vs * (size_t)m);
    if (!vs)
        mem_oom();
    m = 0;
    for (int k = 0; k < nargs; k++)
        if (vec_len(args[k]))
            vs[m++] = args[k];
    Vec *r;
    if (m == 1) {
        r = vec_retain((Vec *)vs[0]);
    } else if ((uint64_t)n * (uint64_t)m > MAX_RESULT) {
        r = bi_error(ev, bi, "result too long");
    } else if (!mem_fits(sizeof(Vec) + (size_t)n * (size_t)m * (numeric ? sizeof(double) : sizeof(Elem))) &&
               mem_take_refusal()) {
        r = bi_error(ev, bi, "out of memory");   /* the budget, mem.h */
    } else {
        uint32_t len = n * (uint32_t)m;
        r = numeric ? vec_new_num(len) : vec_new_obj(len);
        for (uint32_t i = 0; i < n; i++)
            for (int j = 0; j < m; j++) {
                uint32_t at = i * (uint32_t)m + (uint32_t)j, from = i % vs[j]->len;
                if (numeric) {
                    vec_nums(r)[at] = vec_cnums(vs[j])[from];
                } else {
                    Elem e = elem_at(vs[j], from);
                    elem_set(&vec_elems(r)[at], &e);
                }
            }
    }
    free(vs);
    return r;
}

/* }==================================================================== */

/* The vector family (shuffle lives with the random streams). */
const Builtin bi_vector_table[] = {
    {"len", "lenv", 1, 1, {"xs"}, bi_lenv, 0},
    {"sum", "sumv", 1, 2, {"xs", "w"}, bi_sumv, 0},
    {"product", "product", 1, 2, {"xs", "w"}, bi_product, 0},
    {"accumulate", "accumulate", 1, 2, {"xs", "zs"}, bi_accumulate, 0},
    {"mean", "mean", 1, 2, {"xs", "zs"}, bi_mean, 0},
    {"min", "minv", 1, BI_VARIADIC, {"xs"}, bi_minv, 0},
    {"max", "maxv", 1, BI_VARIADIC, {"xs"}, bi_maxv, 0},
    {"minindex", "minindex", 1, BI_VARIADIC, {"xs"}, bi_minindex, 0},
    {"maxindex", "maxindex", 1, BI_VARIADIC, {"xs"}, bi_maxindex, 0},
    {"sort", "sort", 1, 1, {"xs"}, bi_sort, 0},
    {"count", "count", 2, 2, {"xs", "ys"}, bi_count, 0},
    {"zip", "zipv", 0, BI_VARIADIC, {NULL}, bi_zipv, 0},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
