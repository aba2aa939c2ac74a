/* scene.h: what the physics differential tests (test_physics_routes.c,
 * test_particle_pass.c) share to build random !physics node trees: a tiny
 * deterministic generator (splitmix64, so that a failing seed reproduces)
 * and node-building shorthands. Header-only, static functions. */
#ifndef FL_TEST_SCENE_H
#define FL_TEST_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "node.h"
#include "value.h"

/* splitmix64 */
typedef struct Rng { uint64_t x; } Rng;

static inline uint64_t next_u64(Rng *r)
{
    uint64_t z = (r->x += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

/* uniform in [0, 1), 53 bits */
static inline double uni(Rng *r) { return (double)(next_u64(r) >> 11) * 0x1p-53; }
/* true with probability [p] */
static inline bool chance(Rng *r, double p) { return uni(r) < p; }
/* a whole number in 0 .. n-1 */
static inline size_t below(Rng *r, size_t n) { return (size_t)(next_u64(r) % n); }

/* A new node of kind [kind] (the caller owns it). */
static inline Node *mk(const char *kind)
{
    Str *k = str_from(kind);
    Node *n = node_new(k);
    str_release(k);
    return n;
}

/* Set attribute [name] of [n] to [v] (consumes [v]). */
static inline void set(Node *n, const char *name, Vec *v)
{
    Str *s = str_from(name);
    node_set_attr(n, s, v);
    str_release(s);
}

static inline Vec *num(double x) { return vec_num1(x); }

/* Append a new child of kind [kind] to [parent]; returns it (borrowed). */
static inline Node *add(Node *parent, const char *kind)
{
    Node *c = mk(kind);
    node_append(parent, c);
    node_release(c);
    return c;
}

#endif
