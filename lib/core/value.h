/* value.h: Flitter's vector model (LANGUAGE.md §3).
 *
 * Every Flitter value is a vector. A vector is a reference-counted, immutable
 * heap object `Vec`; the null (empty) vector is the NULL pointer, never an
 * allocated vector of length 0. Three representations exist:
 *
 *   VEC_NUM     numeric vector: `len` doubles (symbols and booleans are doubles)
 *   VEC_OBJ     object vector: `len` tagged elements (number, string, node,
 *               function); holds at least one non-number
 *   VEC_STREAM  pseudo-random stream (uniform/normal/beta, §5.8): length 0,
 *               truthy, indexable; identified by its kind and 64-bit key
 *
 * Strings (`Str`), nodes (`Node`) and functions (`Func`) are reference-counted
 * objects that object vectors point to.
 *
 * OWNERSHIP RULE (stated once, for every function in this header and every
 * module that uses it): a function that returns `Vec *`, `Str *`, `Node *` or
 * `Func *` returns a NEW reference that the caller owns and must release; a
 * getter that lends a value it keeps (state_get, node_attr, ...) returns it
 * `const` and BORROWED (vec_share() turns it into a reference of one's own);
 * arguments are BORROWED unless the function's name ends in `_take` or its
 * comment says "consumes". `vec_release(NULL)` is a no-op.
 *
 * The paths whose size the input decides (composition, ranges) ask the
 * runtime's memory budget first (mem.h) and give null past it; an
 * allocation that fails inside the budget aborts the process; every other
 * bad input gives null, never a crash.
 */
#ifndef FL_VALUE_H
#define FL_VALUE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "pool.h"

typedef struct Vec Vec;
typedef struct Str Str;
typedef struct Node Node;
typedef struct Func Func;

/* ------------------------------------------------------------------ */
/* Strings                                                            */
/* ------------------------------------------------------------------ */

/* An immutable UTF-8 string; `bytes` is NUL-terminated (the text itself may
 * contain NUL). Code-point order equals byte order for valid UTF-8. */
struct Str {
    uint32_t refs;   /* reference count */
    uint32_t len;    /* length in bytes, excluding the terminating NUL */
    char bytes[];    /* UTF-8 text followed by NUL */
};

/* Make a string from [len] bytes at [s] (copied). */
Str *str_new(const char *s, size_t len);
/* Make a string from the NUL-terminated [s]. */
Str *str_from(const char *s);
static inline Str *str_retain(Str *s) { if (s) s->refs++; return s; }
static inline void str_release(Str *s)
{
    if (s && --s->refs == 0) pool_release(s, sizeof(Str) + s->len + 1);
}
/* True when both strings hold the same bytes. */
static inline bool str_eq(const Str *a, const Str *b)
{
    return a == b || (a->len == b->len && memcmp(a->bytes, b->bytes, a->len) == 0);
}
/* Byte-wise (= code-point) comparison: <0, 0, >0. */
int str_cmp(const Str *a, const Str *b);
/* FNV-1a 64 over the code points of a UTF-8 string (LANGUAGE.md §3.3).
 * Invalid UTF-8 bytes are taken as single code points of their byte value. */
uint64_t fnv1a_utf8(const char *s, size_t len);

/* ------------------------------------------------------------------ */
/* Functions                                                          */
/* ------------------------------------------------------------------ */

struct Builtin;

/* A function value: a builtin (bi != NULL) or a user closure built by the
 * evaluator (impl points at evaluator data that [destroy] frees). Allocate
 * it with pool_calloc(sizeof(Func)) (pool.h): func_release returns it to
 * the pool, as vec_release and str_release do for vectors and strings. */
struct Func {
    uint32_t refs;                 /* reference count */
    const struct Builtin *bi;      /* builtin descriptor, or NULL */
    const char *bi_name;           /* builtin: its internal name (str()) */
    Str *name;                     /* user: name or "<anon>"; builtin: NULL */
    void *impl;                    /* evaluator's closure data */
    void (*destroy)(Func *f);      /* frees impl (and nothing else) */
};

static inline Func *func_retain(Func *f) { if (f) f->refs++; return f; }
void func_release(Func *f);
/* The name str() gives [f] (LANGUAGE.md §3.13): user name or the builtin's
 * internal name. */
const char *func_name(const Func *f);

/* ------------------------------------------------------------------ */
/* Elements and vectors                                               */
/* ------------------------------------------------------------------ */

typedef enum { EL_NUM, EL_STR, EL_NODE, EL_FUNC } ElemKind;

/* One element of an object vector. The pointer members hold one reference. */
typedef struct Elem {
    uint8_t kind;                 /* ElemKind */
    union {
        double num;               /* EL_NUM */
        Str *str;                 /* EL_STR */
        Node *node;               /* EL_NODE */
        Func *func;               /* EL_FUNC */
    };
} Elem;

typedef enum { VEC_NUM, VEC_OBJ, VEC_STREAM } VecKind;
typedef enum { STREAM_UNIFORM, STREAM_NORMAL, STREAM_BETA } StreamKind;

struct Vec {
    uint32_t refs;    /* reference count */
    uint8_t kind;     /* VecKind */
    uint8_t stream;   /* StreamKind, when kind == VEC_STREAM */
    uint8_t hashed;   /* not a stream, and `key` holds vec_hash(v, false) */
    uint32_t len;     /* number of elements (0 for streams) */
    uint64_t key;     /* stream key (seed hash), when kind == VEC_STREAM;
                         else the cached hash when `hashed` (vec_key_hash) */
    _Alignas(16) unsigned char data[]; /* double[len] or Elem[len] */
};

static inline uint32_t vec_len(const Vec *v) { return v ? v->len : 0; }
/* Numeric: non-null VEC_NUM (null is NOT numeric for arithmetic). */
static inline bool vec_is_num(const Vec *v) { return v && v->kind == VEC_NUM; }
static inline bool vec_is_obj(const Vec *v) { return v && v->kind == VEC_OBJ; }
static inline bool vec_is_stream(const Vec *v) { return v && v->kind == VEC_STREAM; }
/* The doubles of a numeric vector. */
static inline double *vec_nums(Vec *v) { return (double *)(void *)v->data; }
static inline const double *vec_cnums(const Vec *v) { return (const double *)(const void *)v->data; }
/* The elements of an object vector. */
static inline Elem *vec_elems(Vec *v) { return (Elem *)(void *)v->data; }
static inline const Elem *vec_celems(const Vec *v) { return (const Elem *)(const void *)v->data; }
/* True when [v] is a numeric vector of exactly one element. */
static inline bool vec_is_scalar(const Vec *v) { return v && v->kind == VEC_NUM && v->len == 1; }
static inline double vec_scalar(const Vec *v) { return vec_cnums(v)[0]; }

static inline Vec *vec_retain(Vec *v) { if (v) v->refs++; return v; }
/* A new reference to [v], which the caller only borrows as const (from a
 * getter such as state_get or node_attr): the reference count is
 * bookkeeping, not part of the value, so sharing does not change it. */
static inline Vec *vec_share(const Vec *v) { return vec_retain((Vec *)v); }
/* Internal: free [v] once its last reference is gone (vec_release). */
void vec_destroy_(Vec *v);
static inline void vec_release(Vec *v)
{
    if (v && --v->refs == 0) {
        if (v->kind == VEC_NUM) pool_release(v, sizeof(Vec) + (size_t)v->len * sizeof(double));
        else vec_destroy_(v);
    }
}

/* A new numeric vector of [n] > 0 uninitialised doubles; fill via vec_nums(). */
static inline Vec *vec_new_num(uint32_t n)
{
    Vec *v = pool_alloc(sizeof(Vec) + (size_t)n * sizeof(double));
    v->refs = 1;
    v->kind = VEC_NUM;
    v->stream = 0;
    v->hashed = 0;
    v->len = n;
    v->key = 0;
    return v;
}
/* A new object vector of [n] > 0 elements, all initialised to the number 0;
 * fill via vec_elems() (each pointer element must hold its own reference). */
Vec *vec_new_obj(uint32_t n);
/* An object vector of [n] elements left unset: the caller sets every one
 * before the vector is read, released or handed on. */
Vec *vec_new_obj_raw(uint32_t n);
/* Free the object vector [v], held by the caller alone (refs 1), whose
 * elements the caller has taken (moved elsewhere with their references):
 * nothing of them is released. */
void vec_free_taken(Vec *v);
/* A copy of [v] that shares no memory with it (NULL for NULL): numbers
 * and streams copied, strings made anew, nodes copied whole
 * (node_copy_deep); only a function element is shared (retained). For a
 * thread that keeps values out of another thread's tree (the drawing
 * thread, fl_picture_draw): their reference counts are then its own. */
Vec *vec_copy_deep(const Vec *v);
/* A one-element numeric vector. */
static inline Vec *vec_num1(double x)
{
    Vec *v = vec_new_num(1);
    vec_nums(v)[0] = x;
    return v;
}
/* A numeric vector copied from [n] doubles ([n] == 0 gives null; null
 * too past the memory budget, mem.h, with the refusal marked). */
Vec *vec_from_nums(const double *x, uint32_t n);
/* A one-element string vector from [len] UTF-8 bytes. */
Vec *vec_str(const char *s, size_t len);
/* A one-element vector holding the string [s] (consumes [s]). */
Vec *vec_str_take(Str *s);
/* A one-element vector holding node [n] (consumes [n]). */
Vec *vec_node_take(Node *n);
/* A one-element vector holding function [f] (consumes [f]). */
Vec *vec_func_take(Func *f);
/* A pseudo-random stream of [kind] keyed by [key] (LANGUAGE.md §5.8). */
Vec *vec_stream(StreamKind kind, uint64_t key);

/* An object vector whose elements turned out to be all numbers is converted
 * to a numeric vector (consumes [v]); anything else is returned unchanged. */
Vec *vec_normalize_take(Vec *v);

/* Truthiness (§3.4): some number != 0 (NaN counts), non-empty string, any
 * node or function; streams are true; null is false. */
bool vec_truthy(const Vec *v);

/* Composition (§3.2) of [n] parts: concatenation, empty parts and streams
 * vanish, numeric if every part is numeric, null if the total is empty.
 * Null too when the result does not fit the memory budget (mem.h
 * mem_fits; mem_take_refusal() then says so). */
Vec *vec_compose(Vec *const *parts, size_t n);
/* The same, consuming the [n] parts (the result is equal to vec_compose's):
 * the elements of an object part held by nothing else move into the
 * result instead of being retained there and released with the part. */
Vec *vec_compose_take(Vec **parts, size_t n);

/* ------------------------------------------------------------------ */
/* Arithmetic (§3.5): both operands non-empty numeric, else null;       */
/* cyclic broadcast to the longer length.                              */
/* ------------------------------------------------------------------ */
typedef enum { OP_ADD, OP_SUB, OP_MUL, OP_DIV, OP_FLOORDIV, OP_MOD, OP_POW } ArithOp;

/* [a] OP [b] element-wise with cyclic broadcasting. */
Vec *vec_arith(ArithOp op, const Vec *a, const Vec *b);
/* [a] OP [b] on two numbers: the number vec_arith makes of two
 * one-number vectors, bit for bit. */
double num_arith(ArithOp op, double a, double b);
/* vec_arith's numbers on arrays: r[i] = xa[i % na] OP xb[i % nb] for i
 * below the longer length, bit for bit (na, nb >= 1). [r] may be [xa] or
 * [xb] when that operand is the longer, or is one number (each number is
 * read before the same index is written). */
void num_arith_into(ArithOp op, double *r, const double *xa, uint32_t na, const double *xb, uint32_t nb);
/* The same, consuming [a] and [b]: the result is written into an operand
 * that has no other owner and the result's length (no new vector). */
Vec *vec_arith_take(ArithOp op, Vec *a, Vec *b);
/* F1 fused broadcast (§4.17): a[i%na] + (b[i%nb] * c[i%nc]) over
 * max(na,nb,nc) elements, multiply then add, each IEEE-rounded (no FMA). */
Vec *vec_add_mul(const Vec *a, const Vec *b, const Vec *c);
/* Unary minus: numeric → element-wise negation; anything else → null. */
Vec *vec_neg(const Vec *a);
/* Unary plus: numeric → itself (new reference); anything else → null. */
Vec *vec_pos(Vec *a);
/* C floor division and Flitter modulo of two doubles (§3.5). */
double num_floordiv(double a, double b);
double num_mod(double a, double b);

/* ------------------------------------------------------------------ */
/* Comparison, containment, hashing                                    */
/* ------------------------------------------------------------------ */

/* Element equality (§3.6 rule 5): numbers by value, strings by bytes,
 * nodes structurally, functions by identity; different kinds unequal. */
bool elem_equal(const Elem *a, const Elem *b);
/* Vector equality (§3.6 rules 2-6), without the identity shortcut. */
bool vec_equal(const Vec *a, const Vec *b);
/* Exact key equality for the state dictionary (§3.17): like vec_equal but
 * numbers compare by raw bit pattern, so 0 and -0 differ and NaN == NaN
 * when the bits match. */
bool vec_key_equal(const Vec *a, const Vec *b);

#define CMP_INCOMPARABLE 2
/* Ordering (§3.7): -1, 0, +1, or CMP_INCOMPARABLE. */
int vec_cmp(const Vec *a, const Vec *b);
/* Containment `x in y` (§3.8). */
bool vec_contains(const Vec *x, const Vec *y);

/* HASH_UPDATE of §3.16 (SplitMix64 finaliser with [y] xored in). Inline:
 * the template passes hash a column a member at a time. */
static inline uint64_t hash_update(uint64_t h, uint64_t y)
{
    h ^= y;
    h += UINT64_C(0x9e3779b97f4a7c15);
    h ^= h >> 30;
    h *= UINT64_C(0xbf58476d1ce4e5b9);
    h ^= h >> 27;
    h *= UINT64_C(0x94d049bb133111eb);
    h ^= h >> 31;
    return h;
}
#define HASH_START UINT64_C(0xe220a8397b1dcdaf)
/* vec_hash(v, false), computed once per vector and kept in it (numeric
 * vectors and vectors of numbers and strings only, which nothing mutates
 * once built); the state dictionary's key hash. [v] must be non-null. */
uint64_t vec_key_hash(const Vec *v);
/* Keep [h], which must be vec_hash(v, false), in the new numeric vector
 * [v] for vec_key_hash (a maker of keys that computed it on the way). */
static inline void vec_keep_key_hash(Vec *v, uint64_t h)
{
    v->key = h;
    v->hashed = 1;
}
/* Vector hash of §3.16; [floor_floats] floors numbers first (seed hash).
 * Nodes hash structurally, functions by address. null → HASH_START. */
uint64_t vec_hash(const Vec *v, bool floor_floats);
/* The bits of [x] (for comparing numbers bit for bit). */
static inline uint64_t num_bits(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}
/* vec_hash(v, false) of the one-number vector of [x], without making it. */
static inline uint64_t vec_hash_num1(double x) { return hash_update(HASH_START, num_bits(x)); }
/* vec_hash(v, floor_floats) of the numeric vector of the [n] numbers
 * [x], without making it (vec_hash's own loop for numeric vectors). */
uint64_t vec_hash_nums(const double *x, uint32_t n, bool floor_floats);
/* vec_hash_nums(x, n, false) inline: the state dictionary's key hash of
 * numbers a reader computed (state_get_nums), a few at a time. */
static inline uint64_t vec_hash_nums_raw(const double *x, uint32_t n)
{
    uint64_t h = HASH_START;
    for (uint32_t i = 0; i < n; i++) h = hash_update(h, num_bits(x[i]));
    return h;
}

/* ------------------------------------------------------------------ */
/* Ranges and indexing (§3.10, §3.11)                                  */
/* ------------------------------------------------------------------ */

/* start..stop|step; [start]/[step] may be NULL (missing). Invalid → null.
 * Ranges longer than [max_len] elements, or past the memory budget (mem.h;
 * mem_take_refusal() then says so), give null and set *[too_long]. */
Vec *vec_range(const Vec *start, const Vec *stop, const Vec *step,
               uint64_t max_len, bool *too_long);
/* src[index] with 32-bit C int index conversion (or 64-bit when [literal]).
 * Streams are indexed as in §5.8. */
Vec *vec_index(const Vec *src, const Vec *index, bool literal);
/* vec_index(src, the numeric vector of the [ni] numbers [k], literal),
 * without making that vector (null when [ni] is 0). */
Vec *vec_index_nums(const Vec *src, const double *k, uint32_t ni, bool literal);
/* vec_index(src, [k], literal) of a stream or a numeric [src] and the
 * one-number index [k], without making vectors: its number in *out, bit
 * for bit; false (nothing written) for other sources, whose result takes
 * vec_index itself. */
bool vec_index_num1(const Vec *src, double k, bool literal, double *out);
/* The [ni] numbers of stream [kind] with seed [key] at the indexes [k]
 * into [out]: vec_index of that stream by the numeric vector of [k]
 * (which computes its numbers so), without making either vector. */
void stream_index_into(StreamKind kind, uint64_t key, const double *k, uint32_t ni, double *out);
/* vec_index_num1 of stream [kind] with seed [key] at each of the [n]
 * one-number indexes [k] into [out] (one value each, not pairs). */
void stream_index_each(StreamKind kind, uint64_t key, const double *k, uint32_t n, double *out);
/* The number of stream [kind] with seed [key] at the one-number index
 * [k]: vec_index of that stream by [k] (vec_index_num1's), without making
 * either vector. Pure: any thread may call it. */
double stream_value_at(StreamKind kind, uint64_t key, double k);
/* item(v, i) (§3.11): element i mod n as a one-element vector; null if empty;
 * streams give their value at index i. */
Vec *vec_item(const Vec *v, int64_t i);

/* ------------------------------------------------------------------ */
/* Symbols (§3.3)                                                      */
/* ------------------------------------------------------------------ */

/* The numeric value of symbol :[name] ([len] UTF-8 bytes). */
double symbol_value(const char *name, size_t len);

/* A symbol table maps symbol values (by bit pattern) to names; it belongs to
 * one runtime (no global table). symtab_add takes the table's lock;
 * symtab_name takes none: one thread may add while others look names up. */
typedef struct SymTab SymTab;
SymTab *symtab_new(void);
void symtab_free(SymTab *st);
/* Register :[name] and return its value. */
double symtab_add(SymTab *st, const char *name, size_t len);
/* The registered name for [x], or NULL. */
const Str *symtab_name(const SymTab *st, double x);

#endif
