/* forces.c: the force appliers and the barrier soft constraint.
 *
 * Works on the struct-of-arrays particle storage of a PhysSystem (see
 * physics_internal.h): particle p's vectors are pos/vel/force[p*D .. p*D+D),
 * its scalars radius/mass/charge[p]; the pair direction goes through the
 * system's D-double scratch `dir`. Each applier is a PhysApplier whose vector
 * parameters are the 2*D doubles at avec[vec].
 *
 * Implements PHYSICS-ENGINE.md §4 "pair(a, b)" and the applier list
 * (distance, collision, gravity, electrostatic, adhesion, drag, buoyancy,
 * constant, random, field) and "Barrier distance(p)", with the floating-point
 * operations in exactly the order written there (PHYSICS.md gives the maths).
 * The hard rebound lives in step.c with the integration step it calls.
 */
#include <math.h>

#include "physics_internal.h"
#include "streams.h"

/* Python's min(a, b) / max(a, b): the first argument unless the second is
 * strictly smaller / larger (so a NaN first argument is kept). */
static inline double py_min(double a, double b) { return b < a ? b : a; }
static inline double py_max(double a, double b) { return b > a ? b : a; }

/* §4 pair(a, b): d_k = b.pos_k - a.pos_k, s = sum d_k*d_k (k ascending),
 * dist = sqrt(s), inv = 1/dist, dir_k = d_k * inv. */
double phys_pair(PhysSystem *s, size_t a, size_t b)
{
    const size_t D = s->D;
    const double *pa = s->pos + a * D, *pb = s->pos + b * D;
    double *dir = s->dir;
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

/* k = pow(k, power) unless power == 1, then k * strength (§4 distance). */
static inline double shape(double k, double power, double strength)
{
    if (power != 1)
        k = pow(k, power);
    return k * strength;
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
        double k = shape(ap->minimum - dist, ap->power, ap->strength);
        push_apart(fa, fb, dir, k, D);
    } else if (ap->maximum != 0 && dist > ap->maximum) {
        double k = shape(dist - ap->maximum, ap->power, ap->strength);
        pull_together(fa, fb, dir, k, D);
    }
}

void phys_apply_distance(PhysSystem *s, const PhysApplier *ap)
{
    const size_t D = s->D;
    size_t a = (size_t)ap->from, b = (size_t)ap->to;
    double dist = phys_pair(s, a, b);
    distance_force(ap, s->force + a * D, s->force + b * D, s->dir, dist, D);
}

/* One pair applier on the pair (a, b) already measured by phys_pair(). */
static inline void pair_force(PhysSystem *s, const PhysApplier *ap, size_t a,
                              size_t b, double dist)
{
    const size_t D = s->D;
    double *fa = s->force + a * D, *fb = s->force + b * D;
    const double *dir = s->dir;
    switch (ap->kind) {
    case AP_COLLISION: {
        /* §4 collision: both radii nonzero and dist < ra+rb:
         * k = (ra+rb) - dist, power, strength; a.F -= f; b.F += f */
        double ra = s->radius[a], rb = s->radius[b];
        if (ra != 0 && rb != 0) {
            double r = ra + rb;
            if (dist < r)
                push_apart(fa, fb, dir, shape(r - dist, ap->power, ap->strength), D);
        }
        break;
    }
    case AP_GRAVITY: {
        /* §4 gravity: m = max(ra+rb, dist); k = strength*ma*mb/(m*m);
         * a.F += dir*k; b.F -= dir*k */
        double ma = s->mass[a], mb = s->mass[b];
        if (ma != 0 && mb != 0) {
            double m = py_max(s->radius[a] + s->radius[b], dist);
            double k = ap->strength * ma * mb / (m * m);
            pull_together(fa, fb, dir, k, D);
        }
        break;
    }
    case AP_ELECTROSTATIC: {
        /* §4 electrostatic: as gravity with charges; a.F -= dir*k;
         * b.F += dir*k */
        double qa = s->charge[a], qb = s->charge[b];
        if (qa != 0 && qb != 0) {
            double m = py_max(s->radius[a] + s->radius[b], dist);
            double k = ap->strength * qa * qb / (m * m);
            push_apart(fa, fb, dir, k, D);
        }
        break;
    }
    case AP_ADHESION: {
        /* §4 adhesion: o = (ra+rb) - dist, lmin = |ra-rb|,
         * l = lmin*overlap + (ra+rb)*(1-overlap), k = strength*o*(dist-l);
         * a.F += dir*k; b.F -= dir*k */
        double ra = s->radius[a], rb = s->radius[b];
        if (ra != 0 && rb != 0) {
            double r = ra + rb;
            if (dist < r) {
                double o = r - dist;
                double lmin = fabs(ra - rb);
                double l = lmin * ap->overlap + r * (1 - ap->overlap);
                double k = ap->strength * o * (dist - l);
                pull_together(fa, fb, dir, k, D);
            }
        }
        break;
    }
    default:
        break;
    }
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

void phys_apply_particle(PhysSystem *s, PhysApplier *ap, size_t p,
                         double delta)
{
    const size_t D = s->D;
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
        /* §4 random: F_i += strength * source[index]; index += 1 */
        for (size_t i = 0; i < D; i++) {
            F[i] = F[i] + ap->strength * rng_normal(ap->key, ap->index);
            ap->index++;
        }
        break;
    case AP_FIELD: {
        /* §4 field [doc]: F_i += strength * dir_i * charge */
        double q = s->charge[p];
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + ap->strength * x[i] * q;
        break;
    }
    default:
        break;
    }
}

/* §4 Barrier distance(p): x = sum (pos_i - bpos_i)*n_i; [doc] if min > 0
 * and 0 <= x < min: k = min - x, power, strength, F_i += n_i*k; else if
 * max != 0 and x > max: k = x - max, power, strength, F_i -= n_i*k. */
void phys_barrier_distance(PhysSystem *s, const PhysApplier *b, size_t p)
{
    if (!b->enabled)
        return;
    const size_t D = s->D;
    const double *bp = s->avec + b->vec, *nv = bp + D;
    const double *pos = s->pos + p * D;
    double *F = s->force + p * D;
    double x = 0;
    for (size_t i = 0; i < D; i++)
        x = x + (pos[i] - bp[i]) * nv[i];
    if (b->minimum > 0 && x >= 0 && x < b->minimum) {
        double k = shape(b->minimum - x, b->power, b->strength);
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + nv[i] * k;
    } else if (b->maximum != 0 && x > b->maximum) {
        double k = shape(x - b->maximum, b->power, b->strength);
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] - nv[i] * k;
    }
}

/* F += dir*k (plus) or F -= dir*k, per element with f = dir_i*k: one side
 * of push_apart()/pull_together(). */
static inline void add_side(double *F, const double *dir, double k, size_t D,
                            bool plus)
{
    if (plus) {
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + dir[i] * k;
    } else {
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] - dir[i] * k;
    }
}

/* The per-particle half of pair_force(): the same conditions and the same
 * k, then only the one side's element operations (a push apart subtracts
 * from a and adds to b; a pull together the reverse). */
void phys_pair_force_one(const PhysSystem *s, const PhysApplier *ap, size_t a,
                         size_t b, double dist, const double *dir, double *F,
                         bool to_b)
{
    const size_t D = s->D;
    switch (ap->kind) {
    case AP_COLLISION: {
        double ra = s->radius[a], rb = s->radius[b];
        if (ra != 0 && rb != 0) {
            double r = ra + rb;
            if (dist < r)
                add_side(F, dir, shape(r - dist, ap->power, ap->strength), D, to_b);
        }
        break;
    }
    case AP_GRAVITY: {
        double ma = s->mass[a], mb = s->mass[b];
        if (ma != 0 && mb != 0) {
            double m = py_max(s->radius[a] + s->radius[b], dist);
            double k = ap->strength * ma * mb / (m * m);
            add_side(F, dir, k, D, !to_b);
        }
        break;
    }
    case AP_ELECTROSTATIC: {
        double qa = s->charge[a], qb = s->charge[b];
        if (qa != 0 && qb != 0) {
            double m = py_max(s->radius[a] + s->radius[b], dist);
            double k = ap->strength * qa * qb / (m * m);
            add_side(F, dir, k, D, to_b);
        }
        break;
    }
    case AP_ADHESION: {
        double ra = s->radius[a], rb = s->radius[b];
        if (ra != 0 && rb != 0) {
            double r = ra + rb;
            if (dist < r) {
                double o = r - dist;
                double lmin = fabs(ra - rb);
                double l = lmin * ap->overlap + r * (1 - ap->overlap);
                double k = ap->strength * o * (dist - l);
                add_side(F, dir, k, D, !to_b);
            }
        }
        break;
    }
    default:
        break;
    }
}
