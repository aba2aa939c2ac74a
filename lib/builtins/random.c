/* random.c: the built-ins of LANGUAGE.md §5.8: `uniform`, `normal` and
 * `beta`, which return random streams (the generators are in streams.c), and
 * `shuffle`.
 */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "builtins.h"
#include "streams.h"
#include "node.h"

/* {====================================================================
 * Built-ins
 * ===================================================================== */

/* uniform(value) / normal(value) / beta(value): a stream keyed by the seed
 * hash of [value]; no argument or null gives HASH_START. */
static Vec *stream(int nargs, Vec *const *args, StreamKind kind)
{
    return vec_stream(kind, nargs > 0 ? vec_hash(args[0], true) : HASH_START);
}

static Vec *bi_uniform(BI_PARAMS) { return stream(nargs, args, STREAM_UNIFORM); }
static Vec *bi_normal(BI_PARAMS) { return stream(nargs, args, STREAM_NORMAL); }
static Vec *bi_beta(BI_PARAMS) { return stream(nargs, args, STREAM_BETA); }

int bi_stream_kind(const Builtin *bi)
{
    if (!bi) return -1;
    if (bi->fn == bi_uniform) return STREAM_UNIFORM;
    if (bi->fn == bi_normal) return STREAM_NORMAL;
    if (bi->fn == bi_beta) return STREAM_BETA;
    return -1;
}

/* The swap partner of position [i] in the forward Fisher–Yates shuffle of
 * [len] elements, [u] being source value i and [n] the remaining count:
 * (int)floor(u * n) + i. The reference reads out of bounds when that falls
 * outside [0, len) (only possible for u == 1.0 or non-uniform sources);
 * here it is clamped into range instead. */
static uint32_t swap_partner(double u, uint32_t n, uint32_t i, uint32_t len)
{
    double f = floor(u * (double)n);
    int64_t j = (f > -2147483649.0 && f < 2147483648.0) ? (int64_t)(int)f : INT_MIN;
    j += i;
    if (j < 0)
        return 0;
    if (j >= (int64_t)len)
        return len - 1;
    return (uint32_t)j;
}

/* shuffle(source, xs): forward Fisher–Yates driven by stream [source]. */
static Vec *bi_shuffle(BI_PARAMS)
{
    const Vec *src = args[0], *xs = args[1];
    if (!vec_is_stream(src))
        return bi_error(ev, bi, "Argument 'source' has incorrect type (expected "
                                "flitter.language.functions.random.uniform, got flitter.model.Vector)");
    uint32_t len = vec_len(xs);
    if (len == 0)
        return NULL;
    Vec *r;
    if (xs->kind == VEC_NUM) {
        r = vec_from_nums(vec_cnums(xs), len);
        double *x = vec_nums(r);
        uint32_t n = len;
        for (uint32_t i = 0; i + 1 < len; i++) {
            uint32_t j = swap_partner(rng_value(src->stream, src->key, i), n, i, len);
            n--;
            double t = x[i];
            x[i] = x[j];
            x[j] = t;
        }
        return r;
    }
    r = vec_new_obj(len);
    Elem *e = vec_elems(r);
    const Elem *s = vec_celems(xs);
    for (uint32_t i = 0; i < len; i++) {
        e[i] = s[i];
        if (e[i].kind == EL_STR)
            str_retain(e[i].str);
        else if (e[i].kind == EL_NODE)
            node_retain(e[i].node);
        else if (e[i].kind == EL_FUNC)
            func_retain(e[i].func);
    }
    uint32_t n = len;
    for (uint32_t i = 0; i + 1 < len; i++) {
        uint32_t j = swap_partner(rng_value(src->stream, src->key, i), n, i, len);
        n--;
        Elem t = e[i];
        e[i] = e[j];
        e[j] = t;
    }
    return r;
}

/* }==================================================================== */

/* The random family. uniform/normal/beta are classes in the reference,
 * so their internal names are the class names. */
const Builtin bi_random_table[] = {
    {"uniform", "uniform", 0, 1, {"value"}, bi_uniform, 0},
    {"normal", "normal", 0, 1, {"value"}, bi_normal, 0},
    {"beta", "beta", 0, 1, {"value"}, bi_beta, 0},
    {"shuffle", "shuffle", 2, 2, {"source", "xs"}, bi_shuffle, 0},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
