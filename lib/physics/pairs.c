/* pairs.c: faster routes to the exact result of the pair loop.
 *
 * The reference pair loop of one level (forces.c phys_apply_pair_level,
 * PHYSICS-ENGINE.md §4) visits i < len(G.particles), j in i+1 .. npool-1 and
 * adds each applier's contribution to both particles of the pair. Only the
 * order of the additions into one particle's force decides its bits, and
 * that order is fixed:
 *   - a particle at pool index q < len(G.particles) first receives, as the
 *     "to" side b, the contributions of the pairs (i, q) for i < q in
 *     ascending i (they come from earlier rows of the loop), then, as the
 *     "from" side a, those of the pairs (q, j) for j > q in ascending j (its
 *     own row);
 *   - a particle of an ancestor group (q >= len(G.particles)) only ever is
 *     the "to" side, of the pairs (i, q), i ascending;
 *   - within one pair, the appliers add in their order.
 * Every contribution depends only on positions, radii, masses and charges,
 * which the pair loop does not change. So the force of each particle can be
 * summed on its own, gathering its partners in ascending pool index and
 * measuring each pair with the same orientation (pool[min], pool[max]) as
 * the reference: the result is the same bits, and particles no longer write
 * to each other, so ranges of them can run on different threads in any
 * order. (Distance appliers, groups and levels stay in the reference order:
 * levels run one after the other, distance appliers between them on the
 * calling thread.)
 *
 * A pair that no applier of the level acts on adds nothing in the
 * reference: !collision and !adhesion act only when dist < ra + rb, and any
 * pair applier with max_distance only when dist < max_distance. The largest
 * such reach R of a level makes every pair at dist >= R skippable exactly.
 * The uniform grid (cell size h slightly above R) finds the candidates in
 * the 3^D cells around a particle; those are filtered by squared distance
 * against a bound just above R*R, then sorted back into pool order. The
 * grid is dense when the box of cells around the entries has at most about
 * 4 cells per entry (entries laid out cell by cell, so a row of 3 cells is
 * one contiguous run), else hashed by cell. Entries
 * whose position is not finite, or too far out for a 32-bit cell index, go
 * into an "odd" list that is a candidate for everyone (and they scan every
 * partner themselves). Levels with an unlimited reach (gravity or
 * electrostatics without max_distance, infinite radii) and D > 3 gather over
 * all pairs; with one or two threads those use the reference loop itself
 * (the gather measures each pair twice, so two threads only break even),
 * its partners measured in vector blocks (rows.c) when D <= 3.
 *
 * Why the cell test is exact: with h = R * (1 + 2^-20) and |x/h| < 2^30,
 * two entries whose cell indices differ by 2 or more in some coordinate are
 * more than R * (1 + 2^-21) apart in that coordinate, and the rounded
 * difference, square, sum and sqrt of pair() lose far less than that, so
 * the reference computes dist >= R and skips the pair too.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

#include "cpu.h"
#include "mem.h"
#include "physics_internal.h"
#include "workers.h"

#define GRID_MAX_D 3
#define CELL_LIMIT 1073741824.0        /* 2^30: |x/h| beyond this is odd */
#define TARGETS_PER_TASK 256

#define GROW(ptr, cap, need) ((ptr) = mem_grow((ptr), &(cap), (need), sizeof *(ptr)))

/* ------------------------------------------------------------------ */
/* Planning                                                            */
/* ------------------------------------------------------------------ */

/* Distance beyond which applier [ap] never acts, given the largest radius
 * [rmax] among the level's particles (infinite when unlimited). */
static double applier_reach(const PhysApplier *ap, double rmax)
{
    double r = INFINITY;
    if (ap->kind == AP_COLLISION || ap->kind == AP_ADHESION)
        r = rmax + rmax;       /* dist < ra + rb <= 2 * rmax */
    if (ap->maxd != 0 && ap->maxd < r)
        r = ap->maxd;          /* dist < max_distance */
    return r;
}

void phys_plan_levels(PhysSystem *s)
{
    unsigned nth = workers_count(s->workers);
    for (size_t g = 0; g < s->ngroups; g++) {
        const PhysGroup *G = &s->groups[g];
        if (!G->npart)
            continue;
        const uint32_t *pool = s->pool + G->pool_off;
        for (size_t l = 0; l < G->lvl_n; l++) {
            PhysLevel *lv = &s->levels[G->lvl_off + l];
            lv->route = PHYS_ROUTE_SCATTER;
            lv->reach = INFINITY;
            if (s->naive)
                continue;
            double rmax = 0;
            for (size_t q = 0; q < lv->npool; q++) {
                double r = s->radius[pool[q]];
                if (r > rmax)
                    rmax = r;
            }
            const PhysGroup *fg = &s->groups[lv->group];
            double R = 0;
            for (size_t f = 0; f < fg->pair_n; f++) {
                double r = applier_reach(&s->ap[s->gidx[fg->pair_off + f]], rmax);
                if (r > R)
                    R = r;
            }
            lv->reach = R;
            if (R == 0)
                lv->route = PHYS_ROUTE_SKIP;
            else if (R < 0x1p1000 && s->D <= GRID_MAX_D)
                lv->route = PHYS_ROUTE_GRID;
            /* the all-pairs gather measures every pair twice (once for
             * each side), so it only beats the one-thread reference loop
             * with three threads or more, or when a finite reach lets it
             * skip most pairs by their squared distance */
            else if ((nth > 2 && lv->npool >= 512) || R < 0x1p1000)
                lv->route = PHYS_ROUTE_ALL;
            /* otherwise the reference loop itself, its pairs measured in
             * vector blocks (rows.c) */
            else if (phys_tiles_suits(s, lv)) {
                lv->route = PHYS_ROUTE_TILES;
                phys_tiles_reserve(s, lv->npool);
            } else if (phys_rows_suits(s)) {
                lv->route = PHYS_ROUTE_ROWS;
                phys_rows_reserve(s, lv->npool);
            }
        }
    }
}

/* ------------------------------------------------------------------ */
/* The grid                                                            */
/* ------------------------------------------------------------------ */

static inline uint64_t cell_hash(const int32_t *c)
{
    uint64_t h = (uint64_t)(uint32_t)c[0] * 0x9E3779B97F4A7C15u;
    h ^= (uint64_t)(uint32_t)c[1] * 0xC2B2AE3D27D4EB4Fu;
    h ^= (uint64_t)(uint32_t)c[2] * 0x165667B19E3779F9u;
    return h ^ (h >> 29);
}

/* The dense grid is used when its box (padding included) has at most
 * DENSE_PER_ENTRY cells per entry, plus DENSE_SLACK: memory and the clearing
 * of the cell starts stay linear in the entries. */
#define DENSE_PER_ENTRY 4.0
#define DENSE_SLACK 4096.0

/* The grid's per-entry loops are split over the threads when the level
 * is large: every entry's results go to its own places, so they are the
 * same bits on any number of threads. Tasks of at least GRID_CHUNK
 * entries (workers_split). */
#define GRID_CHUNK 512

/* One task's share of the cell loop: the box of its cells and how many
 * of its entries are odd. */
typedef struct GridPart {
    int32_t lo[3], hi[3];
    size_t nodd;
} GridPart;

typedef struct GridRun {
    PhysSystem *s;
    const uint32_t *pool;
    size_t chunk;       /* items per task */
    size_t count;       /* items of the loop in hand */
    GridPart part[WORKERS_MAX_TASKS];
} GridRun;

/* Entry q's cell (cell[3q..3q+2], 0 past D) and whether it is odd
 * (bucket[q] = UINT32_MAX: a coordinate out of CELL_LIMIT cells). */
static void cell_task(void *ctx, size_t t, unsigned thread)
{
    (void)thread;
    GridRun *r = ctx;
    PhysGrid *gr = &r->s->grid;
    const size_t D = r->s->D;
    const double h = gr->h;
    /* the box and count kept here, stored once: the tasks' parts share
     * cache lines, which per-entry stores would pass between the cores */
    GridPart P_ = {{INT32_MAX, INT32_MAX, INT32_MAX}, {INT32_MIN, INT32_MIN, INT32_MIN}, 0}, *P = &P_;
    for (size_t q = t * r->chunk, q1 = workers_task_end(t, r->chunk, r->count); q < q1; q++) {
        const double *x = r->s->pos + (size_t)r->pool[q] * D;
        int32_t *c = gr->cell + 3 * q;
        c[0] = c[1] = c[2] = 0;
        bool ok = true;
        for (size_t k = 0; k < D; k++) {
            double v = x[k] / h;
            if (!(v > -CELL_LIMIT && v < CELL_LIMIT)) {
                ok = false;
                break;
            }
            c[k] = (int32_t)floor(v);
        }
        if (!ok) {
            gr->bucket[q] = UINT32_MAX;
            P->nodd++;
            continue;
        }
        gr->bucket[q] = 0;
        for (size_t k = 0; k < 3; k++) {
            if (c[k] < P->lo[k])
                P->lo[k] = c[k];
            if (c[k] > P->hi[k])
                P->hi[k] = c[k];
        }
    }
    r->part[t] = P_;
}

/* The coordinates of slots [t*chunk, ...) in slot order (sx). */
static void copy_task(void *ctx, size_t t, unsigned thread)
{
    (void)thread;
    GridRun *r = ctx;
    PhysGrid *gr = &r->s->grid;
    const size_t D = r->s->D, m = gr->nslot;
    for (size_t i = t * r->chunk, i1 = workers_task_end(t, r->chunk, r->count); i < i1; i++) {
        const double *x = r->s->pos + (size_t)r->pool[gr->slotq[i]] * D;
        for (size_t k = 0; k < D; k++)
            gr->sx[k * m + i] = x[k];
    }
}

/* Run [fn] over [count] items in tasks; returns the number of tasks. */
static size_t grid_run(GridRun *r, size_t count, WorkersTaskFn fn)
{
    r->count = count;
    size_t ntasks = workers_split(count, GRID_CHUNK, &r->chunk);
    workers_run(workers_count(r->s->workers) > 1 ? r->s->workers : NULL, ntasks, fn, r);
    return ntasks;
}

/* Lay the non-odd entries out cell by cell (counting sort by the dense cell
 * index, filled from the last entry down so each cell's slots come out in
 * ascending pool order) and copy their coordinates into that order. */
static void grid_dense(PhysSystem *s, const uint32_t *pool, size_t n,
                       const int32_t *lo, size_t ncells)
{
    PhysGrid *gr = &s->grid;
    const size_t D = s->D;
    const size_t e0 = gr->ext[0], e01 = gr->ext[0] * gr->ext[1];
    GROW(gr->cellof, gr->capcellof, n);
    GROW(gr->cstart, gr->capcstart, ncells + 1);
    memset(gr->cstart, 0, (ncells + 1) * sizeof *gr->cstart);
    size_t m = 0;
    for (size_t q = 0; q < n; q++) {
        if (gr->bucket[q] == UINT32_MAX) {
            gr->cellof[q] = UINT32_MAX;
            continue;
        }
        const int32_t *c = gr->cell + 3 * q;
        size_t cell = (size_t)(c[0] - lo[0]) + (size_t)(c[1] - lo[1]) * e0 +
                      (size_t)(c[2] - lo[2]) * e01;
        gr->cellof[q] = (uint32_t)cell;
        gr->cstart[cell]++;
        m++;
    }
    for (size_t c = 1; c < ncells; c++)
        gr->cstart[c] += gr->cstart[c - 1];
    gr->cstart[ncells] = (uint32_t)m;
    /* + 4: the AVX2 scan reads whole groups of four slots past a run's
     * end (scan_run_avx2), the padding defined */
    GROW(gr->slotq, gr->capslotq, m + 4);
    GROW(gr->sx, gr->capsx, D * m + 4);
    for (size_t i = 0; i < 4; i++) {
        gr->slotq[m + i] = 0;
        gr->sx[D * m + i] = 0;
    }
    for (size_t q = n; q-- > 0;) {
        uint32_t cell = gr->cellof[q];
        if (cell != UINT32_MAX)
            gr->slotq[--gr->cstart[cell]] = (uint32_t)q;
    }
    gr->nslot = m;
    GridRun r = {.s = s, .pool = pool};
    grid_run(&r, m, copy_task);
}

/* Grid the first [n] pool entries with cell size h: densely when the box
 * of their cells is small enough, else hashed by cell into buckets. */
static void grid_build(PhysSystem *s, const uint32_t *pool, size_t n, double h)
{
    PhysGrid *gr = &s->grid;
    const size_t D = s->D;
    GROW(gr->bucket, gr->capbucket, n);
    GROW(gr->ent, gr->capent, n);
    GROW(gr->odd, gr->capodd, n);
    GROW(gr->cell, gr->capcell, 3 * n);
    gr->h = h;
    gr->nodd = 0;
    GridRun r = {.s = s, .pool = pool};
    size_t ntasks = grid_run(&r, n, cell_task);
    int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX};
    int32_t hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    size_t nodd = 0;
    for (size_t t = 0; t < ntasks; t++) {
        for (size_t k = 0; k < 3; k++) {
            if (r.part[t].lo[k] < lo[k])
                lo[k] = r.part[t].lo[k];
            if (r.part[t].hi[k] > hi[k])
                hi[k] = r.part[t].hi[k];
        }
        nodd += r.part[t].nodd;
    }
    /* the odd entries in ascending pool order */
    for (size_t q = 0; nodd && q < n; q++) {
        if (gr->bucket[q] == UINT32_MAX) {
            gr->odd[gr->nodd++] = (uint32_t)q;
            nodd--;
        }
    }
    /* the dense box: one cell of padding before and after on each axis in
     * use, so the 3^D cells around any entry are inside it */
    double cells = 1;
    for (size_t k = 0; k < 3; k++) {
        if (lo[k] > hi[k])
            lo[k] = hi[k] = 0;
        if (k < D) {
            lo[k] -= 1;
            gr->ext[k] = (size_t)((int64_t)hi[k] - lo[k] + 2);
        } else
            gr->ext[k] = 1;
        cells *= (double)gr->ext[k];
    }
    gr->dense = cells <= DENSE_PER_ENTRY * (double)n + DENSE_SLACK &&
                cells < (double)UINT32_MAX;
    if (gr->dense) {
        grid_dense(s, pool, n, lo, (size_t)cells);
        return;
    }
    size_t nb = 16;
    while (nb < n)
        nb *= 2;
    gr->nb = nb;
    GROW(gr->start, gr->capstart, 2 * nb + 1);
    uint32_t *fill = gr->start + nb + 1;
    memset(gr->start, 0, (nb + 1) * sizeof *gr->start);
    for (size_t q = 0; q < n; q++) {
        if (gr->bucket[q] == UINT32_MAX)
            continue;
        uint32_t b = (uint32_t)(cell_hash(gr->cell + 3 * q) & (nb - 1));
        gr->bucket[q] = b;
        gr->start[b + 1]++;
    }
    for (size_t b = 0; b < nb; b++)
        gr->start[b + 1] += gr->start[b];
    memcpy(fill, gr->start, nb * sizeof *fill);
    for (size_t q = 0; q < n; q++) {
        uint32_t b = gr->bucket[q];
        if (b != UINT32_MAX)
            gr->ent[fill[b]++] = (uint32_t)q;
    }
}

/* ------------------------------------------------------------------ */
/* Gathering                                                           */
/* ------------------------------------------------------------------ */

/* One level in flight, shared read-only by the tasks. */
typedef struct LevelRun {
    PhysSystem *s;
    const uint32_t *pool;
    size_t npart, npool;
    const uint32_t *forces;
    size_t nf;
    double r2;          /* skip a pair when its squared distance is above */
    bool grid;
    bool avx2;          /* run the AVX2 copies of the kernels */
    bool simple;        /* every applier suits simple_block() */
} LevelRun;

/* Squared distance of pool entries, summed as pair() does (k ascending);
 * the same bits whichever of the two is first, as x - y = -(y - x). */
static inline double dist2(const double *pa, const double *pb, size_t D)
{
    double sum = 0;
    for (size_t k = 0; k < D; k++) {
        double d = pb[k] - pa[k];
        sum += d * d;
    }
    return sum;
}

/* §4 pair(a, b) into [dir]; returns dist. */
static inline double pair_into(const double *pa, const double *pb, double *dir,
                               size_t D)
{
    double sum = 0;
    for (size_t k = 0; k < D; k++) {
        double d = pb[k] - pa[k];
        dir[k] = d;
        sum += d * d;
    }
    double dist = sqrt(sum);
    double inv = 1 / dist;
    for (size_t k = 0; k < D; k++)
        dir[k] = dir[k] * inv;
    return dist;
}

/* Add the contributions of partner [e] to pool entry [q]'s force [F]: the
 * pair is measured as (pool[min], pool[max]), as the reference loop does,
 * and q is its "to" side when q > e. */
static inline __attribute__((always_inline)) void
take_pair(const LevelRun *L, size_t q, size_t e, double *F, double *dir,
          const size_t D)
{
    PhysSystem *s = L->s;
    size_t a = L->pool[q < e ? q : e], b = L->pool[q < e ? e : q];
    double dist = pair_into(s->pos + a * D, s->pos + b * D, dir, D);
    for (size_t f = 0; f < L->nf; f++) {
        const PhysApplier *ap = &s->ap[L->forces[f]];
        if (ap->maxd == 0 || dist < ap->maxd)
            phys_pair_force_side(s, ap, a, b, dist, dir, F, q > e, D);
    }
}

/* Is [e] a partner of [q] in the reference loop? Rows are the group's own
 * particles (index < npart), columns run to npool: a pair needs one of the
 * two to be a row. */
static inline bool partner(const LevelRun *L, size_t q, size_t e)
{
    return e != q && (q < L->npart || e < L->npart);
}

/* Gather over every partner, ascending (no sort needed). */
static void gather_all(const LevelRun *L, size_t q, PhysScratch *sc)
{
    PhysSystem *s = L->s;
    const size_t D = s->D;
    const size_t p = L->pool[q];
    double *F = s->force + p * D;
    const double *x = s->pos + p * D;
    size_t lim = q < L->npart ? L->npool : L->npart;
    bool filter = L->r2 < INFINITY;
    for (size_t e = 0; e < lim; e++) {
        if (e == q)
            continue;
        if (filter && dist2(x, s->pos + (size_t)L->pool[e] * D, D) > L->r2)
            continue;
        take_pair(L, q, e, F, sc->dir, D);
    }
}

/* The all-pairs gather for a fixed small D (and the grid gathers' lists of
 * candidates, grid_finish), in blocks of partners: first
 * the differences, squared distances, sqrt and 1/dist of a whole block
 * (independent lanes, so the compiler may use vector instructions; sqrt and
 * division are correctly rounded either way and nothing is contracted into
 * FMA, so each lane has the bits of the scalar pair()), then the appliers
 * partner by partner in ascending order. The differences are taken as
 * x_e - x_q; where q is the "to" side the reference has x_q - x_e, which is
 * exactly the negation (round to nearest is symmetric), so the squares are
 * equal and dir is negated. */
#define BLOCK 8

/* The appliers of a "simple" level (at most SIMPLE_MAX, each !collision,
 * !gravity or !electrostatic) on one block of partners: first every
 * applier's factor k for every lane (the expressions of
 * phys_pair_force_one, with a and b taken in the reference's orientation,
 * which fixes the order of the products ma*mb and qa*qb), then partner by
 * partner and applier by applier the additions into F, in the reference
 * order. A lane whose applier does not act adds nothing, as there. */
#define SIMPLE_MAX 4

static inline __attribute__((always_inline)) void
simple_block(const LevelRun *L, size_t q, size_t e0, size_t n, double *F,
             double d[][BLOCK], const double *ss, const double *dist,
             const double *inv, const size_t D, const uint32_t *es)
{
    /* partner j is es[j] when the block is a list (the grid's candidates),
     * e0 + j when it is a run */
#define PARTNER(j) (es ? (size_t)es[j] : e0 + (j))
    const PhysSystem *s = L->s;
    const uint32_t *pool = L->pool;
    const size_t p = pool[q];
    const double rp = s->radius[p], mp = s->mass[p], cp = s->charge[p];
    double K[SIMPLE_MAX][BLOCK];
    unsigned char act[SIMPLE_MAX][BLOCK];
    double ro[BLOCK], xo[BLOCK];
    unsigned char tob[BLOCK];
    for (size_t j = 0; j < n; j++) {
        ro[j] = s->radius[pool[PARTNER(j)]];
        tob[j] = q > PARTNER(j);
    }
    for (size_t f = 0; f < L->nf; f++) {
        const PhysApplier *ap = &s->ap[L->forces[f]];
        const double str = ap->strength, maxd = ap->maxd;
        double *k = K[f];
        unsigned char *a = act[f];
        if (ap->kind == AP_COLLISION) {
            for (size_t j = 0; j < n; j++) {
                double r = rp + ro[j];           /* ra + rb, either order */
                a[j] = (maxd == 0 || dist[j] < maxd) & (rp != 0) & (ro[j] != 0) &
                       (dist[j] < r);
                k[j] = r - dist[j];
            }
            /* shape(): pow only when power != 1, then * strength */
            if (ap->power != 1) {
                for (size_t j = 0; j < n; j++)
                    if (a[j])
                        k[j] = pow(k[j], ap->power);
            }
            for (size_t j = 0; j < n; j++)
                k[j] = k[j] * str;
            continue;
        }
        /* gravity (masses) or electrostatics (charges): k = strength * xa *
         * xb / (m*m), m = py_max(ra+rb, dist) */
        const double *val = ap->kind == AP_GRAVITY ? s->mass : s->charge;
        const double xp = ap->kind == AP_GRAVITY ? mp : cp;
        for (size_t j = 0; j < n; j++)
            xo[j] = val[pool[PARTNER(j)]];
        for (size_t j = 0; j < n; j++) {
            double r = rp + ro[j];
            double m = dist[j] > r ? dist[j] : r;
            double x = tob[j] ? xo[j] : xp, y = tob[j] ? xp : xo[j];
            a[j] = (maxd == 0 || dist[j] < maxd) & (x != 0) & (y != 0);
            k[j] = str * x * y / (m * m);
        }
    }
    for (size_t j = 0; j < n; j++) {
        size_t e = PARTNER(j);
        if (e == q || ss[j] > L->r2)
            continue;
        bool to_b = q > e;
        double dir[3];
        for (size_t k = 0; k < D; k++)
            dir[k] = (to_b ? -d[k][j] : d[k][j]) * inv[j];
        for (size_t f = 0; f < L->nf; f++) {
            if (!act[f][j])
                continue;
            /* collision and electrostatics push apart (a -= f, b += f),
             * gravity pulls together (a += f, b -= f) */
            bool plus = (s->ap[L->forces[f]].kind == AP_GRAVITY) != to_b;
            phys_add_side(F, dir, K[f][j], D, plus);
        }
    }
}
#undef PARTNER

/* The measures of a full block of partners at [y] (BLOCK pointers to
 * their positions) from [x]: the differences y - x, the squared distances
 * summed over k ascending, sqrt and 1/dist (independent lanes: vector
 * instructions, the scalar pair()'s bits). */
static inline __attribute__((always_inline)) void
measure_block(const double *const *y, const double *x, double d[][BLOCK], double *ss,
              double *dist, double *inv, const size_t D)
{
    for (size_t j = 0; j < BLOCK; j++)
        for (size_t k = 0; k < D; k++)
            d[k][j] = y[j][k] - x[k];
    for (size_t j = 0; j < BLOCK; j++) {
        double sum = 0;
        for (size_t k = 0; k < D; k++)
            sum += d[k][j] * d[k][j];
        ss[j] = sum;
    }
    for (size_t j = 0; j < BLOCK; j++) {
        dist[j] = sqrt(ss[j]);
        inv[j] = 1 / dist[j];
    }
}

static inline __attribute__((always_inline)) void
gather_all_fixed(const LevelRun *L, size_t q, PhysScratch *sc, const size_t D)
{
    PhysSystem *s = L->s;
    const size_t p = L->pool[q];
    double *F = s->force + p * D;
    const double *x = s->pos + p * D;
    const double *pos = s->pos;
    const uint32_t *pool = L->pool;
    const size_t lim = q < L->npart ? L->npool : L->npart;
    const double r2 = L->r2;
    double *dir = sc->dir;
    double d[3][BLOCK], ss[BLOCK], dist[BLOCK], inv[BLOCK];
    for (size_t e0 = 0; e0 < lim; e0 += BLOCK) {
        size_t n = lim - e0 < BLOCK ? lim - e0 : BLOCK;
        if (n == BLOCK) {
            const double *y[BLOCK];
            for (size_t j = 0; j < BLOCK; j++)
                y[j] = pos + (size_t)pool[e0 + j] * D;
            measure_block(y, x, d, ss, dist, inv, D);
        } else {
            for (size_t j = 0; j < n; j++) {
                const double *y = pos + (size_t)pool[e0 + j] * D;
                double sum = 0;
                for (size_t k = 0; k < D; k++) {
                    d[k][j] = y[k] - x[k];
                    sum += d[k][j] * d[k][j];
                }
                ss[j] = sum;
                dist[j] = sqrt(sum);
                inv[j] = 1 / dist[j];
            }
        }
        if (L->simple) {
            simple_block(L, q, e0, n, F, d, ss, dist, inv, D, NULL);
            continue;
        }
        for (size_t j = 0; j < n; j++) {
            size_t e = e0 + j;
            if (e == q || ss[j] > r2)
                continue;
            bool to_b = q > e;
            for (size_t k = 0; k < D; k++)
                dir[k] = (to_b ? -d[k][j] : d[k][j]) * inv[j];
            size_t a = to_b ? pool[e] : p, b = to_b ? p : pool[e];
            for (size_t f = 0; f < L->nf; f++) {
                const PhysApplier *ap = &s->ap[L->forces[f]];
                if (ap->maxd == 0 || dist[j] < ap->maxd)
                    phys_pair_force_side(s, ap, a, b, dist[j], dir, F, to_b, D);
            }
        }
    }
}

/* One copy per dimension; on x86-64 also one compiled for AVX2, chosen at
 * run time when the processor has it (no ifunc resolvers: those run before
 * sanitizer runtimes start). Elsewhere, the portable copies only. */
#define GATHER_COPY(name, dim, attr)                                          \
    attr static void name(const LevelRun *L, size_t q, PhysScratch *sc)      \
    {                                                                         \
        gather_all_fixed(L, q, sc, dim);                                      \
    }

GATHER_COPY(gather_all_1, 1, )
GATHER_COPY(gather_all_2, 2, )
GATHER_COPY(gather_all_3, 3, )

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HAVE_AVX2_COPIES 1
GATHER_COPY(gather_all_1_avx2, 1, __attribute__((target("avx2"))))
GATHER_COPY(gather_all_2_avx2, 2, __attribute__((target("avx2"))))
GATHER_COPY(gather_all_3_avx2, 3, __attribute__((target("avx2"))))
#endif

/* Does this processor run the AVX2 copies? */
static bool use_avx2(void)
{
#ifdef HAVE_AVX2_COPIES
    return cpu_has(CPU_AVX2);
#else
    return false;
#endif
}

static void gather_all_any(const LevelRun *L, size_t q, PhysScratch *sc)
{
#ifdef HAVE_AVX2_COPIES
    if (L->avx2) {
        switch (L->s->D) {
        case 1: gather_all_1_avx2(L, q, sc); return;
        case 2: gather_all_2_avx2(L, q, sc); return;
        case 3: gather_all_3_avx2(L, q, sc); return;
        default: break;
        }
    }
#endif
    switch (L->s->D) {
    case 1: gather_all_1(L, q, sc); break;
    case 2: gather_all_2(L, q, sc); break;
    case 3: gather_all_3(L, q, sc); break;
    default: gather_all(L, q, sc); break;
    }
}

static inline void sort_u32(uint32_t *v, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint32_t x = v[i];
        size_t j = i;
        while (j > 0 && v[j - 1] > x) {
            v[j] = v[j - 1];
            j--;
        }
        v[j] = x;
    }
}

#ifdef HAVE_AVX2_COPIES
/* sort_u32() for at most 16 distinct entries below INT32_MAX, without
 * branches on the data: each entry's rank is the count of entries below
 * it, and it is stored at its rank (two equal entries would take one
 * place and leave another unwritten: a grid gather's candidates are
 * distinct, as every entry is in one cell or in the odd list, the cells'
 * buckets are taken once each and the dense grid's runs do not
 * overlap). */
__attribute__((target("avx2"))) static inline void sort_rank16_avx2(uint32_t *v, size_t n)
{
    uint32_t in[16], rank[16];
    for (size_t i = 0; i < 16; i++)
        in[i] = i < n ? v[i] : (uint32_t)INT32_MAX;
    const __m256i a = _mm256_loadu_si256((const __m256i *)(const void *)in);
    __m256i ra = _mm256_setzero_si256();
    if (n <= 8) {
        for (size_t i = 0; i < n; i++)
            /* lanes above entry i count it: their rank goes up by one */
            ra = _mm256_sub_epi32(ra, _mm256_cmpgt_epi32(a, _mm256_set1_epi32((int32_t)in[i])));
        _mm256_storeu_si256((__m256i *)(void *)rank, ra);
    } else {
        const __m256i b = _mm256_loadu_si256((const __m256i *)(const void *)(in + 8));
        __m256i rb = _mm256_setzero_si256();
        for (size_t i = 0; i < n; i++) {
            const __m256i x = _mm256_set1_epi32((int32_t)in[i]);
            ra = _mm256_sub_epi32(ra, _mm256_cmpgt_epi32(a, x));
            rb = _mm256_sub_epi32(rb, _mm256_cmpgt_epi32(b, x));
        }
        _mm256_storeu_si256((__m256i *)(void *)rank, ra);
        _mm256_storeu_si256((__m256i *)(void *)(rank + 8), rb);
    }
    for (size_t i = 0; i < n; i++)
        v[rank[i]] = in[i];
}
#endif

/* The fewest candidates that take the rank sort and the blocks: below,
 * the insertion sort and take_pair() one by one cost less (discs2k's first
 * frames, with one or two candidates an entry, ran slower in blocks) */
#define GRID_BLOCK_MIN 4

/* The end of a grid gather for entry [q] at [x] with [nc] candidates in
 * sc->cand: the odd entries within reach join them, then the pairs are
 * taken in pool order into [F]. */
static inline __attribute__((always_inline)) void
grid_finish(const LevelRun *L, size_t q, const double *x, double *F,
            PhysScratch *sc, size_t nc, const size_t D, const bool avx2)
{
    const PhysSystem *s = L->s;
    const PhysGrid *gr = &s->grid;
    uint32_t *cand = sc->cand;
    for (size_t i = 0; i < gr->nodd; i++) {
        uint32_t e = gr->odd[i];
        if (partner(L, q, e) &&
            !(dist2(x, s->pos + (size_t)L->pool[e] * D, D) > L->r2))
            cand[nc++] = e;
    }
    if (nc == 0)
        return;
#ifdef HAVE_AVX2_COPIES
    if (avx2 && nc >= GRID_BLOCK_MIN && nc <= 16 && L->npool < INT32_MAX)
        sort_rank16_avx2(cand, nc);
    else
        sort_u32(cand, nc);
#else
    (void)avx2;
    sort_u32(cand, nc);
#endif
    if (L->simple && nc >= GRID_BLOCK_MIN) {
        /* as gather_all_fixed's blocks, over the sorted candidates: a
         * block's lanes past [nc] measure q from itself and are not used */
        double d[3][BLOCK], ss[BLOCK], dist[BLOCK], inv[BLOCK];
        for (size_t i0 = 0; i0 < nc; i0 += BLOCK) {
            const size_t n = nc - i0 < BLOCK ? nc - i0 : BLOCK;
            const double *y[BLOCK];
            for (size_t j = 0; j < BLOCK; j++)
                y[j] = j < n ? s->pos + (size_t)L->pool[cand[i0 + j]] * D : x;
            measure_block(y, x, d, ss, dist, inv, D);
            simple_block(L, q, 0, n, F, d, ss, dist, inv, D, cand + i0);
        }
        return;
    }
    for (size_t i = 0; i < nc; i++)
        take_pair(L, q, cand[i], F, sc->dir, D);
}

/* Gather over the grid neighbours (and the odd entries), in pool order;
 * one copy per D (1, 2, 3: the only ones the grid takes). */
static inline __attribute__((always_inline)) void
gather_grid_fixed(const LevelRun *L, size_t q, PhysScratch *sc, const size_t D,
                  const bool avx2)
{
    PhysSystem *s = L->s;
    const PhysGrid *gr = &s->grid;
    if (gr->bucket[q] == UINT32_MAX) {
        gather_all(L, q, sc);
        return;
    }
    const size_t p = L->pool[q];
    double *F = s->force + p * D;
    const double *x = s->pos + p * D;
    const int32_t *c = gr->cell + 3 * q;
    /* the distinct buckets of the 3^D cells around q's */
    uint32_t bk[27];
    size_t nbk = 0;
    int32_t o[3] = {0, 0, 0};
    for (size_t k = 0; k < D; k++)
        o[k] = -1;
    for (;;) {
        int32_t cc[3] = {c[0] + o[0], c[1] + o[1], c[2] + o[2]};
        uint32_t b = (uint32_t)(cell_hash(cc) & (gr->nb - 1));
        bool seen = false;
        for (size_t i = 0; i < nbk && !seen; i++)
            seen = bk[i] == b;
        if (!seen)
            bk[nbk++] = b;
        size_t k = 0;
        while (k < D && o[k] == 1)
            o[k++] = -1;
        if (k == D)
            break;
        o[k]++;
    }
    uint32_t *cand = sc->cand;
    size_t nc = 0;
    for (size_t i = 0; i < nbk; i++) {
        for (uint32_t j = gr->start[bk[i]]; j < gr->start[bk[i] + 1]; j++) {
            uint32_t e = gr->ent[j];
            if (partner(L, q, e) &&
                !(dist2(x, s->pos + (size_t)L->pool[e] * D, D) > L->r2))
                cand[nc++] = e;
        }
    }
    grid_finish(L, q, x, F, sc, nc, D, avx2);
}

#ifdef HAVE_AVX2_COPIES
/* Byte shuffles that move the 32-bit lanes set in a 4-bit mask to the
 * front, in lane order (the rest zero). */
static const uint8_t pack_lanes4[16][16] = {
    {128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128},
    {4, 5, 6, 7, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 4, 5, 6, 7, 128, 128, 128, 128, 128, 128, 128, 128},
    {8, 9, 10, 11, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 8, 9, 10, 11, 128, 128, 128, 128, 128, 128, 128, 128},
    {4, 5, 6, 7, 8, 9, 10, 11, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 128, 128, 128, 128},
    {12, 13, 14, 15, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 12, 13, 14, 15, 128, 128, 128, 128, 128, 128, 128, 128},
    {4, 5, 6, 7, 12, 13, 14, 15, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 4, 5, 6, 7, 12, 13, 14, 15, 128, 128, 128, 128},
    {8, 9, 10, 11, 12, 13, 14, 15, 128, 128, 128, 128, 128, 128, 128, 128},
    {0, 1, 2, 3, 8, 9, 10, 11, 12, 13, 14, 15, 128, 128, 128, 128},
    {4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 128, 128, 128, 128},
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
};

/* gather_dense_fixed()'s scan of the slots [j, end) of one run, four slots
 * at a time: the same squared distances (sum over k ascending of
 * (sx - x)^2; the scalar loop's leading 0 + d0^2 is d0^2, a square being
 * +0 or more, or NaN), the same test !(sum > r2) and partner rule, the
 * candidates appended in slot order as the scalar loop appends them. A
 * run's last group of four reads up to 3 slots past its end (the grid's
 * arrays are padded: grid_dense) and leaves them out. Writes up to 3
 * entries past the new count (the caller's array has room:
 * ensure_scratch). Returns the new count. */
__attribute__((target("avx2"))) static size_t
scan_run_avx2(const PhysGrid *gr, uint32_t j, uint32_t end, const double *x,
              const size_t D, double r2, uint32_t q, bool rowq, uint32_t npart,
              uint32_t *cand, size_t nc)
{
    const size_t m = gr->nslot;
    const double *sx = gr->sx;
    __m256d X[GRID_MAX_D];
    for (size_t k = 0; k < D; k++)
        X[k] = _mm256_set1_pd(x[k]);
    const __m256d R2 = _mm256_set1_pd(r2);
    /* unsigned comparisons as signed ones after flipping the top bit */
    const __m128i top = _mm_set1_epi32(INT32_MIN);
    const __m128i Q = _mm_set1_epi32((int32_t)q);
    const __m128i NP = _mm_xor_si128(_mm_set1_epi32((int32_t)npart), top);
    const __m128i ROW = _mm_set1_epi32(rowq ? -1 : 0);
    for (; j < end; j += 4) {
        __m256d d = _mm256_sub_pd(_mm256_loadu_pd(sx + j), X[0]);
        __m256d sum = _mm256_mul_pd(d, d);
        for (size_t k = 1; k < D; k++) {
            d = _mm256_sub_pd(_mm256_loadu_pd(sx + k * m + j), X[k]);
            sum = _mm256_add_pd(sum, _mm256_mul_pd(d, d));
        }
        const int near = ~_mm256_movemask_pd(_mm256_cmp_pd(sum, R2, _CMP_GT_OQ)) & 0xf;
        const __m128i e = _mm_loadu_si128((const __m128i *)(const void *)(gr->slotq + j));
        const __m128i row = _mm_or_si128(ROW, _mm_cmpgt_epi32(NP, _mm_xor_si128(e, top)));
        const __m128i ok = _mm_andnot_si128(_mm_cmpeq_epi32(e, Q), row);
        /* the last group of a run: only its slots before [end] count */
        const int lanes = end - j >= 4 ? 0xf : (1 << (end - j)) - 1;
        const int mask = near & lanes & _mm_movemask_ps(_mm_castsi128_ps(ok));
        const __m128i packed = _mm_shuffle_epi8(
            e, _mm_loadu_si128((const __m128i *)(const void *)pack_lanes4[mask]));
        _mm_storeu_si128((__m128i *)(void *)(cand + nc), packed);
        nc += (size_t)__builtin_popcount((unsigned)mask);
    }
    return nc;
}
#endif

/* Gather over the dense grid (grid_dense) for the entry in slot [i]: the
 * 3^D cells around its own are 3^(D-1) runs of 3 consecutive cells, each a
 * contiguous run of slots whose coordinates are read in order; candidates
 * within the reach, then the odd entries, sorted into pool order. */
static inline __attribute__((always_inline)) void
gather_dense_fixed(const LevelRun *L, size_t i, PhysScratch *sc, const size_t D,
                   const bool avx2)
{
    PhysSystem *s = L->s;
    const PhysGrid *gr = &s->grid;
    const size_t m = gr->nslot;
    const size_t q = gr->slotq[i];
    const size_t p = L->pool[q];
    double *F = s->force + p * D;
    double x[GRID_MAX_D];
    for (size_t k = 0; k < D; k++)
        x[k] = gr->sx[k * m + i];
    const size_t cq = gr->cellof[q];
    const size_t e0 = gr->ext[0], e01 = gr->ext[0] * gr->ext[1];
    const double r2 = L->r2;
    uint32_t *cand = sc->cand;
    size_t nc = 0;
    const int lo1 = D > 1 ? -1 : 0, lo2 = D > 2 ? -1 : 0;
    const bool rowq = q < L->npart;   /* partner(): as bits, no branches */
    for (int dz = lo2; dz <= -lo2; dz++) {
        for (int dy = lo1; dy <= -lo1; dy++) {
            size_t mid = cq + (size_t)((ptrdiff_t)dz * (ptrdiff_t)e01 +
                                       (ptrdiff_t)dy * (ptrdiff_t)e0);
            const uint32_t end = gr->cstart[mid + 2];
#ifdef HAVE_AVX2_COPIES
            if (avx2) {
                nc = scan_run_avx2(gr, gr->cstart[mid - 1], end, x, D, r2, (uint32_t)q, rowq,
                                   (uint32_t)L->npart, cand, nc);
                continue;
            }
#else
            (void)avx2;
#endif
            /* branch-free: about half the slots scanned are within
             * reach, so a branch on it would mispredict that often; the
             * slot's entry is written always and kept when it counts */
            for (uint32_t j = gr->cstart[mid - 1]; j < end; j++) {
                double sum = 0;
                for (size_t k = 0; k < D; k++) {
                    double d = gr->sx[k * m + j] - x[k];
                    sum += d * d;
                }
                uint32_t e = gr->slotq[j];
                cand[nc] = e;
                nc += !(sum > r2) & (e != q) & (rowq | (e < L->npart));
            }
        }
    }
    grid_finish(L, q, x, F, sc, nc, D, avx2);
}

#define GRID_COPY(name, dim, attr, avx)                                       \
    attr static void name(const LevelRun *L, size_t q, PhysScratch *sc)      \
    {                                                                         \
        gather_grid_fixed(L, q, sc, dim, avx);                                \
    }                                                                         \
    attr static void name##_dense(const LevelRun *L, size_t i, PhysScratch *sc) \
    {                                                                         \
        gather_dense_fixed(L, i, sc, dim, avx);                               \
    }

GRID_COPY(gather_grid_1, 1, , false)
GRID_COPY(gather_grid_2, 2, , false)
GRID_COPY(gather_grid_3, 3, , false)
#ifdef HAVE_AVX2_COPIES
GRID_COPY(gather_grid_1_avx2, 1, __attribute__((target("avx2"))), true)
GRID_COPY(gather_grid_2_avx2, 2, __attribute__((target("avx2"))), true)
GRID_COPY(gather_grid_3_avx2, 3, __attribute__((target("avx2"))), true)
#endif

/* A gather of one entry: over the hashed grid (by pool entry q) or over
 * the dense grid (by slot i). */
typedef void (*GatherFn)(const LevelRun *L, size_t qi, PhysScratch *sc);

/* The copy of the grid gather for this level: [dense] form, D = 1..3 (the
 * only ones the grid takes), AVX2 when the processor has it. */
static GatherFn grid_gather_fn(const LevelRun *L, bool dense)
{
    static const GatherFn plain[2][3] = {
        {gather_grid_1, gather_grid_2, gather_grid_3},
        {gather_grid_1_dense, gather_grid_2_dense, gather_grid_3_dense},
    };
    size_t d = L->s->D < 3 ? L->s->D - 1 : 2;
#ifdef HAVE_AVX2_COPIES
    static const GatherFn avx2[2][3] = {
        {gather_grid_1_avx2, gather_grid_2_avx2, gather_grid_3_avx2},
        {gather_grid_1_avx2_dense, gather_grid_2_avx2_dense, gather_grid_3_avx2_dense},
    };
    if (L->avx2)
        return avx2[dense][d];
#endif
    return plain[dense][d];
}

/* Task [t]: the targets t*TARGETS_PER_TASK .. (anchors never step, so
 * their force is not needed). */
static void level_task(void *ctx, size_t t, unsigned thread)
{
    const LevelRun *L = ctx;
    PhysSystem *s = L->s;
    PhysScratch *sc = &s->scratch[thread];
    size_t end = (t + 1) * TARGETS_PER_TASK;
    if (L->grid && s->grid.dense) {
        /* the dense grid's slots in cell order (neighbours in cache), then
         * the odd entries, which gather over every partner */
        const PhysGrid *gr = &s->grid;
        const size_t m = gr->nslot;
        const GatherFn dense = grid_gather_fn(L, true);
        for (size_t i = t * TARGETS_PER_TASK; i < end && i < m + gr->nodd; i++) {
            size_t q = i < m ? gr->slotq[i] : gr->odd[i - m];
            if (s->anchor[L->pool[q]])
                continue;
            if (phys_interrupted(s))
                return;
            if (i < m)
                dense(L, i, sc);
            else
                gather_all(L, q, sc);
        }
        return;
    }
    const GatherFn hashed = L->grid ? grid_gather_fn(L, false) : NULL;
    if (end > L->npool)
        end = L->npool;
    for (size_t q = t * TARGETS_PER_TASK; q < end; q++) {
        if (s->anchor[L->pool[q]])
            continue;
        if (phys_interrupted(s))
            return;
        if (hashed)
            hashed(L, q, sc);
        else
            gather_all_any(L, q, sc);
    }
}

/* Per-thread scratch for a level of [npool] entries. */
static void ensure_scratch(PhysSystem *s, unsigned nth, size_t npool)
{
    if (nth > s->capscratch) {
        size_t old = s->capscratch;
        GROW(s->scratch, s->capscratch, nth);
        memset(s->scratch + old, 0, (s->capscratch - old) * sizeof *s->scratch);
    }
    for (unsigned i = 0; i < nth; i++) {
        PhysScratch *sc = &s->scratch[i];
        GROW(sc->dir, sc->capdir, s->D);
        /* + 4: the AVX2 scan stores four candidates at a time (scan_run_avx2) */
        GROW(sc->cand, sc->capcand, npool + 4);
    }
}

/* The tiles and rows routes run a level whole. A level of more pairs
 * than a slice (s->slice_pairs) runs as consecutive slices of its rows,
 * asking for the interrupt between them (phys_interrupted): rows r0..r1
 * against pool entries r0..n is a level of its own (the same shape, its
 * pool r0 entries on), and its pairs are those the reference loop takes
 * next, in its order, after the slices before it, so every force adds the
 * same contributions in the same order. */
static void run_slices(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv,
                       void (*route)(PhysSystem *, const PhysGroup *, const PhysLevel *))
{
    const size_t rows = g->npart, n = lv->npool;
    /* the rows route, on one thread and with any applier, takes about
     * four times as long a pair */
    const double most = route == phys_run_rows ? s->slice_pairs / 4 : s->slice_pairs;
    /* a split first pass runs its tiles levels whole (they are small:
     * tiles.c, split_cut); a rows level is the pass's thread's own work */
    if (phys_level_pairs(rows, n) <= most || (route == phys_run_tiles && phys_tiles_split_active(s))) {
        route(s, g, lv);
        return;
    }
    for (size_t r0 = 0, r1; r0 < rows; r0 = r1) {
        if (phys_interrupted(s))
            return;
        double pairs = (double)(n - 1 - r0);
        for (r1 = r0 + 1; r1 < rows && pairs + (double)(n - 1 - r1) <= most; r1++)
            pairs += (double)(n - 1 - r1);
        PhysGroup gs = *g;
        gs.pool_off += r0;
        gs.npart = r1 - r0;
        PhysLevel ls = *lv;
        ls.npool = n - r0;
        route(s, &gs, &ls);
    }
}

void phys_run_level(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv)
{
    if (phys_interrupted(s))   /* a level of a step cut short is not begun */
        return;
    switch (lv->route) {
    case PHYS_ROUTE_SKIP:
        return;
    case PHYS_ROUTE_SCATTER:
        phys_apply_pair_level(s, g, lv);
        return;
    case PHYS_ROUTE_ROWS:
        run_slices(s, g, lv, phys_run_rows);
        return;
    case PHYS_ROUTE_TILES:
        run_slices(s, g, lv, phys_run_tiles);
        return;
    default:
        break;
    }
    const PhysGroup *fg = &s->groups[lv->group];
    LevelRun L = {
        .s = s, .pool = s->pool + g->pool_off, .npart = g->npart,
        .npool = lv->npool, .forces = s->gidx + fg->pair_off, .nf = fg->pair_n,
        .r2 = INFINITY, .grid = lv->route == PHYS_ROUTE_GRID,
        /* the portable copies at the portable level (phys_set_simd,
         * fl_debug_options.simd), so the tests run both against the reference */
        .avx2 = s->simd >= PHYS_SIMD_AVX2 && use_avx2(),
    };
    L.simple = L.nf <= SIMPLE_MAX;
    for (size_t f = 0; f < L.nf && L.simple; f++) {
        PhysApplierKind k = s->ap[L.forces[f]].kind;
        L.simple = k == AP_COLLISION || k == AP_GRAVITY || k == AP_ELECTROSTATIC;
    }
    /* a bound at least R*R: (R*R rounded) * (1 + 2^-50) rounded; sqrt(s) <
     * R needs s < R*R exactly, so nothing above the bound can act */
    double R = lv->reach;
    if (R > 0x1p-400 && R < 0x1p400)
        L.r2 = R * R * (1 + 0x1p-50);
    if (L.grid) {
        grid_build(s, L.pool, L.npool, R * (1 + 0x1p-20));
    }
    unsigned nth = workers_count(s->workers);
    ensure_scratch(s, nth, L.npool);
    size_t ntasks = (L.npool + TARGETS_PER_TASK - 1) / TARGETS_PER_TASK;
    workers_run(nth > 1 ? s->workers : NULL, ntasks, level_task, &L);
}

void phys_pairs_free(PhysSystem *s)
{
    PhysGrid *gr = &s->grid;
    free(gr->bucket); free(gr->cell); free(gr->start); free(gr->ent);
    free(gr->odd);
    free(gr->cellof); free(gr->cstart); free(gr->slotq); free(gr->sx);
    for (size_t i = 0; i < s->capscratch; i++) {
        free(s->scratch[i].dir);
        free(s->scratch[i].cand);
    }
    free(s->scratch);
    free(s->rows);
    free(s->tiles);
    free(s->ttasks);
    free(s->tprog);
    free(s->trec);
    free(s->tsplit);
    free(s->tune);
    free(s->rnd);
}
