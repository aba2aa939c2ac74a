/* step.c: the per-particle appliers, the barriers, the integration step and
 * the step loop.
 *
 * Operates on a collected PhysSystem (physics_internal.h): particle vectors
 * in struct-of-arrays storage (pos/vel/acc/force/own, D doubles per particle,
 * groups contiguous in group-list order), the group list with its per-group
 * applier chains, pair levels and pools, and the applier array.
 *
 * Implements PHYSICS-ENGINE.md §4: the "loop:" (clock, delta, extra steps,
 * the two passes over the groups and the force reset between steps), the
 * per-particle appliers (drag, buoyancy, constant, random, field), the
 * barrier soft force ("Barrier distance(p)"),
 * `step(p, clock, dt)` (velocity/position update with the speed-of-light
 * clamp, PHYSICS.md "!particle") and `Barrier rebound(p, clock, dt)` (the
 * hard bounce of PHYSICS.md "Barriers"), with the floating-point operations
 * in the order written there.
 */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "physics_internal.h"
#include "streams.h"
#include "workers.h"

/* Particles per task when a group's particle pass is split over threads,
 * and the smallest group that is split. */
#define PASS_CHUNK 512

/* §4 step(p, clock, dt):
 *   a = copy of v
 *   if mass != 0 and every F_i is finite:
 *      k = dt / mass; v_i = v_i + F_i*k, s = sum v_i*v_i
 *      if c > 0 and s > c*c: k = c / sqrt(s); v_i = v_i*k
 *   a_i = (v_i - a_i) / dt ; pos_i = pos_i + v_i*dt
 * The particle's own-force ease is applied at collection ([doc]); only
 * upstream (Flitter 1.0.0b28, physics.h) does the step need the [clock]:
 * after k = dt / mass, if ease > 0 and clock < ease: k = k * (clock/ease). */
static inline __attribute__((always_inline)) void
particle_step(PhysSystem *s, size_t p, double clock, double dt, const size_t D)
{
    double *pos = s->pos + p * D, *v = s->vel + p * D, *a = s->acc + p * D;
    const double *F = s->force + p * D;
    const double mass = s->mass[p], c = s->c;
    phys_copy(a, v, D);
    if (mass != 0) {
        bool finite = true;
        for (size_t i = 0; i < D; i++) {
            if (!isfinite(F[i])) {
                finite = false;
                break;
            }
        }
        if (finite) {
            double k = dt / mass;
            if (s->upstream) {
                const double e = s->ease[p];
                if (e > 0 && clock < e)
                    k = k * (clock / e);
            }
            double sum = 0;
            for (size_t i = 0; i < D; i++) {
                double x = v[i] + F[i] * k;
                v[i] = x;
                sum += x * x;
            }
            if (c > 0 && sum > c * c) {
                k = c / sqrt(sum);
                for (size_t i = 0; i < D; i++)
                    v[i] = v[i] * k;
            }
        }
    }
    for (size_t i = 0; i < D; i++) {
        a[i] = (v[i] - a[i]) / dt;
        pos[i] = pos[i] + v[i] * dt;
    }
}

/* §4 Barrier rebound(p, clock, dt), all sums over i ascending:
 *   x = -radius + sum (pos_i - bpos_i)*n_i ; u = sum v_i*n_i ;
 *   w = sum a_i*n_i ; if x >= 0: return ; r = x / u
 *   if u >= 0 or r > dt: pos_i = pos_i - x*n_i; return
 *   pos_i = pos_i - r*v_i ; v_i = (v_i - r*a_i)*rest ; u' = sum v_i*n_i ;
 *   v_i = v_i - 2*u'*n_i ; if w < 0 and u'/w < r: r = u'/w ; step(p, r) */
static inline __attribute__((always_inline)) void
barrier_rebound(PhysSystem *s, const PhysApplier *b, size_t p, double clock,
                double dt, const size_t D)
{
    if (!b->enabled)
        return;
    const double *bp = s->avec + b->vec, *nv = bp + D;
    double *pos = s->pos + p * D, *v = s->vel + p * D;
    const double *a = s->acc + p * D;
    double x = -s->radius[p], u = 0, w = 0;
    for (size_t i = 0; i < D; i++) {
        double n = nv[i];
        x = x + (pos[i] - bp[i]) * n;
        u = u + v[i] * n;
        w = w + a[i] * n;
    }
    if (x >= 0)
        return;
    double r = x / u;
    if (u >= 0 || r > dt) {
        for (size_t i = 0; i < D; i++)
            pos[i] = pos[i] - x * nv[i];
        return;
    }
    double u2 = 0;
    for (size_t i = 0; i < D; i++) {
        pos[i] = pos[i] - r * v[i];
        double y = (v[i] - r * a[i]) * b->restitution;
        v[i] = y;
        u2 = u2 + y * nv[i];
    }
    for (size_t i = 0; i < D; i++)
        v[i] = v[i] - 2 * u2 * nv[i];
    if (w < 0) {
        double t = u2 / w;
        if (t < r)
            r = t;
    }
    particle_step(s, p, clock, r, D);
}

/* §4: per-particle applier [ap] (drag, buoyancy, constant, random, field)
 * on non-anchor particle [p], for a step of [delta]. */
static inline __attribute__((always_inline)) void
apply_particle(PhysSystem *s, PhysApplier *ap, size_t p, double delta,
               const size_t D)
{
    double *F = s->force + p * D;
    const double *v = s->vel + p * D;
    const double *x = s->avec + ap->vec;
    switch (ap->kind) {
    case AP_DRAG: {
        /* §4 drag: s = sum (v_i - flow_i)^2;
         * k = min(strength * sqrt(s) * pow(radius, D-1), mass/delta);
         * F_i -= (v_i - flow_i)*k */
        double r = s->radius[p];
        if (r != 0) {
            double sum = 0;
            for (size_t i = 0; i < D; i++) {
                double d = v[i] - x[i];
                sum += d * d;
            }
            /* pow(r, 0) is 1 and pow(r, 1) is r exactly (r > 0 here) */
            double rp = D == 1 ? 1 : D == 2 ? r : pow(r, (double)(D - 1));
            double k = py_min(ap->strength * sqrt(sum) * rp,
                              s->mass[p] / delta);
            for (size_t i = 0; i < D; i++)
                F[i] = F[i] - (v[i] - x[i]) * k;
        }
        break;
    }
    case AP_BUOYANCY: {
        /* §4 buoyancy: k = strength * (mass - pow(radius, D)*density);
         * F_i += g_i*k */
        double r = s->radius[p], m = s->mass[p];
        if (r != 0 && m != 0) {
            double k = ap->strength * (m - pow(r, (double)D) * ap->density);
            for (size_t i = 0; i < D; i++)
                F[i] = F[i] + x[i] * k;
        }
        break;
    }
    case AP_CONSTANT: {
        /* §4 constant: F_i += (F'_i + A_i*mass) * strength */
        const double *A = x + D;
        double m = s->mass[p];
        for (size_t i = 0; i < D; i++) {
            double f = x[i] + A[i] * m;
            F[i] = F[i] + f * ap->strength;
        }
        break;
    }
    case AP_RANDOM:
        /* §4 random: F_i += strength * source[index]; index += 1 (the
         * source's values are made in pairs, i&~1 and i|1, so both are
         * kept once made) */
        for (size_t i = 0; i < D; i++) {
            const uint64_t e = ap->index & ~(uint64_t)1;
            if (ap->pair_at != e) {
                /* drawn ahead (random_ahead) or now: the same function of
                 * key and index either way */
                const uint64_t k = (e - ap->pre_at) / 2;
                if (e >= ap->pre_at && k < ap->pre_n)
                    memcpy(ap->pair, s->rnd + ap->pre_off + 2 * k, sizeof ap->pair);
                else
                    rng_normal_pair(ap->key, e, ap->pair);
                ap->pair_at = e;
            }
            F[i] = F[i] + ap->strength * ap->pair[ap->index & 1];
            ap->index++;
        }
        break;
    case AP_FIELD: {
        /* §4 field [doc]: F_i += strength * dir_i * charge; upstream
         * (Flitter 1.0.0b28): F_i += strength * dir_i */
        if (s->upstream) {
            for (size_t i = 0; i < D; i++)
                F[i] = F[i] + ap->strength * x[i];
            break;
        }
        double q = s->charge[p];
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + ap->strength * x[i] * q;
        break;
    }
    default:
        break;
    }
}

/* Whether barrier_distance() can add anything for barrier [b]: enabled,
 * not an upstream barrier with min <= 0, and with a minimum > 0 or a
 * maximum != 0 (a NaN maximum counts: it is measured against). */
static inline bool barrier_soft(const PhysSystem *s, const PhysApplier *b)
{
    return b->enabled && !(s->upstream && b->minimum <= 0) &&
           (b->minimum > 0 || b->maximum != 0);
}

/* §4 Barrier distance(p): x = sum (pos_i - bpos_i)*n_i; [doc] if min > 0
 * and 0 <= x < min: k = min - x, power, strength, F_i += n_i*k; else if
 * max != 0 and x > max: k = x - max, power, strength, F_i -= n_i*k.
 * Upstream (Flitter 1.0.0b28), a barrier with min <= 0 does nothing here. */
static inline __attribute__((always_inline)) void
barrier_distance(PhysSystem *s, const PhysApplier *b, size_t p,
                 const size_t D)
{
    if (!barrier_soft(s, b))
        return;
    const double *bp = s->avec + b->vec, *nv = bp + D;
    const double *pos = s->pos + p * D;
    double *F = s->force + p * D;
    double x = 0;
    for (size_t i = 0; i < D; i++)
        x = x + (pos[i] - bp[i]) * nv[i];
    if (b->minimum > 0 && x >= 0 && x < b->minimum) {
        double k = phys_shape(b->minimum - x, b->power, b->strength);
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + nv[i] * k;
    } else if (b->maximum != 0 && x > b->maximum) {
        double k = phys_shape(x - b->maximum, b->power, b->strength);
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] - nv[i] * k;
    }
}

/* §4 first pass for group [g]: its distance appliers, then (if it has
 * particles) the pair appliers of it and each ancestor over the growing
 * pool. */
static void pair_pass(PhysSystem *s, const PhysGroup *g)
{
    /* a step cut short (phys_interrupted) goes no further */
    if (atomic_load_explicit(&s->cut, memory_order_relaxed))
        return;
    phys_apply_distances(s, s->gidx + g->dist_off, g->dist_n);
    if (g->npart == 0)
        return;
    for (size_t l = 0; l < g->lvl_n; l++)
        phys_run_level(s, g, &s->levels[g->lvl_off + l]);
}

/* §4 second pass for particles [q0, q1) of group [g] (with particles):
 * particle appliers and barrier soft forces of the chain, step, rebounds,
 * force reset; compiled once for each D of 1..3 (the per-element loops
 * then unroll) and once for any D.
 *
 * Each particle's work reads and writes only that particle (and reads the
 * appliers), so it is done a block of STEP_BLOCK particles at a time: the
 * appliers and steps of the whole block, then its rebounds. Every
 * particle sees the same operations in the same order; the processor no
 * longer has each rebound's reads of the position wait for the step's
 * writes of it just before (a read of both elements at once cannot be
 * served from two pending stores), so the steps of a block overlap. */
#define STEP_BLOCK 64

/* The most barriers of a chain sorted into the lists below; a longer chain
 * runs every barrier for every particle. */
#define RANGE_BARRIERS 32

static inline __attribute__((always_inline)) void
particle_range_fixed(PhysSystem *s, const PhysGroup *g, double clock,
                     double delta, bool more, size_t q0, size_t q1,
                     const size_t D)
{
    const uint32_t *pf = s->chain + g->pf_off;
    const uint32_t *bl = s->chain + g->b_off;
    /* The chain's barriers that can act, in chain order: those whose soft
     * force can be non-zero (barrier_distance() returns at once for the
     * others) and the enabled ones (barrier_rebound() returns at once for
     * the others). Nothing changes a barrier during the pass, so leaving
     * out the early returns changes no operation on any particle. */
    uint32_t soft[RANGE_BARRIERS], hard[RANGE_BARRIERS];
    size_t nsoft = g->b_n, nhard = g->b_n;
    const uint32_t *sl = bl, *hl = bl;
    if (g->b_n <= RANGE_BARRIERS) {
        nsoft = nhard = 0;
        for (size_t j = 0; j < g->b_n; j++) {
            const PhysApplier *b = &s->ap[bl[j]];
            if (!b->enabled)
                continue;
            hard[nhard++] = bl[j];
            if (barrier_soft(s, b))
                soft[nsoft++] = bl[j];
        }
        sl = soft;
        hl = hard;
    }
    for (size_t b0 = q0; b0 < q1; b0 += STEP_BLOCK) {
        const size_t b1 = q1 - b0 < STEP_BLOCK ? q1 : b0 + STEP_BLOCK;
        for (size_t q = b0; q < b1; q++) {
            size_t p = g->pstart + q;
            if (s->anchor[p])
                continue;
            for (size_t j = 0; j < g->pf_n; j++)
                apply_particle(s, &s->ap[pf[j]], p, delta, D);
            for (size_t j = 0; j < nsoft; j++)
                barrier_distance(s, &s->ap[sl[j]], p, D);
            particle_step(s, p, clock, delta, D);
        }
        for (size_t q = b0; q < b1; q++) {
            size_t p = g->pstart + q;
            if (s->anchor[p])
                continue;
            for (size_t j = 0; j < nhard; j++)
                barrier_rebound(s, &s->ap[hl[j]], p, clock, delta, D);
            if (more)
                phys_copy(s->force + p * D, s->own + p * D, D);
        }
    }
}

#define RANGE_COPY(name, dim)                                                  \
    static void name(PhysSystem *s, const PhysGroup *g, double clock,         \
                     double delta, bool more, size_t q0, size_t q1)           \
    {                                                                          \
        particle_range_fixed(s, g, clock, delta, more, q0, q1, dim);           \
    }
RANGE_COPY(particle_range_1, 1)
RANGE_COPY(particle_range_2, 2)
RANGE_COPY(particle_range_3, 3)
RANGE_COPY(particle_range_any, s->D)
#undef RANGE_COPY

static void particle_range(PhysSystem *s, const PhysGroup *g, double clock,
                           double delta, bool more, size_t q0, size_t q1)
{
    switch (s->D) {
    case 1: particle_range_1(s, g, clock, delta, more, q0, q1); break;
    case 2: particle_range_2(s, g, clock, delta, more, q0, q1); break;
    case 3: particle_range_3(s, g, clock, delta, more, q0, q1); break;
    default: particle_range_any(s, g, clock, delta, more, q0, q1); break;
    }
}

typedef struct PassRun {
    PhysSystem *s;
    const PhysGroup *g;
    double clock, delta;
    bool more;
} PassRun;

static void pass_task(void *ctx, size_t t, unsigned thread)
{
    (void)thread;
    const PassRun *r = ctx;
    size_t q1 = (t + 1) * PASS_CHUNK;
    if (q1 > r->g->npart)
        q1 = r->g->npart;
    particle_range(r->s, r->g, r->clock, r->delta, r->more, t * PASS_CHUNK, q1);
}

/* The second pass of group [g]. Each particle's appliers, step and
 * rebounds read the appliers and write only that particle, so large groups
 * are split over the threads with the same bits, unless a !random applier
 * is in the chain: its draw index advances particle by particle. */
static void particle_pass(PhysSystem *s, const PhysGroup *g, double clock,
                          double delta, bool more)
{
    if (s->literal) {
        phys_literal_particle_pass(s, g, clock, delta, more);
        return;
    }
    bool split = s->workers && g->npart >= 2 * PASS_CHUNK;
    const uint32_t *pf = s->chain + g->pf_off;
    for (size_t j = 0; split && j < g->pf_n; j++)
        split = s->ap[pf[j]].kind != AP_RANDOM;
    if (!split) {
        particle_range(s, g, clock, delta, more, 0, g->npart);
        return;
    }
    PassRun r = {s, g, clock, delta, more};
    workers_run(s->workers, (g->npart + PASS_CHUNK - 1) / PASS_CHUNK,
                     pass_task, &r);
}

/* {===== !random draws made on a second thread during the first pass
 *
 * The normal draws of a !random applier are a function of its key and draw
 * index alone (streams.h), not of the particles, so the draws a step's
 * particle pass will take can be made while the pair pass runs. When the
 * pair pass keeps to one thread (every level on a one-thread route) and a
 * second thread is there, the first pass is one job of two tasks: the pair
 * pass of every group, and the draws, from each applier's next index for as
 * many draws as the particles of the groups whose chains hold it take (an
 * anchor takes none: a few draws to spare). The particle pass copies a pair
 * drawn ahead instead of drawing it; the values are the same bits. The
 * same job, with or without draws, lets middle-sized all-pairs levels take
 * the split route of tiles.c: the second task helps with their near parts
 * (phys_tiles_help_posted between its draws, then phys_tiles_help until
 * the pair pass ends). The draws come in chunks that either thread may
 * claim (phys_draw_chunk): the pair pass's thread makes the ones left when
 * its pass ends, and those it can while it waits for a near part, instead
 * of waiting idle. */

/* Fewest pairs of draws worth a job of their own. */
#define AHEAD_MIN_PAIRS 32

typedef struct FirstPass {
    PhysSystem *s;
    atomic_uint roles;  /* FIRST_PASS_PAIRS, FIRST_PASS_HELPER: taken */
    bool split;         /* the pair pass's levels may take the split route */
} FirstPass;

enum { FIRST_PASS_PAIRS = 1, FIRST_PASS_HELPER = 2 };

/* Whether the pair pass of [s] runs on one thread: no level on the
 * gather routes (split over the threads) or on two-thread tiles. */
static bool pairs_one_thread(const PhysSystem *s)
{
    for (size_t gi = 0; gi < s->ngroups; gi++) {
        const PhysGroup *g = &s->groups[gi];
        if (g->npart == 0)
            continue;
        for (size_t l = 0; l < g->lvl_n; l++) {
            const PhysLevel *lv = &s->levels[g->lvl_off + l];
            switch (lv->route) {
            case PHYS_ROUTE_SKIP:
            case PHYS_ROUTE_SCATTER:
            case PHYS_ROUTE_ROWS:
                break;
            case PHYS_ROUTE_TILES:
                if (phys_tiles_threaded(s, g, lv))
                    return false;
                break;
            default:
                return false;
            }
        }
    }
    return true;
}

/* Pairs of draws a chunk (phys_draw_chunk): between two looks for a split
 * level to help with, a short while (bench/PROFILE.md, "lib/physics/step.c:
 * the size of a chunk of draws"). */
#define DRAW_CHUNK 16
/* Pairs of draws a chunk of the next frame's (DrawsAhead): smaller, as a
 * thread waiting in a pair pass makes them between two looks at what it
 * waits for (same subsection). */
#define AHEAD_CHUNK 8

/* Pairs of draws of applier [ap] (pre_at, pre_n) that the frame before
 * made into s->ahead: copied to the applier's place in s->rnd (sized);
 * returns how many, the first of its pairs. */
static uint64_t take_ahead(PhysSystem *s, const PhysApplier *ap)
{
    const DrawsAhead *a = &s->ahead;
    for (size_t i = 0; i < a->nseg; i++) {
        const AheadSeg *g = &a->seg[i];
        if (g->key != ap->key)
            continue;
        /* the segment's pairs 0 .. made-1 are made (its chunks below done) */
        const uint64_t made = a->done <= g->chunk ? 0
                              : a->done - g->chunk >= (g->n + AHEAD_CHUNK - 1) / AHEAD_CHUNK
                                  ? g->n
                                  : (uint64_t)(a->done - g->chunk) * AHEAD_CHUNK;
        const uint64_t first = ap->pre_at / 2;
        if (first >= made)
            return 0;
        const uint64_t m = made - first < ap->pre_n ? made - first : ap->pre_n;
        memcpy(s->rnd + ap->pre_off, a->buf + g->off + 2 * first, 2 * m * sizeof(double));
        return m;
    }
    return 0;
}

/* Plan this step's draws ahead: each !random applier's range (pre_at,
 * pre_n, pre_off, pre_chunk, pre_done), room for them in s->rnd, the ones
 * the frame before made (take_ahead) and the chunks of the rest
 * (s->draw_chunks, which first_pass clears before). Returns the pairs of
 * draws left to make: 0 with nothing planned (too few to be worth it, or
 * no memory) or all made. */
static size_t plan_ahead(PhysSystem *s)
{
    phys_draws_ahead_settle(s);
    size_t total = 0;
    for (size_t a = 0; a < s->nap; a++) {
        PhysApplier *ap = &s->ap[a];
        if (ap->kind != AP_RANDOM)
            continue;
        ap->pre_n = ap->pre_done = 0;
        uint64_t draws = 0;
        for (size_t gi = 0; gi < s->ngroups; gi++) {
            const PhysGroup *g = &s->groups[gi];
            const uint32_t *pf = s->chain + g->pf_off;
            for (size_t j = 0; j < g->pf_n; j++)
                if (pf[j] == a)
                    draws += (uint64_t)g->npart * s->D;
        }
        ap->pre_draws = draws;
        ap->pre_at = ap->index & ~(uint64_t)1;
        ap->pre_n = (draws + (ap->index & 1) + 1) / 2;
        ap->pre_off = 2 * total;
        total += ap->pre_n;
    }
    if (total < AHEAD_MIN_PAIRS || total > SIZE_MAX / 4 / sizeof(double))
        goto none;
    if (2 * total > s->caprnd) {
        double *r = realloc(s->rnd, 2 * total * sizeof(double));
        if (!r)
            goto none;
        s->rnd = r;
        s->caprnd = 2 * total;
    }
    size_t chunks = 0, left = 0;
    for (size_t a = 0; a < s->nap; a++) {
        PhysApplier *ap = &s->ap[a];
        if (ap->kind != AP_RANDOM)
            continue;
        ap->pre_done = take_ahead(s, ap);
        ap->pre_chunk = chunks;
        chunks += (ap->pre_n - ap->pre_done + DRAW_CHUNK - 1) / DRAW_CHUNK;
        left += ap->pre_n - ap->pre_done;
    }
    s->draw_chunks = chunks;
    atomic_store_explicit(&s->draw_next, 0, memory_order_relaxed);
    s->ahead_pairs[0] += total - left;
    s->ahead_pairs[1] += total;
    return left;
none:
    for (size_t a = 0; a < s->nap; a++)
        s->ap[a].pre_n = 0;
    return 0;
}

bool phys_draw_chunk(PhysSystem *s)
{
    /* a look first: a waiting thread calls this at each pause */
    if (s->draw_chunks == 0 ||
        atomic_load_explicit(&s->draw_next, memory_order_relaxed) >= s->draw_chunks)
        return false;
    const size_t c = atomic_fetch_add_explicit(&s->draw_next, 1, memory_order_relaxed);
    if (c >= s->draw_chunks)
        return false;
    for (size_t a = 0; a < s->nap; a++) {
        const PhysApplier *ap = &s->ap[a];
        if (ap->kind != AP_RANDOM || ap->pre_n == 0 || c < ap->pre_chunk ||
            c - ap->pre_chunk >= (ap->pre_n - ap->pre_done + DRAW_CHUNK - 1) / DRAW_CHUNK)
            continue;
        const uint64_t k0 = ap->pre_done + (uint64_t)(c - ap->pre_chunk) * DRAW_CHUNK;
        const uint64_t k1 = ap->pre_n - k0 < DRAW_CHUNK ? ap->pre_n : k0 + DRAW_CHUNK;
        double *out = s->rnd + ap->pre_off;
        for (uint64_t k = k0; k < k1; k++)
            rng_normal_pair(ap->key, ap->pre_at + 2 * k, out + 2 * k);
        break;
    }
    return true;
}

/* Chunks of the planned draws until none is left to claim (the helper's
 * draws, and the pair pass's thread's once its pass ends); with [help], before each, the part of a split level posted
 * meanwhile (phys_tiles_help_posted): the pair pass waits for that, not
 * for the draws. */
static void draw_ahead(PhysSystem *s, bool help)
{
    for (;;) {
        if (help)
            phys_tiles_help_posted(s);
        if (!phys_draw_chunk(s))
            return;
    }
}

/* A task of the first pass's job takes one of its two roles: the pair
 * pass of every group, or the planned draws and the parts of split levels
 * the pair pass leaves it (tiles.c, "Two threads for a middle-sized
 * level") until the pass ends. The calling thread (thread 0) takes the
 * pair pass unless a task it ran before took it, a worker the helper's
 * role unless another worker took it: so the pair pass stays on the
 * thread whose particle pass wrote the positions and forces it reads, and
 * reads them from its own cache (when a task's index decided, a worker
 * that claimed the first task often took the pair pass: bench/PROFILE.md,
 * "lib/physics/step.c: which thread takes the pair pass"). The two tasks
 * always take the two roles.
 * The caller, running both, takes the pair pass first, as the helper's
 * waits end with it; a worker runs both only when the helper's role
 * returned without waiting (draws alone, no level split), so in either
 * order. */
static void first_pass_task(void *ctx, size_t t, unsigned thread)
{
    (void)t;
    FirstPass *fp = ctx;
    PhysSystem *s = fp->s;
    const unsigned mine = thread == 0 ? FIRST_PASS_PAIRS : FIRST_PASS_HELPER;
    const unsigned had = atomic_fetch_or(&fp->roles, mine);
    const bool pairs = thread == 0 ? !(had & FIRST_PASS_PAIRS) : (had & FIRST_PASS_HELPER) != 0;
    if (pairs) {
        for (size_t g = 0; g < s->ngroups; g++)
            pair_pass(s, &s->groups[g]);
        if (fp->split)
            phys_tiles_split_end(s);
        draw_ahead(s, false);      /* the draws no thread has claimed yet */
        return;
    }
    draw_ahead(s, fp->split);
    if (fp->split)
        phys_tiles_help(s);
}

/* The first pass of one step (§4: the pair pass of every group), with the
 * draws of the step made alongside when that pays, and levels split
 * between the two threads when that pays; in the [last] step of a frame,
 * the next frame's draws made ready, for the threads of a split level to
 * make while they wait (phys_ahead_chunk) and for the background job
 * after. */
static void ahead_prepare(PhysSystem *s);

static void first_pass(PhysSystem *s, bool random, bool last)
{
    Workers *w = s->workers;
    bool ahead = false, split = false;
    s->draw_chunks = 0;
    if (!s->literal && workers_count(w) >= 2 && pairs_one_thread(s)) {
        const double draw_pairs = random ? (double)plan_ahead(s) : 0;
        if (random && last)
            ahead_prepare(s);
        ahead = draw_pairs > 0;
        split = phys_tiles_split_wanted(s, draw_pairs) && phys_tiles_split_begin(s, draw_pairs);
    }
    if (!ahead && !split) {
        for (size_t g = 0; g < s->ngroups; g++)
            pair_pass(s, &s->groups[g]);
        return;
    }
    FirstPass fp = {s, 0, split};
    /* the pair pass inside the job keeps to its thread */
    s->workers = NULL;
    workers_run(w, 2, first_pass_task, &fp);
    s->workers = w;
}

/* }===== */

/* {===== The next frame's draws
 *
 * A step's !random draws depend on nothing but each applier's key and
 * draw index, and next frame's keys are known: the seed is P;run;iteration
 * (world.c keeps the hashes of this frame's and the next frame's,
 * seed_now and seed_next), each further !random's seed;0, and draws start
 * at index 0 each frame. So when the last step of a frame has planned its
 * draws, the next frame's first step's draws are made ready in s->ahead
 * (ahead_prepare), in chunks that any thread may claim: the threads of
 * the step's split level make them while they wait (phys_ahead_chunk,
 * tiles.c), and after the pair pass the pool's other thread makes those
 * left as a background job (workers_background) while this thread runs
 * the particle pass, writes the state and evaluates and collects the next
 * frame. The next plan_ahead ends the job (the chunks not yet begun are
 * left) and copies the pairs made of each applier whose key came true
 * (take_ahead); a value is the same function of key and index whoever
 * makes it, so a guess that fails (another run, a new tree, the state's
 * :iteration changed) costs only the work. Any other job on the pool's
 * threads ends the background job first:
 * a split particle pass of a group without !random, the parallel writes
 * and fills of systems of 1,024 particles or more, an evaluator's loop
 * kernel, another system's pair pass; for such frames the window is
 * shorter or none. */

/* Make chunk [c] of the next frame's draws of [a]. */
static void ahead_make(DrawsAhead *a, size_t c)
{
    for (size_t i = 0; i < a->nseg; i++) {
        const AheadSeg *g = &a->seg[i];
        if (c < g->chunk || c - g->chunk >= (g->n + AHEAD_CHUNK - 1) / AHEAD_CHUNK)
            continue;
        const uint64_t k0 = (uint64_t)(c - g->chunk) * AHEAD_CHUNK;
        const uint64_t k1 = g->n - k0 < AHEAD_CHUNK ? g->n : k0 + AHEAD_CHUNK;
        for (uint64_t k = k0; k < k1; k++)
            rng_normal_pair(g->key, 2 * k, a->buf + g->off + 2 * k);
        return;
    }
}

bool phys_ahead_chunk(PhysSystem *s)
{
    DrawsAhead *a = &s->ahead;
    /* a look first: once every chunk is claimed, a waiting thread calls
     * this at each pause, and should not write the counter's line */
    if (!a->ready || atomic_load_explicit(&a->next, memory_order_relaxed) >= a->limit)
        return false;
    const size_t c = atomic_fetch_add_explicit(&a->next, 1, memory_order_relaxed);
    if (c >= a->limit)
        return false;
    ahead_make(a, c);
    return true;
}

/* The background job's task: chunks until none is left or it is ended
 * early (the stop flag, looked at between chunks). */
static void ahead_task(void *ctx, size_t t, unsigned thread)
{
    (void)t;
    (void)thread;
    PhysSystem *s = ctx;
    while (!atomic_load_explicit(&s->ahead.stop, memory_order_relaxed) && phys_ahead_chunk(s)) {
    }
}

void phys_draws_ahead_settle(PhysSystem *s)
{
    DrawsAhead *a = &s->ahead;
    if (a->running) {
        workers_end_background(a->pool, &a->job, !a->wait);
        a->running = false;
    }
    if (!a->ready)
        return;
    /* every chunk claimed below the limit was made before its thread went
     * on: the first pass's job and the background job have ended */
    const size_t n = atomic_load_explicit(&a->next, memory_order_relaxed);
    a->done = n < a->limit ? n : a->limit;
    a->ready = false;
}

/* In the last step of a frame whose draws were planned, before its first
 * pass's job: make the next frame's draws ready (the section's comment).
 * Nothing when this frame's keys are not the ones seed_now foretells (the
 * guess would then be wrong too), or when an applier planned none (one in
 * an empty group, say). */
static void ahead_prepare(PhysSystem *s)
{
    /* plan_ahead, just before, settled the frame before's draws */
    DrawsAhead *a = &s->ahead;
    a->nseg = 0;
    a->done = 0;
    if (!s->seed_ok || workers_count(s->workers) < 2)
        return;
    uint64_t now = s->seed_now;
    size_t total = 0, chunks = 0, n = 0;
    for (size_t i = 0; i < s->nap; i++) {
        const PhysApplier *ap = &s->ap[i];
        if (ap->kind != AP_RANDOM)
            continue;
        if (ap->key != now || ap->pre_n == 0)
            return;
        now = hash_update(now, num_bits(0.0));
        n++;
    }
    if (n > a->capseg) {
        AheadSeg *g = realloc(a->seg, n * sizeof *g);
        if (!g)
            return;
        a->seg = g;
        a->capseg = n;
    }
    uint64_t next = s->seed_next;
    for (size_t i = 0; i < s->nap; i++) {
        const PhysApplier *ap = &s->ap[i];
        if (ap->kind != AP_RANDOM)
            continue;
        const uint64_t pairs = (ap->pre_draws + 1) / 2;
        if (pairs > SIZE_MAX / 4 / sizeof(double) - total) {
            a->nseg = 0;
            return;
        }
        a->seg[a->nseg++] = (AheadSeg){next, pairs, 2 * total, chunks};
        total += pairs;
        chunks += (pairs + AHEAD_CHUNK - 1) / AHEAD_CHUNK;
        next = hash_update(next, num_bits(0.0));
    }
    if (2 * total > a->capbuf) {
        double *b = realloc(a->buf, 2 * total * sizeof(double));
        if (!b) {
            a->nseg = 0;
            return;
        }
        a->buf = b;
        a->capbuf = 2 * total;
    }
    a->limit = s->ahead_limit < 0 || (size_t)s->ahead_limit > chunks ? chunks
                                                                     : (size_t)s->ahead_limit;
    a->wait = s->ahead_limit >= 0;
    atomic_store_explicit(&a->next, 0, memory_order_relaxed);
    atomic_store_explicit(&a->stop, false, memory_order_relaxed);
    a->ready = true;
}

/* After the last step's first pass: the next frame's draws that its job
 * left, as a background job. */
static void ahead_start(PhysSystem *s)
{
    DrawsAhead *a = &s->ahead;
    if (!a->ready || a->running)
        return;
    const size_t made = atomic_load_explicit(&a->next, memory_order_relaxed);
    s->ahead_pairs[2] += made < a->limit ? made : a->limit;
    if (made >= a->limit)
        return;
    a->pool = s->workers;
    a->running = workers_background(s->workers, &a->job, 2, ahead_task, s, &a->stop);
}

/* }===== */

/* §4 loop:
 *   delta = min(resolution, time - last); last = last + delta
 *   more  = last < time  (realtime: and spare performance, once per frame)
 *   ... passes ...; clock = clock + delta; if not more: break
 * Guards beyond the spec: if `last + delta` no longer moves `last`
 * (rounding at huge times) the loop stops instead of spinning forever; it
 * also stops at s->frame->max_steps steps or when s->frame->interrupt is
 * set (physics.h), and a step whose pair pass the interrupt cut short
 * (phys_interrupted) is abandoned: the particles keep the last whole
 * step's positions and velocities and the clock its time, as when the
 * step limit stops a frame. */
double phys_run_steps(PhysSystem *s, double time, double last, double clock,
                      double resolution, bool realtime, bool extra)
{
    const PhysicsFrame *fr = s->frame;
    long steps = 0;
    bool random = false;
    for (size_t a = 0; a < s->nap && !random; a++)
        random = s->ap[a].kind == AP_RANDOM;
    for (;;) {
        double gap = time - last;
        double delta = gap < resolution ? gap : resolution;
        double next = last + delta;
        bool more = next < time && (!realtime || extra);
        if (!(next > last))
            more = false;
        /* bounded work (physics.h): the step limit and the interrupt flag
         * end the loop after a whole step, so the state stays consistent */
        if (more && fr && fr->max_steps > 0 && ++steps >= fr->max_steps) {
            more = false;
            if (fr->capped)
                *fr->capped = true;
        }
        if (more && fr && fr->interrupt && __atomic_load_n(fr->interrupt, __ATOMIC_RELAXED))
            more = false;
        atomic_store_explicit(&s->cut, false, memory_order_relaxed);
        first_pass(s, random, !more);
        if (atomic_load_explicit(&s->cut, memory_order_relaxed)) {
            /* interrupted part way (phys_interrupted): the step is not
             * taken and the clock stays where it was; the partial sums
             * in the forces go with the next frame's collection, which
             * starts every force from the particle's own */
            break;
        }
        last = next;
        if (random && !more)
            ahead_start(s);
        for (size_t g = 0; g < s->ngroups; g++) {
            if (s->groups[g].npart)
                particle_pass(s, &s->groups[g], clock, delta, more);
        }
        clock = clock + delta;
        if (!more)
            break;
        extra = false;
    }
    return clock;
}
