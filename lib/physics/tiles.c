/* tiles.c: the reference pair loop in tiles of W rows by W partners.
 *
 * The route for levels of unlimited reach (!gravity or !electrostatic
 * without max_distance) whose appliers are all !collision, !gravity or
 * !electrostatic, D = 1..3, on one thread (two threads: "Several threads"
 * and "Two threads for a middle-sized level" below). It performs the reference loop of
 * phys_apply_pair_level (PHYSICS-ENGINE.md §4): rows i < len(G.particles),
 * partners j = i+1 .. npool-1, every pair measured once, with exactly the
 * additions of the reference into every force and, for each force, in the
 * reference order. What decides a force's bits is only the order of the
 * additions into it:
 *   - particle q first receives its "to" contributions (as b of the pairs
 *     (i, q), i ascending: the earlier rows), then its "from" contributions
 *     (as a of (q, j), j ascending: its own row); within a pair, appliers
 *     in their order.
 * The loop is cut into row blocks of W rows (i0 .. i0+W-1; W = 8 with
 * AVX-512, 4 with AVX2 (with or without AVX-512VL), 2 in the portable
 * copy) and, within a block, column tiles of W partners (j0 = i0, i0+W,
 * ...: the first one is the block's own "diagonal" tile, where only j > i
 * counts). A tile measures its W x W
 * pairs row by row, each row as one vector of W lanes
 * (lanes = partners j), each lane with the operations and operand order of
 * pair() and pair_force() in forces.c (sqrt and division are correctly
 * rounded in vector form too, and the build contracts nothing into FMA:
 * -ffp-contract=off), then
 *   - the partners' forces (the "to" side, one lane each) receive the rows'
 *     contributions as vector additions, row after row and applier after
 *     applier: for each j, rows ascending, as in the reference; the row
 *     blocks run in order, so the earlier rows' contributions came first;
 *   - the rows' forces (the "from" side) receive the tile's contributions
 *     lane after lane (j ascending) and applier after applier, one scalar
 *     sum per row (the 8 rows' sums are independent, so they interleave);
 *     tiles run in ascending j0, so each row sums its partners in ascending
 *     j. A row's sum starts from its force once every "to" contribution is
 *     in: after its block's diagonal tile has added those of the earlier
 *     rows of the block (earlier blocks added theirs before).
 * A lane where an applier does not act (or that is no partner: j <= i in
 * the diagonal tile, j >= npool past the end) takes part as +0 in a
 * subtraction and -0 in an addition, which leave every value as it is (-0
 * and NaN included), as the reference's skipped addition does.
 *
 * Several threads: the partners are cut into chunks of TILE_CHUNK columns
 * (a row block's first work starts at its diagonal tile instead), the row
 * blocks into groups of TILE_GROUP_ROWS rows, and a task is one group's
 * row blocks, in order, against one chunk (each block from its diagonal
 * on). A task may start once the same group's previous task is done (the
 * row sums run through the chunks in ascending order, handed on through a
 * buffer per row block) and the previous group's task over the same chunk
 * is done (each partner receives the rows' contributions in row order).
 * So every force receives the additions of one thread, in its order,
 * whichever thread runs a task. (Tasks of one row block, 8 rows with
 * AVX-512 and 2 with the portable copy, handed the chunks' forces from
 * thread to thread four to sixteen times as often, and were slower with
 * every copy of the kernel than groups of 32 rows: bench/PROFILE.md,
 * "lib/physics/tiles.c: how the threaded route cuts a level into tasks".)
 * The tasks are listed by wavefront (group + chunk, then group), so
 * every task's two predecessors come before it in the list, and the
 * threads take them in list order: a thread waits only for tasks already
 * taken, never for one after its own, so the run cannot deadlock and ends
 * on one thread too. Only levels with enough pairs to pay for the
 * hand-offs take this route (TILES_PIPE_PAIRS; middle-sized levels have a
 * route of their own, "Two threads for a middle-sized level"). (The
 * earlier split, one cut into two column ranges handed on row block by
 * row block, left the second thread idle for much of the level: same
 * subsection of bench/PROFILE.md.)
 *
 * The level's positions, radii, masses/charges and forces are copied into
 * pool order (struct of arrays, padded to whole tiles) before and the
 * forces copied back after. The kernel is compiled for AVX-512, for AVX2
 * with and without AVX-512VL and for the portable baseline
 * (tiles_kernel.h) and chosen at run time by the system's SIMD level
 * (phys_simd_best(), phys_set_simd) or, by default on a processor with
 * AVX-512, by timing the 4 x 4 tiles against it (tune_route below).
 */
#include <math.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define HAVE_X86_TILES 1
#endif

#include "cpu.h"
#include "physics_internal.h"
#include "workers.h"

#define TILE_W 8
#define TILE_MAX_D 3
#define TILE_MAX_F 4

typedef double v8d __attribute__((vector_size(8 * sizeof(double))));
typedef int64_t v8i __attribute__((vector_size(8 * sizeof(int64_t))));
typedef double v4d __attribute__((vector_size(4 * sizeof(double))));
typedef int64_t v4i __attribute__((vector_size(4 * sizeof(int64_t))));
typedef double v2d __attribute__((vector_size(2 * sizeof(double))));
typedef int64_t v2i __attribute__((vector_size(2 * sizeof(int64_t))));

enum { TILE_COLLISION, TILE_PUSH, TILE_PULL };

typedef struct TileApplier {
    int kind;            /* TILE_PUSH: electrostatic, TILE_PULL: gravity */
    double strength, maxd, power;
} TileApplier;

/* One level in pool order; every array is padded to [stride] entries, a
 * whole number of the widest tiles (TILE_W). */
typedef struct TileLevel {
    size_t npart, npool, stride;
    size_t nf;
    TileApplier ap[TILE_MAX_F];
    const double *x;                 /* x[k*stride + q] */
    const double *rad;
    const double *val[TILE_MAX_F];   /* mass, charge or radius per applier */
    double *F;                       /* F[k*stride + q] */
    bool fast;                       /* no applier has a max_distance: the
                                        kernel may take its fast tiles */
} TileLevel;

/* The common levels get kernel copies with everything about their
 * appliers but the strengths known at compile time (the same operations,
 * without the run-time branches and with registers to spare): one or two
 * appliers of these kinds, in this order, each of power 1 and without
 * max_distance. In the compile-time description (the `spec` of
 * tiles_kernel.h; 0 = read from T->ap at run time), applier f's kind is in
 * bits 2f and 2f+1, and bit 8 marks it as given. */
#define TILE_NSPECS 6
#define TILE_SPEC_NF(si) ((si) < 2 ? 1u : 2u)
#define TILE_SPEC_BITS(si)                                                     \
    (0x100u | ((si) == 0 ? TILE_PUSH                                          \
             : (si) == 1 ? TILE_PULL                                          \
             : (si) == 2 ? TILE_PUSH | TILE_COLLISION << 2                    \
             : (si) == 3 ? TILE_COLLISION | TILE_PUSH << 2                    \
             : (si) == 4 ? TILE_PULL | TILE_COLLISION << 2                    \
                         : TILE_COLLISION | TILE_PULL << 2))
/* Applier f's kind: from the description, or from the applier [ap]. */
#define TILE_KIND(spec, ap, f) \
    ((spec) ? (int)(((spec) >> (2 * (f))) & 3) : (ap)->kind)

/* The specialised copy that fits level [T], or -1. */
static int tile_spec_of(const TileLevel *T)
{
    if (T->nf > 2)
        return -1;
    unsigned bits = 0x100u;
    for (size_t f = 0; f < T->nf; f++) {
        const TileApplier *ap = &T->ap[f];
        if (ap->maxd != 0 || (ap->kind == TILE_COLLISION && ap->power != 1))
            return -1;
        bits |= (unsigned)ap->kind << (2 * f);
    }
    for (int si = 0; si < TILE_NSPECS; si++)
        if (TILE_SPEC_NF(si) == T->nf && TILE_SPEC_BITS(si) == bits)
            return si;
    return -1;
}

/* Columns per chunk of the threaded route (a multiple of every W). */
#define TILE_CHUNK 128

/* Rows per task of the threaded route (a multiple of every W): a task
 * runs TILE_GROUP_ROWS / W row blocks, in order, against one chunk. */
#define TILE_GROUP_ROWS 32
/* A group is whole row blocks of every width and never straddles two
 * chunks, so all its blocks' diagonals lie in its first chunk, the chunk
 * of its first task (list_tasks, TK(level_run)) */
_Static_assert(TILE_CHUNK % TILE_GROUP_ROWS == 0 && TILE_GROUP_ROWS % TILE_W == 0,
               "tile groups: whole blocks, whole groups a chunk");

/* One task of a threaded level (see "Several threads" above): the row
 * blocks of group [grp] (blocks grp*TILE_GROUP_ROWS/W ..) against chunk
 * [k]. */
typedef struct TileTask {
    size_t grp;
    size_t seq;       /* its place among the group's tasks */
    size_t above;     /* tasks of group grp-1 done before it may start */
    size_t k;         /* the chunk */
} TileTask;

/* How many of a group's tasks are done (in order), on a cache line of
 * its own. */
typedef struct TileProgress {
    _Alignas(64) atomic_size_t done;
} TileProgress;

/* The split route's parts (tiles_kernel.h TK(level_run)). */
enum { TILE_SPLIT_FAR = 1, TILE_SPLIT_NEAR, TILE_SPLIT_REPLAY };

/* What one call runs: the whole level (wave false: one thread), or tasks
 * of the list, taken in order from *next, until none is left. */
typedef struct TilePart {
    bool wave;
    const TileTask *tasks;
    size_t ntasks;
    atomic_size_t *next;
    TileProgress *prog;          /* per group of row blocks */
    double *buf;                 /* per row block: D x W partial sums */
    /* the split route ("Two threads for a middle-sized level"): which of
     * its parts (TILE_SPLIT_*, 0 when not split), the cut and the record
     * of the far part */
    int split;
    size_t cut;
    double *rec;
} TilePart;

/* One pause of a polling wait ([spins] counts them): a yield every 64th,
 * else a spin-loop hint. */
static inline void tile_pause(unsigned *spins)
{
    if (++*spins % 64 == 0)
        sched_yield();
#if defined(__x86_64__) || defined(__i386__)
    else
        __builtin_ia32_pause();
#endif
}

/* Wait until [done] reaches [until] (a task taken earlier, by another
 * thread, finishing). */
static void tile_wait(atomic_size_t *done, size_t until)
{
    unsigned spins = 0;
    while (atomic_load_explicit(done, memory_order_acquire) < until)
        tile_pause(&spins);
}

/* The portable copy: 2 x 2 tiles (SSE2 on x86-64, plain code elsewhere). */
static inline void sqrt_portable(v2d *x)
{
#ifdef HAVE_X86_TILES
    *x = (v2d)_mm_sqrt_pd((__m128d)*x);
#else
    for (int i = 0; i < 2; i++)
        (*x)[i] = sqrt((*x)[i]);
#endif
}

/* Per lane a > b ? a : b. */
static inline v2d max_portable(v2d a, v2d b)
{
#ifdef HAVE_X86_TILES
    return (v2d)_mm_max_pd((__m128d)a, (__m128d)b);
#else
    v2d m;
    for (int i = 0; i < 2; i++)
        m[i] = a[i] > b[i] ? a[i] : b[i];
    return m;
#endif
}

#define TK(name) name##_portable
#define TK_SPECIALISE 1
#define TK_ANY(m) (((m)[0] | (m)[1]) != 0)
#define TK_MAX(a, b) max_portable(a, b)
#define TK_ALL(m) (((m)[0] & (m)[1]) != 0)
#define TK_TARGET
#define TK_W 2
#define TK_VD v2d
#define TK_VI v2i
#define TK_SQRT(p) sqrt_portable(p)
#include "tiles_kernel.h"

#ifdef HAVE_X86_TILES
/* AVX2: 4 x 4 tiles (tiles_kernel_4.h). */
#define TK(name) name##_avx2
#define TK_TARGET __attribute__((target("avx2")))
#include "tiles_kernel_4.h"

/* AVX2's 4 x 4 tiles with AVX-512VL: the same operations, encoded so as
 * to use 32 vector registers instead of 16. The 3-D kernel keeps a row
 * block's sums and its lanes' values in registers where the AVX2 copy
 * spills them to the stack, and 4 lanes a division or square root cost
 * less than half of 8 on some processors, so this copy can beat both the
 * plain AVX2 one and AVX-512 (bench/PROFILE.md,
 * "lib/physics/tiles.c: 4 x 4 tiles in AVX-512VL's registers"). */
#define TK(name) name##_avx2vl
#define TK_TARGET __attribute__((target("avx2,avx512f,avx512vl")))
#include "tiles_kernel_4.h"

/* AVX-512: 8 x 8 tiles. */
__attribute__((target("avx512f"))) static inline void sqrt_avx512(v8d *x)
{
    *x = (v8d)_mm512_sqrt_pd((__m512d)*x);
}

#define TK(name) name##_avx512
#define TK_SPECIALISE 1
#define TK_ANY(m) (_mm512_test_epi64_mask((__m512i)(m), (__m512i)(m)) != 0)
#define TK_MAX(a, b) ((v8d)_mm512_max_pd((__m512d)(a), (__m512d)(b)))
#define TK_ALL(m) (_mm512_test_epi64_mask((__m512i)(m), (__m512i)(m)) == 0xff)
#define TK_TARGET __attribute__((target("avx512f")))
#define TK_W 8
#define TK_VD v8d
#define TK_VI v8i
#define TK_SQRT(p) sqrt_avx512(p)
#include "tiles_kernel.h"
#endif

/* Whether this processor runs the kernels of PHYS_SIMD_* level [level]. */
static bool simd_runs(int level)
{
#ifdef HAVE_X86_TILES
    switch (level) {
    case PHYS_SIMD_AVX2:
        return cpu_has(CPU_AVX2);
    case PHYS_SIMD_AVX2_VL:
        return cpu_has(CPU_AVX2) && cpu_has(CPU_AVX512F) && cpu_has(CPU_AVX512VL);
    case PHYS_SIMD_AVX512:
        return cpu_has(CPU_AVX512F);
    default:
        return level == PHYS_SIMD_PORTABLE;
    }
#else
    return level == PHYS_SIMD_PORTABLE;
#endif
}

int phys_simd_best(void)
{
    return phys_simd_cap(PHYS_SIMD_AVX512);
}

int phys_simd_cap(int level)
{
    if (level > PHYS_SIMD_AVX512)
        level = PHYS_SIMD_AVX512;
    /* a level the processor lacks (AVX-512 without VL, on the Xeon Phi,
     * lacks only the one below it) gives the next one down it has */
    while (level > PHYS_SIMD_PORTABLE && !simd_runs(level))
        level--;
    return level < PHYS_SIMD_PORTABLE ? PHYS_SIMD_PORTABLE : level;
}

static size_t tiles_stride(size_t npool)
{
    return (npool + TILE_W - 1) / TILE_W * TILE_W;
}

bool phys_tiles_suits(const PhysSystem *s, const PhysLevel *lv)
{
    if (s->D < 1 || s->D > TILE_MAX_D)
        return false;
    const PhysGroup *fg = &s->groups[lv->group];
    if (fg->pair_n > TILE_MAX_F)
        return false;
    for (size_t f = 0; f < fg->pair_n; f++) {
        PhysApplierKind k = s->ap[s->gidx[fg->pair_off + f]].kind;
        if (k != AP_COLLISION && k != AP_GRAVITY && k != AP_ELECTROSTATIC)
            return false;
    }
    return true;
}

void phys_tiles_reserve(PhysSystem *s, size_t npool)
{
    /* x (D rows), radius, up to TILE_MAX_F value rows, F (D rows), the
     * partial sums handed between threads (D per row block lane) */
    size_t need = (3 * s->D + 1 + TILE_MAX_F) * tiles_stride(npool);
    if (need <= s->captiles)
        return;
    size_t cap = s->captiles ? s->captiles : 64;
    while (cap < need)
        cap *= 2;
    free(s->tiles);
    s->tiles = aligned_alloc(64, cap * sizeof(double));
    if (!s->tiles)
        phys_oom();
    s->captiles = cap;
}

/* Levels with fewer pairs do not take the threaded route: the hand-offs
 * of its tasks (a wake-up and one per task) cost more there. They run on
 * one thread, beside the step's draws on the second (step.c), or on the
 * split route below. The threshold lies between the sizes where one
 * thread won and those where the threaded route won, timed before the
 * split route existed (bench/PROFILE.md, "lib/physics/tiles.c: the fewest
 * pairs of a threaded level"). */
#define TILES_PIPE_PAIRS 32768.0

/* One level in flight. */
typedef struct TileRun {
    const TileLevel *T;
    int simd;
    int spec;           /* tile_spec_of(T) */
    size_t D;
    const TileTask *tasks;
    size_t ntasks;
    TileProgress *prog;
    double *buf;
    atomic_size_t next;
    size_t cut;         /* the split route's cut */
    double *rec;        /* and its record */
} TileRun;

/* Run the level ([wave] false, [split] 0), take tasks of it ([wave]) or
 * run one part of it on the split route ([split] TILE_SPLIT_*), with the
 * kernel of run->simd. */
static void tiles_part(TileRun *run, bool wave, int split)
{
    TilePart P = {wave, run->tasks, run->ntasks, &run->next, run->prog, run->buf,
                  split, run->cut, run->rec};
#ifdef HAVE_X86_TILES
    if (run->simd == PHYS_SIMD_AVX512)
        level_avx512(run->T, &P, run->D, run->spec);
    else if (run->simd == PHYS_SIMD_AVX2_VL)
        level_avx2vl(run->T, &P, run->D, run->spec);
    else if (run->simd == PHYS_SIMD_AVX2)
        level_avx2(run->T, &P, run->D, run->spec);
    else
#endif
        level_portable(run->T, &P, run->D, run->spec);
}

/* Every worker task takes tasks of the list until none is left (on one
 * thread, the first takes them all). */
static void tiles_task(void *ctx, size_t t, unsigned thread)
{
    (void)t;
    (void)thread;
    tiles_part(ctx, true, 0);
}

/* List the tasks of a level of [npart] rows and [n] partners in groups of
 * TILE_GROUP_ROWS rows (see "Several threads" above), into s->ttasks,
 * reset the groups' progress counters, and return how many tasks there
 * are. A group's first task is over the chunk of its diagonal. */
static size_t list_tasks(PhysSystem *s, size_t npart, size_t n)
{
    const size_t C = TILE_CHUNK, G = TILE_GROUP_ROWS;
    const size_t K = (n + C - 1) / C, ng = (npart + G - 1) / G;
    size_t count = 0;
    for (size_t g = 0; g < ng; g++)
        count += K - g * G / C;
    if (count > s->capttasks) {
        free(s->ttasks);
        s->ttasks = malloc(count * sizeof *s->ttasks);
        if (!s->ttasks)
            phys_oom();
        s->capttasks = count;
    }
    if (ng > s->captprog) {
        free(s->tprog);
        s->tprog = aligned_alloc(_Alignof(TileProgress), ng * sizeof *s->tprog);
        if (!s->tprog)
            phys_oom();
        s->captprog = ng;
    }
    for (size_t g = 0; g < ng; g++)
        atomic_init(&s->tprog[g].done, 0);
    size_t m = 0;
    for (size_t w = 0; w + 1 < ng + K; w++) {
        for (size_t g = w >= K ? w - K + 1 : 0; g < ng && g <= w; g++) {
            const size_t k = w - g, kg = g * G / C;
            if (k < kg)
                continue;
            TileTask *t = &s->ttasks[m++];
            t->grp = g;
            t->seq = k - kg;
            t->above = g ? k - (g - 1) * G / C + 1 : 0;
            t->k = k;
        }
    }
    return m;
}

/* Up to this many pairs, a level of a system with !random may take the
 * split route rather than the threaded one (see "Two threads for a
 * middle-sized level" below), its draws on the helper: with !random the
 * split route won at the middle sizes timed, and this limit lies between
 * the largest level where it won and the smallest where the threaded
 * route did. Without !random the two were even at middle sizes and the
 * threaded route faster above them, so the split route stops at
 * TILES_PIPE_PAIRS there (bench/PROFILE.md, "lib/physics/tiles.c: when a
 * level is split between two threads"). */
#define SPLIT_RANDOM_PAIRS 98304.0

/* Whether [s] has a !random applier (whose draws the split route's helper
 * makes). */
static bool has_random(const PhysSystem *s)
{
    for (size_t a = 0; a < s->nap; a++)
        if (s->ap[a].kind == AP_RANDOM)
            return true;
    return false;
}

bool phys_tiles_threaded(const PhysSystem *s, const PhysGroup *g, const PhysLevel *lv)
{
    const double pairs = phys_level_pairs(g->npart, lv->npool);
    return workers_count(s->workers) >= 2 && pairs >= TILES_PIPE_PAIRS &&
           !(pairs < SPLIT_RANDOM_PAIRS && has_random(s));
}

/* {===== Two threads for a middle-sized level
 *
 * A level below TILES_PIPE_PAIRS runs on one thread, while the first pass
 * (step.c) gives the second one the step's !random draws. The split route
 * lets that second thread take part of the level too, with the same
 * additions in the same order as the level on one thread. It cuts the
 * pool at a multiple m of every width (m <= the group's particles), so
 * rows and partners fall into "near" (below m) and "far" (from m on):
 *   - a near particle first receives its contributions from near pairs
 *     (rows and partners below m), then those of its own row against the
 *     far partners (j >= m, after every near j);
 *   - a far particle first receives the near rows' contributions (i < m,
 *     before every far i), then those of far pairs.
 * So the level is three parts:
 *   NEAR    the near rows against the near partners, their row sums kept
 *           in the row blocks' buffers (as a chunk of the threaded route
 *           hands them on);
 *   FAR     the near rows against the far partners, the far partners'
 *           forces taking the rows' contributions as they would, and each
 *           tile's contributions to the rows' own forces recorded (per
 *           tile: which appliers act, then the contributions, lanes =
 *           rows), then the far rows, as on one thread;
 *   REPLAY  once both are done, each near row block's sums continue from
 *           the buffer with the recorded contributions, partner after
 *           partner and applier after applier, as TK(tile) adds them (an
 *           applier that acts nowhere in a tile is left out, as there).
 * NEAR and FAR write disjoint forces (m is a multiple of 8 doubles, so not
 * even a cache line is shared) and read what the level does not change.
 * The thread running the pair pass posts the level, runs FAR, then runs
 * NEAR itself unless the helper (phys_tiles_help, the first pass's second
 * task, after its draws) claimed it (else it makes the step's draws that
 * are left while it waits: split_wait), and REPLAY: the record stays in
 * the cache of the thread that wrote it. Whichever thread runs NEAR, the
 * result is the same bits; a helper that comes late, before its claim,
 * only costs the time it would have saved (one that is descheduled after
 * its claim holds the pass's thread up until it is done). The helper
 * polls (with a yield every 64 pauses) from its draws to the end of the
 * pair pass, including levels of other routes. In the last step of a
 * frame, both threads make chunks of the next frame's draws while they
 * wait (phys_ahead_chunk, 8 pairs between two looks; what that takes:
 * bench/PROFILE.md, "lib/physics/step.c: the size of a chunk of draws").
 *
 * The cut balances the two threads: the helper's draws and NEAR (about
 * m * m / 2 pairs) against FAR and REPLAY (the rest of the pairs and a
 * few adds per recorded pair). */

/* Fewest pairs of a level on the split route, and what a pair of normal
 * draws (rng_normal_pair: a log, a square root, a sine and a cosine)
 * counts for in pairs of NEAR: 32, the value whose cut balanced
 * petri200's two threads best; the ratio of the timings alone would give
 * less, but NEAR's full tiles run faster than the one-thread kernel
 * (bench/PROFILE.md, "lib/physics/tiles.c: what a pair of draws counts
 * for on the split route"). */
#define SPLIT_PAIRS 4096.0
#define SPLIT_DRAW_PAIRS 32.0

/* The hand-off between the pair pass and its helper: state holds a
 * sequence number (one per level posted) above the status bits. */
enum { SPLIT_IDLE, SPLIT_POSTED, SPLIT_CLAIMED, SPLIT_DONE, SPLIT_SELF, SPLIT_OVER };
#define SPLIT_STATUS 7u
#define SPLIT_SEQ 8u

struct TileSplit {
    _Alignas(64) atomic_uint_fast64_t state;
    TileRun *run;       /* the level posted (valid while it is claimed) */
    double other;       /* the helper's other work, in pairs */
    bool active;        /* a helper is there (between begin and end) */
};

/* The cut of a level of [npart] rows and [n] partners when the helper
 * has [other] pairs' worth of other work, or 0 when it does not split. */
static size_t split_cut(size_t npart, size_t n, double other)
{
    const double pairs = phys_level_pairs(npart, n);
    if (pairs < SPLIT_PAIRS || pairs >= (other > 0 ? SPLIT_RANDOM_PAIRS : TILES_PIPE_PAIRS))
        return 0;
    /* the helper's NEAR (m * m / 2 pairs) and other work against FAR (the
     * rest of the pairs, at about 5/3 the cost a pair: its tiles are
     * recorded, and more of them are part-filled): m * m = (5 pairs - 3
     * other) / 4, to the nearest multiple of the widest width */
    const double mm = (5 * pairs - 3 * other) / 4;
    if (mm <= 0)
        return 0;
    size_t m = (size_t)(sqrt(mm) / TILE_W + 0.5) * TILE_W;
    if (m > npart / TILE_W * TILE_W)
        m = npart / TILE_W * TILE_W;
    return m >= 2 * TILE_W && m < n ? m : 0;
}

/* Room for the FAR part's record: [m] rows against [n] partners, [nf]
 * appliers, [D] elements: m / W row blocks of ceil(n / W) tiles of
 * (1 + W nf D) W doubles (tiles_kernel.h, TK(tile_rec)), for the widest
 * need of the kernel's widths. */
static double *split_reserve(PhysSystem *s, size_t m, size_t n, size_t nf, size_t D)
{
    size_t need = 0;
    for (size_t W = 2; W <= TILE_W; W *= 2) {
        size_t w = m * ((n + W - 1) / W) * (1 + W * nf * D);
        need = w > need ? w : need;
    }
    need = (need + 7) / 8 * 8;
    if (need > s->captrec) {
        free(s->trec);
        s->trec = aligned_alloc(64, need * sizeof(double));
        if (!s->trec)
            phys_oom();
        s->captrec = need;
    }
    return s->trec;
}

/* Wait until [st] holds [want], making chunks of the step's draws
 * meanwhile while some are left (phys_draw_chunk), then of the next
 * frame's (phys_ahead_chunk), else spinning (and yielding now and then). */
static void split_wait(PhysSystem *s, atomic_uint_fast64_t *st, uint64_t want)
{
    unsigned spins = 0;
    while (atomic_load_explicit(st, memory_order_acquire) != want)
        if (!phys_draw_chunk(s) && !phys_ahead_chunk(s))
            tile_pause(&spins);
}

/* The pair pass's side of a split level: post it, run FAR, then NEAR
 * unless the helper claimed it (else wait for it), then REPLAY. */
static void split_run(PhysSystem *s, TileRun *run)
{
    struct TileSplit *h = s->tsplit;
    const bool alone = s->split_mode == PHYS_SPLIT_ALONE;   /* never posted */
    const uint64_t seq = (atomic_load_explicit(&h->state, memory_order_relaxed) / SPLIT_SEQ + 1) * SPLIT_SEQ;
    if (!alone) {
        h->run = run;
        atomic_store_explicit(&h->state, seq | SPLIT_POSTED, memory_order_release);
    }
    tiles_part(run, false, TILE_SPLIT_FAR);
    uint_fast64_t want = seq | SPLIT_POSTED;
    if (alone || (s->split_mode != PHYS_SPLIT_HELPER &&
                  atomic_compare_exchange_strong_explicit(&h->state, &want, seq | SPLIT_SELF,
                                                          memory_order_acq_rel, memory_order_acquire))) {
        tiles_part(run, false, TILE_SPLIT_NEAR);
        s->split_near[1]++;
    } else {
        split_wait(s, &h->state, seq | SPLIT_DONE);
        s->split_near[0]++;
    }
    tiles_part(run, false, TILE_SPLIT_REPLAY);
}

bool phys_tiles_split_wanted(const PhysSystem *s, double other)
{
    if (s->split_mode == PHYS_SPLIT_OFF)
        return false;
    for (size_t gi = 0; gi < s->ngroups; gi++) {
        const PhysGroup *g = &s->groups[gi];
        for (size_t l = 0; g->npart && l < g->lvl_n; l++) {
            const PhysLevel *lv = &s->levels[g->lvl_off + l];
            if (lv->route == PHYS_ROUTE_TILES && split_cut(g->npart, lv->npool, other * SPLIT_DRAW_PAIRS))
                return true;
        }
    }
    return false;
}

bool phys_tiles_split_begin(PhysSystem *s, double other)
{
    if (!s->tsplit) {
        s->tsplit = aligned_alloc(64, (sizeof *s->tsplit + 63) / 64 * 64);
        if (!s->tsplit)
            return false;
        atomic_init(&s->tsplit->state, SPLIT_IDLE);
    }
    struct TileSplit *h = s->tsplit;
    h->other = other * SPLIT_DRAW_PAIRS;
    h->run = NULL;
    const uint64_t seq = atomic_load_explicit(&h->state, memory_order_relaxed) / SPLIT_SEQ * SPLIT_SEQ;
    atomic_store_explicit(&h->state, seq | SPLIT_IDLE, memory_order_relaxed);
    h->active = true;
    return true;
}

bool phys_tiles_split_active(const PhysSystem *s)
{
    return s->tsplit && s->tsplit->active;
}

void phys_tiles_split_end(PhysSystem *s)
{
    struct TileSplit *h = s->tsplit;
    h->active = false;
    const uint64_t seq = atomic_load_explicit(&h->state, memory_order_relaxed) / SPLIT_SEQ * SPLIT_SEQ;
    atomic_store_explicit(&h->state, seq | SPLIT_OVER, memory_order_release);
}

/* The helper's claim of the level in state [st] (as last read), and its
 * NEAR part when the claim succeeds. */
static void split_claim(struct TileSplit *h, uint_fast64_t st)
{
    const uint64_t seq = st & ~(uint64_t)SPLIT_STATUS;
    if (atomic_compare_exchange_strong_explicit(&h->state, &st, seq | SPLIT_CLAIMED,
                                                memory_order_acq_rel, memory_order_acquire)) {
        tiles_part(h->run, false, TILE_SPLIT_NEAR);
        atomic_store_explicit(&h->state, seq | SPLIT_DONE, memory_order_release);
    }
}

void phys_tiles_help_posted(PhysSystem *s)
{
    struct TileSplit *h = s->tsplit;
    uint_fast64_t st = atomic_load_explicit(&h->state, memory_order_acquire);
    if ((st & SPLIT_STATUS) == SPLIT_POSTED)
        split_claim(h, st);
}

void phys_tiles_help(PhysSystem *s)
{
    struct TileSplit *h = s->tsplit;
    unsigned spins = 0;
    for (;;) {
        uint_fast64_t st = atomic_load_explicit(&h->state, memory_order_acquire);
        if ((st & SPLIT_STATUS) == SPLIT_OVER) {
            /* tests (phys_set_ahead): every chunk made here, so that the
             * count made by the pair pass's threads is known */
            if (s->ahead.wait && s->split_mode == PHYS_SPLIT_HELPER)
                while (phys_ahead_chunk(s)) {
                }
            return;
        }
        if ((st & SPLIT_STATUS) == SPLIT_POSTED) {
            split_claim(h, st);
            continue;
        }
        if (!phys_ahead_chunk(s))
            tile_pause(&spins);
    }
}

/* }===== */

/* AVX-512 against 4 x 4 tiles (PhysSystem.simd_auto): every route gives
 * the same bits, but which is faster depends on the processor and the
 * level. On one Xeon, petri200's 2-D level of 200 charged discs ran
 * faster with AVX2 than with AVX-512 (its divisions and square roots no
 * faster a lane in 512 bits, the clock lower), and charges1k's 3-D level
 * of 1,000 on two threads faster with AVX-512, until the AVX2 copy took
 * AVX-512VL's registers (tune_four); with them, the 4 x 4 tiles were as
 * fast or faster for every kind of level timed on that Xeon
 * (bench/PROFILE.md, "lib/physics/tiles.c: AVX-512 against 4 x 4 tiles,
 * timed on each system"). So each kind of level (threaded or not, D, the
 * specialised copy) is timed on its first runs: TUNE_WARM runs with the 4 x 4 tiles
 * untimed, then the two routes in turn, up to TUNE_RUNS each; the one
 * with the lower best time a pair is kept for it from then on, or as soon
 * as each has run twice and one's best is TUNE_CLEAR times the other's (a
 * slow route is not run more than it must be; two runs each, so that one
 * run slowed by something else does not decide). */
#define TUNE_WARM 2
#define TUNE_RUNS 4
#define TUNE_CLEAR 1.25
#define TUNE_KINDS (3 * TILE_MAX_D * (TILE_NSPECS + 1))

typedef struct TileTune {
    uint16_t runs;              /* runs of this kind so far */
    int8_t choice;              /* PHYS_SIMD_*, or -1 while timing */
    double best[2];             /* least nanoseconds a pair so far: [0]
                                   4 x 4 tiles, [1] AVX-512 */
} TileTune;

/* The tuner's 4 x 4 route: AVX2 with AVX-512VL where the processor has
 * it (every processor with AVX-512 but the Xeon Phi), else AVX2. */
static int tune_four(void)
{
    return phys_simd_cap(PHYS_SIMD_AVX2_VL);
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

/* The route for a level of kind [kind] (s->simd_auto): its choice, or the
 * next one to time. */
static int tune_route(PhysSystem *s, size_t kind)
{
    if (!s->tune) {
        s->tune = calloc(TUNE_KINDS, sizeof *s->tune);
        if (!s->tune)
            return s->simd;
        for (size_t i = 0; i < TUNE_KINDS; i++)
            s->tune[i].choice = -1;
    }
    TileTune *t = &s->tune[kind];
    if (t->choice >= 0)
        return t->choice;
    if (t->runs < TUNE_WARM)
        return tune_four();
    return (t->runs - TUNE_WARM) % 2 ? PHYS_SIMD_AVX512 : tune_four();
}

/* Record a run of kind [kind] with [route]: [ns] for [pairs]. */
static void tune_record(PhysSystem *s, size_t kind, int route, double ns, double pairs)
{
    TileTune *t = &s->tune[kind];
    if (t->runs >= TUNE_WARM) {
        const double a = ns / (pairs > 1 ? pairs : 1);
        double *b = &t->best[route == PHYS_SIMD_AVX512];
        if (*b == 0 || a < *b)
            *b = a;
        const unsigned k = (unsigned)(t->runs - TUNE_WARM) / 2 + 1;   /* runs of each so far */
        if (route == PHYS_SIMD_AVX512 &&
            (k == TUNE_RUNS ||
             (k >= 2 && (t->best[0] > TUNE_CLEAR * t->best[1] || t->best[1] > TUNE_CLEAR * t->best[0]))))
            t->choice = (int8_t)(t->best[0] < t->best[1] ? tune_four() : PHYS_SIMD_AVX512);
    }
    t->runs++;
}

void phys_run_tiles(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv)
{
    const size_t D = s->D, n = lv->npool;
    const uint32_t *pool = s->pool + g->pool_off;
    const PhysGroup *fg = &s->groups[lv->group];
    const size_t ns = tiles_stride(n);
    phys_tiles_reserve(s, n);
    double *x = s->tiles, *rad = x + D * ns, *vals = rad + ns;
    double *F = vals + TILE_MAX_F * ns;
    TileLevel T = {.npart = g->npart, .npool = n, .stride = ns,
                   .nf = fg->pair_n, .x = x, .rad = rad, .F = F, .fast = true};
    bool need_mass = false, need_charge = false;
    for (size_t f = 0; f < T.nf; f++) {
        const PhysApplier *ap = &s->ap[s->gidx[fg->pair_off + f]];
        TileApplier *t = &T.ap[f];
        t->kind = ap->kind == AP_COLLISION ? TILE_COLLISION
                  : ap->kind == AP_GRAVITY ? TILE_PULL : TILE_PUSH;
        t->strength = ap->strength;
        t->maxd = ap->maxd;
        t->power = ap->power;
        T.fast = T.fast && ap->maxd == 0;
        need_mass |= ap->kind == AP_GRAVITY;
        need_charge |= ap->kind == AP_ELECTROSTATIC;
    }
    double *mass = vals, *charge = vals + ns;
    for (size_t f = 0; f < T.nf; f++)
        T.val[f] = T.ap[f].kind == TILE_PULL ? mass
                   : T.ap[f].kind == TILE_PUSH ? charge : rad;
    for (size_t q = 0; q < n; q++) {
        size_t p = pool[q];
        for (size_t k = 0; k < D; k++) {
            x[k * ns + q] = s->pos[p * D + k];
            F[k * ns + q] = s->force[p * D + k];
        }
        rad[q] = s->radius[p];
        if (need_mass)
            mass[q] = s->mass[p];
        if (need_charge)
            charge[q] = s->charge[p];
    }
    for (size_t q = n; q < ns; q++) {
        for (size_t k = 0; k < D; k++)
            x[k * ns + q] = F[k * ns + q] = 0;
        rad[q] = mass[q] = charge[q] = 0;
    }
    if (T.nf == 0)
        return;
    TileRun run = {.T = &T, .simd = s->simd, .spec = tile_spec_of(&T), .D = D,
                   .buf = F + D * ns};
    atomic_init(&run.next, 0);
    /* the split route only inside a first pass with a helper; the threaded
     * route for every level of TILES_PIPE_PAIRS or more outside one (a
     * level that phys_tiles_threaded() left to the first pass, when the
     * step made no job of it: no draws planned, another level threaded,
     * or the literal particle pass), never inside (s->workers is NULL) */
    const size_t cut = s->tsplit && s->tsplit->active ? split_cut(g->npart, n, s->tsplit->other) : 0;
    const bool threaded = !cut && workers_count(s->workers) >= 2 &&
                          phys_level_pairs(g->npart, n) >= TILES_PIPE_PAIRS;
    const size_t route = cut ? 2 : threaded;
    const size_t kind = (route * TILE_MAX_D + (D - 1)) * (TILE_NSPECS + 1) + (size_t)(run.spec + 1);
    double t0 = 0;
    if (s->simd_auto) {
        run.simd = tune_route(s, kind);
        t0 = now_ns();
    }
    if (cut) {
        run.cut = cut;
        run.rec = split_reserve(s, cut, n - cut, T.nf, D);
        split_run(s, &run);
    } else if (!threaded) {
        tiles_part(&run, false, 0);
    } else {
        run.ntasks = list_tasks(s, T.npart, n);
        run.tasks = s->ttasks;
        run.prog = s->tprog;
        unsigned nw = workers_count(s->workers);
        workers_run(s->workers, nw < WORKERS_MAX_TASKS ? nw : WORKERS_MAX_TASKS, tiles_task, &run);
    }
    if (s->simd_auto && s->tune && s->tune[kind].choice < 0)
        tune_record(s, kind, run.simd, now_ns() - t0, phys_level_pairs(g->npart, n));
    for (size_t q = 0; q < n; q++) {
        size_t p = pool[q];
        for (size_t k = 0; k < D; k++)
            s->force[p * D + k] = F[k * ns + q];
    }
}
