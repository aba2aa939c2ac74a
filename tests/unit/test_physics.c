/* test_physics.c: unit tests of the !physics engine (lib/physics).
 *
 * Each test builds a small !physics node tree with node_new/node_set_attr/
 * node_append, runs frames through phys_run_frame and checks the state
 * dictionary. Most tests run frame 0 at time 0 (no step: :last starts equal
 * to time) and frame 1 at time 0.25 with resolution 0.25, i.e. exactly one
 * step of dt = 0.25; the inputs are chosen so that the expected values of
 * PHYSICS-ENGINE.md §4 are exact doubles, written out by hand and compared
 * with ==. Where an intermediate is inexact, the expectation is computed with
 * the same operations in the same order as the spec.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "node.h"
#include "physics.h"
#include "state.h"
#include "value.h"
#include "streams.h"

/* ------------------------------------------------------------------ */
/* Helpers                                                             */
/* ------------------------------------------------------------------ */

#define EQ(a, b)                                                        \
    do {                                                                \
        double a_ = (a), b_ = (b);                                      \
        if (!(a_ == b_))                                                \
            fail_msg("%s = %.17g, expected %.17g", #a, a_, b_);         \
    } while (0)

static Node *mk(const char *kind)
{
    Str *k = str_from(kind);
    Node *n = node_new(k);
    str_release(k);
    return n;
}

/* Set attribute [name] of [n] to [v] (consumes v). */
static void set(Node *n, const char *name, Vec *v)
{
    Str *s = str_from(name);
    node_set_attr(n, s, v);
    str_release(s);
}

static Vec *num(double x) { return vec_num1(x); }
static Vec *nums2(double x, double y) { double d[2] = {x, y}; return vec_from_nums(d, 2); }
static Vec *nums3(double x, double y, double z) { double d[3] = {x, y, z}; return vec_from_nums(d, 3); }
static Vec *sym(const char *name) { return vec_num1(symbol_value(name, strlen(name))); }

/* Append [child] to [parent], dropping our reference; returns child. */
static Node *add(Node *parent, Node *child)
{
    node_append(parent, child);
    node_release(child);
    return child;
}

/* A !physics node with state=:P (symbol [prefix]) and [dims] dimensions. */
static Node *physics(const char *prefix, double dims)
{
    Node *n = mk("physics");
    set(n, "state", sym(prefix));
    set(n, "dimensions", num(dims));
    return n;
}

/* A particle (or anchor) with id=:name and position. */
static Node *particle(Node *parent, const char *kind, const char *id, Vec *pos)
{
    Node *p = mk(kind);
    set(p, "id", sym(id));
    if (pos)
        set(p, "position", pos);
    return add(parent, p);
}

static Node *applier(Node *parent, const char *kind)
{
    return add(parent, mk(kind));
}

typedef struct Fixture {
    PhysicsWorld *w;
    StateDict *sd;
} Fixture;

static int setup(void **st)
{
    Fixture *f = test_malloc(sizeof *f);
    f->w = phys_new();
    f->sd = state_new();
    *st = f;
    return 0;
}

static int teardown(void **st)
{
    Fixture *f = *st;
    phys_free(f->w);
    state_free(f->sd);
    test_free(f);
    return 0;
}

/* Run one lockstep frame of the given !physics nodes at [time]. */
static void frame_n(Fixture *f, Node **nodes, size_t n, double time, double fps)
{
    PhysicsFrame fr = {.time = time, .fps = fps, .realtime = false,
                       .performance = 2};
    phys_run_frame(f->w, nodes, n, f->sd, &fr);
}

static void frame(Fixture *f, Node *phys, double time)
{
    frame_n(f, &phys, 1, time, 4);   /* fps 4: default resolution 0.25 */
}

/* Frame 0 at time 0 then frame 1 at time 0.25: exactly one 0.25 step. */
static void one_step(Fixture *f, Node *phys)
{
    frame(f, phys, 0);
    frame(f, phys, 0.25);
}

/* Key P;a[;b] from symbols (b may be NULL). */
static Vec *key(const char *p, const char *a, const char *b)
{
    Vec *parts[3] = {sym(p), a ? sym(a) : NULL, b ? sym(b) : NULL};
    Vec *k = vec_compose(parts, 3);
    for (int i = 0; i < 3; i++)
        vec_release(parts[i]);
    return k;
}

/* The state value under P;a[;b] (borrowed), or NULL. */
static const Vec *sget(Fixture *f, const char *p, const char *a, const char *b)
{
    Vec *k = key(p, a, b);
    const Vec *v = state_get(f->sd, k);
    vec_release(k);
    return v;
}

/* Element [i] of the numeric state value P;a[;b] of length [len]. */
static double sval(Fixture *f, const char *p, const char *a, const char *b,
                   uint32_t len, uint32_t i)
{
    const Vec *v = sget(f, p, a, b);
    if (!vec_is_num(v) || v->len != len)
        fail_msg("state %s;%s%s%s is not a %u-vector", p, a ? a : "",
                 b ? ";" : "", b ? b : "", len);
    return vec_cnums(v)[i];
}

static void sput(Fixture *f, const char *p, const char *a, Vec *v)
{
    Vec *k = key(p, a, NULL);
    state_set(f->sd, k, v);
    vec_release(k);
    vec_release(v);
}

#define POS(f, id, D, i) sval(f, "t", id, NULL, D, i)
#define VEL(f, id, D, i) sval(f, "t", id, "velocity", D, i)

/* ------------------------------------------------------------------ */
/* Force appliers (PHYSICS-ENGINE.md §4), one 0.25 step each           */
/* ------------------------------------------------------------------ */

static void test_distance_max(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    particle(ph, "particle", "a", nums2(0, 0));
    particle(ph, "particle", "b", nums2(4, 0));
    Node *d = applier(ph, "distance");
    set(d, "from", sym("a"));
    set(d, "to", sym("b"));
    set(d, "max", num(2));
    set(d, "strength", num(3));
    one_step(f, ph);
    /* dir = (1,0), k = (4-2)*3 = 6: a.F = +6, b.F = -6; v = F*0.25 */
    EQ(VEL(f, "a", 2, 0), 1.5);
    EQ(VEL(f, "a", 2, 1), 0);
    EQ(POS(f, "a", 2, 0), 0.375);
    EQ(VEL(f, "b", 2, 0), -1.5);
    EQ(POS(f, "b", 2, 0), 3.625);
    node_release(ph);
}

static void test_distance_min_power(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    particle(ph, "particle", "a", num(0));
    particle(ph, "particle", "b", num(1));
    Node *d = applier(ph, "distance");
    set(d, "from", sym("a"));
    set(d, "to", sym("b"));
    set(d, "minimum", num(3));
    set(d, "power", num(2));
    set(d, "strength", num(0.5));
    one_step(f, ph);
    /* k = pow(3-1, 2)*0.5 = 2: a.F -= 2, b.F += 2 */
    EQ(VEL(f, "a", 1, 0), -0.5);
    EQ(POS(f, "a", 1, 0), -0.125);
    EQ(VEL(f, "b", 1, 0), 0.5);
    EQ(POS(f, "b", 1, 0), 1.125);
    node_release(ph);
}

static void test_distance_fixed_missing_id(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    particle(ph, "particle", "a", num(0));
    particle(ph, "particle", "b", num(1));
    Node *d = applier(ph, "distance");       /* fixed=2 pushes apart */
    set(d, "from", sym("a"));
    set(d, "to", sym("b"));
    set(d, "fixed", num(2));
    set(d, "min", num(100));                 /* ignored: fixed wins */
    Node *e = applier(ph, "distance");       /* unknown id: ignored */
    set(e, "from", sym("a"));
    set(e, "to", sym("nobody"));
    set(e, "max", num(0.5));
    one_step(f, ph);
    EQ(VEL(f, "a", 1, 0), -0.25);             /* k = 2-1 = 1 */
    EQ(VEL(f, "b", 1, 0), 0.25);
    node_release(ph);
}

static void test_collision(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    set(particle(ph, "particle", "a", nums2(0, 0)), "radius", num(1));
    set(particle(ph, "particle", "b", nums2(0, 2)), "radius", num(2));
    particle(ph, "particle", "z", nums2(0, 1));  /* radius 0: ignored */
    Node *c = applier(ph, "collision");
    set(c, "strength", num(4));
    set(c, "power", num(2));
    one_step(f, ph);
    /* dist 2 < 3: k = pow(1, 2)*4 = 4 along dir (0,1): a.F -= 4, b.F += 4 */
    EQ(VEL(f, "a", 2, 0), 0);
    EQ(VEL(f, "a", 2, 1), -1);
    EQ(POS(f, "a", 2, 1), -0.25);
    EQ(VEL(f, "b", 2, 1), 1);
    EQ(POS(f, "b", 2, 1), 2.25);
    EQ(VEL(f, "z", 2, 1), 0);
    EQ(POS(f, "z", 2, 1), 1);
    node_release(ph);
}

static void test_gravity(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(particle(ph, "particle", "a", num(0)), "mass", num(2));
    set(particle(ph, "particle", "b", num(4)), "mass", num(4));
    Node *p0 = particle(ph, "particle", "m0", num(10));   /* massless */
    set(p0, "mass", num(0));
    Node *g = applier(ph, "gravity");
    set(g, "strength", num(8));
    set(g, "max_distance", num(5));   /* only the a-b pair is near enough */
    one_step(f, ph);
    /* k = 8*2*4/(4*4) = 4: a.F += 4, b.F -= 4 */
    EQ(VEL(f, "a", 1, 0), 0.5);
    EQ(POS(f, "a", 1, 0), 0.125);
    EQ(VEL(f, "b", 1, 0), -0.25);
    EQ(POS(f, "b", 1, 0), 3.9375);
    EQ(POS(f, "m0", 1, 0), 10);
    node_release(ph);
}

static void test_gravity_overlap_clamp(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *a = particle(ph, "particle", "a", num(0));
    set(a, "mass", num(2));
    set(a, "radius", num(4));
    Node *b = particle(ph, "particle", "b", num(4));
    set(b, "mass", num(4));
    set(b, "radius", num(4));
    set(applier(ph, "gravity"), "strength", num(8));
    one_step(f, ph);
    /* m = max(4+4, 4) = 8: k = 8*2*4/64 = 1 */
    EQ(VEL(f, "a", 1, 0), 0.125);
    EQ(VEL(f, "b", 1, 0), -0.0625);
    node_release(ph);
}

static void test_electrostatic(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(particle(ph, "particle", "a", num(0)), "charge", num(2));
    set(particle(ph, "particle", "b", num(2)), "charge", num(-1));
    set(particle(ph, "particle", "c", num(3)), "charge", num(1));
    Node *e = applier(ph, "electrostatic");
    set(e, "max_distance", num(2.5));   /* a-c (3) is cut off */
    one_step(f, ph);
    /* a-b: k = 1*2*-1/4 = -0.5; a.F -= dir*k = +0.5, b.F -= 0.5
     * b-c: dist 1, k = -1*1/1 = -1; b.F += 1, c.F -= 1 */
    EQ(VEL(f, "a", 1, 0), 0.125);
    EQ(POS(f, "a", 1, 0), 0.03125);
    EQ(VEL(f, "b", 1, 0), 0.125);
    EQ(VEL(f, "c", 1, 0), -0.25);
    node_release(ph);
}

static void test_adhesion(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(particle(ph, "particle", "a", num(0)), "radius", num(2));
    set(particle(ph, "particle", "b", num(2.5)), "radius", num(1));
    Node *a = applier(ph, "adhesion");
    set(a, "strength", num(4));
    set(a, "overlap", num(0.5));
    one_step(f, ph);
    /* o = 3-2.5 = 0.5, l = 1*0.5 + 3*0.5 = 2, k = 4*0.5*(2.5-2) = 1:
     * a.F += 1, b.F -= 1 */
    EQ(VEL(f, "a", 1, 0), 0.25);
    EQ(VEL(f, "b", 1, 0), -0.25);
    EQ(POS(f, "b", 1, 0), 2.4375);
    node_release(ph);
}

static void test_drag(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    Node *p = particle(ph, "particle", "p", nums2(0, 0));
    set(p, "radius", num(2));
    set(p, "velocity", nums2(3, 4));
    Node *q = particle(ph, "particle", "q", nums2(0, 0));   /* clamped */
    set(q, "radius", num(2));
    set(q, "velocity", nums2(8, 9));
    Node *r = particle(ph, "particle", "r", nums2(0, 0));   /* no radius */
    set(r, "velocity", nums2(1, 1));
    Node *d = applier(ph, "drag");
    set(d, "strength", num(0.25));
    set(d, "flow", nums2(0, 1));
    one_step(f, ph);
    /* p: v-flow = (3,3), s = 18, k = 0.25*sqrt(18)*pow(2,1) < 4 */
    double k = 0.25 * sqrt(18.0) * 2;
    double vx = 3 + (0 - 3 * k) * 0.25, vy = 4 + (0 - 3 * k) * 0.25;
    EQ(VEL(f, "p", 2, 0), vx);
    EQ(VEL(f, "p", 2, 1), vy);
    EQ(POS(f, "p", 2, 0), vx * 0.25);
    /* q: v-flow = (8,8), k = 0.25*sqrt(128)*2 > mass/delta = 4: clamped to
     * 4, so the velocity relative to the medium goes exactly to zero */
    EQ(VEL(f, "q", 2, 0), 0);
    EQ(VEL(f, "q", 2, 1), 1);
    EQ(POS(f, "q", 2, 1), 0.25);
    EQ(VEL(f, "r", 2, 0), 1);
    node_release(ph);
}

static void test_buoyancy(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 3);
    Node *p = particle(ph, "particle", "p", nums3(0, 0, 0));
    set(p, "radius", num(1));
    set(p, "mass", num(2));
    Node *q = particle(ph, "particle", "q", nums3(0, 0, 0));
    set(q, "radius", num(2));            /* displaced 8 > mass 1: rises */
    set(q, "mass", num(1));
    Node *b = applier(ph, "buoyancy");   /* default gravity 0;0;-1 */
    set(b, "density", num(1));
    one_step(f, ph);
    /* p: k = 1*(2 - 1*1) = 1, F = (0,0,-1), dt/m = 0.125 */
    EQ(VEL(f, "p", 3, 2), -0.125);
    EQ(POS(f, "p", 3, 2), -0.03125);
    EQ(VEL(f, "p", 3, 0), 0);
    /* q: k = 1 - 8 = -7, F = (0,0,7) */
    EQ(VEL(f, "q", 3, 2), 1.75);
    node_release(ph);
}

static void test_buoyancy_explicit_gravity(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    Node *p = particle(ph, "particle", "p", nums2(0, 0));
    set(p, "radius", num(1));
    set(p, "mass", num(2));
    Node *b = applier(ph, "buoyancy");
    set(b, "gravity", nums2(4, 0));
    set(b, "density", num(0.5));
    set(b, "strength", num(2));
    one_step(f, ph);
    /* k = 2*(2 - pow(1,2)*0.5) = 3; F = (12, 0); v = 12*0.125 */
    EQ(VEL(f, "p", 2, 0), 1.5);
    EQ(VEL(f, "p", 2, 1), 0);
    node_release(ph);
}

static void test_constant(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    set(particle(ph, "particle", "p", nums2(0, 0)), "mass", num(4));
    Node *c = applier(ph, "constant");
    set(c, "force", nums2(1, 0));
    set(c, "acceleration", nums2(0, 2));
    set(c, "strength", num(2));
    one_step(f, ph);
    /* F = ((1+0*4)*2, (0+2*4)*2) = (2, 16); dt/m = 0.0625 */
    EQ(VEL(f, "p", 2, 0), 0.125);
    EQ(VEL(f, "p", 2, 1), 1);
    EQ(POS(f, "p", 2, 0), 0.03125);
    EQ(POS(f, "p", 2, 1), 0.25);
    node_release(ph);
}

static void test_field(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    set(particle(ph, "particle", "p", nums2(0, 0)), "charge", num(-2));
    particle(ph, "particle", "n", nums2(0, 0));          /* no charge */
    Node *fl = applier(ph, "field");
    set(fl, "direction", nums2(1, 2));
    set(fl, "strength", num(3));
    one_step(f, ph);
    /* [doc] F = strength*dir*charge = (-6, -12) */
    EQ(VEL(f, "p", 2, 0), -1.5);
    EQ(VEL(f, "p", 2, 1), -3);
    EQ(VEL(f, "n", 2, 0), 0);
    EQ(VEL(f, "n", 2, 1), 0);
    node_release(ph);
}

static uint64_t seed_key(const char *p, double run, double iteration,
                         int zeros)
{
    Vec *parts[6] = {sym(p), num(run), num(iteration), NULL, NULL, NULL};
    for (int i = 0; i < zeros; i++)
        parts[3 + i] = num(0);
    Vec *seed = vec_compose(parts, 6);
    uint64_t k = vec_hash(seed, true);
    vec_release(seed);
    for (int i = 0; i < 6; i++)
        vec_release(parts[i]);
    return k;
}

static void test_random(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    particle(ph, "particle", "a", nums2(0, 0));
    particle(ph, "particle", "b", nums2(0, 0));
    set(applier(ph, "random"), "strength", num(2));
    set(applier(ph, "random"), "strength", num(4));
    one_step(f, ph);
    /* frame 1: seed P;0;1, then P;0;1;0 for the second applier; draws in
     * particle order, one per dimension, indices continuing per applier */
    uint64_t k1 = seed_key("t", 0, 1, 0), k2 = seed_key("t", 0, 1, 1);
    for (uint32_t i = 0; i < 2; i++) {
        double fa = 0 + 2 * rng_normal(k1, i);
        fa = fa + 4 * rng_normal(k2, i);
        double fb = 0 + 2 * rng_normal(k1, 2 + i);
        fb = fb + 4 * rng_normal(k2, 2 + i);
        EQ(VEL(f, "a", 2, i), 0 + fa * 0.25);
        EQ(VEL(f, "b", 2, i), 0 + fb * 0.25);
    }
    node_release(ph);
}

/* ------------------------------------------------------------------ */
/* Barriers                                                            */
/* ------------------------------------------------------------------ */

static void test_barrier_bounce(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(particle(ph, "particle", "p", num(0.5)), "velocity", num(-4));
    Node *b = applier(ph, "barrier");
    set(b, "position", num(0));
    set(b, "normal", num(3));            /* normalised to 1 */
    set(b, "restitution", num(0.5));
    one_step(f, ph);
    /* step: pos -0.5; rebound: x = -0.5, u = -4, r = 0.125: pos = 0,
     * v = -4*0.5 = -2, reflected to 2, then step(0.125): pos = 0.25 */
    EQ(POS(f, "p", 1, 0), 0.25);
    EQ(VEL(f, "p", 1, 0), 2);
    node_release(ph);
}

static void test_barrier_pushout_and_disabled(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    /* already behind the barrier, moving away from it: pushed out */
    Node *p = particle(ph, "particle", "p", nums2(0, -1));
    set(p, "velocity", nums2(0, 2));
    set(p, "radius", num(0.5));
    Node *b = applier(ph, "barrier");
    set(b, "position", nums2(0, 0));
    set(b, "normal", nums2(0, 1));
    Node *z = applier(ph, "barrier");        /* zero normal: disabled */
    set(z, "position", nums2(0, 100));
    set(z, "normal", nums2(0, 0));
    set(z, "min", num(1000));
    one_step(f, ph);
    /* step: pos y = -0.5; x = -0.5 - 0.5 = -1, u = 2 >= 0: pos -= x*n */
    EQ(POS(f, "p", 2, 1), 0.5);
    EQ(VEL(f, "p", 2, 1), 2);
    node_release(ph);
}

static void test_soft_barrier(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    particle(ph, "particle", "lo", nums2(0, 1));
    particle(ph, "particle", "hi", nums2(5, 3));
    Node *b = applier(ph, "barrier");
    set(b, "position", nums2(0, 0));
    set(b, "normal", nums2(0, 1));
    set(b, "min", num(2));
    set(b, "strength", num(3));
    Node *c = applier(ph, "barrier");        /* [doc] max without min */
    set(c, "position", nums2(0, 0));
    set(c, "normal", nums2(0, 1));
    set(c, "max", num(1));
    set(c, "strength", num(2));
    set(c, "power", num(2));
    one_step(f, ph);
    /* lo: x = 1 < min: F += n*(2-1)*3 = (0,3); below max */
    EQ(VEL(f, "lo", 2, 1), 0.75);
    EQ(POS(f, "lo", 2, 1), 1.1875);
    /* hi: x = 3 > max: F -= n*pow(2,2)*2 = (0,-8) */
    EQ(VEL(f, "hi", 2, 1), -2);
    EQ(POS(f, "hi", 2, 1), 2.5);
    EQ(POS(f, "hi", 2, 0), 5);
    node_release(ph);
}

/* ------------------------------------------------------------------ */
/* Ease, speed of light, anchors, zero mass                            */
/* ------------------------------------------------------------------ */

/* Put the system mid-run: clock [clock], last time 0, run 0. */
static void preset_clock(Fixture *f, double clock)
{
    sput(f, "t", "clock", num(clock));
    sput(f, "t", "last", num(0));
    sput(f, "t", "run", num(0));
    sput(f, "t", "iteration", num(0));
    sput(f, "t", NULL, num(0));
}

static void test_ease_ramp(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    particle(ph, "particle", "p", num(0));
    Node *q = particle(ph, "particle", "q", num(0));
    set(q, "force", num(4));
    set(q, "ease", num(2));
    Node *c = applier(ph, "constant");
    set(c, "force", num(1));
    set(c, "strength", num(4));
    set(c, "ease", num(2));
    preset_clock(f, 0.5);
    frame(f, ph, 0.25);
    /* strength = 4*(0.5/2) = 1: p.F = 1 + constant; q.F = 4*0.25 + 1 = 2 */
    EQ(VEL(f, "p", 1, 0), 0.25);
    EQ(VEL(f, "q", 1, 0), 0.5);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.75);
    node_release(ph);
}

static void test_ease_zero_at_start_full_after(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *q = particle(ph, "particle", "q", num(0));
    set(q, "force", num(4));
    set(q, "ease", num(1));
    set(particle(ph, "particle", "p", num(0)), "mass", num(1));
    Node *c = applier(ph, "constant");
    set(c, "force", num(1));
    set(c, "ease", num(1));
    one_step(f, ph);                 /* clock 0 at frame start: no force */
    EQ(VEL(f, "q", 1, 0), 0);
    EQ(VEL(f, "p", 1, 0), 0);
    node_release(ph);
    /* clock 3 > ease 1: full strength (the reference scaled by clock/e) */
    Fixture g;
    g.w = phys_new();
    g.sd = state_new();
    ph = physics("t", 1);
    q = particle(ph, "particle", "q", num(0));
    set(q, "force", num(4));
    set(q, "ease", num(1));
    c = applier(ph, "constant");
    set(c, "force", num(1));
    set(c, "ease", num(1));
    preset_clock(&g, 3);
    frame(&g, ph, 0.25);
    EQ(VEL(&g, "q", 1, 0), 1.25);
    node_release(ph);
    phys_free(g.w);
    state_free(g.sd);
}

static void test_speed_of_light(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    set(ph, "speed_of_light", num(2));
    set(particle(ph, "particle", "a", nums2(0, 0)), "force", nums2(0, 32));
    set(particle(ph, "particle", "b", nums2(0, 0)), "force", nums2(24, 32));
    set(particle(ph, "particle", "c", nums2(0, 0)), "force", nums2(4, 0));
    one_step(f, ph);
    /* a: v = (0,8), s = 64 > 4: k = 2/8 = 0.25 -> (0,2) */
    EQ(VEL(f, "a", 2, 1), 2);
    EQ(POS(f, "a", 2, 1), 0.5);
    /* b: v = (6,8), k = 2/sqrt(100) */
    double k = 2 / sqrt(100.0);
    EQ(VEL(f, "b", 2, 0), 6 * k);
    EQ(VEL(f, "b", 2, 1), 8 * k);
    /* c: |v| = 1 < 2: untouched */
    EQ(VEL(f, "c", 2, 0), 1);
    node_release(ph);
}

static void test_anchor_does_not_move(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *a = particle(ph, "anchor", "a", num(0));
    set(a, "force", num(100));
    set(a, "velocity", num(7));
    particle(ph, "particle", "p", num(4));
    Node *d = applier(ph, "distance");
    set(d, "from", sym("a"));
    set(d, "to", sym("p"));
    set(d, "max", num(2));
    set(applier(ph, "constant"), "force", num(1000));
    one_step(f, ph);
    EQ(POS(f, "a", 1, 0), 0);
    EQ(VEL(f, "a", 1, 0), 7);     /* fvec(velocity), as written */
    /* p: distance pulls back by 2, constant pushes 1000 */
    EQ(VEL(f, "p", 1, 0), (-2 + 1000) * 0.25);
    /* an anchor follows its position attribute; it is never read back */
    set(a, "position", num(10));
    frame(f, ph, 0.5);
    EQ(POS(f, "a", 1, 0), 10);
    node_release(ph);
}

static void test_zero_mass_and_nonfinite(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *z = particle(ph, "particle", "z", num(1));
    set(z, "mass", num(-3));             /* clamped to 0 */
    set(z, "velocity", num(2));
    Node *n = particle(ph, "particle", "n", num(0));
    set(n, "force", num(INFINITY));      /* non-finite force: no dv */
    set(n, "velocity", num(1));
    Node *x = particle(ph, "particle", "x", num(INFINITY));
    set(x, "velocity", num(1));
    set(applier(ph, "constant"), "force", num(8));
    one_step(f, ph);
    EQ(VEL(f, "z", 1, 0), 2);
    EQ(POS(f, "z", 1, 0), 1.5);
    EQ(VEL(f, "n", 1, 0), 1);
    EQ(POS(f, "n", 1, 0), 0.25);
    assert_null(sget(f, "t", "x", NULL));        /* inf: not written */
    EQ(VEL(f, "x", 1, 0), 3);
    node_release(ph);
}

/* ------------------------------------------------------------------ */
/* Clock and steps                                                     */
/* ------------------------------------------------------------------ */

static void test_lockstep_extra_steps(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(ph, "resolution", num(0.25));
    particle(ph, "particle", "p", num(0));
    set(applier(ph, "constant"), "force", num(1));
    frame_n(f, &ph, 1, 0, 1);
    frame_n(f, &ph, 1, 1, 1);            /* delta 1 = four 0.25 steps */
    EQ(sval(f, "t", "clock", NULL, 1, 0), 1);
    EQ(sval(f, "t", "last", NULL, 1, 0), 1);
    EQ(VEL(f, "p", 1, 0), 1);            /* 0.25, 0.5, 0.75, 1 */
    EQ(POS(f, "p", 1, 0), 0.625);        /* 1/16 + 2/16 + 3/16 + 4/16 */
    EQ(sval(f, "t", "iteration", NULL, 1, 0), 1);
    /* a delta smaller than resolution: one step of the delta */
    frame_n(f, &ph, 1, 1.125, 1);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 1.125);
    EQ(VEL(f, "p", 1, 0), 1.125);
    node_release(ph);
}

static void test_realtime_extra_step(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(ph, "resolution", num(0.25));
    particle(ph, "particle", "p", num(0));
    PhysicsFrame fr = {.time = 0, .fps = 60, .realtime = true,
                       .performance = 2};
    phys_run_frame(f->w, &ph, 1, f->sd, &fr);
    fr.time = 1;                       /* good performance: one extra step */
    phys_run_frame(f->w, &ph, 1, f->sd, &fr);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.5);
    EQ(sval(f, "t", "last", NULL, 1, 0), 1);
    fr.time = 2;
    fr.performance = 1;                /* poor performance: no extra step */
    phys_run_frame(f->w, &ph, 1, f->sd, &fr);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.75);
    node_release(ph);
}

static void test_time_attribute_and_default_resolution(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    particle(ph, "particle", "p", num(0));
    set(applier(ph, "constant"), "force", num(1));
    frame_n(f, &ph, 1, 0, 4);
    frame_n(f, &ph, 1, 0.5, 4);          /* resolution 1/4: two steps */
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.5);
    EQ(VEL(f, "p", 1, 0), 0.5);
    EQ(POS(f, "p", 1, 0), 0.1875);
    /* time attribute replaces the frame time; going backwards: no step */
    set(ph, "time", num(0.25));
    frame_n(f, &ph, 1, 1, 4);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.5);
    EQ(sval(f, "t", "last", NULL, 1, 0), 0.25);
    EQ(POS(f, "p", 1, 0), 0.1875);
    node_release(ph);
}

/* ------------------------------------------------------------------ */
/* State keys, runs, groups, systems                                   */
/* ------------------------------------------------------------------ */

static void test_state_keys(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    particle(ph, "particle", "p", nums2(1, 2));
    frame(f, ph, 3);
    /* frame 0: clock keys but no particle keys (no step yet) */
    EQ(sval(f, "t", NULL, NULL, 1, 0), 3);
    EQ(sval(f, "t", "last", NULL, 1, 0), 3);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0);
    EQ(sval(f, "t", "run", NULL, 1, 0), 0);
    EQ(sval(f, "t", "iteration", NULL, 1, 0), 0);
    assert_null(sget(f, "t", "p", NULL));
    assert_int_equal(state_count(f->sd), 5);
    frame(f, ph, 3.25);
    EQ(sval(f, "t", NULL, NULL, 1, 0), 3);
    EQ(sval(f, "t", "last", NULL, 1, 0), 3.25);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.25);
    EQ(sval(f, "t", "iteration", NULL, 1, 0), 1);
    EQ(POS(f, "p", 2, 0), 1);
    EQ(POS(f, "p", 2, 1), 2);
    EQ(VEL(f, "p", 2, 1), 0);
    assert_int_equal(state_count(f->sd), 7);
    node_release(ph);
}

static void test_state_read_back(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    particle(ph, "particle", "p", nums2(0, 0));
    one_step(f, ph);
    /* someone moves the particle in the state: the engine continues from
     * there; a wrong-length value falls back to the attribute */
    sput(f, "t", "p", nums2(10, 20));
    Vec *k = key("t", "p", "velocity");
    Vec *v = nums3(1, 1, 1);
    state_set(f->sd, k, v);
    vec_release(v);
    vec_release(k);
    frame(f, ph, 0.5);
    EQ(POS(f, "p", 2, 0), 10);
    EQ(POS(f, "p", 2, 1), 20);
    EQ(VEL(f, "p", 2, 0), 0);
    node_release(ph);
}

static void test_stale_keys_nulled(void **st)
{
    Fixture *f = *st;
    sput(f, "other", NULL, num(42));            /* not ours */
    Node *ph = physics("t", 1);
    particle(ph, "particle", "p", num(0));
    particle(ph, "particle", "q", num(1));
    one_step(f, ph);
    assert_non_null(sget(f, "t", "q", NULL));
    assert_non_null(sget(f, "t", "q", "velocity"));
    node_release(ph);
    ph = physics("t", 1);                       /* q is gone */
    particle(ph, "particle", "p", num(0));
    frame(f, ph, 0.5);
    assert_null(sget(f, "t", "q", NULL));
    assert_null(sget(f, "t", "q", "velocity"));
    assert_non_null(sget(f, "t", "p", NULL));
    EQ(sval(f, "other", NULL, NULL, 1, 0), 42);
    node_release(ph);
}

/* Particles leaving, coming back and changing order: each id keeps its own
 * state (the key table follows ids, not storage slots), a departed id's
 * keys are nulled and it restarts from its attributes when it returns. */
static void test_ids_leave_return_reorder(void **st)
{
    Fixture *f = *st;
    static const char *const order[4][3] = {
        {"a", "b", "c"}, {"a", "b", "c"}, {"c", "a", NULL}, {"b", "a", "c"}};
    for (int fr = 0; fr < 4; fr++) {
        Node *ph = physics("t", 1);
        for (int i = 0; i < 3 && order[fr][i]; i++) {
            const char *id = order[fr][i];
            Node *p = particle(ph, "particle", id, num(10.0 * (id[0] - 'a')));
            set(p, "velocity", num(1));
        }
        frame(f, ph, 0.25 * fr);
        node_release(ph);
        if (fr == 2) {
            assert_null(sget(f, "t", "b", NULL));
            assert_null(sget(f, "t", "b", "velocity"));
            EQ(POS(f, "a", 1, 0), 0.5);
            EQ(POS(f, "c", 1, 0), 20.5);
        }
    }
    EQ(POS(f, "a", 1, 0), 0.75);
    EQ(POS(f, "b", 1, 0), 10.25);      /* back from its attribute */
    EQ(POS(f, "c", 1, 0), 20.75);
    EQ(VEL(f, "b", 1, 0), 1);
    assert_int_equal(state_count(f->sd), 5 + 6);
}

static void test_run_reset(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    set(ph, "run", num(0.9));                   /* floored to 0 */
    set(particle(ph, "particle", "p", num(0)), "velocity", num(4));
    particle(ph, "particle", "q", num(5));
    frame(f, ph, 0);
    frame(f, ph, 0.25);
    frame(f, ph, 0.5);
    EQ(POS(f, "p", 1, 0), 2);
    EQ(sval(f, "t", "iteration", NULL, 1, 0), 2);
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.5);
    node_release(ph);
    /* run 1 without q: keys cleared, p restarts from its attributes */
    ph = physics("t", 1);
    set(ph, "run", num(1.5));
    set(particle(ph, "particle", "p", num(0)), "velocity", num(4));
    frame(f, ph, 0.75);
    EQ(sval(f, "t", "run", NULL, 1, 0), 1);
    EQ(sval(f, "t", "iteration", NULL, 1, 0), 0);
    EQ(sval(f, "t", NULL, NULL, 1, 0), 0.75);     /* run start time */
    EQ(sval(f, "t", "clock", NULL, 1, 0), 0.25);  /* 0 + one step */
    EQ(POS(f, "p", 1, 0), 1);                     /* from 0, not 2 */
    assert_null(sget(f, "t", "q", NULL));
    assert_null(sget(f, "t", "q", "velocity"));
    node_release(ph);
}

static void test_prefix_change(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    particle(ph, "particle", "p", num(0));
    one_step(f, ph);
    assert_non_null(sget(f, "t", "p", NULL));
    set(ph, "state", sym("u"));         /* new prefix: fresh system state */
    frame(f, ph, 0.5);
    assert_null(sget(f, "t", "p", NULL));
    assert_null(sget(f, "t", "p", "velocity"));
    EQ(sval(f, "u", "last", NULL, 1, 0), 0.5);
    assert_null(sget(f, "u", "p", NULL));     /* no step: last == time */
    frame(f, ph, 0.75);
    EQ(sval(f, "u", "p", NULL, 1, 0), 0);
    node_release(ph);
}

static void test_duplicate_ids(void **st)
{
    /* lookup by id takes the later particle in tree (pre-)order, while
     * state writes go in group order, so the group's x is written last */
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *g = add(ph, mk("group"));
    particle(g, "particle", "x", num(0));
    particle(ph, "particle", "x", num(10));
    particle(ph, "particle", "y", num(20));
    Node *d = applier(ph, "distance");
    set(d, "from", sym("x"));
    set(d, "to", sym("y"));
    set(d, "max", num(5));
    one_step(f, ph);
    /* x@10 - y: k = 10-5 = 5 */
    EQ(POS(f, "y", 1, 0), 19.6875);
    EQ(VEL(f, "y", 1, 0), -1.25);
    EQ(POS(f, "x", 1, 0), 0);            /* x@0 written after x@10 */
    node_release(ph);
}

static void test_groups_visibility(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *g1 = add(ph, mk("group"));
    Node *g2 = add(ph, mk("group"));
    set(particle(g1, "particle", "a", num(0)), "radius", num(1));
    set(particle(g2, "particle", "b", num(1)), "radius", num(1));
    set(particle(ph, "particle", "c", num(-1)), "radius", num(1));
    set(applier(ph, "collision"), "strength", num(4));
    set(applier(g2, "constant"), "force", num(8));  /* only b */
    Node *d = applier(g1, "distance");      /* explicit ids cross groups */
    set(d, "from", sym("a"));
    set(d, "to", sym("b"));
    set(d, "min", num(3));
    one_step(f, ph);
    /* collision sees a-c and b-c but not a-b (siblings):
     * a-c: dist 1 < 2: k = 4: c.F -= 4 (dir c->a is +1... from=a,to=c:
     *   dir = -1, a.F -= -4 = +4, c.F += -4)
     * b-c: dist 2: no overlap. distance a-b: k = 3-1 = 2, dir +1:
     *   a.F -= 2, b.F += 2. constant: b.F += 8 */
    EQ(VEL(f, "a", 1, 0), (4 - 2) * 0.25);
    EQ(VEL(f, "b", 1, 0), (2 + 8) * 0.25);
    EQ(VEL(f, "c", 1, 0), -4 * 0.25);
    node_release(ph);
}

static void test_nested_group_pool(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 1);
    Node *g = add(ph, mk("group"));
    Node *h = add(g, mk("group"));
    set(particle(ph, "particle", "top", num(10)), "charge", num(1));
    set(particle(g, "particle", "mid", num(0)), "charge", num(1));
    set(particle(h, "particle", "low", num(1)), "charge", num(1));
    applier(g, "electrostatic");             /* sees mid and low only */
    one_step(f, ph);
    /* mid-low: dist 1, k = 1: mid.F -= 1, low.F += 1; top untouched */
    EQ(VEL(f, "mid", 1, 0), -0.25);
    EQ(VEL(f, "low", 1, 0), 0.25);
    EQ(VEL(f, "top", 1, 0), 0);
    node_release(ph);
}

static void test_four_dimensions(void **st)
{
    Fixture *f = *st;
    Node *ph = physics("t", 4);
    double a[4] = {0, 0, 0, 0}, b[4] = {0, 0, 0, 4};
    particle(ph, "particle", "a", vec_from_nums(a, 4));
    particle(ph, "particle", "b", vec_from_nums(b, 4));
    Node *d = applier(ph, "distance");
    set(d, "from", sym("a"));
    set(d, "to", sym("b"));
    set(d, "max", num(2));
    set(applier(ph, "constant"), "acceleration", num(1));  /* 1;1;1;1 */
    one_step(f, ph);
    EQ(VEL(f, "a", 4, 0), 0.25);
    EQ(VEL(f, "a", 4, 3), (2 + 1) * 0.25);
    EQ(VEL(f, "b", 4, 3), (-2 + 1) * 0.25);
    EQ(POS(f, "b", 4, 3), 4 + -0.25 * 0.25);
    node_release(ph);
}

static void test_skipped_and_multiple_systems(void **st)
{
    Fixture *f = *st;
    Node *bad1 = physics("x", 0);                /* dimensions < 1 */
    particle(bad1, "particle", "p", num(0));
    Node *bad2 = mk("physics");                  /* no state */
    set(bad2, "dimensions", num(1));
    Node *bad3 = physics("y", 1);                /* resolution <= 0 */
    set(bad3, "resolution", num(0));
    Node *ok1 = physics("t", 1);
    set(particle(ok1, "particle", "p", num(0)), "velocity", num(1));
    Node *ok2 = physics("u", 1);
    set(particle(ok2, "particle", "p", num(0)), "velocity", num(2));
    Node *all[5] = {bad1, bad2, bad3, ok1, ok2};
    frame_n(f, all, 5, 0, 4);
    frame_n(f, all, 5, 0.25, 4);
    assert_null(sget(f, "x", NULL, NULL));
    assert_null(sget(f, "y", "clock", NULL));
    EQ(POS(f, "p", 1, 0), 0.25);
    EQ(sval(f, "u", "p", NULL, 1, 0), 0.5);
    assert_int_equal(state_count(f->sd), 2 * 7);
    /* fewer systems next frame: surplus freed, the rest carries on */
    frame_n(f, all + 3, 1, 0.5, 4);
    EQ(POS(f, "p", 1, 0), 0.5);
    node_release(bad1);
    node_release(bad2);
    node_release(bad3);
    node_release(ok1);
    node_release(ok2);
}

static void test_many_particles_reuse(void **st)
{
    /* a larger system over several frames: key cache and buffers reused,
     * momentum conserved by the symmetric pair forces */
    Fixture *f = *st;
    Node *ph = physics("t", 2);
    for (int i = 0; i < 40; i++) {
        Node *p = mk("particle");
        set(p, "id", num(i));
        set(p, "position", nums2(i % 7, i / 7));
        set(p, "radius", num(0.75));
        add(ph, p);
    }
    applier(ph, "collision");
    for (int fr = 0; fr < 6; fr++)
        frame(f, ph, fr * 0.25);
    double px = 0, py = 0;
    for (int i = 0; i < 40; i++) {
        Vec *parts[3] = {sym("t"), num(i), sym("velocity")};
        Vec *k = vec_compose(parts, 3);
        const Vec *v = state_get(f->sd, k);
        assert_true(vec_is_num(v) && v->len == 2);
        px += vec_cnums(v)[0];
        py += vec_cnums(v)[1];
        vec_release(k);
        for (int j = 0; j < 3; j++)
            vec_release(parts[j]);
    }
    assert_true(fabs(px) < 1e-9 && fabs(py) < 1e-9);
    assert_int_equal(state_count(f->sd), 5 + 80);
    node_release(ph);
}

/* Two particles with different radius, mass, charge and own force, under
 * a field (charge), a constant acceleration (mass) and a collision
 * (radius); [swap] lists B before A. With [a]/[b] given, those very nodes
 * are appended (a static tree), else fresh equal copies. */
static Node *two_particles(bool swap, Node *a, Node *b)
{
    Node *ph = physics("t", 2);
    Node *p[2] = {a, b};
    for (int i = 0; i < 2; i++) {
        if (p[i]) {
            node_retain(p[i]);
            continue;
        }
        p[i] = mk("particle");
        set(p[i], "id", sym(i ? "b" : "a"));
        set(p[i], "position", nums2(i ? 1.5 : 0, 0.25));
        set(p[i], "radius", num(i ? 1 : 0.75));
        set(p[i], "mass", num(i ? 3 : 0.5));
        set(p[i], "charge", num(i ? -2 : 1));
        set(p[i], "force", nums2(i ? 0 : 1, i ? 2 : 0));
    }
    add(ph, p[swap ? 1 : 0]);
    add(ph, p[swap ? 0 : 1]);
    Node *fl = applier(ph, "field");
    set(fl, "direction", nums2(1, 0));
    Node *c = applier(ph, "constant");
    set(c, "acceleration", nums2(0, -1));
    applier(ph, "collision");
    return ph;
}

static void test_same_nodes_moved(void **st)
{
    /* the engine keeps what it read from a particle node while the same
     * node fills the same slot; nodes that change slots (here swapped
     * between frames) must be read again: the same bits as fresh nodes */
    Fixture *f = *st;
    Fixture g = {phys_new(), state_new()};
    Node *a = mk("particle"), *b = mk("particle");
    {
        Node *ref = two_particles(false, NULL, NULL);
        node_release(a);
        node_release(b);
        a = node_retain(ref->children[0]);
        b = node_retain(ref->children[1]);
        node_release(ref);
    }
    static const bool swaps[] = {false, false, true, true, false, true};
    for (int fr = 0; fr < 6; fr++) {
        Node *kept = two_particles(swaps[fr], a, b);
        Node *fresh = two_particles(swaps[fr], NULL, NULL);
        frame(f, kept, 0.25 * fr);
        frame(&g, fresh, 0.25 * fr);
        node_release(kept);
        node_release(fresh);
        for (int i = 0; i < 2 && fr > 0; i++) {   /* frame 0 makes no step */
            const char *id = i ? "b" : "a";
            for (int k = 0; k < 2; k++) {
                double x = POS(f, id, 2, k), y = POS(&g, id, 2, k);
                double u = VEL(f, id, 2, k), v = VEL(&g, id, 2, k);
                assert_memory_equal(&x, &y, sizeof x);
                assert_memory_equal(&u, &v, sizeof u);
            }
        }
    }
    /* and the forces did act: b moved against the field, a with it */
    assert_true(POS(f, "a", 2, 0) > 0 && POS(f, "b", 2, 0) < 1.5);
    node_release(a);
    node_release(b);
    phys_free(g.w);
    state_free(g.sd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
#define T(name) cmocka_unit_test_setup_teardown(name, setup, teardown)
        T(test_distance_max),
        T(test_distance_min_power),
        T(test_distance_fixed_missing_id),
        T(test_collision),
        T(test_gravity),
        T(test_gravity_overlap_clamp),
        T(test_electrostatic),
        T(test_adhesion),
        T(test_drag),
        T(test_buoyancy),
        T(test_buoyancy_explicit_gravity),
        T(test_constant),
        T(test_field),
        T(test_random),
        T(test_barrier_bounce),
        T(test_barrier_pushout_and_disabled),
        T(test_soft_barrier),
        T(test_ease_ramp),
        T(test_ease_zero_at_start_full_after),
        T(test_speed_of_light),
        T(test_anchor_does_not_move),
        T(test_zero_mass_and_nonfinite),
        T(test_lockstep_extra_steps),
        T(test_realtime_extra_step),
        T(test_time_attribute_and_default_resolution),
        T(test_state_keys),
        T(test_state_read_back),
        T(test_stale_keys_nulled),
        T(test_run_reset),
        T(test_prefix_change),
        T(test_duplicate_ids),
        T(test_groups_visibility),
        T(test_nested_group_pool),
        T(test_four_dimensions),
        T(test_skipped_and_multiple_systems),
        T(test_many_particles_reuse),
        T(test_ids_leave_return_reorder),
        T(test_same_nodes_moved),
#undef T
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
