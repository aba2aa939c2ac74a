/* stateio.c: a system's state keys, read-back and writes.
 *
 * Implements the state side of PHYSICS-ENGINE.md §2: the prefix P and the
 * clock keys built from it, the particle keys of each storage slot (from
 * the key table of keys.c), the nulling of keys written last frame but not
 * this one (step 7) and the position/velocity writes (step 8), which
 * overwrite a value vector in place when nothing else holds it.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics_internal.h"
#include "workers.h"

/* Grow array [ptr] (capacity variable [cap]) to at least [need] elements. */
#define GROW(ptr, cap, need) \
    ((ptr) = mem_grow((ptr), &(cap), (need), sizeof *(ptr)))

bool phys_state_scalar(const StateDict *sd, const Vec *key, double *out)
{
    const Vec *v = state_get(sd, key);
    if (!vec_is_scalar(v))
        return false;
    *out = vec_scalar(v);
    return true;
}

void phys_state_set_num(StateDict *sd, const Vec *key, double x)
{
    Vec *v = vec_num1(x);
    state_set(sd, key, v);
    vec_release(v);
}

static Vec *compose2(const Vec *a, const Vec *b)
{
    Vec *parts[2] = {(Vec *)a, (Vec *)b};
    return vec_compose(parts, 2);
}

static Vec *compose_sym(const Vec *a, const char *sym)
{
    Vec *s = vec_num1(symbol_value(sym, strlen(sym)));
    Vec *r = compose2(a, s);
    vec_release(s);
    return r;
}

/* Forget every cached particle key (the slots only borrow them). */
static void release_slots(PhysSystem *s)
{
    phys_cache_drop(s);
    phys_slot_nodes_drop(s);
    phys_keys_clear(s);
    if (s->capslots)
        memset(s->slots, 0, s->capslots * sizeof *s->slots);
}

void phys_release_prev(PhysSystem *s)
{
    for (size_t i = 0; i < s->nprev; i++)
        vec_release(s->prev[i]);
    s->nprev = 0;
}
/* Point the system at prefix [P]: rebuild the clock keys and drop the key
 * cache when P changed. */
void phys_set_prefix(PhysSystem *s, const Vec *P)
{
    if (s->prefix && vec_key_equal(s->prefix, P))
        return;
    release_slots(s);
    vec_release(s->prefix);
    vec_release(s->kclock);
    vec_release(s->klast);
    vec_release(s->krun);
    vec_release(s->kiter);
    s->prefix = vec_retain((Vec *)P);
    s->prefix_hash = vec_hash(P, false);
    s->kclock = compose_sym(P, "clock");
    s->klast = compose_sym(P, "last");
    s->krun = compose_sym(P, "run");
    s->kiter = compose_sym(P, "iteration");
}

/* The keys of storage slot [i], holding the particle [pn] (§2 step 8
 * keys), from the system's key table (keys.c). */
PhysKeySlot *phys_slot_keys(PhysSystem *s, size_t i, const PhysPNode *pn)
{
    PhysKeySlot *k = &s->slots[i];
    PhysKeyEnt *e;
    /* the same id vector as last frame's particle in this slot (a static
     * tree hands the same vectors every frame): its entry, unhashed; an
     * entry holds its id, so the same pointer means the same id */
    k->hit = k->ent1 && k->ent1 <= s->nkent && s->kent[k->ent1 - 1].id == pn->id;
    if (k->hit) {
        e = &s->kent[k->ent1 - 1];
        if (e->seen == s->kframe)
            s->dupids = true;
        e->seen = s->kframe;
    } else {
        e = (PhysKeyEnt *)phys_keys_get(s, pn->id, pn->idhash, &s->dupids);
        k->ent1 = (uint32_t)(e - s->kent) + 1;
    }
    k->pkey = e->pkey;
    k->vkey = e->vkey;
    k->phash = e->phash;
    k->vhash = e->vhash;
    k->pval = k->vval = NULL;
    return k;
}
/* ------------------------------------------------------------------ */
/* State keys                                                          */
/* ------------------------------------------------------------------ */

/* §2 step 7: every key collected on the previous frame (the particle
 * position and velocity keys, as in the reference) that is not collected
 * this frame is set to null; this frame's keys become the new list. */
void phys_null_stale_keys(PhysSystem *s, StateDict *sd)
{
    const size_t nk = 2 * s->n;
    bool same = s->nprev == nk;
    for (size_t i = 0; same && i < s->n; i++)
        same = s->prev[2 * i] == s->slots[i].pkey &&
               s->prev[2 * i + 1] == s->slots[i].vkey;
    if (same)
        return;
    size_t capn = s->capnext;
    GROW(s->next, capn, nk);
    capn = s->capnext;
    GROW(s->nexthash, capn, nk);
    s->capnext = capn;
    for (size_t i = 0; i < s->n; i++) {
        s->next[2 * i] = s->slots[i].pkey;
        s->nexthash[2 * i] = s->slots[i].phash;
        s->next[2 * i + 1] = s->slots[i].vkey;
        s->nexthash[2 * i + 1] = s->slots[i].vhash;
    }
    /* with no keys of last frame's (a system's first frame), nothing is
     * looked up: no index of this frame's */
    if (s->nprev)
        phys_hash_reset(&s->newkeys, nk);
    for (size_t i = 0; s->nprev && i < nk; i++)
        phys_hash_put(&s->newkeys, s->next[i], s->nexthash[i], i);
    for (size_t i = 0; i < s->nprev; i++) {
        Vec *k = s->prev[i];
        if (phys_hash_get(&s->newkeys, k, vec_hash(k, false)) == SIZE_MAX)
            state_set(sd, k, NULL);
    }
    phys_release_prev(s);
    GROW(s->prev, s->capprev, nk);
    for (size_t i = 0; i < nk; i++)
        s->prev[i] = vec_retain(s->next[i]);
    s->nprev = nk;
}

/* Whether slot [k]'s value [cur] (read at collection; [cached] is the
 * slot's retained copy) may be overwritten in place: it is still the
 * state's (nothing set this key since, unless two particles share it) and
 * only the state and the slot's cache hold it. */
static bool writable_in_place(const PhysSystem *s, const Vec *cur, const Vec *cached)
{
    return cur && !s->dupids && cur->refs == 1 + (cur == cached);
}

/* Whether all [D] numbers of [x] are finite. */
static bool all_finite(const double *x, size_t D)
{
    for (size_t d = 0; d < D; d++)
        if (!isfinite(x[d]))
            return false;
    return true;
}

/* Write the [D] numbers [x] of a slot into its value [cur] ([cached]: the
 * slot's retained copy) when that may go in place. True when done, or
 * when x is not all finite (no write at all); false when the write must go
 * through the dictionary. */
static bool put_in_place(const PhysSystem *s, Vec *cur, const Vec *cached, const double *x)
{
    if (!all_finite(x, s->D))
        return true;
    if (!writable_in_place(s, cur, cached))
        return false;
    phys_copy(vec_nums(cur), x, s->D);
    return true;
}

/* The writes of slots [i0, i1) that go in place, each to its own vector
 * (distinct slots hold distinct vectors when no two share an id, which
 * writable_in_place() asks); returns how many writes were left for
 * write_slot(). */
static size_t write_in_place(PhysSystem *s, size_t i0, size_t i1)
{
    const size_t D = s->D;
    size_t left = 0;
    for (size_t i = i0; i < i1; i++) {
        const PhysKeySlot *k = &s->slots[i];
        left += !put_in_place(s, k->pval, k->cp, s->pos + i * D);
        left += !put_in_place(s, k->vval, k->cv, s->vel + i * D);
    }
    return left;
}

/* Slot [i]'s writes, in place or through the dictionary. */
static void write_slot(PhysSystem *s, StateDict *sd, size_t i)
{
    const size_t D = s->D;
    PhysKeySlot *k = &s->slots[i];
    const double *vecs[2] = {s->pos + i * D, s->vel + i * D};
    const Vec *keys[2] = {k->pkey, k->vkey};
    for (int j = 0; j < 2; j++) {
        if (put_in_place(s, j ? k->vval : k->pval, j ? k->cv : k->cp, vecs[j]))
            continue;
        /* in place when only the state holds the value; the slot takes
         * what the state holds now (an equal vector may have been kept) */
        *(j ? &k->vval : &k->pval) = state_set_nums(sd, keys[j], vecs[j], (uint32_t)D);
    }
}

/* How many slots ahead write_slots() fetches the dictionary's slots of
 * their keys: a system's first writes are as many lookups into a table
 * larger than the cache */
#define WRITE_AHEAD 8

/* write_slot() of slots [i0, i1) in order. */
static void write_slots(PhysSystem *s, StateDict *sd, size_t i0, size_t i1)
{
    for (size_t i = i0; i < i1; i++) {
        if (i + WRITE_AHEAD < i1) {
            /* the keys with no value yet, which will be looked up */
            const PhysKeySlot *a = &s->slots[i + WRITE_AHEAD];
            if (!a->pval)
                state_prefetch(sd, a->phash);
            if (!a->vval)
                state_prefetch(sd, a->vhash);
        }
        write_slot(s, sd, i);
    }
}

/* Particles per task of the in-place writes, and half the fewest that are
 * split over threads. */
#define WRITE_CHUNK 512

typedef struct WriteRun {
    PhysSystem *s;
    size_t left[WORKERS_MAX_TASKS];    /* per task */
    size_t chunk;
} WriteRun;

static void write_task(void *ctx, size_t t, unsigned thread)
{
    (void)thread;
    WriteRun *r = ctx;
    r->left[t] = write_in_place(r->s, t * r->chunk, workers_task_end(t, r->chunk, r->s->n));
}

/* §2 step 8 writes: position and velocity of every particle (anchors too)
 * in group order, each only when all its elements are finite. A value
 * vector only the state and the slot hold is overwritten in place. Those
 * writes touch nothing shared, so a large system first does them on all
 * threads; then every task that left a write through the dictionary has
 * its slots written again in order on this thread, as one pass would
 * (rewriting an in-place value writes the same numbers). Every key ends
 * with the value of the one-by-one pass: a vector written in place is
 * held by one key only, so no other slot's write can reach it. */
void phys_write_particles(PhysSystem *s, StateDict *sd)
{
    const size_t n = s->n;
    /* the keys that have no value of the particle's (a system's first
     * step, when the dictionary cannot hold them all yet): it grows to
     * hold them at once */
    if (state_count(sd) < 2 * n) {
        size_t fresh = 0;
        for (size_t i = 0; i < n; i++)
            fresh += !s->slots[i].pval + !s->slots[i].vval;
        if (fresh > 64)
            state_reserve(sd, fresh);
    }
    if (!s->workers || n < 2 * WRITE_CHUNK) {
        write_slots(s, sd, 0, n);
        return;
    }
    WriteRun r = {.s = s};
    size_t ntasks = workers_split(n, WRITE_CHUNK, &r.chunk);
    workers_run(s->workers, ntasks, write_task, &r);
    for (size_t t = 0; t < ntasks; t++) {
        if (!r.left[t])
            continue;
        write_slots(s, sd, t * r.chunk, workers_task_end(t, r.chunk, n));
    }
}

/* ------------------------------------------------------------------ */
/* Values kept across frames                                           */
/* ------------------------------------------------------------------ */

/* Reading a particle's position and velocity back costs two state lookups
 * (hash probes into a large table: cache misses at 100,000 particles). A
 * slot whose particle is the same as last frame's (same id vector) keeps,
 * retained, the two value vectors the state held at the end of that frame.
 * They are still the state's values when no state_set of a key of two or
 * more elements and no clear has happened since: the dictionary's compound
 * write count is unchanged (particle keys P;id have at least two elements;
 * the beat counter's one-element key, set every frame, does not count).
 * The size is compared too (belt and braces: a delete changes it). A retained vector
 * cannot be freed, so a stale one is never read as freed memory. */
void phys_cache_check(PhysSystem *s, const StateDict *sd)
{
    s->cuse = s->cvalid && s->csd == sd &&
              state_counts(sd).compound == s->csets && state_count(sd) == s->ccount;
    s->cvalid = false;
}

void phys_cache_keep(PhysSystem *s, const StateDict *sd)
{
    if (s->dupids) {
        phys_cache_drop(s);
        return;
    }
    for (size_t i = 0; i < s->n; i++) {
        PhysKeySlot *k = &s->slots[i];
        if (k->cp != k->pval) {
            vec_release(k->cp);
            k->cp = vec_retain(k->pval);
        }
        if (k->cv != k->vval) {
            vec_release(k->cv);
            k->cv = vec_retain(k->vval);
        }
    }
    s->csd = sd;
    s->csets = state_counts(sd).compound;
    s->ccount = state_count(sd);
    s->cvalid = true;
}

void phys_cache_drop(PhysSystem *s)
{
    for (size_t i = 0; i < s->capslots; i++) {
        vec_release(s->slots[i].cp);
        vec_release(s->slots[i].cv);
        s->slots[i].cp = s->slots[i].cv = NULL;
    }
    s->cvalid = false;
}
