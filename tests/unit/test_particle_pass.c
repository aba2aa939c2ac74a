/* test_particle_pass.c: property test of the two routes of the particle pass.
 *
 * What it tests. The particle pass of PHYSICS-ENGINE.md §4 (the
 * per-particle appliers !drag, !buoyancy, !constant, !random and !field,
 * the barrier soft forces, the integration step and the barrier rebounds)
 * has two implementations: the specialised route of lib/physics/step.c
 * (compiled once for each D of 1..3 and once for any D; a group of 1024
 * particles or more split over threads unless a !random applier is in its
 * chain) and the literal route of lib/physics/literal.c (one particle at a
 * time, D known only at run time, written as the spec reads), chosen with
 * phys_set_particles(). They must give the same bits, with the documented
 * physics and with Flitter 1.0.0b28's (PhysicsFrame.upstream), which
 * differ at four places of the particle pass and of collection.
 *
 * Why. The simulations are chaotic and the goldens are compared bit for
 * bit, so an ulp anywhere shows up frames later. The specialised copies
 * give the compiler room to rewrite the arithmetic: gcc turned drag's
 * pow(radius, 2.0) into radius*radius in the D = 3 copy, which differs
 * from glibc's pow by an ulp for about 1 radius in 1,200 (d9a4d48). So
 * !drag and !buoyancy are common in D = 3..5, with many distinct
 * non-round radii, strengths that keep the drag below its cap, and enough
 * steps for an ulp in a force to reach a velocity's bits.
 *
 * How. From each seed a splitmix64 generator builds a random !physics
 * system; the same frames (time 0, 0.25, ... at fps 4; the resolution
 * varies, so a frame takes one to seven steps, sometimes with a partial
 * last one) run through the reference (naive pair loop, literal particle pass,
 * one thread) and the fast route (grid/tiled pairs, specialised particle
 * pass) on one thread, and on two threads for some systems; the whole
 * state dictionaries must hold the same keys with the same bits (memcmp of
 * the doubles). A failure names the seed, the physics mode, the thread
 * count and the state entry; FLITTER_PROPTEST_SEED=S reruns that one
 * system. FLITTER_PROPTEST_SYSTEMS=N sets how many systems run in all
 * (default 50,000: 60 to 90 s in the debugoptimized build on two cores;
 * one in 50 is medium and one in 250 big, the rest small).
 *
 * The systems: D = 1..5; 1..60 particles (most; a few more in
 * subgroups), 100..600 (some), 1024..2000 in one group (a few, with pair
 * appliers of bounded reach only, as the reference pair loop is O(n^2),
 * and mostly without !random, so the fast pass splits them over threads;
 * the others have a !random at the top, which keeps them on one); every per-particle applier with its
 * options (flow, density, gravity, force, acceleration, direction; vectors
 * of length D, of length 1 (repeated) and of a wrong length (ignored)),
 * random strengths (sometimes the default) and eases on both sides of the
 * clock reached in the run; several !random appliers in one chain;
 * barriers inside the particle box with axis, oblique, diagonal and zero
 * normals, restitution, power, min/minimum, max/maximum, only max,
 * min <= 0, with particles aimed at them; particles with zero or nonzero
 * radius, mass and charge (negative too), their own eased force, anchors;
 * a speed of light that clamps; !distance with min/max/fixed/power, the
 * pair appliers with power, overlap and max_distance; groups nested two
 * deep with their own appliers and barriers (chains of parent appliers);
 * a `run` that changes in a later frame; NaN and infinite elements in
 * some positions, velocities and forces.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "node.h"
#include "physics.h"
#include "scene.h"
#include "state.h"
#include "value.h"

#define MAX_D 5

/* The number of systems when FLITTER_PROPTEST_SYSTEMS is not set. */
#define DEFAULT_SYSTEMS 50000

/* Seeds: small systems count up from 1, medium ones from MEDIUM_SEED, big
 * ones from BIG_SEED; the range of a seed says which kind it builds. */
#define MEDIUM_SEED 1000000u
#define BIG_SEED 2000000u

/* Frame time step and frame rate of every run (time = 0.25 * frame). */
#define FRAME_TIME 0.25
#define FPS 4.0

/* The state prefix of every system. */
#define PREFIX 7.0

/* ------------------------------------------------------------------ */
/* Random systems                                                      */
/* ------------------------------------------------------------------ */

/* What the generator of one system needs to know. */
typedef struct Scene {
    size_t D;
    size_t nids;          /* particles so far (ids 0 .. nids-1) */
    double box;           /* side of the box the particles start in */
    double clock_end;     /* the clock at the end of the run */
    double special;       /* chance of a non-finite element in a vector */
    double p_drag;        /* chance that a particle applier is !drag or !buoyancy */
    bool no_random;       /* leave out !random (the fast pass may split) */
    bool bounded;         /* pair appliers of bounded reach only */
} Scene;

/* The normal of the nearest barrier in a group's chain, which its
 * particles are sometimes sent towards. */
typedef struct Aim {
    bool set;
    double n[MAX_D];      /* unit normal */
} Aim;

/* Up to MAX_D coordinates, each (uni - 0.5) * side. */
static void rcoords(Rng *r, size_t D, double side, double *x)
{
    for (size_t i = 0; i < D; i++)
        x[i] = (uni(r) - 0.5) * side;
}

/* A random D-vector in a box of side [side]; with chance [special] one
 * element NaN or infinite. */
static Vec *rvec(Rng *r, size_t D, double side, double special)
{
    static const double odd[] = {NAN, INFINITY, -INFINITY};
    double x[MAX_D];
    rcoords(r, D, side, x);
    if (chance(r, special))
        x[below(r, D)] = odd[below(r, 3)];
    return vec_from_nums(x, (uint32_t)D);
}

/* A vector attribute as fvec() reads it (PHYSICS-ENGINE.md §1): mostly of
 * length D, sometimes of length 1 (repeated to D), sometimes of a wrong
 * length (the default). */
static void set_fvec(Rng *r, const Scene *sc, Node *n, const char *name, double side)
{
    double u = uni(r);
    if (u < 0.15) {
        set(n, name, num((uni(r) - 0.5) * side));
    } else if (u < 0.2) {
        double x[MAX_D + 1];
        rcoords(r, sc->D + 1, side, x);
        set(n, name, vec_from_nums(x, (uint32_t)sc->D + 1));
    } else {
        set(n, name, rvec(r, sc->D, side, 0));
    }
}

/* `strength` in [lo, hi), or the default 1 now and then. */
static void set_strength(Rng *r, Node *n, double lo, double hi)
{
    if (!chance(r, 0.12))
        set(n, "strength", num(lo + uni(r) * (hi - lo)));
}

/* `ease` now and then: mostly somewhere in 0 .. 1.6 times the clock at
 * the end of the run, so some frames are eased and some are not;
 * sometimes 0 or negative (no easing). */
static void maybe_ease(Rng *r, const Scene *sc, Node *n)
{
    double u = uni(r);
    if (u < 0.3)
        set(n, "ease", num(uni(r) * 1.6 * sc->clock_end));
    else if (u < 0.34)
        set(n, "ease", num(chance(r, 0.5) ? 0 : -uni(r)));
}

/* A !drag, !buoyancy, !constant, !random or !field applier. */
static void add_particle_applier(Rng *r, Scene *sc, Node *g)
{
    size_t kind = chance(r, sc->p_drag) ? below(r, 2) : 2 + below(r, 3);
    if (kind == 3 && sc->no_random)
        kind = 4;
    Node *a;
    switch (kind) {
    case 0:
        /* k = strength * speed * radius^(D-1) stays mostly below its cap
         * mass/delta, so the radius reaches the velocity's bits */
        a = add(g, "drag");
        set_strength(r, a, 0.02, 2);
        if (chance(r, 0.5))
            set_fvec(r, sc, a, "flow", 3);
        break;
    case 1:
        a = add(g, "buoyancy");
        set_strength(r, a, 0.1, 3);
        if (chance(r, 0.7))
            set(a, "density", num(uni(r) * 3));
        if (chance(r, 0.6))
            set_fvec(r, sc, a, "gravity", 4);
        break;
    case 2:
        a = add(g, "constant");
        set_strength(r, a, -1, 2);
        if (chance(r, 0.6))
            set_fvec(r, sc, a, "force", 4);
        if (chance(r, 0.6))
            set_fvec(r, sc, a, "acceleration", 4);
        break;
    case 3:
        a = add(g, "random");
        set_strength(r, a, 0, 3);
        break;
    default:
        a = add(g, "field");
        set_strength(r, a, -2, 3);
        if (chance(r, 0.85))
            set_fvec(r, sc, a, "direction", 4);
        break;
    }
    maybe_ease(r, sc, a);
}

/* `min`/`minimum` and `max`/`maximum` of a !distance or !barrier: either,
 * both or neither, under either name; a min sometimes 0 or negative. */
static void set_limits(Rng *r, Node *n, double lo, double hi, bool nonpositive)
{
    size_t which = below(r, 4);   /* 0 none, 1 min, 2 max, 3 both */
    double mn = lo + uni(r) * (hi - lo);
    if (nonpositive && chance(r, 0.3))
        mn = chance(r, 0.5) ? 0 : -uni(r);
    if (which & 1)
        set(n, chance(r, 0.5) ? "min" : "minimum", num(mn));
    if (which & 2) {
        double mx = (mn > 0 ? mn : lo) + uni(r) * (hi - lo);
        if (chance(r, 0.1))
            mx = -uni(r);
        set(n, chance(r, 0.5) ? "max" : "maximum", num(mx));
    }
}

static void maybe_power(Rng *r, Node *n)
{
    static const double powers[] = {0, 0.5, 1, 1.5, 2, 3};
    if (chance(r, 0.4))
        set(n, "power", num(powers[below(r, 6)]));
}

/* A !barrier inside the particle box; its normal (if usable) becomes the
 * group's aim. */
static void add_barrier(Rng *r, Scene *sc, Node *g, Aim *aim)
{
    const size_t D = sc->D;
    Node *b = add(g, "barrier");
    double x[MAX_D], m[MAX_D] = {0};
    rcoords(r, D, 0.6 * sc->box, x);
    set(b, "position", vec_from_nums(x, (uint32_t)D));
    size_t kind = below(r, 10);
    if (kind == 0) {
        /* zero normal: the barrier does nothing */
        set(b, "normal", vec_from_nums(m, (uint32_t)D));
    } else if (kind <= 3) {
        m[below(r, D)] = chance(r, 0.5) ? 1 : -(0.5 + uni(r));
        set(b, "normal", vec_from_nums(m, (uint32_t)D));
    } else if (kind == 4) {
        /* a single number: the diagonal */
        double c = chance(r, 0.5) ? 1 : -2.5;
        for (size_t i = 0; i < D; i++)
            m[i] = c;
        set(b, "normal", num(c));
    } else {
        rcoords(r, D, 2, m);
        set(b, "normal", vec_from_nums(m, (uint32_t)D));
    }
    double mm = 0;
    for (size_t i = 0; i < D; i++)
        mm += m[i] * m[i];
    if (mm > 1e-6) {
        aim->set = true;
        for (size_t i = 0; i < D; i++)
            aim->n[i] = m[i] / sqrt(mm);
    }
    if (chance(r, 0.8))
        set(b, "restitution", num(uni(r) * 1.3 - 0.1));
    maybe_power(r, b);
    set_strength(r, b, 0.5, 20);
    set_limits(r, b, 0.1, 0.4 * sc->box, true);
    maybe_ease(r, sc, b);
}

/* A !distance between two particles made so far (or one not made yet). */
static void add_distance(Rng *r, Scene *sc, Node *g)
{
    if (!sc->nids)
        return;
    Node *d = add(g, "distance");
    set(d, "from", num((double)below(r, sc->nids)));
    set(d, "to", num((double)below(r, sc->nids + 2)));
    if (chance(r, 0.25))
        set(d, "fixed", num(0.5 + uni(r) * 2));
    else
        set_limits(r, d, 0.2, 3, false);
    maybe_power(r, d);
    set_strength(r, d, 0.5, 10);
    maybe_ease(r, sc, d);
}

/* A pair applier; with sc->bounded, only ones of bounded reach. */
static void add_pair_applier(Rng *r, Scene *sc, Node *g)
{
    static const char *const kinds[] = {"collision", "adhesion", "gravity", "electrostatic"};
    const char *k = kinds[below(r, 4)];
    Node *a = add(g, k);
    set_strength(r, a, 0.5, 15);
    bool unlimited = !strcmp(k, "gravity") || !strcmp(k, "electrostatic");
    if ((unlimited && sc->bounded) || chance(r, unlimited ? 0.5 : 0.25))
        set(a, "max_distance", num(0.5 + uni(r) * 3));
    if (!strcmp(k, "collision"))
        maybe_power(r, a);
    if (!strcmp(k, "adhesion") && chance(r, 0.5))
        set(a, "overlap", num(uni(r) * 1.4 - 0.2));
    maybe_ease(r, sc, a);
}

/* [n] particles (anchors now and then) in group [g], some sent towards
 * the barrier of [aim]. */
static void add_particles(Rng *r, Scene *sc, Node *g, size_t n, const Aim *aim)
{
    const size_t D = sc->D;
    for (size_t i = 0; i < n; i++) {
        /* the first particle of a system is finite, so its state is kept */
        double special = sc->nids ? sc->special : 0;
        Node *p = add(g, chance(r, 0.05) ? "anchor" : "particle");
        set(p, "id", num((double)sc->nids++));
        set(p, "position", rvec(r, D, sc->box, special));
        double v[MAX_D];
        rcoords(r, D, 4, v);
        if (aim->set && chance(r, 0.6)) {
            double speed = 1 + 3 * uni(r);
            for (size_t k = 0; k < D; k++)
                v[k] -= speed * aim->n[k];
        }
        if (chance(r, special / 2))
            v[below(r, D)] = chance(r, 0.5) ? NAN : -INFINITY;
        if (!chance(r, 0.05))
            set(p, "velocity", vec_from_nums(v, (uint32_t)D));
        /* non-round radii: 0.2 + uni has 52 random bits */
        double u = uni(r);
        if (u < 0.08)
            set(p, "radius", num(0));
        else if (u > 0.03 + 0.08)
            set(p, "radius", num(0.2 + uni(r)));
        u = uni(r);
        if (u < 0.05)
            set(p, "mass", num(0));
        else if (u > 0.1)
            set(p, "mass", num(0.5 + uni(r)));
        u = uni(r);
        if (u < 0.15)
            set(p, "charge", num(0));
        else if (u > 0.3)
            set(p, "charge", num(2 * uni(r) - 1));
        if (chance(r, 0.25))
            set(p, "force", rvec(r, D, 6, special / 2));
        if (chance(r, 0.2))
            set(p, "ease", num(uni(r) * 1.6 * sc->clock_end));
    }
}

/* Fill group [g] at [depth]: appliers and barriers, [n] particles,
 * subgroups of a few particles (above depth 2), more particles. Returns
 * the aim of its particles ([aim], the chain's, or its own barrier's). */
static Aim fill_group(Rng *r, Scene *sc, Node *g, int depth, size_t n,
                      Aim aim)
{
    size_t na = below(r, 6);
    for (size_t i = 0; i < na; i++) {
        double u = uni(r);
        if (u < 0.45)
            add_particle_applier(r, sc, g);
        else if (u < 0.65)
            add_barrier(r, sc, g, &aim);
        else if (u < 0.75)
            add_distance(r, sc, g);
        else
            add_pair_applier(r, sc, g);
    }
    add_particles(r, sc, g, n, &aim);
    if (depth < 2) {
        size_t ng = below(r, 3);
        for (size_t i = 0; i < ng; i++)
            (void)fill_group(r, sc, add(g, "group"), depth + 1, 1 + below(r, 8), aim);
    }
    if (chance(r, 0.3))
        add_particles(r, sc, g, 1 + below(r, 6), &aim);
    if (chance(r, 0.3))
        add_distance(r, sc, g);
    return aim;
}

/* One generated system and how it is run. */
typedef struct System {
    uint64_t seed;
    size_t D;
    size_t particles;     /* particles and anchors */
    int frames;
    int run_frame;        /* first frame given root[1] (frames: never) */
    bool threads2;        /* also compare the fast route on two threads */
    Node *root[2];        /* the !physics node; the same with `run` changed */
} System;

/* Steps in a frame of 0.25: 5; 3 (perhaps a tiny fourth, from rounding);
 * 2.5 and 3.57.. (a partial last step); 1; 1 (of 0.25, below the
 * resolution); 6.25; 4. */
static const double resolutions[] = {0.05, 0.25 / 3, 0.1, 0.07, 0.25, 0.3, 0.04, 0.0625};

static void make_system(System *sys, uint64_t seed)
{
    Rng r = {seed};
    const bool big = seed >= BIG_SEED, medium = !big && seed >= MEDIUM_SEED;
    memset(sys, 0, sizeof *sys);
    sys->seed = seed;
    sys->frames = big ? 3 + (int)below(&r, 2) : 4 + (int)below(&r, 2);
    sys->threads2 = big || medium || chance(&r, 0.25);
    Scene sc = {.D = 1 + below(&r, MAX_D)};
    sc.clock_end = FRAME_TIME * (sys->frames - 1);
    sc.special = chance(&r, 0.25) ? (big ? 0.003 : 0.03) : 0;
    sc.p_drag = sc.D >= 3 ? 0.7 : 0.35;
    sc.no_random = big ? chance(&r, 0.7) : chance(&r, 0.2);
    sc.bounded = big;
    size_t n = big ? 1024 + below(&r, 977) : medium ? 100 + below(&r, 501)
                                                     : 1 + below(&r, 60);
    /* a density that keeps many discs touching */
    double nn = (double)(n < 30 ? 30 : n);
    sc.box = pow(nn, 1.0 / (double)sc.D) * (sc.D == 1 ? 0.8 : 1.4);

    Node *ph = mk("physics");
    set(ph, "state", num(PREFIX));
    set(ph, "dimensions", num((double)sc.D));
    set(ph, "resolution", num(resolutions[below(&r, sizeof resolutions / sizeof *resolutions)]));
    if (chance(&r, 0.25))
        set(ph, "speed_of_light", num(1 + 3 * uni(&r)));
    sys->run_frame = sys->frames;
    double run_after = 0;
    if (chance(&r, 0.2)) {
        sys->run_frame = 2 + (int)below(&r, (size_t)sys->frames - 2);
        if (chance(&r, 0.5))
            set(ph, "run", num(0.5));   /* floored: 0 */
        run_after = 1 + 3 * uni(&r);
    }
    Aim aim = {0};
    if (big && !sc.no_random) {
        /* a !random in the chain of every group: the fast pass keeps the
         * big group on one thread, whatever the thread count */
        Node *a = add(ph, "random");
        set_strength(&r, a, 0, 3);
        maybe_ease(&r, &sc, a);
    }
    if (big && chance(&r, 0.5)) {
        /* the big group one level down, under the root's appliers and
         * barriers, beside a few particles of the root */
        aim = fill_group(&r, &sc, ph, 2, 1 + below(&r, 20), aim);
        (void)fill_group(&r, &sc, add(ph, "group"), 1, n, aim);
    } else {
        (void)fill_group(&r, &sc, ph, 0, n, aim);
    }
    sys->D = sc.D;
    sys->particles = sc.nids;
    sys->root[0] = ph;
    /* the same children under a root whose `run` has changed */
    Node *ph2 = mk("physics");
    for (uint32_t i = 0; i < ph->nattrs; i++)
        node_set_attr(ph2, ph->attrs[i].name, vec_retain(ph->attrs[i].value));
    set(ph2, "run", num(run_after));
    for (uint32_t i = 0; i < ph->nchildren; i++)
        node_append(ph2, ph->children[i]);
    sys->root[1] = ph2;
}

static void free_system(System *sys)
{
    node_release(sys->root[0]);
    node_release(sys->root[1]);
}

/* ------------------------------------------------------------------ */
/* Running and comparing                                               */
/* ------------------------------------------------------------------ */

/* Run the frames of [sys] in a fresh world: [reference] true is the naive
 * pair loop with the literal particle pass, false the fast routes. */
static StateDict *simulate(const System *sys, bool reference, unsigned threads,
                           bool upstream)
{
    PhysicsWorld *w = phys_new();
    phys_set_pairs(w, reference);
    phys_set_particles(w, reference);
    phys_set_threads(w, threads);
    StateDict *sd = state_new();
    for (int f = 0; f < sys->frames; f++) {
        PhysicsFrame fr = {.time = FRAME_TIME * f, .fps = FPS, .realtime = false,
                           .performance = 2, .upstream = upstream};
        Node *root = sys->root[f >= sys->run_frame];
        phys_run_frame(w, &root, 1, sd, &fr);
    }
    phys_free(w);
    return sd;
}

/* The key [k] as text, for failure messages (the symbols the engine
 * writes by name). */
static void key_text(const Vec *k, char *buf, size_t size)
{
    static const char *const symbols[] = {"velocity", "clock", "last", "run", "iteration"};
    size_t used = 0;
    buf[0] = 0;
    for (uint32_t i = 0; k->kind == VEC_NUM && i < k->len && used + 32 < size; i++) {
        double x = vec_cnums(k)[i];
        const char *name = NULL;
        for (size_t j = 0; j < sizeof symbols / sizeof *symbols; j++)
            if (x == symbol_value(symbols[j], strlen(symbols[j])))
                name = symbols[j];
        if (name)
            used += (size_t)snprintf(buf + used, size - used, "%s:%s", i ? ";" : "", name);
        else
            used += (size_t)snprintf(buf + used, size - used, "%s%.17g", i ? ";" : "", x);
    }
}

/* Both dictionaries hold the same keys with bit-identical values. */
static void assert_same_state(const StateDict *ref, const StateDict *fast,
                              const System *sys, bool upstream, unsigned threads)
{
    const char *mode = upstream ? "upstream" : "documented";
    size_t na, nb;
    StateEntry *ea = state_entries(ref, &na);
    StateEntry *eb = state_entries(fast, &nb);
    free(eb);
    if (na != nb) {
        free(ea);
        fail_msg("seed %llu (%s physics, %u threads): %zu state entries on the "
                 "reference route, %zu on the fast one",
                 (unsigned long long)sys->seed, mode, threads, na, nb);
    }
    for (size_t i = 0; i < na; i++) {
        const Vec *va = ea[i].value;
        const Vec *vb = state_get(fast, ea[i].key);
        bool same = vb && va->kind == VEC_NUM && vb->kind == VEC_NUM &&
                    va->len == vb->len &&
                    memcmp(vec_cnums(va), vec_cnums(vb), va->len * sizeof(double)) == 0;
        if (!same) {
            char key[200];
            key_text(ea[i].key, key, sizeof key);
            uint32_t e = 0;
            while (vb && e < va->len && e < vb->len &&
                   !memcmp(vec_cnums(va) + e, vec_cnums(vb) + e, sizeof(double)))
                e++;
            double x = e < va->len ? vec_cnums(va)[e] : NAN;
            double y = vb && e < vb->len ? vec_cnums(vb)[e] : NAN;
            free(ea);
            fail_msg("seed %llu (D=%zu, %zu particles, %s physics, %u threads): "
                     "state[%s] element %u is %a on the reference route, %a on "
                     "the fast one%s",
                     (unsigned long long)sys->seed, sys->D, sys->particles, mode,
                     threads, key, e, x, y, vb ? "" : " (missing)");
        }
    }
    free(ea);
}

/* Particles that head into a top-level barrier at the start and move away
 * from it at the end (velocity . normal from < 0 to > 0), in [sd]: the
 * generator's evidence that rebounds happen. */
static size_t turned_at_barriers(const System *sys, const StateDict *sd)
{
    const Node *ph = sys->root[0];
    const size_t D = sys->D;
    const double vsym = symbol_value("velocity", 8);
    size_t turned = 0;
    for (uint32_t b = 0; b < ph->nchildren; b++) {
        const Node *bar = ph->children[b];
        const Vec *m = node_attr(bar, "normal");
        if (!node_is(bar, "barrier") || !m || m->len != D)
            continue;
        const double *n = vec_cnums(m);
        /* every particle of the system: the top-level chain reaches all */
        const Node *stack[8];
        uint32_t at[8];
        int depth = 0;
        stack[0] = ph;
        at[0] = 0;
        while (depth >= 0) {
            const Node *g = stack[depth];
            if (at[depth] >= g->nchildren) {
                depth--;
                continue;
            }
            const Node *c = g->children[at[depth]++];
            if (node_is(c, "group") && depth < 7) {
                stack[++depth] = c;
                at[depth] = 0;
                continue;
            }
            const Vec *v0 = node_attr(c, "velocity");
            const Vec *id = node_attr(c, "id");
            if (!node_is(c, "particle") || !v0 || v0->len != D || !id)
                continue;
            double key[3] = {PREFIX, vec_scalar(id), vsym};
            Vec *k = vec_from_nums(key, 3);
            const Vec *v1 = state_get(sd, k);
            vec_release(k);
            if (!v1 || v1->len != D)
                continue;
            double u0 = 0, u1 = 0;
            for (size_t i = 0; i < D; i++) {
                u0 += vec_cnums(v0)[i] * n[i];
                u1 += vec_cnums(v1)[i] * n[i];
            }
            turned += u0 < 0 && u1 > 0;
        }
    }
    return turned;
}

/* Totals over the tests of one run (main prints them). */
typedef struct Totals {
    size_t systems;
    size_t upstream;      /* systems also run with upstream physics */
    size_t threads2;      /* systems also run on two threads */
    size_t max_particles;
    size_t per_d[MAX_D + 1];
    size_t turned;        /* particles turned by top-level barriers */
} Totals;

/* Run [sys] through both routes (one thread, and two when the system asks
 * for it) in the documented mode, and in the upstream mode too if
 * [upstream]; count it in [t]. */
static void check_system(const System *sys, bool upstream, Totals *t)
{
    for (int mode = 0; mode <= (int)upstream; mode++) {
        StateDict *ref = simulate(sys, true, 1, mode);
        /* the five keys of the system and at least one particle's two */
        assert_true(state_count(ref) > 6);
        if (!mode)
            t->turned += turned_at_barriers(sys, ref);
        StateDict *fast = simulate(sys, false, 1, mode);
        assert_same_state(ref, fast, sys, mode, 1);
        state_free(fast);
        if (sys->threads2) {
            fast = simulate(sys, false, 2, mode);
            assert_same_state(ref, fast, sys, mode, 2);
            state_free(fast);
        }
        state_free(ref);
    }
    t->systems++;
    t->upstream += upstream;
    t->threads2 += sys->threads2;
    t->per_d[sys->D]++;
    if (sys->particles > t->max_particles)
        t->max_particles = sys->particles;
}

/* FLITTER_PROPTEST_SYSTEMS, or DEFAULT_SYSTEMS. */
static size_t system_count(void)
{
    const char *s = getenv("FLITTER_PROPTEST_SYSTEMS");
    if (s && *s) {
        char *end;
        unsigned long long n = strtoull(s, &end, 10);
        if (*end == 0)
            return (size_t)n;
    }
    return DEFAULT_SYSTEMS;
}

/* FLITTER_PROPTEST_SEED if set (then only that system runs). */
static bool single_seed(uint64_t *seed)
{
    const char *s = getenv("FLITTER_PROPTEST_SEED");
    if (!s || !*s)
        return false;
    char *end;
    *seed = strtoull(s, &end, 10);
    return *end == 0;
}

/* Run the systems of seeds first .. first+n-1 (with FLITTER_PROPTEST_SEED
 * set: that seed alone, if it lies in [first, end)); every other one also
 * with upstream physics. Returns this call's totals, added to [t]. */
static Totals run_systems(uint64_t first, uint64_t end, size_t n,
                          const char *what, Totals *t)
{
    Totals mine = {0};
    uint64_t only;
    if (single_seed(&only)) {
        n = only >= first && only < end;
        first = only;
    }
    for (uint64_t seed = first; seed < first + n; seed++) {
        System sys;
        make_system(&sys, seed);
        check_system(&sys, seed % 2 == 1, &mine);
        free_system(&sys);
    }
    printf("%s: %zu systems (D=1..5: %zu %zu %zu %zu %zu; up to %zu particles; "
           "%zu also upstream, %zu also on 2 threads; %zu particles turned at "
           "barriers) same bits on both routes\n",
           what, mine.systems, mine.per_d[1], mine.per_d[2], mine.per_d[3],
           mine.per_d[4], mine.per_d[5], mine.max_particles, mine.upstream,
           mine.threads2, mine.turned);
    fflush(stdout);
    t->systems += mine.systems;
    t->upstream += mine.upstream;
    t->threads2 += mine.threads2;
    t->turned += mine.turned;
    for (size_t d = 1; d <= MAX_D; d++)
        t->per_d[d] += mine.per_d[d];
    if (mine.max_particles > t->max_particles)
        t->max_particles = mine.max_particles;
    return mine;
}

/* How the systems divide: one in 50 medium, one in 250 big, the rest
 * small (the three kinds then take about the same time). */
static size_t medium_count(void) { return system_count() / 50; }
static size_t big_count(void) { return system_count() / 250; }
static size_t small_count(void)
{
    return system_count() - medium_count() - big_count();
}

/* ------------------------------------------------------------------ */
/* Tests                                                               */
/* ------------------------------------------------------------------ */

/* 1..60 particles: every feature combination shows up somewhere. */
static void test_small_systems(void **st)
{
    Totals mine = run_systems(1, MEDIUM_SEED, small_count(), "small systems", *st);
    /* the generator sends particles into barriers (a check of the test:
     * with enough systems, some must turn) */
    if (mine.systems >= 100)
        assert_true(mine.turned > 0);
}

/* 100..600 particles, two threads too. */
static void test_medium_systems(void **st)
{
    (void)run_systems(MEDIUM_SEED, BIG_SEED, medium_count(), "medium systems", *st);
}

/* 1024..2000 particles in one group: the fast pass splits it over two
 * threads (unless a !random is in its chain). */
static void test_big_systems(void **st)
{
    (void)run_systems(BIG_SEED, UINT64_MAX, big_count(), "big systems", *st);
}

/* One system of D = 3 whose particles pass through a !drag (and a
 * !buoyancy): one radius one ulp larger changes the final state, so a
 * route that computes pow(radius, 2) an ulp off for one radius in 1,200
 * is seen. */
static void test_radius_ulp_reaches_state(void **st)
{
    (void)st;
    for (int upstream = 0; upstream <= 1; upstream++) {
        StateDict *sd[2];
        for (int bump = 0; bump <= 1; bump++) {
            Rng r = {77};
            Node *ph = mk("physics");
            set(ph, "state", num(PREFIX));
            set(ph, "dimensions", num(3));
            set(ph, "resolution", num(0.05));
            set(add(ph, "drag"), "strength", num(0.4));
            set(add(ph, "buoyancy"), "strength", num(0.5));
            for (int i = 0; i < 8; i++) {
                Node *p = add(ph, "particle");
                set(p, "id", num(i));
                set(p, "position", rvec(&r, 3, 5, 0));
                set(p, "velocity", rvec(&r, 3, 6, 0));
                double radius = 0.2 + uni(&r);
                set(p, "radius", num(bump && i == 3 ? nextafter(radius, 2) : radius));
            }
            System sys = {.seed = 77, .D = 3, .particles = 8, .frames = 5,
                          .run_frame = 5, .root = {ph, ph}};
            sd[bump] = simulate(&sys, true, 1, upstream);
            StateDict *fast = simulate(&sys, false, 1, upstream);
            assert_same_state(sd[bump], fast, &sys, upstream, 1);
            state_free(fast);
            node_release(ph);
        }
        size_t n;
        StateEntry *e = state_entries(sd[0], &n);
        bool differs = false;
        for (size_t i = 0; i < n; i++) {
            const Vec *v = state_get(sd[1], e[i].key);
            if (!v || v->len != e[i].value->len ||
                memcmp(vec_cnums(v), vec_cnums(e[i].value), v->len * sizeof(double)))
                differs = true;
        }
        free(e);
        assert_true(differs);
        state_free(sd[0]);
        state_free(sd[1]);
    }
}

/* A particle sent at a barrier bounces off it: its velocity along the
 * normal changes sign and it ends on the barrier's side, on both routes
 * with the same bits; D = 1..5, oblique normals. */
static void test_barrier_rebound(void **st)
{
    (void)st;
    for (size_t D = 1; D <= MAX_D; D++) {
        for (int upstream = 0; upstream <= 1; upstream++) {
            Node *ph = mk("physics");
            set(ph, "state", num(PREFIX));
            set(ph, "dimensions", num((double)D));
            set(ph, "resolution", num(0.05));
            double m[MAX_D], pos[MAX_D], vel[MAX_D], mm = 0;
            for (size_t i = 0; i < D; i++) {
                m[i] = 1 + 0.5 * (double)i;
                mm += m[i] * m[i];
            }
            for (size_t i = 0; i < D; i++) {
                pos[i] = 0.5 * m[i] / sqrt(mm);   /* 0.5 in front */
                vel[i] = -3 * m[i] / sqrt(mm);    /* 3 towards it */
            }
            Node *b = add(ph, "barrier");
            set(b, "position", vec_from_nums((double[MAX_D]){0}, (uint32_t)D));
            set(b, "normal", vec_from_nums(m, (uint32_t)D));
            set(b, "restitution", num(0.8));
            Node *p = add(ph, "particle");
            set(p, "id", num(1));
            set(p, "radius", num(0.25));
            set(p, "position", vec_from_nums(pos, (uint32_t)D));
            set(p, "velocity", vec_from_nums(vel, (uint32_t)D));
            System sys = {.seed = 0, .D = D, .particles = 1, .frames = 3,
                          .run_frame = 3, .root = {ph, ph}};
            StateDict *ref = simulate(&sys, true, 1, upstream);
            StateDict *fast = simulate(&sys, false, 1, upstream);
            assert_same_state(ref, fast, &sys, upstream, 1);
            assert_int_equal(turned_at_barriers(&sys, ref), 1);
            Vec *k = vec_from_nums((double[]){PREFIX, 1}, 2);
            const Vec *x = state_get(ref, k);
            vec_release(k);
            assert_non_null(x);
            double side = -0.25;
            for (size_t i = 0; i < D; i++)
                side += vec_cnums(x)[i] * m[i] / sqrt(mm);
            assert_true(side >= 0);
            state_free(ref);
            state_free(fast);
            node_release(ph);
        }
    }
}

int main(void)
{
    Totals totals = {0};
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_radius_ulp_reaches_state),
        cmocka_unit_test(test_barrier_rebound),
        cmocka_unit_test_prestate(test_small_systems, &totals),
        cmocka_unit_test_prestate(test_medium_systems, &totals),
        cmocka_unit_test_prestate(test_big_systems, &totals),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    if (!failed)
        printf("particle pass: %zu systems (D=1..5, up to %zu particles, %zu with "
           "upstream physics) same bits on both routes\n",
           totals.systems, totals.max_particles, totals.upstream);
    fflush(stdout);
    return failed;
}
