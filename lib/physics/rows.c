/* rows.c: the reference pair loop, measured a block of partners at a time.
 *
 * The route for levels whose reach is unlimited (!gravity or !electrostatic
 * without max_distance) when there are not enough threads for the
 * per-particle gather of pairs.c to pay off: it runs the reference loop of
 * phys_apply_pair_level (PHYSICS-ENGINE.md §4) itself, row i = 0 ..
 * len(G.particles)-1, partners j = i+1 .. npool-1, so every pair is
 * measured once and every addition into a force happens in the reference
 * order: within row i, a = pool[i] receives its "from" contributions for j
 * ascending, and each b = pool[j] receives one "to" contribution, after
 * those of the earlier rows and before those of its own row; within a
 * pair, the appliers add in their order, a's element before b's (distinct
 * particles, so that order does not matter).
 *
 * What changes is only how the pair values are computed: for a block of
 * BLOCK consecutive partners, the differences d_k = x_j,k - x_i,k, the
 * squared distance (k ascending), dist = sqrt(s), inv = 1/dist and each
 * applier's factor k are computed lane by lane, as independent lanes the
 * compiler turns into vector instructions (sqrt and division are correctly
 * rounded in vector form too, nothing is contracted into FMA: the build has
 * -ffp-contract=off), each lane with exactly the operations and operand
 * order of pair() and pair_force() in forces.c. The positions and scalars
 * of the level are first copied into pool order (struct of arrays), so the
 * lanes load contiguous memory.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cpu.h"
#include "mem.h"
#include "physics_internal.h"

#define BLOCK 8
#define ROWS_MAX_D 3
#define ROWS_SIMPLE_MAX 4

/* Everything one row needs, in pool order. */
typedef struct RowLevel {
    const PhysSystem *s;
    const uint32_t *pool;
    size_t npart, npool;
    size_t stride;      /* npool rounded up past a whole block */
    const uint32_t *forces;
    size_t nf;
    bool simple;        /* every applier is collision, gravity or electrostatic */
    const double *x;    /* x[k*stride + q], zero past npool */
    const double *rad, *mass, *charge;   /* [q] */
} RowLevel;

/* The values of one block of row i: the lanes j = j0 .. j0+BLOCK-1 (the
 * arrays are padded, so every block has BLOCK lanes; those past the end,
 * j >= npool, are computed and never used), d = x_j - x_i per element and
 * dist, inv of pair(pool[i], pool[j]). */
static inline __attribute__((always_inline)) void
block_measure(const RowLevel *L, const double *xi, size_t j0,
              double d[][BLOCK], double *dist, double *inv, const size_t D)
{
    const double *x = L->x;
    const size_t ns = L->stride;
    for (size_t k = 0; k < D; k++)
        for (size_t l = 0; l < BLOCK; l++)
            d[k][l] = x[k * ns + j0 + l] - xi[k];
    for (size_t l = 0; l < BLOCK; l++) {
        double sum = 0;
        for (size_t k = 0; k < D; k++)
            sum += d[k][l] * d[k][l];
        dist[l] = sqrt(sum);
        inv[l] = 1 / dist[l];
    }
}

/* For a simple level, after block_measure(): whether each applier acts on
 * each lane (act, 0 or 1) and the vector f = dir*k it adds (G[f][k][l]),
 * with the expressions of pair_force() for a = pool[i], b = pool[j]; m
 * lanes are real. Turns d into dir. */
static inline __attribute__((always_inline)) void
block_values(const RowLevel *L, size_t i, size_t j0, size_t m,
             double d[][BLOCK], const double *dist, const double *inv,
             int64_t act[][BLOCK], double G[][ROWS_MAX_D][BLOCK],
             const size_t D)
{
    const PhysSystem *s = L->s;
    const size_t nf = L->nf;
    const double *rad = L->rad;
    const double ra = rad[i];
    double K[ROWS_SIMPLE_MAX][BLOCK];
    /* each applier's k for the block, as pair_force() computes it
     * with a = pool[i], b = pool[j] */
    for (size_t f = 0; f < nf; f++) {
        const PhysApplier *ap = &s->ap[L->forces[f]];
        const double str = ap->strength, maxd = ap->maxd;
        double *kk = K[f];
        int64_t *ac = act[f];
        if (ap->kind == AP_COLLISION) {
            for (size_t l = 0; l < BLOCK; l++) {
                double rb = rad[j0 + l];
                double r = ra + rb;
                ac[l] = ((maxd == 0) | (dist[l] < maxd)) & (ra != 0) &
                        (rb != 0) & (dist[l] < r);
                kk[l] = r - dist[l];
            }
            if (ap->power != 1) {
                for (size_t l = 0; l < m; l++)
                    if (ac[l])
                        kk[l] = pow(kk[l], ap->power);
            }
            for (size_t l = 0; l < BLOCK; l++)
                kk[l] = kk[l] * str;
            continue;
        }
        const double *val = ap->kind == AP_GRAVITY ? L->mass : L->charge;
        const double va = val[i];
        for (size_t l = 0; l < BLOCK; l++) {
            size_t j = j0 + l;
            double vb = val[j];
            double r = ra + rad[j];
            double mm = dist[l] > r ? dist[l] : r;   /* py_max(r, dist) */
            ac[l] = ((maxd == 0) | (dist[l] < maxd)) & (va != 0) & (vb != 0);
            kk[l] = str * va * vb / (mm * mm);
        }
    }
    /* f = dir*k per applier, lane by lane (dir = d*inv, then
     * dir*k: the two roundings of pair() and push_apart()) */
    for (size_t k = 0; k < D; k++)
        for (size_t l = 0; l < BLOCK; l++)
            d[k][l] = d[k][l] * inv[l];
    for (size_t f = 0; f < nf; f++)
        for (size_t k = 0; k < D; k++)
            for (size_t l = 0; l < BLOCK; l++)
                G[f][k][l] = d[k][l] * K[f][l];
}

static inline __attribute__((always_inline)) void
row_fixed(const RowLevel *L, size_t i, double *force, const size_t D)
{
    const PhysSystem *s = L->s;
    const size_t n = L->npool, ns = L->stride, nf = L->nf;
    const double *x = L->x;
    const size_t a = L->pool[i];
    double xi[ROWS_MAX_D], fa[ROWS_MAX_D];
    for (size_t k = 0; k < D; k++) {
        xi[k] = x[k * ns + i];
        fa[k] = force[a * D + k];
    }
    double d[ROWS_MAX_D][BLOCK], dist[BLOCK], inv[BLOCK];
    double G[ROWS_SIMPLE_MAX][ROWS_MAX_D][BLOCK];
    bool grav[ROWS_SIMPLE_MAX];
    for (size_t f = 0; f < nf && L->simple; f++)
        grav[f] = s->ap[L->forces[f]].kind == AP_GRAVITY;
    int64_t act[ROWS_SIMPLE_MAX][BLOCK];   /* lane acts: 0 or 1 */
    for (size_t j0 = i + 1; j0 < n; j0 += BLOCK) {
        const size_t m = n - j0 < BLOCK ? n - j0 : BLOCK;
        block_measure(L, xi, j0, d, dist, inv, D);
        if (L->simple) {
            block_values(L, i, j0, m, d, dist, inv, act, G, D);
            for (size_t l = 0; l < m; l++) {
                double *fb = force + (size_t)L->pool[j0 + l] * D;
                for (size_t f = 0; f < nf; f++) {
                    if (!act[f][l])
                        continue;
                    if (grav[f]) {
                        /* pull together: a.F += f; b.F -= f */
#pragma GCC unroll 3
                        for (size_t k = 0; k < D; k++) {
                            fa[k] = fa[k] + G[f][k][l];
                            fb[k] = fb[k] - G[f][k][l];
                        }
                    } else {
                        /* push apart: a.F -= f; b.F += f */
#pragma GCC unroll 3
                        for (size_t k = 0; k < D; k++) {
                            fa[k] = fa[k] - G[f][k][l];
                            fb[k] = fb[k] + G[f][k][l];
                        }
                    }
                }
            }
        } else {
            /* any applier: pair_force()'s two sides, a's then b's */
            for (size_t k = 0; k < D; k++)
                force[a * D + k] = fa[k];
            for (size_t l = 0; l < m; l++) {
                size_t b = L->pool[j0 + l];
                double dir[ROWS_MAX_D];
                for (size_t k = 0; k < D; k++)
                    dir[k] = d[k][l] * inv[l];
                for (size_t f = 0; f < nf; f++) {
                    const PhysApplier *ap = &s->ap[L->forces[f]];
                    if (ap->maxd == 0 || dist[l] < ap->maxd) {
                        phys_pair_force_one(s, ap, a, b, dist[l], dir,
                                            force + a * D, false);
                        phys_pair_force_one(s, ap, a, b, dist[l], dir,
                                            force + b * D, true);
                    }
                }
            }
            for (size_t k = 0; k < D; k++)
                fa[k] = force[a * D + k];
        }
    }
    for (size_t k = 0; k < D; k++)
        force[a * D + k] = fa[k];
}

#define ROW_COPY(name, dim, attr)                                             \
    attr static void name(const RowLevel *L, double *force)                  \
    {                                                                         \
        for (size_t i = 0; i < L->npart; i++)                                 \
            row_fixed(L, i, force, dim);                                      \
    }

ROW_COPY(rows_1, 1, )
ROW_COPY(rows_2, 2, )
ROW_COPY(rows_3, 3, )
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HAVE_AVX2_ROWS 1
ROW_COPY(rows_1_avx2, 1, __attribute__((target("avx2"))))
ROW_COPY(rows_2_avx2, 2, __attribute__((target("avx2"))))
ROW_COPY(rows_3_avx2, 3, __attribute__((target("avx2"))))
#endif

/* Pool entries padded past one more whole block. */
static size_t rows_stride(size_t n)
{
    return (n + 2 * BLOCK - 1) / BLOCK * BLOCK;
}

void phys_rows_reserve(PhysSystem *s, size_t npool)
{
    size_t need = (s->D + 3) * rows_stride(npool);
    if (need <= s->caprows)
        return;
    size_t cap = s->caprows ? s->caprows : 64;
    while (cap < need)
        cap *= 2;
    double *p = realloc(s->rows, cap * sizeof *p);
    if (!p) {
        mem_oom();
    }
    s->rows = p;
    s->caprows = cap;
}

bool phys_rows_suits(const PhysSystem *s)
{
    return s->D >= 1 && s->D <= ROWS_MAX_D;
}

void phys_run_rows(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv)
{
    const size_t D = s->D, n = lv->npool;
    const PhysGroup *fg = &s->groups[lv->group];
    RowLevel L = {
        .s = s, .pool = s->pool + g->pool_off, .npart = g->npart, .npool = n,
        .forces = s->gidx + fg->pair_off, .nf = fg->pair_n,
    };
    L.simple = L.nf <= ROWS_SIMPLE_MAX;
    for (size_t f = 0; f < L.nf && L.simple; f++) {
        PhysApplierKind k = s->ap[L.forces[f]].kind;
        L.simple = k == AP_COLLISION || k == AP_GRAVITY || k == AP_ELECTROSTATIC;
    }
    const size_t ns = rows_stride(n);
    L.stride = ns;
    phys_rows_reserve(s, n);
    double *x = s->rows;
    for (size_t q = 0; q < n; q++) {
        size_t p = L.pool[q];
        for (size_t k = 0; k < D; k++)
            x[k * ns + q] = s->pos[p * D + k];
        x[D * ns + q] = s->radius[p];
        x[(D + 1) * ns + q] = s->mass[p];
        x[(D + 2) * ns + q] = s->charge[p];
    }
    for (size_t k = 0; k < D + 3; k++)
        memset(x + k * ns + n, 0, (ns - n) * sizeof *x);
    L.x = x;
    L.rad = x + D * ns;
    L.mass = x + (D + 1) * ns;
    L.charge = x + (D + 2) * ns;
#ifdef HAVE_AVX2_ROWS
    if (cpu_has(CPU_AVX2)) {
        switch (D) {
        case 1: rows_1_avx2(&L, s->force); return;
        case 2: rows_2_avx2(&L, s->force); return;
        default: rows_3_avx2(&L, s->force); return;
        }
    }
#endif
    switch (D) {
    case 1: rows_1(&L, s->force); break;
    case 2: rows_2(&L, s->force); break;
    default: rows_3(&L, s->force); break;
    }
}
