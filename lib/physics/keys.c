/* keys.c: the particle state keys of a system, kept while the particle
 * lives.
 *
 * Every particle writes state[P;id] and state[P;id;:velocity]
 * (PHYSICS-ENGINE.md §2 step 8). Building those keys means composing
 * vectors and hashing them, so a system keeps one PhysKeyEnt per particle id
 * it has seen: the id (retained), both keys and their hashes. Entries are
 * found through an open-addressing index (linear probing, entry index + 1,
 * 0 = empty, capacity a power of two at least twice the entries) hashed by
 * vec_hash(id, false) and compared with vec_key_equal. An entry lives as
 * long as its id is collected on every frame: phys_keys_sweep() drops the
 * ones not seen on the current frame (compacting the array and rebuilding
 * the index, only when something died). Adding, removing or reordering
 * particles therefore never rebuilds the keys of the others.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "physics_internal.h"

static void oom(void)
{
    mem_oom();
}

static void release_ent(PhysKeyEnt *e)
{
    vec_release(e->id);
    vec_release(e->pkey);
    vec_release(e->vkey);
}

/* Rebuild the index for room for [n] entries (at least the ones there
 * are). */
static void reindex_for(PhysSystem *s, size_t n)
{
    size_t need = 16;
    if (n < s->nkent)
        n = s->nkent;
    while (need < 2 * (n + 1))
        need *= 2;
    if (need > s->capkidx) {
        free(s->kidx);
        s->kidx = malloc(need * sizeof *s->kidx);
        if (!s->kidx)
            oom();
        s->capkidx = need;
    }
    memset(s->kidx, 0, s->capkidx * sizeof *s->kidx);
    size_t mask = s->capkidx - 1;
    for (size_t i = 0; i < s->nkent; i++) {
        size_t j = (size_t)s->kent[i].idhash & mask;
        while (s->kidx[j])
            j = (j + 1) & mask;
        s->kidx[j] = (uint32_t)(i + 1);
    }
}

static void reindex(PhysSystem *s)
{
    reindex_for(s, s->nkent);
}

void phys_keys_reserve(PhysSystem *s, size_t n)
{
    if (n >= UINT32_MAX)
        return;
    if (n > s->capkent) {
        PhysKeyEnt *k = realloc(s->kent, n * sizeof *k);
        if (!k)
            oom();
        s->kent = k;
        s->capkent = n;
    }
    if (2 * (n + 1) > s->capkidx)
        reindex_for(s, n);
}

/* The keys P;id and P;id;:velocity of entry [e]: what vec_compose makes
 * of them, built directly when P and the id are numbers (the usual case:
 * a symbol prefix, a numeric id), and their hashes (vec_hash, folded on
 * from P's), kept in the key vectors too (vec_key_hash), so the state
 * dictionary does not hash them again. */
static void make_keys(PhysSystem *s, const Vec *id, PhysKeyEnt *e)
{
    const Vec *P = s->prefix;
    const size_t n = (size_t)vec_len(P) + vec_len(id);
    if (vec_is_num(P) && vec_is_num(id) && n < UINT32_MAX &&
        mem_fits(2 * sizeof(Vec) + (2 * n + 1) * sizeof(double))) {
        Vec *p = vec_new_num((uint32_t)n), *v = vec_new_num((uint32_t)n + 1);
        double *dp = vec_nums(p), *dv = vec_nums(v);
        /* vec_hash folds the numbers in order: P's part once per prefix */
        uint64_t h = s->prefix_hash;
        for (uint32_t j = 0; j < P->len; j++)
            dp[j] = vec_cnums(P)[j];
        for (uint32_t j = 0; j < id->len; j++) {
            dp[P->len + j] = vec_cnums(id)[j];
            h = hash_update(h, num_bits(vec_cnums(id)[j]));
        }
        for (size_t j = 0; j < n; j++)
            dv[j] = dp[j];
        dv[n] = s->sym_velocity;
        e->pkey = p;
        e->vkey = v;
        e->phash = h;
        e->vhash = hash_update(h, num_bits(s->sym_velocity));
        vec_keep_key_hash(p, e->phash);
        vec_keep_key_hash(v, e->vhash);
        return;
    }
    Vec *parts[2] = {s->prefix, (Vec *)id};
    e->pkey = vec_compose(parts, 2);
    Vec *vel = vec_num1(s->sym_velocity);
    parts[0] = e->pkey;
    parts[1] = vel;
    e->vkey = vec_compose(parts, 2);
    vec_release(vel);
    e->phash = e->pkey ? vec_key_hash(e->pkey) : vec_hash(NULL, false);
    e->vhash = e->vkey ? vec_key_hash(e->vkey) : vec_hash(NULL, false);
}

const PhysKeyEnt *phys_keys_get(PhysSystem *s, const Vec *id, uint64_t idhash,
                                bool *dup)
{
    if (s->capkidx) {
        size_t mask = s->capkidx - 1;
        for (size_t j = (size_t)idhash & mask; s->kidx[j]; j = (j + 1) & mask) {
            PhysKeyEnt *e = &s->kent[s->kidx[j] - 1];
            if (e->idhash == idhash && vec_key_equal(e->id, id)) {
                if (e->seen == s->kframe)
                    *dup = true;
                e->seen = s->kframe;
                return e;
            }
        }
    }
    if (s->nkent + 1 >= UINT32_MAX)
        oom();
    if (s->nkent == s->capkent) {
        size_t cap = s->capkent ? 2 * s->capkent : 64;
        PhysKeyEnt *k = realloc(s->kent, cap * sizeof *k);
        if (!k)
            oom();
        s->kent = k;
        s->capkent = cap;
    }
    PhysKeyEnt *e = &s->kent[s->nkent++];
    e->id = vec_retain((Vec *)id);
    make_keys(s, id, e);
    e->idhash = idhash;
    e->seen = s->kframe;
    if (2 * (s->nkent + 1) > s->capkidx) {
        reindex(s);
    } else {
        size_t mask = s->capkidx - 1, j = (size_t)idhash & mask;
        while (s->kidx[j])
            j = (j + 1) & mask;
        s->kidx[j] = (uint32_t)s->nkent;
    }
    return e;
}

void phys_keys_sweep(PhysSystem *s)
{
    size_t k = 0;
    for (size_t i = 0; i < s->nkent; i++) {
        if (s->kent[i].seen != s->kframe)
            release_ent(&s->kent[i]);
        else if (k++ != i)
            s->kent[k - 1] = s->kent[i];
    }
    if (k != s->nkent) {
        s->nkent = k;
        reindex(s);
    }
    s->kframe++;
}

void phys_keys_clear(PhysSystem *s)
{
    for (size_t i = 0; i < s->nkent; i++)
        release_ent(&s->kent[i]);
    s->nkent = 0;
    if (s->capkidx)
        memset(s->kidx, 0, s->capkidx * sizeof *s->kidx);
}

void phys_keys_free(PhysSystem *s)
{
    phys_keys_clear(s);
    free(s->kent);
    free(s->kidx);
}
