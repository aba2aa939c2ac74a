/* literal.c: the literal route of the particle pass.
 *
 * PHYSICS-ENGINE.md §4's second pass over a group, written as the spec is
 * and nothing more: one particle at a time, the number of dimensions read
 * at run time, every sum over i ascending, every applier and barrier taken
 * from the group's own lists and then its parent's, grandparent's ... (the
 * chains "PF" and "B" walked, not read from the precomputed chain), one
 * !random draw at a time, pow() and sqrt() called as written. It shares no
 * code with step.c's specialised route (compiled per D, with inline
 * helpers and the paired normal draws), which must give the same bits:
 * `--particles literal` (phys_set_particles) selects this route and
 * tests/unit/test_particle_pass.c compares the two on generated systems.
 * Keep it slow and plain; speed belongs in step.c.
 *
 * Both physics modes are here: PHYSICS.md's (the default) and Flitter
 * 1.0.0b28's published behaviour at the four [doc] places (s->upstream,
 * physics.h).
 */
#include <math.h>

#include "physics_internal.h"
#include "streams.h"

/* §4 distance/barrier: k = pow(k, power) if power != 1; k = k * strength */
static double lit_shape(double k, double power, double strength)
{
    if (power != 1)
        k = pow(k, power);
    k = k * strength;
    return k;
}

/* §4 step(p, clock, dt):
 *   a = copy of v
 *   if mass != 0 and every F_i is finite:
 *      k = dt / mass
 *      (upstream: if ease > 0 and clock < ease: k = k * (clock / ease))
 *      v_i = v_i + F_i*k, s = sum v_i*v_i
 *      if c > 0 and s > c*c: k = c / sqrt(s); v_i = v_i*k
 *   a_i = (v_i - a_i) / dt ; pos_i = pos_i + v_i*dt */
static void lit_step(PhysSystem *s, size_t p, double clock, double dt)
{
    const size_t D = s->D;
    double *pos = s->pos + p * D, *v = s->vel + p * D, *a = s->acc + p * D;
    const double *F = s->force + p * D;
    for (size_t i = 0; i < D; i++)
        a[i] = v[i];
    if (s->mass[p] != 0) {
        bool finite = true;
        for (size_t i = 0; i < D; i++)
            if (isinf(F[i]) || isnan(F[i]))
                finite = false;
        if (finite) {
            double k = dt / s->mass[p];
            if (s->upstream && s->ease[p] > 0 && clock < s->ease[p])
                k = k * (clock / s->ease[p]);
            double sum = 0;
            for (size_t i = 0; i < D; i++) {
                v[i] = v[i] + F[i] * k;
                sum = sum + v[i] * v[i];
            }
            if (s->c > 0 && sum > s->c * s->c) {
                k = s->c / sqrt(sum);
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

/* §4 per-particle appliers: drag, buoyancy, constant, random, field
 * ([doc]: times the charge; upstream without it). */
static void lit_apply(PhysSystem *s, PhysApplier *ap, size_t p, double delta)
{
    const size_t D = s->D;
    double *F = s->force + p * D;
    const double *v = s->vel + p * D;
    const double *x = s->avec + ap->vec;   /* flow | gravity | force | direction */
    const double *y = x + D;               /* constant: acceleration */
    const double radius = s->radius[p], mass = s->mass[p];
    switch (ap->kind) {
    case AP_DRAG:
        /* s = sum (v_i - flow_i)^2;
         * k = min(strength * sqrt(s) * pow(radius, D-1), mass/delta);
         * F_i -= (v_i - flow_i)*k */
        if (radius != 0) {
            double sum = 0;
            for (size_t i = 0; i < D; i++)
                sum = sum + (v[i] - x[i]) * (v[i] - x[i]);
            double k = ap->strength * sqrt(sum) * pow(radius, (double)D - 1);
            k = py_min(k, mass / delta);
            for (size_t i = 0; i < D; i++)
                F[i] = F[i] - (v[i] - x[i]) * k;
        }
        break;
    case AP_BUOYANCY:
        /* k = strength * (mass - pow(radius, D)*density); F_i += g_i*k */
        if (radius != 0 && mass != 0) {
            double k = ap->strength * (mass - pow(radius, (double)D) * ap->density);
            for (size_t i = 0; i < D; i++)
                F[i] = F[i] + x[i] * k;
        }
        break;
    case AP_CONSTANT:
        /* F_i += (F'_i + A_i*mass) * strength */
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + (x[i] + y[i] * mass) * ap->strength;
        break;
    case AP_RANDOM:
        /* F_i += strength * source[index]; index += 1 */
        for (size_t i = 0; i < D; i++) {
            F[i] = F[i] + ap->strength * rng_normal(ap->key, ap->index);
            ap->index = ap->index + 1;
        }
        break;
    case AP_FIELD:
        /* [doc] F_i += strength * dir_i * charge; upstream F_i += strength * dir_i */
        for (size_t i = 0; i < D; i++) {
            if (s->upstream)
                F[i] = F[i] + ap->strength * x[i];
            else
                F[i] = F[i] + ap->strength * x[i] * s->charge[p];
        }
        break;
    default:
        break;
    }
}

/* §4 Barrier distance(p) (soft constraint): x = sum (pos_i - bpos_i)*n_i;
 * [doc] if min > 0 and 0 <= x < min: k = min - x, power, strength,
 * F_i += n_i*k; else if max != 0 and x > max: k = x - max, power,
 * strength, F_i -= n_i*k. Upstream: nothing at all when min <= 0. */
static void lit_barrier_distance(PhysSystem *s, const PhysApplier *b, size_t p)
{
    if (!b->enabled)
        return;
    if (s->upstream && b->minimum <= 0)
        return;
    const size_t D = s->D;
    const double *bpos = s->avec + b->vec, *n = bpos + D;
    const double *pos = s->pos + p * D;
    double *F = s->force + p * D;
    double x = 0;
    for (size_t i = 0; i < D; i++)
        x = x + (pos[i] - bpos[i]) * n[i];
    if (b->minimum > 0 && 0 <= x && x < b->minimum) {
        double k = lit_shape(b->minimum - x, b->power, b->strength);
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + n[i] * k;
    } else if (b->maximum != 0 && x > b->maximum) {
        double k = lit_shape(x - b->maximum, b->power, b->strength);
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] - n[i] * k;
    }
}

/* §4 Barrier rebound(p, clock, dt) (hard bounce), all sums over i ascending:
 *   x = -radius + sum (pos_i - bpos_i)*n_i ; u = sum v_i*n_i ; w = sum a_i*n_i
 *   if x >= 0: return
 *   r = x / u
 *   if u >= 0 or r > dt: pos_i = pos_i - x*n_i; return
 *   pos_i = pos_i - r*v_i ; v_i = (v_i - r*a_i)*rest ; u' = sum v_i*n_i ;
 *   v_i = v_i - 2*u'*n_i
 *   if w < 0 and u'/w < r: r = u'/w
 *   step(p, clock, r) */
static void lit_rebound(PhysSystem *s, const PhysApplier *b, size_t p,
                        double clock, double dt)
{
    if (!b->enabled)
        return;
    const size_t D = s->D;
    const double *bpos = s->avec + b->vec, *n = bpos + D;
    double *pos = s->pos + p * D, *v = s->vel + p * D;
    const double *a = s->acc + p * D;
    double x = -s->radius[p], u = 0, w = 0;
    for (size_t i = 0; i < D; i++) {
        x = x + (pos[i] - bpos[i]) * n[i];
        u = u + v[i] * n[i];
        w = w + a[i] * n[i];
    }
    if (x >= 0)
        return;
    double r = x / u;
    if (u >= 0 || r > dt) {
        for (size_t i = 0; i < D; i++)
            pos[i] = pos[i] - x * n[i];
        return;
    }
    for (size_t i = 0; i < D; i++)
        pos[i] = pos[i] - r * v[i];
    for (size_t i = 0; i < D; i++)
        v[i] = (v[i] - r * a[i]) * b->restitution;
    double u2 = 0;
    for (size_t i = 0; i < D; i++)
        u2 = u2 + v[i] * n[i];
    for (size_t i = 0; i < D; i++)
        v[i] = v[i] - 2 * u2 * n[i];
    if (w < 0 && u2 / w < r)
        r = u2 / w;
    lit_step(s, p, clock, r);
}

/* The group of [g]'s parent, or NULL for the !physics node's own group. */
static const PhysGroup *parent_of(const PhysSystem *s, const PhysGroup *g)
{
    return g->parent < 0 ? NULL : &s->groups[g->parent];
}

void phys_literal_particle_pass(PhysSystem *s, const PhysGroup *g,
                                double clock, double delta, bool more)
{
    const size_t D = s->D;
    for (size_t q = 0; q < g->npart; q++) {
        const size_t p = g->pstart + q;
        if (s->anchor[p])
            continue;
        /* for f in PF: apply f(p, delta) */
        for (const PhysGroup *A = g; A; A = parent_of(s, A))
            for (size_t j = 0; j < A->part_n; j++)
                lit_apply(s, &s->ap[s->gidx[A->part_off + j]], p, delta);
        /* for b in B: b.distance(p) */
        for (const PhysGroup *A = g; A; A = parent_of(s, A))
            for (size_t j = 0; j < A->bar_n; j++)
                lit_barrier_distance(s, &s->ap[s->gidx[A->bar_off + j]], p);
        lit_step(s, p, clock, delta);
        /* for b in B: b.rebound(p, clock, delta) */
        for (const PhysGroup *A = g; A; A = parent_of(s, A))
            for (size_t j = 0; j < A->bar_n; j++)
                lit_rebound(s, &s->ap[s->gidx[A->bar_off + j]], p, clock, delta);
        /* if more: p.force = p.own */
        if (more)
            for (size_t i = 0; i < D; i++)
                s->force[p * D + i] = s->own[p * D + i];
    }
}
