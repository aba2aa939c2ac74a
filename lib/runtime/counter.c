/* counter.c: the `!counter` renderer node (COUNTERS.md). */
#include "counter.h"

#include <string.h>

/* Attribute [name] of [n] when it is a numeric vector, else [dflt]
 * (COUNTERS.md "fvec"); a new reference. */
static Vec *fvec(const Node *n, const char *name, Vec *dflt)
{
    const Vec *v = node_attr(n, name);
    return vec_is_num(v) ? vec_share(v) : vec_retain(dflt);
}

/* c.when(a, b) of COUNTERS.md: element-wise choice with wrap-around, null
 * unless all three are numeric; a new reference. A single condition (the
 * usual reset=, absent or a number) picks all of [a] or [b]: the picked
 * vector itself when it is already the result's length. */
static Vec *when(const Vec *c, const Vec *a, const Vec *b)
{
    if (!vec_is_num(c) || !vec_is_num(a) || !vec_is_num(b)) return NULL;
    uint32_t n = c->len;
    if (a->len > n) n = a->len;
    if (b->len > n) n = b->len;
    if (c->len == 1) {
        const Vec *pick = vec_cnums(c)[0] != 0.0 ? a : b;
        if (pick->len == n) return vec_share(pick);
    }
    Vec *r = vec_new_num(n);
    double *d = vec_nums(r);
    const double *xc = vec_cnums(c), *xa = vec_cnums(a), *xb = vec_cnums(b);
    /* (the wrapped indices counted, not divided: i % len for each) */
    uint32_t ic = 0, ia = 0, ib = 0;
    for (uint32_t i = 0; i < n; i++) {
        d[i] = xc[ic] != 0.0 ? xa[ia] : xb[ib];
        if (++ic == c->len) ic = 0;
        if (++ia == a->len) ia = 0;
        if (++ib == b->len) ib = 0;
    }
    return r;
}

/* clamp(v, lo, hi) of COUNTERS.md, with Python's max/min comparison rules;
 * a new reference ([v] itself when there is no bound to apply). */
static Vec *clamp(Vec *v, const Vec *lo, const Vec *hi)
{
    if (!vec_is_num(v)) return vec_retain(v);
    bool has_lo = vec_is_num(lo), has_hi = vec_is_num(hi);
    if (!has_lo && !has_hi) return vec_retain(v);
    uint32_t n = v->len;
    if (has_lo && lo->len > n) n = lo->len;
    if (has_hi && hi->len > n) n = hi->len;
    Vec *r = vec_new_num(n);
    double *out = vec_nums(r);
    const double *xv = vec_cnums(v), *xlo = has_lo ? vec_cnums(lo) : NULL, *xhi = has_hi ? vec_cnums(hi) : NULL;
    /* (the wrapped indices counted, not divided) */
    uint32_t iv = 0, ilo = 0, ihi = 0;
    for (uint32_t i = 0; i < n; i++) {
        double d = xv[iv];
        if (++iv == v->len) iv = 0;
        if (has_lo) {
            double y = xlo[ilo];
            if (y > d) d = y;
            if (++ilo == lo->len) ilo = 0;
        }
        if (has_hi) {
            double y = xhi[ihi];
            if (y < d) d = y;
            if (++ihi == hi->len) ihi = 0;
        }
        out[i] = d;
    }
    return r;
}

void counter_update(const Node *node, StateDict *state, double frame_time)
{
    const Vec *key = node_attr(node, "state");
    if (!vec_len(key)) return;
    Vec *now = vec_num1(frame_time);
    Vec *zero = vec_num1(0.0);
    Vec *time = fvec(node, "time", now);
    Vec *rate = fvec(node, "rate", zero);
    Vec *initial = fvec(node, "initial", zero);
    Vec *reset = fvec(node, "reset", zero);
    Vec *min_alt = fvec(node, "min", NULL), *max_alt = fvec(node, "max", NULL);
    Vec *minimum = fvec(node, "minimum", min_alt), *maximum = fvec(node, "maximum", max_alt);

    Vec *sym_time = vec_num1(symbol_value("time", 4));
    Vec *parts[2] = {(Vec *)key, sym_time};   /* vec_compose only reads its parts */
    Vec *time_key = vec_compose(parts, 2);

    Vec *current = vec_share(state_get(state, key));
    if (!current) {
        current = vec_retain(initial);
    } else {
        const Vec *last = state_get(state, time_key);
        Vec *elapsed = vec_arith(OP_SUB, time, last);
        Vec *change = vec_arith(OP_MUL, elapsed, rate);
        Vec *advanced = vec_arith(OP_ADD, change, current);
        vec_release(current);
        current = when(reset, initial, advanced);
        vec_release(elapsed);
        vec_release(change);
        vec_release(advanced);
    }
    Vec *clamped = clamp(current, minimum, maximum);
    state_set(state, key, clamped);
    state_set(state, time_key, time);

    vec_release(clamped);
    vec_release(current);
    vec_release(time_key);
    vec_release(sym_time);
    vec_release(minimum);
    vec_release(maximum);
    vec_release(min_alt);
    vec_release(max_alt);
    vec_release(reset);
    vec_release(initial);
    vec_release(rate);
    vec_release(time);
    vec_release(zero);
    vec_release(now);
}
