/* world.c: physics systems and the frame driver.
 *
 * A PhysicsWorld is an array of PhysSystem pointers, the i-th driven by the
 * i-th top-level !physics node of the frame (systems beyond the frame's
 * count are freed, as the reference destroys surplus renderers). A
 * PhysSystem (physics_internal.h) keeps every per-frame array (particles in
 * struct-of-arrays storage, appliers, groups and their index lists, hash
 * indexes, the tree-walk stack) and only grows them, so a steady frame
 * allocates nothing per particle except the position/velocity vectors it
 * stores in the state dictionary. The state keys P;id and P;id;:velocity are
 * kept per particle id while it lives (keys.c).
 *
 * Implements PHYSICS-ENGINE.md §2 (one frame: run reset, read-back of
 * :clock/:last/:run/:iteration, collection, nulling of keys not written
 * again, the steps, the final writes); collection (§1, §3) is in collect.c,
 * the state side in stateio.c, the steps in step.c, the appliers in
 * forces.c. PHYSICS.md "State interaction" and "Groups" describe the
 * behaviour.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "physics_internal.h"
#include "workers.h"

struct PhysicsWorld {
    PhysSystem **sys;
    size_t n, cap;
    bool naive;             /* --pairs naive: the reference pair loop only */
    bool literal;           /* --particles literal: literal.c's particle pass */
    unsigned threads;       /* wanted threads; the pool is made on first use */
    Workers *workers;   /* NULL until needed or when threads == 1 */
    int simd;               /* PHYS_SIMD_* level of the tile kernel */
    int split;              /* PHYS_SPLIT_* */
    int ahead;              /* phys_set_ahead's limit */
    double slice;           /* phys_set_slice's pairs, or 0 */
    long cut_after;         /* phys_set_cut_after's polls, or 0 */
    bool simd_auto;         /* no level asked for (phys_set_simd not
                               called since phys_new): the systems time
                               the 4 x 4 tiles (with AVX-512VL where the
                               processor has it) against AVX-512 (tiles.c) */
};

/* ------------------------------------------------------------------ */
/* Allocation                                                          */
/* ------------------------------------------------------------------ */

void phys_oom(void)
{
    mem_oom();
}

/* Grow array [ptr] (capacity variable [cap]) to at least [need] elements. */
/* Grow array [ptr] (capacity variable [cap]) to at least [need] elements. */
#define GROW(ptr, cap, need) \
    ((ptr) = mem_grow((ptr), &(cap), (need), sizeof *(ptr)))


/* ------------------------------------------------------------------ */
/* Systems                                                             */
/* ------------------------------------------------------------------ */

static PhysSystem *system_new(void)
{
    PhysSystem *s = calloc(1, sizeof *s);
    if (!s)
        phys_oom();
    s->sym_velocity = symbol_value("velocity", 8);
    return s;
}


static void system_free(PhysSystem *s)
{
    if (!s)
        return;
    phys_draws_ahead_settle(s);
    free(s->ahead.seg);
    free(s->ahead.buf);
    phys_cache_drop(s);
    phys_slot_nodes_drop(s);
    phys_kids_drop(s);
    free(s->kids); free(s->clocked);
    phys_keys_free(s);
    phys_release_prev(s);
    vec_release(s->prefix);
    vec_release(s->kclock);
    vec_release(s->klast);
    vec_release(s->krun);
    vec_release(s->kiter);
    free(s->pos); free(s->vel); free(s->acc); free(s->force); free(s->own);
    free(s->radius); free(s->mass); free(s->charge); free(s->ease); free(s->anchor);
    free(s->dir); free(s->dgeo);
    free(s->ap); free(s->avec);
    free(s->groups); free(s->gidx); free(s->chain); free(s->levels);
    free(s->pool);
    free(s->pn); free(s->walk); free(s->filled);
    free(s->ids.slot); free(s->newkeys.slot);
    free(s->slots); free(s->prev); free(s->next); free(s->nexthash);
    phys_pairs_free(s);
    phys_names_free(s);
    free(s);
}

/* ------------------------------------------------------------------ */
/* One frame of one system (PHYSICS-ENGINE.md §2)                      */
/* ------------------------------------------------------------------ */

/* How many arrays of D numbers a particle may need at most (position,
 * velocity, acceleration, force, own force, direction, anchor, geometry
 * and the pair routes' copies), for the budget check of system_frame. */
#define SYSTEM_ARRAYS 16

/* The nodes below [n] (particles, anchors, appliers, in groups too). */
static size_t count_nodes(const Node *n)
{
    size_t c = n->nchildren;
    for (uint32_t i = 0; i < n->nchildren; i++)
        if (n->children[i]->nchildren) c += count_nodes(n->children[i]);
    return c;
}

static void system_frame(PhysSystem *s, const Node *node, StateDict *sd,
                         const PhysicsFrame *fr)
{
    phys_cache_check(s, sd);
    /* §2.1: run, dimensions and the prefix P; skip unusable nodes */
    int64_t run = phys_attr_int(node, "run", 0);
    int64_t D = phys_attr_int(node, "dimensions", 0);
    if (D < 1 || D > (int64_t)PHYS_MAX_DIMENSIONS)
        return;
    /* the memory budget (mem.h): a system whose per-particle arrays would
     * not fit is skipped, and the runtime logs a physics error */
    const bool same_tree = phys_kids_same(s, node);
    size_t nodes = same_tree && s->kids_nodes != SIZE_MAX ? s->kids_nodes : count_nodes(node);
    if (same_tree)
        s->kids_nodes = nodes;
    if (!mem_fits((nodes + 1) * (SYSTEM_ARRAYS * (size_t)D * sizeof(double) + 256)))
        return;
    if (!mem_fits((nodes + 1) * (SYSTEM_ARRAYS * (size_t)D * sizeof(double) + 256)))
        return;
    const Vec *P = node_attr(node, "state");
    if (!P)
        return;
    /* §2.2: time, resolution (default 1/fps), speed of light */
    double time = phys_attr_float(node, "time", fr->time);
    double resolution = phys_attr_float(node, "resolution", 1 / fr->fps);
    if (!isfinite(time) || !isfinite(resolution)) {
        if (fr->nonfinite)
            *fr->nonfinite = true;
        return;
    }
    if (resolution <= 0)
        return;
    s->frame = fr;
    s->upstream = fr->upstream;
    s->D = (size_t)D;
    s->c = py_max(0, phys_attr_float(node, "speed_of_light", 0));
    phys_set_prefix(s, P);
    /* §2.3: read back :clock, :last, :run, :iteration */
    double clock = 0, last = time, x;
    if (!phys_state_scalar(sd, s->kclock, &clock))
        clock = 0;
    if (!phys_state_scalar(sd, s->klast, &last))
        last = time;
    int64_t last_run = phys_state_scalar(sd, s->krun, &x) ? phys_floor_i64(x) : run;
    int64_t iteration = phys_state_scalar(sd, s->kiter, &x) ? phys_floor_i64(x) + 1 : 0;
    /* §2.4: a new run nulls our keys and restarts clock and iteration
     * (`last` is not reset) */
    if (run != last_run) {
        s->cuse = false;
        for (size_t i = 0; i < s->nprev; i++)
            state_set(sd, s->prev[i], NULL);
        phys_release_prev(s);
        phys_state_set_num(sd, P, time);
        clock = 0;
        iteration = 0;
    }
    /* §2.5 */
    phys_state_set_num(sd, s->krun, (double)run);
    phys_state_set_num(sd, s->kiter, (double)iteration);
    /* §2.6: collect (the !random seed is P;run;iteration) */
    PhysCollect c = {P, run, iteration, clock, NULL, fr->upstream, same_tree};
    bool ok = phys_collect(s, &c, node, sd);
    const bool random = c.seed != NULL;
    vec_release(c.seed);
    if (!ok)
        return;
    /* the hashes of this frame's seed and of the next frame's, should
     * nothing change (step.c, "the next frame's draws"): vec_hash of
     * P;run;iteration without making the vector */
    s->seed_ok = random && P->kind != VEC_STREAM && iteration < INT64_MAX;
    if (s->seed_ok) {
        const uint64_t h = hash_update(vec_hash(P, true), num_bits(floor((double)run)));
        s->seed_now = hash_update(h, num_bits(floor((double)iteration)));
        s->seed_next = hash_update(h, num_bits(floor((double)(iteration + 1))));
    }
    /* §2.7: null last frame's keys not collected now; ensure state[P] */
    phys_null_stale_keys(s, sd);
    if (!vec_is_scalar(state_get(sd, P)))
        phys_state_set_num(sd, P, time);
    /* §2.8: step, then write positions and velocities. Spare performance
     * (realtime only) is the reference's `performance > 1.5`, which buys
     * at most one extra step per frame. */
    if (time > last) {
        clock = phys_run_steps(s, time, last, clock, resolution,
                               fr->realtime, fr->performance > 1.5);
        phys_write_particles(s, sd);
    }
    /* §2.9 */
    phys_state_set_num(sd, s->klast, time);
    phys_state_set_num(sd, s->kclock, clock);
    phys_cache_keep(s, sd);
}
/* ------------------------------------------------------------------ */
/* Public interface                                                    */
/* ------------------------------------------------------------------ */

/* A new world with no systems: every core, the fast routes, the best
 * vector instructions, timed (phys_set_simd). */
PhysicsWorld *phys_new(void)
{
    PhysicsWorld *w = calloc(1, sizeof *w);
    if (!w)
        phys_oom();
    w->ahead = -1;
    phys_set_threads(w, 0);
    phys_set_pairs(w, false);
    phys_set_particles(w, false);
    phys_set_simd(w, PHYS_SIMD_AVX512);
    w->simd_auto = true;
    return w;
}

void phys_set_threads(PhysicsWorld *w, unsigned n)
{
    if (n == 0)
        n = workers_available_cores();
    if (n != w->threads) {
        for (size_t i = 0; i < w->n; i++)
            phys_draws_ahead_settle(w->sys[i]);
        workers_free(w->workers);
        w->workers = NULL;
    }
    w->threads = n;
}

Workers *phys_workers(PhysicsWorld *w)
{
    if (w->threads > 1 && !w->workers)
        w->workers = workers_new(w->threads);
    return w->workers;
}

void phys_set_pairs(PhysicsWorld *w, bool naive)
{
    w->naive = naive;
}

void phys_set_particles(PhysicsWorld *w, bool literal)
{
    w->literal = literal;
}

void phys_set_split(PhysicsWorld *w, int mode)
{
    w->split = mode == PHYS_SPLIT_OFF || mode == PHYS_SPLIT_ALONE || mode == PHYS_SPLIT_HELPER
                   ? mode : PHYS_SPLIT_AUTO;
}

void phys_split_counts(const PhysicsWorld *w, uint64_t out[2])
{
    out[0] = out[1] = 0;
    for (size_t i = 0; i < w->n; i++) {
        out[0] += w->sys[i]->split_near[0];
        out[1] += w->sys[i]->split_near[1];
    }
}

void phys_set_ahead(PhysicsWorld *w, int limit)
{
    w->ahead = limit < 0 ? -1 : limit;
}

void phys_set_slice(PhysicsWorld *w, double pairs)
{
    w->slice = pairs > 0 ? pairs : 0;
}

void phys_set_cut_after(PhysicsWorld *w, long polls)
{
    w->cut_after = polls > 0 ? polls : 0;
}

void phys_ahead_counts(const PhysicsWorld *w, uint64_t out[3])
{
    out[0] = out[1] = out[2] = 0;
    for (size_t i = 0; i < w->n; i++)
        for (int k = 0; k < 3; k++)
            out[k] += w->sys[i]->ahead_pairs[k];
}

int phys_set_simd(PhysicsWorld *w, int level)
{
    w->simd = phys_simd_cap(level);
    w->simd_auto = false;
    return w->simd;
}

/* Free [w] and all its systems (NULL is a no-op). */
void phys_free(PhysicsWorld *w)
{
    if (!w)
        return;
    for (size_t i = 0; i < w->n; i++)
        system_free(w->sys[i]);
    free(w->sys);
    workers_free(w->workers);
    free(w);
}

/* Simulate one frame: the i-th node drives the i-th system (created on
 * first use; systems beyond [n] are freed). PHYSICS-ENGINE.md §2-4. */
void phys_run_frame(PhysicsWorld *w, Node *const *nodes, size_t n,
                    StateDict *state, const PhysicsFrame *frame)
{
    while (w->n > n)
        system_free(w->sys[--w->n]);
    GROW(w->sys, w->cap, n);
    while (w->n < n)
        w->sys[w->n++] = system_new();
    if (w->threads > 1 && !w->workers && !w->naive)
        w->workers = workers_new(w->threads);
    for (size_t i = 0; i < n; i++) {
        PhysSystem *s = w->sys[i];
        s->naive = w->naive;
        s->literal = w->literal;
        s->simd = w->simd;
        s->split_mode = w->split;
        s->ahead_limit = w->ahead;
        s->slice_pairs = w->slice > 0 ? w->slice : PHYS_SLICE_PAIRS;
        s->cut_after = w->cut_after;
        atomic_store_explicit(&s->polls, 0, memory_order_relaxed);
        s->simd_auto = w->simd_auto && w->simd == PHYS_SIMD_AVX512;
        s->workers = w->naive ? NULL : w->workers;
        system_frame(s, nodes[i], state, frame);
    }
}

