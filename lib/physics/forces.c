/* forces.c: the pair force appliers.
 *
 * Works on the struct-of-arrays particle storage of a PhysSystem (see
 * physics_internal.h): particle p's vectors are pos/vel/force[p*D .. p*D+D),
 * its scalars radius/mass/charge[p]; the pair direction goes through the
 * system's D-double scratch `dir`. Each applier is a PhysApplier whose vector
 * parameters are the 2*D doubles at avec[vec].
 *
 * Implements PHYSICS-ENGINE.md §4 "pair(a, b)", !distance and the
 * reference all-pairs loop of the pair appliers (collision, gravity,
 * electrostatic, adhesion: each defined once, in physics_internal.h's
 * phys_pair_force_side, for this loop and the fast routes alike), with the
 * floating-point operations in exactly the order written there (PHYSICS.md
 * gives the maths). The per-particle appliers (drag, buoyancy, constant,
 * random, field), the barriers and the step live in step.c.
 */
#include <math.h>

#include "physics_internal.h"

/* §4 pair(a, b): d_k = b.pos_k - a.pos_k, s = sum d_k*d_k (k ascending),
 * dist = sqrt(s), inv = 1/dist, dir_k = d_k * inv. */
static inline double pair_of(const double *pa, const double *pb, double *dir,
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

double phys_pair(PhysSystem *s, size_t a, size_t b)
{
    const size_t D = s->D;
    return pair_of(s->pos + a * D, s->pos + b * D, s->dir, D);
}

/* a.F -= dir*k; b.F += dir*k (per element, f = dir_i*k computed once). */
static inline void push_apart(double *fa, double *fb, const double *dir,
                              double k, size_t D)
{
    for (size_t i = 0; i < D; i++) {
        double f = dir[i] * k;
        fa[i] = fa[i] - f;
        fb[i] = fb[i] + f;
    }
}

/* a.F += dir*k; b.F -= dir*k. */
static inline void pull_together(double *fa, double *fb, const double *dir,
                                 double k, size_t D)
{
    for (size_t i = 0; i < D; i++) {
        double f = dir[i] * k;
        fa[i] = fa[i] + f;
        fb[i] = fb[i] - f;
    }
}

/* §4 distance: below min push apart by (min - dist)^power * strength, else
 * above max pull together by (dist - max)^power * strength. */
static inline void distance_force(const PhysApplier *ap, double *fa,
                                  double *fb, const double *dir, double dist,
                                  size_t D)
{
    if (ap->minimum != 0 && dist < ap->minimum) {
        double k = phys_shape(ap->minimum - dist, ap->power, ap->strength);
        push_apart(fa, fb, dir, k, D);
    } else if (ap->maximum != 0 && dist > ap->maximum) {
        double k = phys_shape(dist - ap->maximum, ap->power, ap->strength);
        pull_together(fa, fb, dir, k, D);
    }
}

void phys_apply_distances(PhysSystem *s, const uint32_t *list, size_t n)
{
    const size_t D = s->D;
    if (n == 0)
        return;
    if (n > SIZE_MAX / (D + 1))
        phys_oom();
    s->dgeo = mem_grow(s->dgeo, &s->capdgeo, n * (D + 1), sizeof *s->dgeo);
    /* pair i: dist at geo[i*(D+1)], dir after it */
    double *geo = s->dgeo;
    for (size_t i = 0; i < n; i++) {
        const PhysApplier *ap = &s->ap[list[i]];
        if (ap->from < 0 || ap->to < 0)
            continue;
        double *g = geo + i * (D + 1);
        g[0] = pair_of(s->pos + (size_t)ap->from * D, s->pos + (size_t)ap->to * D,
                       g + 1, D);
    }
    for (size_t i = 0; i < n; i++) {
        const PhysApplier *ap = &s->ap[list[i]];
        if (ap->from < 0 || ap->to < 0)
            continue;
        const double *g = geo + i * (D + 1);
        distance_force(ap, s->force + (size_t)ap->from * D,
                       s->force + (size_t)ap->to * D, g + 1, g[0], D);
    }
}

/* One pair applier on the pair (a, b) already measured by phys_pair(): its
 * one definition, phys_pair_force_side() (physics_internal.h), which the
 * fast routes call for one side of a pair, applied to a's side and then
 * to b's. The same bits as computing k once and updating both sides per
 * element: k is the same operations on the same numbers, and a's and b's
 * elements are updated by the same subtraction or addition of dir_i*k
 * (PHYSICS-ENGINE.md §4, pair appliers). */
static inline void pair_force(PhysSystem *s, const PhysApplier *ap, size_t a,
                              size_t b, double dist)
{
    const size_t D = s->D;
    phys_pair_force_side(s, ap, a, b, dist, s->dir, s->force + a * D, false, D);
    phys_pair_force_side(s, ap, a, b, dist, s->dir, s->force + b * D, true, D);
}

/* §4 group loop: for i in 0..len(G.particles)-1, j in i+1..len(pool)-1:
 * pair(pool[i], pool[j]); for f in forces: if f.maxd == 0 or dist < f.maxd:
 * apply f. */
void phys_apply_pair_level(PhysSystem *s, const PhysGroup *g,
                           const PhysLevel *lv)
{
    const PhysGroup *fg = &s->groups[lv->group];
    const uint32_t *forces = s->gidx + fg->pair_off;
    const size_t nf = fg->pair_n;
    const uint32_t *pool = s->pool + g->pool_off;
    const size_t n = lv->npool;
    for (size_t i = 0; i < g->npart; i++) {
        if (phys_interrupted(s))
            return;
        size_t a = pool[i];
        for (size_t j = i + 1; j < n; j++) {
            size_t b = pool[j];
            double dist = phys_pair(s, a, b);
            for (size_t f = 0; f < nf; f++) {
                const PhysApplier *ap = &s->ap[forces[f]];
                if (ap->maxd == 0 || dist < ap->maxd)
                    pair_force(s, ap, a, b, dist);
            }
        }
    }
}

void phys_pair_force_one(const PhysSystem *s, const PhysApplier *ap, size_t a,
                         size_t b, double dist, const double *dir, double *F,
                         bool to_b)
{
    phys_pair_force_side(s, ap, a, b, dist, dir, F, to_b, s->D);
}
