/* value.c: Flitter's vector model (LANGUAGE.md §3).
 *
 * Vectors are one allocation each: the `Vec` header followed by either
 * `len` doubles (VEC_NUM) or `len` 16-byte tagged elements (VEC_OBJ).
 * Streams (VEC_STREAM) carry only a kind and a key. The null vector is the
 * NULL pointer. Everything is reference counted and immutable once shared;
 * see the ownership rule at the top of value.h.
 *
 * This file also holds strings (`Str`), symbol values and the per-runtime
 * symbol table (an open-addressing hash set keyed by the symbol's bit
 * pattern, linear probing, grown at 50% load).
 */
#include "value.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cpu.h"
#include "mem.h"
#include "streams.h"
#include "node.h"
#include "pool.h"
#include "utf8.h"

/* ====================================================================
 * Memory
 * ==================================================================== */

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) {
        mem_oom();
    }
    return p;
}

/* ====================================================================
 * Strings
 * ==================================================================== */

Str *str_new(const char *s, size_t len)
{
    if (len > UINT32_MAX - 16) {
        mem_fail("string too long");
    }
    Str *r = pool_alloc(sizeof(Str) + len + 1);
    r->refs = 1;
    r->len = (uint32_t)len;
    if (len) memcpy(r->bytes, s, len);
    r->bytes[len] = '\0';
    return r;
}

Str *str_from(const char *s) { return str_new(s, strlen(s)); }


int str_cmp(const Str *a, const Str *b)
{
    uint32_t n = a->len < b->len ? a->len : b->len;
    int c = memcmp(a->bytes, b->bytes, n);
    if (c) return c;
    return a->len < b->len ? -1 : a->len > b->len ? 1 : 0;
}

uint64_t fnv1a_utf8(const char *s, size_t len)
{
    uint64_t y = UINT64_C(0xcbf29ce484222325);
    size_t i = 0;
    while (i < len) {
        uint32_t c;
        i += utf8_decode((const unsigned char *)s + i, len - i, &c);
        y = (y ^ c) * UINT64_C(0x100000001b3);
    }
    return y;
}

/* ====================================================================
 * Functions
 * ==================================================================== */

void func_release(Func *f)
{
    if (!f || --f->refs) return;
    if (f->destroy) f->destroy(f);
    str_release(f->name);
    pool_release(f, sizeof *f);
}

const char *func_name(const Func *f)
{
    if (f->bi) return f->bi_name;
    return f->name ? f->name->bytes : "<anon>";
}

/* ====================================================================
 * Vectors: construction and destruction
 * ==================================================================== */

static Vec *vec_alloc(uint8_t kind, uint32_t n, size_t elem_size)
{
    Vec *v = pool_alloc(sizeof(Vec) + (size_t)n * elem_size);
    v->refs = 1;
    v->kind = kind;
    v->stream = 0;
    v->hashed = 0;
    v->len = n;
    v->key = 0;
    return v;
}

Vec *vec_new_obj_raw(uint32_t n) { return vec_alloc(VEC_OBJ, n, sizeof(Elem)); }

void vec_free_taken(Vec *v) { pool_release(v, sizeof(Vec) + (size_t)v->len * sizeof(Elem)); }

Vec *vec_new_obj(uint32_t n)
{
    Vec *v = vec_alloc(VEC_OBJ, n, sizeof(Elem));
    Elem *e = vec_elems(v);
    for (uint32_t i = 0; i < n; i++) {
        e[i].kind = EL_NUM;
        e[i].num = 0.0;
    }
    return v;
}

Vec *vec_from_nums(const double *x, uint32_t n)
{
    if (!n) return NULL;
    /* the budget (mem.h): null, with the refusal marked for the caller */
    if (!mem_fits(sizeof(Vec) + (size_t)n * sizeof(double))) return NULL;
    Vec *v = vec_new_num(n);
    double *d = vec_nums(v);
    if (n <= 4) {   /* a position or a colour: no call */
        for (uint32_t i = 0; i < n; i++) d[i] = x[i];
    } else {
        memcpy(d, x, n * sizeof(double));
    }
    return v;
}

Vec *vec_str_take(Str *s)
{
    Vec *v = vec_new_obj(1);
    vec_elems(v)[0].kind = EL_STR;
    vec_elems(v)[0].str = s;
    return v;
}

Vec *vec_str(const char *s, size_t len) { return vec_str_take(str_new(s, len)); }

Vec *vec_copy_deep(const Vec *v)
{
    if (!v) return NULL;
    if (v->kind == VEC_STREAM) return vec_stream((StreamKind)v->stream, v->key);
    if (v->kind == VEC_NUM) {
        Vec *c = vec_new_num(v->len);
        if (v->len) memcpy(vec_nums(c), vec_cnums(v), (size_t)v->len * sizeof(double));
        return c;
    }
    Vec *c = vec_new_obj_raw(v->len);
    const Elem *from = vec_celems(v);
    Elem *to = vec_elems(c);
    for (uint32_t i = 0; i < v->len; i++) {
        to[i].kind = from[i].kind;
        switch (from[i].kind) {
        case EL_NUM: to[i].num = from[i].num; break;
        case EL_STR: to[i].str = str_new(from[i].str->bytes, from[i].str->len); break;
        case EL_NODE: to[i].node = node_copy_deep(from[i].node); break;
        default: to[i].func = func_retain(from[i].func); break;
        }
    }
    return c;
}

Vec *vec_node_take(Node *n)
{
    Vec *v = vec_new_obj(1);
    vec_elems(v)[0].kind = EL_NODE;
    vec_elems(v)[0].node = n;
    return v;
}

Vec *vec_func_take(Func *f)
{
    Vec *v = vec_new_obj(1);
    vec_elems(v)[0].kind = EL_FUNC;
    vec_elems(v)[0].func = f;
    return v;
}

Vec *vec_stream(StreamKind kind, uint64_t key)
{
    Vec *v = vec_alloc(VEC_STREAM, 0, 0);
    v->stream = (uint8_t)kind;
    v->key = key;
    return v;
}

static void elem_release(Elem *e)
{
    switch (e->kind) {
    case EL_STR: str_release(e->str); break;
    case EL_NODE: node_release(e->node); break;
    case EL_FUNC: func_release(e->func); break;
    default: break;
    }
}

static void elem_retain(Elem *e)
{
    switch (e->kind) {
    case EL_STR: str_retain(e->str); break;
    case EL_NODE: node_retain(e->node); break;
    case EL_FUNC: func_retain(e->func); break;
    default: break;
    }
}

void vec_destroy_(Vec *v)
{
    if (v->kind == VEC_OBJ) {
        Elem *e = vec_elems(v);
        for (uint32_t i = 0; i < v->len; i++) elem_release(&e[i]);
        pool_release(v, sizeof(Vec) + (size_t)v->len * sizeof(Elem));
    } else {
        pool_release(v, sizeof(Vec) + (size_t)v->len * sizeof(double));
    }
}

Vec *vec_normalize_take(Vec *v)
{
    if (!v || v->kind != VEC_OBJ) return v;
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < v->len; i++)
        if (e[i].kind != EL_NUM) return v;
    Vec *r = vec_new_num(v->len);
    for (uint32_t i = 0; i < v->len; i++) vec_nums(r)[i] = e[i].num;
    vec_release(v);
    return r;
}

/* ====================================================================
 * Truthiness and composition (§3.2, §3.4)
 * ==================================================================== */

bool vec_truthy(const Vec *v)
{
    if (!v) return false;
    if (v->kind == VEC_STREAM) return true;
    if (v->kind == VEC_NUM) {
        const double *x = vec_cnums(v);
        for (uint32_t i = 0; i < v->len; i++)
            if (x[i] != 0.0 || isnan(x[i])) return true;
        return false;
    }
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < v->len; i++) {
        switch (e[i].kind) {
        case EL_NUM: if (e[i].num != 0.0 || isnan(e[i].num)) return true; break;
        case EL_STR: if (e[i].str->len) return true; break;
        default: return true;
        }
    }
    return false;
}

Vec *vec_compose(Vec *const *parts, size_t n)
{
    uint64_t total = 0;
    bool numeric = true;
    size_t nonempty = 0, last = 0;
    /* the parts were usually made a while ago (the nodes of a long
     * sequence): fetch them a few ahead, here and in the loop below */
    for (size_t i = 0; i < n; i++) {
        const Vec *p = parts[i];
        if (i + 8 < n) __builtin_prefetch(parts[i + 8]);
        if (!p || p->len == 0) continue;
        total += p->len;
        nonempty++;
        last = i;
        if (p->kind != VEC_NUM) numeric = false;
    }
    if (total == 0) return NULL;
    if (nonempty == 1) return vec_retain(parts[last]);
    if (total > UINT32_MAX) {
        mem_fail("vector too long");
    }
    /* the budget (mem.h): null, with the refusal marked for the caller */
    if (!mem_fits(sizeof(Vec) + total * (numeric ? sizeof(double) : sizeof(Elem)))) return NULL;
    if (numeric) {
        Vec *r = vec_new_num((uint32_t)total);
        double *d = vec_nums(r);
        for (size_t i = 0; i < n; i++) {
            const Vec *p = parts[i];
            if (!p || !p->len) continue;
            if (p->len == 1) *d = vec_cnums(p)[0];   /* the common case: no call */
            else memcpy(d, vec_cnums(p), p->len * sizeof(double));
            d += p->len;
        }
        return r;
    }
    Vec *r = vec_new_obj((uint32_t)total);
    Elem *d = vec_elems(r);
    for (size_t i = 0; i < n; i++) {
        const Vec *p = parts[i];
        if (!p || !p->len) continue;
        if (p->kind == VEC_NUM) {
            for (uint32_t j = 0; j < p->len; j++) {
                d[j].kind = EL_NUM;
                d[j].num = vec_cnums(p)[j];
            }
        } else {
            memcpy(d, vec_celems(p), p->len * sizeof(Elem));
            for (uint32_t j = 0; j < p->len; j++) elem_retain(&d[j]);
        }
        d += p->len;
    }
    return r;
}

Vec *vec_compose_take(Vec **parts, size_t n)
{
    uint64_t total = 0;
    bool numeric = true;
    size_t nonempty = 0;
    /* the parts were usually made a while ago (the nodes of a long
     * sequence): fetch them a few ahead, here and in the loop below */
    for (size_t i = 0; i < n; i++) {
        const Vec *p = parts[i];
        if (i + 8 < n) __builtin_prefetch(parts[i + 8]);
        if (!p || p->len == 0) continue;
        total += p->len;
        nonempty++;
        if (p->kind != VEC_NUM) numeric = false;
    }
    if (numeric || nonempty <= 1) {
        /* nothing to move: compose as vec_compose does */
        Vec *r = vec_compose(parts, n);
        for (size_t i = 0; i < n; i++) vec_release(parts[i]);
        return r;
    }
    if (total > UINT32_MAX) mem_fail("vector too long");
    if (!mem_fits(sizeof(Vec) + total * sizeof(Elem))) {
        for (size_t i = 0; i < n; i++) vec_release(parts[i]);
        return NULL;
    }
    /* every element is set below */
    Vec *r = vec_new_obj_raw((uint32_t)total);
    Elem *d = vec_elems(r);
    for (size_t i = 0; i < n; i++) {
        Vec *p = parts[i];
        uint32_t len = vec_len(p);
        if (i + 8 < n) __builtin_prefetch(parts[i + 8], 1);
        if (!len) {
            vec_release(p);   /* null or a stream */
            continue;
        }
        if (p->kind == VEC_NUM) {
            for (uint32_t j = 0; j < len; j++) {
                d[j].kind = EL_NUM;
                d[j].num = vec_cnums(p)[j];
            }
            vec_release(p);
        } else if (p->refs == 1) {
            /* the last reference: the elements move, with their references
             * (one element, a node of a long sequence, without a call) */
            if (len == 1) d[0] = vec_celems(p)[0];
            else memcpy(d, vec_celems(p), len * sizeof(Elem));
            pool_release(p, sizeof(Vec) + (size_t)len * sizeof(Elem));
        } else {
            memcpy(d, vec_celems(p), len * sizeof(Elem));
            for (uint32_t j = 0; j < len; j++) elem_retain(&d[j]);
            vec_release(p);
        }
        d += len;
    }
    return r;
}

/* ====================================================================
 * Arithmetic (§3.5)
 * ==================================================================== */

double num_floordiv(double a, double b) { return floor(a / b); }

double num_mod(double a, double b) { return a - floor(a / b) * b; }

static inline double arith1(ArithOp op, double a, double b)
{
    switch (op) {
    case OP_ADD: return a + b;
    case OP_SUB: return a - b;
    case OP_MUL: return a * b;
    case OP_DIV: return a / b;
    case OP_FLOORDIV: return floor(a / b);
    case OP_MOD: return a - floor(a / b) * b;
    case OP_POW: return pow(a, b);
    }
    return NAN;
}

/* One operation over [n] numbers, the operands' steps 1 (a vector of [n])
 * or 0 (one number repeated): the literal loops, one per operation (not
 * arith1's switch for every number). */
#define ARITH_LOOPS(LOOP)                                                   \
    switch (op) {                                                           \
    case OP_ADD: LOOP(x + y); break;                                        \
    case OP_SUB: LOOP(x - y); break;                                        \
    case OP_MUL: LOOP(x * y); break;                                        \
    case OP_DIV: LOOP(x / y); break;                                        \
    case OP_FLOORDIV: LOOP(floor(x / y)); break;                            \
    case OP_MOD: LOOP(x - floor(x / y) * y); break;                         \
    default: LOOP(arith1(op, x, y)); break;                                 \
    }

static inline __attribute__((always_inline)) void arith_span(ArithOp op, double *r, const double *xa, bool va,
                                                            const double *xb, bool vb, uint32_t n)
{
#define SPAN(EXPR)                                                          \
    do {                                                                    \
        if (va && vb) {                                                     \
            for (uint32_t i = 0; i < n; i++) { double x = xa[i], y = xb[i]; r[i] = (EXPR); } \
        } else if (va) {                                                    \
            const double y = xb[0];                                         \
            for (uint32_t i = 0; i < n; i++) { double x = xa[i]; r[i] = (EXPR); } \
        } else {                                                            \
            const double x = xa[0];                                         \
            for (uint32_t i = 0; i < n; i++) { double y = xb[i]; r[i] = (EXPR); } \
        }                                                                   \
    } while (0)
    ARITH_LOOPS(SPAN)
#undef SPAN
}

/* Spans at least this long take the AVX copy where there is one (shorter
 * ones: its set-up would cost more than it saves). */
#define ARITH_AVX_MIN 8

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define HAVE_ARITH_AVX 1
/* arith_span four numbers at a time, for the operations whose every
 * number AVX computes to the same bits as the literal loop (IEEE
 * addition, subtraction, multiplication and division are exact to the
 * bit whatever the width, and vroundpd's floor is floor(), -0 and NaN
 * included), the last n % 4 by the literal loop's expression; other
 * operations (pow) by the literal loop. */
__attribute__((target("avx"))) static void arith_span_avx(ArithOp op, double *r, const double *xa, bool va,
                                                          const double *xb, bool vb, uint32_t n)
{
    if (op > OP_MOD) {
        arith_span(op, r, xa, va, xb, vb, n);
        return;
    }
    const __m256d ka = _mm256_set1_pd(xa[0]), kb = _mm256_set1_pd(xb[0]);
    const uint32_t n4 = n & ~3u;
#define FLOOR4(q) _mm256_round_pd((q), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)
#define SPAN4(EXPR4)                                                        \
    do {                                                                    \
        if (va && vb) {                                                     \
            for (uint32_t i = 0; i < n4; i += 4) {                          \
                __m256d x = _mm256_loadu_pd(xa + i), y = _mm256_loadu_pd(xb + i); \
                _mm256_storeu_pd(r + i, (EXPR4));                           \
            }                                                               \
        } else if (va) {                                                    \
            const __m256d y = kb;                                           \
            for (uint32_t i = 0; i < n4; i += 4) {                          \
                __m256d x = _mm256_loadu_pd(xa + i);                        \
                _mm256_storeu_pd(r + i, (EXPR4));                           \
            }                                                               \
        } else {                                                            \
            const __m256d x = ka;                                           \
            for (uint32_t i = 0; i < n4; i += 4) {                          \
                __m256d y = _mm256_loadu_pd(xb + i);                        \
                _mm256_storeu_pd(r + i, (EXPR4));                           \
            }                                                               \
        }                                                                   \
    } while (0)
    switch (op) {
    case OP_ADD: SPAN4(_mm256_add_pd(x, y)); break;
    case OP_SUB: SPAN4(_mm256_sub_pd(x, y)); break;
    case OP_MUL: SPAN4(_mm256_mul_pd(x, y)); break;
    case OP_DIV: SPAN4(_mm256_div_pd(x, y)); break;
    case OP_FLOORDIV: SPAN4(FLOOR4(_mm256_div_pd(x, y))); break;
    default: SPAN4(_mm256_sub_pd(x, _mm256_mul_pd(FLOOR4(_mm256_div_pd(x, y)), y))); break;
    }
#undef SPAN4
#undef FLOOR4
    if (n4 < n)
        arith_span(op, r + n4, va ? xa + n4 : xa, va, vb ? xb + n4 : xb, vb, n - n4);
}
#endif

/* arith_span by the fastest copy this processor runs. */
static void arith_span_fast(ArithOp op, double *r, const double *xa, bool va, const double *xb, bool vb,
                            uint32_t n)
{
#ifdef HAVE_ARITH_AVX
    if (n >= ARITH_AVX_MIN && cpu_has(CPU_AVX)) {
        arith_span_avx(op, r, xa, va, xb, vb, n);
        return;
    }
#endif
    arith_span(op, r, xa, va, xb, vb, n);
}

/* Most numbers of the repeated shorter operand of a cyclic broadcast: a
 * shorter operand of up to this many numbers is laid out end to end into
 * a tile of whole repeats, and the longer one taken a tile at a time as
 * two vectors of one length. */
#define ARITH_TILE 64

/* num_arith_into's cyclic broadcast, both operands longer than one number
 * and of different lengths, one of them [n] long (kept out of
 * num_arith_into's frame: its tile). */
static void arith_cycle(ArithOp op, double *r, const double *xa, uint32_t na, const double *xb, uint32_t nb,
                        uint32_t n)
{
    const uint32_t ns = na < nb ? na : nb;
    if (ns <= ARITH_TILE / 2) {
        /* a tile holds whole repeats of the shorter, so the tile that
         * starts at i (a multiple of its length) is xs[(i + j) % ns] */
        double tile[ARITH_TILE];
        const double *xs = na < nb ? xa : xb;
        const uint32_t nt = ARITH_TILE / ns * ns;
        for (uint32_t j = 0; j < nt; j++) tile[j] = xs[j % ns];
        for (uint32_t i = 0; i < n; i += nt) {
            const uint32_t m = n - i < nt ? n - i : nt;
            if (na < nb) arith_span_fast(op, r + i, tile, true, xb + i, true, m);
            else arith_span_fast(op, r + i, xa + i, true, tile, true, m);
        }
        return;
    }
#define CYCLE(EXPR)                                                         \
    for (uint32_t i = 0, ia = 0, ib = 0; i < n; i++) {                      \
        double x = xa[ia], y = xb[ib];                                      \
        r[i] = (EXPR);                                                      \
        if (++ia == na) ia = 0;                                             \
        if (++ib == nb) ib = 0;                                             \
    }
    ARITH_LOOPS(CYCLE)
#undef CYCLE
}

void num_arith_into(ArithOp op, double *r, const double *xa, uint32_t na, const double *xb, uint32_t nb)
{
    const uint32_t n = na > nb ? na : nb;
    if (na != nb && na != 1 && nb != 1) arith_cycle(op, r, xa, na, xb, nb, n);
    /* (a few numbers, the most usual: the literal loop here, no call) */
    else if (n < ARITH_AVX_MIN) arith_span(op, r, xa, na != 1 || n == 1, xb, nb != 1 || n == 1, n);
    else arith_span_fast(op, r, xa, na != 1, xb, nb != 1, n);
}

/* r[i] = a[i % na] OP b[i % nb] for i < n (n: the longer length); [r]
 * may be a's or b's own storage when that operand has n elements. */
static void arith_into(ArithOp op, double *r, const Vec *a, const Vec *b)
{
    num_arith_into(op, r, vec_cnums(a), a->len, vec_cnums(b), b->len);
}

double num_arith(ArithOp op, double a, double b) { return arith1(op, a, b); }

Vec *vec_arith(ArithOp op, const Vec *a, const Vec *b)
{
    if (!vec_is_num(a) || !vec_is_num(b) || !a->len || !b->len) return NULL;
    uint32_t n = a->len > b->len ? a->len : b->len;
    Vec *v = vec_new_num(n);
    arith_into(op, vec_nums(v), a, b);
    return v;
}

/* [v] (consumed) as the destination of an n-element numeric result, when
 * nothing else can see it; else NULL. */
static bool reusable(const Vec *v, uint32_t n) { return v->refs == 1 && v->len == n; }

Vec *vec_arith_take(ArithOp op, Vec *a, Vec *b)
{
    if (vec_is_scalar(a) && vec_is_scalar(b)) {
        /* the common case: one number each, no broadcasting loop */
        double x = vec_cnums(a)[0], y = vec_cnums(b)[0], z;
        switch (op) {
        case OP_ADD: z = x + y; break;
        case OP_SUB: z = x - y; break;
        case OP_MUL: z = x * y; break;
        case OP_DIV: z = x / y; break;
        default: z = arith1(op, x, y); break;
        }
        Vec *v;
        if (a->refs == 1) {
            v = a;
            vec_release(b);
        } else if (b->refs == 1) {
            v = b;
            vec_release(a);
        } else {
            vec_release(a);
            vec_release(b);
            return vec_num1(z);
        }
        v->hashed = 0;
        vec_nums(v)[0] = z;
        return v;
    }
    if (!vec_is_num(a) || !vec_is_num(b) || !a->len || !b->len) {
        vec_release(a);
        vec_release(b);
        return NULL;
    }
    uint32_t n = a->len > b->len ? a->len : b->len;
    Vec *v;
    if (reusable(a, n)) {
        v = a;
        v->hashed = 0;
        arith_into(op, vec_nums(v), a, b);
        vec_release(b);
    } else if (reusable(b, n)) {
        v = b;
        v->hashed = 0;
        arith_into(op, vec_nums(v), a, b);
        vec_release(a);
    } else {
        v = vec_new_num(n);
        arith_into(op, vec_nums(v), a, b);
        vec_release(a);
        vec_release(b);
    }
    return v;
}

Vec *vec_add_mul(const Vec *a, const Vec *b, const Vec *c)
{
    if (!vec_is_num(a) || !vec_is_num(b) || !vec_is_num(c)) return NULL;
    uint32_t na = a->len, nb = b->len, nc = c->len;
    if (!na || !nb || !nc) return NULL;
    const double *xa = vec_cnums(a), *xb = vec_cnums(b), *xc = vec_cnums(c);
    if ((na | nb | nc) == 1) {
        double p = xb[0] * xc[0];
        return vec_num1(xa[0] + p);
    }
    uint32_t n = na > nb ? na : nb;
    if (nc > n) n = nc;
    Vec *v = vec_new_num(n);
    double *r = vec_nums(v);
    /* (the wrapped indices counted, not divided) */
    for (uint32_t i = 0, ia = 0, ib = 0, ic = 0; i < n; i++) {
        double p = xb[ib] * xc[ic];
        r[i] = xa[ia] + p;
        if (++ia == na) ia = 0;
        if (++ib == nb) ib = 0;
        if (++ic == nc) ic = 0;
    }
    return v;
}

Vec *vec_neg(const Vec *a)
{
    if (!vec_is_num(a)) return NULL;
    Vec *v = vec_new_num(a->len);
    for (uint32_t i = 0; i < a->len; i++) vec_nums(v)[i] = -vec_cnums(a)[i];
    return v;
}

Vec *vec_pos(Vec *a)
{
    return vec_is_num(a) ? vec_retain(a) : NULL;
}

/* ====================================================================
 * Equality, ordering, containment (§3.6-3.8)
 * ==================================================================== */

bool elem_equal(const Elem *a, const Elem *b)
{
    if (a->kind != b->kind) return false;
    switch (a->kind) {
    case EL_NUM: return a->num == b->num;
    case EL_STR: return str_eq(a->str, b->str);
    case EL_NODE: return node_equal(a->node, b->node);
    case EL_FUNC: return a->func == b->func;
    }
    return false;
}

bool vec_equal(const Vec *a, const Vec *b)
{
    uint32_t na = vec_len(a), nb = vec_len(b);
    if (na != nb) return false;
    if (na == 0) {
        /* streams compare equal when kind and key match; null == null */
        if (vec_is_stream(a) || vec_is_stream(b))
            return vec_is_stream(a) && vec_is_stream(b) && a->stream == b->stream && a->key == b->key;
        return true;
    }
    if (a->kind != b->kind) return false;
    if (a->kind == VEC_NUM) {
        const double *x = vec_cnums(a), *y = vec_cnums(b);
        for (uint32_t i = 0; i < na; i++)
            if (!(x[i] == y[i])) return false;
        return true;
    }
    const Elem *x = vec_celems(a), *y = vec_celems(b);
    for (uint32_t i = 0; i < na; i++)
        if (!elem_equal(&x[i], &y[i])) return false;
    return true;
}

static uint64_t dbits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

bool vec_key_equal(const Vec *a, const Vec *b)
{
    uint32_t na = vec_len(a), nb = vec_len(b);
    if (na != nb) return false;
    if (na == 0) return vec_equal(a, b);
    if (a->kind != b->kind) return false;
    if (a->kind == VEC_NUM) {
        const double *x = vec_cnums(a), *y = vec_cnums(b);
        for (uint32_t i = 0; i < na; i++)
            if (dbits(x[i]) != dbits(y[i])) return false;
        return true;
    }
    const Elem *x = vec_celems(a), *y = vec_celems(b);
    for (uint32_t i = 0; i < na; i++) {
        if (x[i].kind == EL_NUM && y[i].kind == EL_NUM) {
            if (dbits(x[i].num) != dbits(y[i].num)) return false;
        } else if (!elem_equal(&x[i], &y[i])) {
            return false;
        }
    }
    return true;
}

int vec_cmp(const Vec *a, const Vec *b)
{
    uint32_t na = vec_len(a), nb = vec_len(b);
    if (na == 0 && nb == 0) return 0;
    if (na && nb && a->kind == VEC_NUM && b->kind == VEC_NUM) {
        const double *x = vec_cnums(a), *y = vec_cnums(b);
        uint32_t n = na < nb ? na : nb;
        for (uint32_t i = 0; i < n; i++) {
            if (x[i] == y[i]) continue;
            return x[i] < y[i] ? -1 : 1;
        }
    } else if (na && nb && a->kind == VEC_OBJ && b->kind == VEC_OBJ) {
        const Elem *x = vec_celems(a), *y = vec_celems(b);
        uint32_t n = na < nb ? na : nb;
        for (uint32_t i = 0; i < n; i++) {
            if (elem_equal(&x[i], &y[i])) continue;
            if (x[i].kind == EL_NUM && y[i].kind == EL_NUM)
                return x[i].num < y[i].num ? -1 : 1;
            if (x[i].kind == EL_STR && y[i].kind == EL_STR)
                return str_cmp(x[i].str, y[i].str) < 0 ? -1 : 1;
            return CMP_INCOMPARABLE;
        }
    } else if (na == 0) {
        return -1;
    } else if (nb == 0) {
        return 1;
    } else {
        return CMP_INCOMPARABLE;
    }
    return na == nb ? 0 : (na < nb ? -1 : 1);
}

bool vec_contains(const Vec *x, const Vec *y)
{
    uint32_t nx = vec_len(x), ny = vec_len(y);
    if (nx == 0) return true;
    if (nx > ny) return false;
    if (x->kind == VEC_OBJ && y->kind == VEC_NUM) return false;
    for (uint32_t s = 0; s + nx <= ny; s++) {
        bool match = true;
        for (uint32_t i = 0; i < nx && match; i++) {
            if (x->kind == VEC_NUM && y->kind == VEC_NUM) {
                match = vec_cnums(x)[i] == vec_cnums(y)[s + i];
            } else if (x->kind == VEC_NUM) {
                const Elem *e = &vec_celems(y)[s + i];
                match = e->kind == EL_NUM && e->num == vec_cnums(x)[i];
            } else {
                match = elem_equal(&vec_celems(x)[i], &vec_celems(y)[s + i]);
            }
        }
        if (match) return true;
    }
    return false;
}

/* ====================================================================
 * Hashing (§3.16)
 * ==================================================================== */

uint64_t vec_hash_nums(const double *x, uint32_t n, bool floor_floats)
{
    uint64_t h = HASH_START;
    /* (a loop each: no test of floor_floats per number) */
    if (floor_floats)
        for (uint32_t i = 0; i < n; i++) h = hash_update(h, dbits(floor(x[i])));
    else
        h = vec_hash_nums_raw(x, n);
    return h;
}

uint64_t vec_hash(const Vec *v, bool floor_floats)
{
    uint64_t h = HASH_START;
    if (!v) return h;
    if (v->kind == VEC_STREAM) return hash_update(hash_update(h, v->stream), v->key);
    if (v->kind == VEC_NUM) return vec_hash_nums(vec_cnums(v), v->len, floor_floats);
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < v->len; i++) {
        uint64_t y;
        switch (e[i].kind) {
        case EL_NUM: y = dbits(floor_floats ? floor(e[i].num) : e[i].num); break;
        case EL_STR: y = fnv1a_utf8(e[i].str->bytes, e[i].str->len); break;
        case EL_NODE: y = node_hash(e[i].node); break;
        default: y = (uint64_t)(uintptr_t)e[i].func; break;
        }
        h = hash_update(h, y);
    }
    return h;
}

uint64_t vec_key_hash(const Vec *v)
{
    if (v->hashed) return v->key;
    uint64_t h = vec_hash(v, false);
    bool keep = v->kind == VEC_NUM;
    if (v->kind == VEC_OBJ) {
        keep = true;
        for (uint32_t i = 0; i < v->len && keep; i++)
            keep = vec_celems(v)[i].kind == EL_NUM || vec_celems(v)[i].kind == EL_STR;
    }
    if (keep) {
        /* a memo, not a change of value: the vector's elements are fixed */
        Vec *m = (Vec *)v;
        m->key = h;
        m->hashed = 1;
    }
    return h;
}

/* ====================================================================
 * Ranges, indexing, items (§3.10, §3.11, §5.8)
 * ==================================================================== */

Vec *vec_range(const Vec *start, const Vec *stop, const Vec *step,
               uint64_t max_len, bool *too_long)
{
    double a = 0.0, s = 1.0, b;
    if (start) {
        if (!vec_is_scalar(start)) return NULL;
        a = vec_scalar(start);
    }
    if (!vec_is_scalar(stop)) return NULL;
    b = vec_scalar(stop);
    if (step) {
        if (!vec_is_scalar(step)) return NULL;
        s = vec_scalar(step);
        if (s == 0.0) return NULL;
    }
    double q = ceil((b - a) / s);
    /* C conversion of NaN/inf gives INT64_MIN on x86 → null */
    if (!(q > 0.0) || isinf(q)) return NULL;
    if (q >= 9223372036854775808.0) return NULL;
    int64_t n = (int64_t)q;
    /* past the budget (mem.h) too: too long, with the refusal marked */
    if ((uint64_t)n > max_len || !mem_fits(sizeof(Vec) + (size_t)n * sizeof(double))) {
        if (too_long) *too_long = true;
        return NULL;
    }
    Vec *r = vec_new_num((uint32_t)n);
    double *d = vec_nums(r);
    for (int64_t i = 0; i < n; i++) d[i] = a + s * (double)i;
    return r;
}

/* floor(k) converted to a 32-bit C int, x86 semantics for out-of-range. */
static int32_t index32(double k)
{
    double f = floor(k);
    if (!(f >= -2147483648.0 && f < 2147483648.0)) return INT32_MIN;
    return (int32_t)f;
}

static int64_t index64(double k)
{
    double f = floor(k);
    if (!(f >= -9223372036854775808.0 && f < 9223372036854775808.0)) return INT64_MIN;
    return (int64_t)f;
}

static uint32_t wrap(int64_t j, uint32_t n)
{
    if ((uint64_t)j < n) return (uint32_t)j;   /* (the common case, without a division) */
    int64_t m = j % (int64_t)n;
    if (m < 0) m += n;
    return (uint32_t)m;
}

/* Element wrap(index32(k) or index64(k), n) of a vector of [n] (>= 1):
 * an index from 0 up to the length (and below 2**31, where index32's
 * conversion holds) is its own floor's element, the truncation, without
 * floor() and the range tests; any other (negative, too large, NaN) takes
 * them. */
static inline uint32_t element_of(double k, uint32_t n, bool literal)
{
    if (k >= 0.0 && k < (double)n && k < 2147483648.0) return (uint32_t)k;
    return wrap(literal ? index64(k) : index32(k), n);
}

void stream_index_into(StreamKind kind, uint64_t key, const double *k, uint32_t ni, double *out)
{
    for (uint32_t i = 0; i < ni; i++) {
        const uint64_t e = (uint64_t)index64(k[i]);
        /* both values of a normal pair (e even, then e + 1, as [..2]
         * asks) from one Box–Muller step: rng_normal_pair's are
         * rng_normal's bits */
        if (kind == STREAM_NORMAL && !(e & 1) && i + 1 < ni && (uint64_t)index64(k[i + 1]) == e + 1) {
            rng_normal_pair(key, e, out + i);
            i++;
            continue;
        }
        out[i] = rng_value(kind, key, e);
    }
}

double stream_value_at(StreamKind kind, uint64_t key, double k)
{
    return rng_value(kind, key, (uint64_t)index64(k));
}

void stream_index_each(StreamKind kind, uint64_t key, const double *k, uint32_t n, double *out)
{
    if (kind == STREAM_UNIFORM) {   /* rng_value's, without its switch a number */
        for (uint32_t i = 0; i < n; i++) out[i] = rng_uniform(key, (uint64_t)index64(k[i]));
        return;
    }
    for (uint32_t i = 0; i < n; i++) out[i] = rng_value(kind, key, (uint64_t)index64(k[i]));
}

Vec *vec_index(const Vec *src, const Vec *index, bool literal)
{
    if (!vec_is_num(index) || !index->len) return NULL;
    return vec_index_nums(src, vec_cnums(index), index->len, literal);
}

Vec *vec_index_nums(const Vec *src, const double *k, uint32_t ni, bool literal)
{
    if (!ni) return NULL;
    if (vec_is_stream(src)) {
        Vec *r = vec_new_num(ni);
        stream_index_into((StreamKind)src->stream, src->key, k, ni, vec_nums(r));
        return r;
    }
    uint32_t n = vec_len(src);
    if (!n) return NULL;
    if (src->kind == VEC_NUM) {
        Vec *r = vec_new_num(ni);
        const double *s = vec_cnums(src);
        double *d = vec_nums(r);
        for (uint32_t i = 0; i < ni; i++) d[i] = s[element_of(k[i], n, literal)];
        return r;
    }
    Vec *r = vec_new_obj(ni);
    for (uint32_t i = 0; i < ni; i++) {
        int64_t j = literal ? index64(k[i]) : index32(k[i]);
        vec_elems(r)[i] = vec_celems(src)[wrap(j, n)];
        elem_retain(&vec_elems(r)[i]);
    }
    return vec_normalize_take(r);
}

bool vec_index_num1(const Vec *src, double k, bool literal, double *out)
{
    if (vec_is_stream(src)) {
        *out = rng_value((StreamKind)src->stream, src->key, (uint64_t)index64(k));
        return true;
    }
    if (!src || src->kind != VEC_NUM || !src->len) return false;
    *out = vec_cnums(src)[element_of(k, src->len, literal)];
    return true;
}

Vec *vec_item(const Vec *v, int64_t i)
{
    if (vec_is_stream(v)) return vec_num1(rng_value((StreamKind)v->stream, v->key, (uint64_t)i));
    uint32_t n = vec_len(v);
    if (!n) return NULL;
    uint32_t j = wrap(i, n);
    if (v->kind == VEC_NUM) return vec_num1(vec_cnums(v)[j]);
    Elem e = vec_celems(v)[j];
    if (e.kind == EL_NUM) return vec_num1(e.num);
    Vec *r = vec_new_obj(1);
    vec_elems(r)[0] = e;
    elem_retain(&vec_elems(r)[0]);
    return r;
}

/* ====================================================================
 * Symbols and the symbol table (§3.3)
 * ==================================================================== */

double symbol_value(const char *name, size_t len)
{
    uint64_t h = fnv1a_utf8(name, len);
    uint64_t bits = UINT64_C(0xFFE0000000000000) | (h >> 12);
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

/* The slots of a symbol table. A table that grows gets new slots and
 * keeps the old ones (retired) until symtab_free: a thread looking a name
 * up may still be reading them. */
typedef struct SymSlots {
    size_t cap;                /* slots (power of two) */
    uint64_t *bits;            /* symbol bit patterns; 0 = empty (never a
                                  symbol); set once, by an atomic store after
                                  the slot's name */
    Str **names;               /* names per slot */
    struct SymSlots *retired;  /* the slots before the last growth, or NULL */
} SymSlots;

struct SymTab {
    SymSlots *slots;           /* the current slots: an atomic pointer */
    size_t count;              /* used slots */
    pthread_mutex_t lock;      /* taken by symtab_add: a frame's evaluation
                                  may add names (a program simplified again)
                                  while the drawing thread looks names up
                                  (fl_picture_draw), without the lock */
};

static SymSlots *symslots_new(size_t cap, SymSlots *retired)
{
    SymSlots *t = xmalloc(sizeof *t);
    t->cap = cap;
    t->bits = calloc(cap, sizeof(uint64_t));
    t->names = calloc(cap, sizeof(Str *));
    if (!t->bits || !t->names) mem_oom();
    t->retired = retired;
    return t;
}

SymTab *symtab_new(void)
{
    SymTab *st = xmalloc(sizeof *st);
    st->slots = symslots_new(64, NULL);
    st->count = 0;
    pthread_mutex_init(&st->lock, NULL);
    return st;
}

void symtab_free(SymTab *st)
{
    if (!st) return;
    SymSlots *t = st->slots;
    for (size_t i = 0; i < t->cap; i++) str_release(t->names[i]);   /* (the retired share them) */
    while (t) {
        SymSlots *older = t->retired;
        free(t->bits);
        free(t->names);
        free(t);
        t = older;
    }
    pthread_mutex_destroy(&st->lock);
    free(st);
}

/* The slot of [bits] in [t]: its own, or the empty one where it would go. */
static size_t symtab_slot(const SymSlots *t, uint64_t bits)
{
    size_t i = (size_t)(hash_update(0, bits) & (t->cap - 1));
    for (;;) {
        uint64_t b = __atomic_load_n(&t->bits[i], __ATOMIC_ACQUIRE);
        if (!b || b == bits) return i;
        i = (i + 1) & (t->cap - 1);
    }
}

double symtab_add(SymTab *st, const char *name, size_t len)
{
    double x = symbol_value(name, len);
    uint64_t b = dbits(x);
    pthread_mutex_lock(&st->lock);
    SymSlots *t = st->slots;
    size_t i = symtab_slot(t, b);
    if (t->bits[i]) {
        pthread_mutex_unlock(&st->lock);
        return x;
    }
    if ((st->count + 1) * 2 > t->cap) {
        SymSlots *grown = symslots_new(t->cap * 2, t);
        for (size_t k = 0; k < t->cap; k++) {
            if (!t->bits[k]) continue;
            size_t j = symtab_slot(grown, t->bits[k]);
            grown->bits[j] = t->bits[k];
            grown->names[j] = t->names[k];
        }
        __atomic_store_n(&st->slots, grown, __ATOMIC_RELEASE);
        t = grown;
        i = symtab_slot(t, b);
    }
    t->names[i] = str_new(name, len);
    __atomic_store_n(&t->bits[i], b, __ATOMIC_RELEASE);
    st->count++;
    pthread_mutex_unlock(&st->lock);
    return x;
}

const Str *symtab_name(const SymTab *st, double x)
{
    if (!st) return NULL;
    uint64_t b = dbits(x);
    if (!b) return NULL;
    /* no lock: the slots read are the current ones or retired ones, and a
     * slot's bits are stored after its name, once */
    const SymSlots *t = __atomic_load_n(&st->slots, __ATOMIC_ACQUIRE);
    size_t i = symtab_slot(t, b);
    return __atomic_load_n(&t->bits[i], __ATOMIC_ACQUIRE) ? t->names[i] : NULL;
}
