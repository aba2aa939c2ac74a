/* test_physics_routes.c: differential test of the physics pair routes.
 *
 * The neighbour grid and the per-particle gather (lib/physics/pairs.c) and
 * the blocked reference loop of unlimited-reach levels (lib/physics/rows.c,
 * taken with one or two threads) must give the same bits as the reference
 * all-pairs loop (PHYSICS-ENGINE.md §4), for every thread count. Each case builds a random !physics scene from a
 * fixed seed (so a failure is reproducible), runs the same frames through a
 * world set to `phys_set_pairs(w, true)` (naive) and through worlds on the
 * fast route with 1, 2 and 4 threads, and compares the whole state
 * dictionaries entry by entry, bit for bit (memcmp of the doubles).
 *
 * The scenes mix what can break an exactness argument: D = 1..4, nested
 * groups (pools and pair levels of several ancestors), anchors, zero
 * radius/mass/charge, coincident particles (dist 0), NaN and infinite
 * positions and velocities, huge coordinates (outside the grid), the four
 * pair appliers mixed in one level with and without max_distance, distance
 * appliers, barriers, drag, constant and random forces, several steps per
 * frame. Sizes reach past the thresholds where work is split across
 * threads (256 targets per task; the all-pairs gather needs 512 targets
 * and three threads or more; the particle pass 1024 particles).
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

/* A random D-vector: mostly in a box of side [box], sometimes special. */
static Vec *rvec(Rng *r, size_t D, double box, double special)
{
    double x[4];
    for (size_t i = 0; i < D; i++)
        x[i] = (uni(r) - 0.5) * box;
    if (chance(r, special)) {
        static const double odd[] = {NAN, INFINITY, -INFINITY, 1e15, -3e12};
        x[below(r, D)] = odd[below(r, 5)];
    }
    return vec_from_nums(x, (uint32_t)D);
}

typedef struct Scene {
    size_t D;
    size_t nids;           /* particles so far (ids 0 .. nids-1) */
    double box;            /* side of the box the particles start in */
    Vec *lastpos;          /* for coincident particles */
    bool no_random;        /* leave out !random (its draws are sequential) */
    double special;        /* chance of a non-finite or far-out element */
    bool nonzero;          /* no zero radius, mass or charge */
} Scene;

static void add_particles(Rng *r, Scene *sc, Node *g, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        Node *p = add(g, chance(r, 0.05) ? "anchor" : "particle");
        set(p, "id", num((double)sc->nids++));
        Vec *pos;
        bool far = false;
        for (uint32_t k = 0; sc->lastpos && k < sc->lastpos->len; k++)
            far = far || fabs(vec_cnums(sc->lastpos)[k]) >= 1e12;
        if (sc->lastpos && chance(r, 0.03)) {
            pos = vec_retain(sc->lastpos);          /* coincident */
        } else if (far && chance(r, 0.7)) {
            /* a neighbour far outside the grid's range */
            double x[4];
            for (size_t k = 0; k < sc->D; k++)
                x[k] = vec_cnums(sc->lastpos)[k] + (uni(r) - 0.5) * 0.5;
            pos = vec_from_nums(x, (uint32_t)sc->D);
        } else
            pos = rvec(r, sc->D, sc->box, sc->special);
        vec_release(sc->lastpos);
        sc->lastpos = vec_retain(pos);
        set(p, "position", pos);
        set(p, "velocity", rvec(r, sc->D, 4, sc->special / 2));
        const double zr = sc->nonzero ? 0 : 0.1, zm = sc->nonzero ? 0 : 0.05;
        set(p, "radius", num(chance(r, zr) ? 0 : 0.2 + uni(r)));
        set(p, "mass", num(chance(r, zm) ? 0 : 0.5 + uni(r)));
        double q;
        if (sc->nonzero)
            q = (0.05 + uni(r)) * (chance(r, 0.5) ? 1 : -1);
        else
            q = chance(r, 0.3) ? 0 : uni(r) - 0.5;
        set(p, "charge", num(q));
    }
}

static void add_pair_applier(Rng *r, Node *g)
{
    static const char *kinds[] = {"collision", "gravity", "electrostatic", "adhesion"};
    const char *k = kinds[below(r, 4)];
    Node *a = add(g, k);
    set(a, "strength", num(0.5 + uni(r) * 20));
    bool unlimited = strcmp(k, "gravity") == 0 || strcmp(k, "electrostatic") == 0;
    if (chance(r, unlimited ? 0.7 : 0.3))
        set(a, "max_distance", num(0.5 + uni(r) * 3));
    if (strcmp(k, "collision") == 0 && chance(r, 0.3))
        set(a, "power", num(1.5));
}

static void add_other_applier(Rng *r, Scene *sc, Node *g)
{
    switch (below(r, 5)) {
    case 0: {
        if (!sc->nids)
            return;
        Node *d = add(g, "distance");
        set(d, "from", num((double)below(r, sc->nids)));
        set(d, "to", num((double)below(r, sc->nids + 2)));   /* may not exist */
        set(d, "max", num(1 + uni(r)));
        set(d, "min", num(0.5 * uni(r)));
        break;
    }
    case 1: {
        Node *b = add(g, "barrier");
        double x[4] = {0}, n[4] = {0};
        x[0] = -sc->box;
        n[0] = 1;
        set(b, "position", vec_from_nums(x, (uint32_t)sc->D));
        set(b, "normal", vec_from_nums(n, (uint32_t)sc->D));
        set(b, "restitution", num(0.5));
        break;
    }
    case 2:
        set(add(g, "drag"), "strength", num(0.01));
        break;
    case 3:
        set(add(g, "constant"), "acceleration", rvec(r, sc->D, 2, 0));
        break;
    default:
        if (sc->no_random)
            set(add(g, "drag"), "strength", num(0.02));
        else
            set(add(g, "random"), "strength", num(0.3));
        break;
    }
}

/* Fill group [g] at [depth] with particles, appliers and subgroups. */
static void fill_group(Rng *r, Scene *sc, Node *g, int depth, size_t big)
{
    add_particles(r, sc, g, big ? big : 1 + below(r, 40));
    size_t na = 1 + below(r, 4);
    for (size_t i = 0; i < na; i++) {
        if (chance(r, 0.6))
            add_pair_applier(r, g);
        else
            add_other_applier(r, sc, g);
    }
    if (depth < 2) {
        size_t ng = below(r, 3);
        for (size_t i = 0; i < ng; i++)
            fill_group(r, sc, add(g, "group"), depth + 1, 0);
    }
    if (chance(r, 0.5))
        add_particles(r, sc, g, 1 + below(r, 10));   /* after the subgroups */
}

/* A !physics node of [D] dimensions, state 7, resolution 0.05. */
static Node *physics_node(size_t D)
{
    Node *ph = mk("physics");
    set(ph, "state", num(7));
    set(ph, "dimensions", num((double)D));
    set(ph, "resolution", num(0.05));
    return ph;
}

static Node *random_scene(uint64_t seed, size_t big, bool no_random)
{
    Rng r = {seed};
    /* one NaN among unlimited-reach partners makes every force NaN (and
     * the step then leaves velocities alone), so of the large scenes, the
     * seeds with seed % 8 < 6 have no special values at all; large scenes
     * take D = 1 + seed % 4 */
    Scene sc = {.D = 1 + below(&r, 4), .no_random = no_random,
                .special = big && seed % 8 < 6 ? 0 : 0.02};
    if (big)
        sc.D = 1 + seed % 4;
    /* a density that keeps many discs touching */
    double n = big ? (double)big : 60;
    sc.box = sc.D == 1 ? n * 0.8 : sc.D == 2 ? sqrt(n) * 1.2 : cbrt(n) * 1.5;
    Node *ph = physics_node(sc.D);
    fill_group(&r, &sc, ph, 0, big);
    vec_release(sc.lastpos);
    return ph;
}

/* [frames] frames of [ph] in world [w] (freed), 0.25 s apart in lockstep:
 * the state they leave. */
static StateDict *run_frames(PhysicsWorld *w, Node *ph, int frames)
{
    StateDict *sd = state_new();
    for (int f = 0; f < frames; f++) {
        PhysicsFrame fr = {.time = 0.25 * f, .fps = 4, .realtime = false,
                           .performance = 2};
        phys_run_frame(w, &ph, 1, sd, &fr);
    }
    phys_free(w);
    return sd;
}

/* Run [frames] frames (times 0, 0.25, ...: 5 steps each after the first)
 * of [ph] in a fresh world, with vector instructions [simd] (a
 * PHYS_SIMD_* level; -1: the world's own choice, the 4 x 4 tiles or
 * AVX-512 timed on the first steps of each kind of level, tiles.c). */
static StateDict *simulate_simd(Node *ph, bool naive, unsigned threads,
                                int frames, int simd)
{
    PhysicsWorld *w = phys_new();
    phys_set_pairs(w, naive);
    phys_set_threads(w, threads);
    if (simd >= 0) phys_set_simd(w, simd);
    return run_frames(w, ph, frames);
}

/* The same with the world's own choice of vector instructions. */
static StateDict *simulate(Node *ph, bool naive, unsigned threads, int frames)
{
    return simulate_simd(ph, naive, threads, frames, -1);
}

/* Both dictionaries hold the same keys with bit-identical values. */
static void assert_same_state(const StateDict *a, const StateDict *b,
                              uint64_t seed, unsigned threads)
{
    size_t na, nb;
    StateEntry *ea = state_entries(a, &na);
    StateEntry *eb = state_entries(b, &nb);
    free(eb);
    if (na != nb) {
        free(ea);
        fail_msg("seed %llu threads %u: %zu state entries vs %zu",
                 (unsigned long long)seed, threads, na, nb);
    }
    for (size_t i = 0; i < na; i++) {
        const Vec *va = ea[i].value;
        const Vec *vb = state_get(b, ea[i].key);
        bool same = vb && va->kind == VEC_NUM && vb->kind == VEC_NUM &&
                    va->len == vb->len &&
                    memcmp(vec_cnums(va), vec_cnums(vb),
                           va->len * sizeof(double)) == 0;
        if (!same) {
            /* the entry, for whoever reads the failure: its key's numbers
             * and the first values of both sides */
            fprintf(stderr, "key:");
            for (uint32_t k = 0; ea[i].key->kind == VEC_NUM && k < ea[i].key->len; k++)
                fprintf(stderr, " %g", vec_cnums(ea[i].key)[k]);
            fprintf(stderr, "\nfirst:");
            for (uint32_t k = 0; va->kind == VEC_NUM && k < va->len && k < 4; k++)
                fprintf(stderr, " %.17g", vec_cnums(va)[k]);
            fprintf(stderr, "\nsecond:");
            for (uint32_t k = 0; vb && vb->kind == VEC_NUM && k < vb->len && k < 4; k++)
                fprintf(stderr, " %.17g", vec_cnums(vb)[k]);
            fprintf(stderr, "\n");
            free(ea);
            fail_msg("seed %llu threads %u: state entry %zu differs",
                     (unsigned long long)seed, threads, i);
        }
    }
    free(ea);
}

/* Three frames of [ph] give the reference loop's bits (one thread) with
 * each thread count of threads[0 .. n-1], in each vector width (portable,
 * AVX2, AVX2 with AVX-512VL, AVX-512, as far as the processor has them). */
static void assert_widths_match(Node *ph, uint64_t seed, const unsigned *threads,
                                size_t n)
{
    StateDict *ref = simulate(ph, true, 1, 3);
    for (size_t ti = 0; ti < n; ti++) {
        for (int simd = PHYS_SIMD_PORTABLE; simd <= PHYS_SIMD_AVX512; simd++) {
            StateDict *sd = simulate_simd(ph, false, threads[ti], 3, simd);
            assert_same_state(ref, sd, seed, threads[ti]);
            state_free(sd);
        }
    }
    state_free(ref);
}

static void check_scene(uint64_t seed, size_t big, int frames, bool no_random)
{
    Node *ph = random_scene(seed, big, no_random);
    StateDict *ref = simulate(ph, true, 1, frames);
    assert_true(state_count(ref) > 4);
    static const unsigned threads[] = {1, 2, 4};
    for (size_t t = 0; t < 3; t++) {
        StateDict *sd = simulate(ph, false, threads[t], frames);
        assert_same_state(ref, sd, seed, threads[t]);
        state_free(sd);
    }
    /* each vector width on its own (tiles.c), one thread */
    for (int simd = PHYS_SIMD_PORTABLE; simd <= PHYS_SIMD_AVX512; simd++) {
        StateDict *sd = simulate_simd(ph, false, 1, frames, simd);
        assert_same_state(ref, sd, seed, 1);
        state_free(sd);
    }
    state_free(ref);
    node_release(ph);
}

/* Many small scenes: every feature combination shows up somewhere. */
static void test_small_scenes(void **st)
{
    (void)st;
    for (uint64_t seed = 1; seed <= 150; seed++)
        check_scene(seed, 0, 4, false);
}

/* Large levels, so targets are split into several tasks per thread and
 * unlimited levels take the threaded all-pairs gather. */
static void test_large_scenes(void **st)
{
    (void)st;
    for (uint64_t seed = 1000; seed < 1016; seed++)
        check_scene(seed, 520 + 23 * (seed - 1000), 3, false);
}

/* Groups big enough (2 * 512 particles) for the particle pass (appliers,
 * step, barriers) to be split over threads too; no !random there, as its
 * draws keep the pass on one thread. */
static void test_split_particle_pass(void **st)
{
    (void)st;
    for (uint64_t seed = 2000; seed < 2003; seed++)
        check_scene(seed, 2100 + 300 * (seed - 2000), 2, true);
}

/* Discs on both sides of the edge of the grid's range: with radius 1 the
 * reach is 2 and the cell size h = 2 * (1 + 2^-20), so |x| >= 2^30 * h
 * is outside the grid (pairs.c). The in-grid disc must still find its
 * out-of-grid neighbours, which it only can through the "odd" list. */
static void test_grid_edge(void **st)
{
    (void)st;
    double edge = 0x1p30 * (2 * (1 + 0x1p-20));
    double xs[] = {edge - 0.75, edge + 0.25, edge - 1.5, edge + 1.0};
    Node *ph = mk("physics");
    set(ph, "state", num(7));
    set(ph, "dimensions", num(2));
    for (int i = 0; i < 4; i++) {
        Node *p = add(ph, "particle");
        double x[2] = {xs[i], 0.5 * i};
        set(p, "id", num(i));
        set(p, "radius", num(1));
        set(p, "position", vec_from_nums(x, 2));
    }
    set(add(ph, "collision"), "strength", num(10));
    StateDict *ref = simulate(ph, true, 1, 3);
    StateDict *sd = simulate(ph, false, 1, 3);
    assert_same_state(ref, sd, 0, 1);
    state_free(ref);
    state_free(sd);
    node_release(ph);
}

/* 3 frames of [ph] on the fast route with 1, 2 and 4 threads give the
 * reference loop's dictionary, bit for bit. */
static void check_threads_124(Node *ph, uint64_t seed)
{
    StateDict *ref = simulate(ph, true, 1, 3);
    static const unsigned threads[] = {1, 2, 4};
    for (size_t ti = 0; ti < 3; ti++) {
        StateDict *sd = simulate(ph, false, threads[ti], 3);
        assert_same_state(ref, sd, seed, threads[ti]);
        state_free(sd);
    }
    state_free(ref);
}

/* The step's !random draws made ahead in chunks that either thread of the
 * first pass may claim (step.c, phys_draw_chunk): systems of !random
 * alone, or with a small pair level beside it, whose planned pairs are no
 * multiple of a chunk (16 pairs), with no anchor, so the last pair of the
 * last chunk is drawn for a particle (D = 2: both its values; D = 1 and 3
 * with an odd count: its first); a second !random in a nested group (its
 * chunks follow the first's); against the reference loop on 1, 2 and 4
 * threads, bit for bit. */
static void test_draw_chunks(void **st)
{
    (void)st;
    static const size_t counts[] = {33, 41, 47, 65, 203, 1001};
    for (size_t D = 1; D <= 3; D++) {
        for (size_t ci = 0; ci < sizeof counts / sizeof *counts; ci++) {
            const uint64_t seed = 12000 + 10 * D + ci;
            Rng r = {seed};
            Node *ph = physics_node(D);
            Node *g = ci % 2 ? add(ph, "group") : ph;
            for (size_t i = 0; i < counts[ci]; i++) {
                Node *p = add(i < counts[ci] / 2 ? ph : g, "particle");
                set(p, "id", num((double)i));
                set(p, "position", rvec(&r, D, 8, 0));
                set(p, "radius", num(0.3));
                set(p, "charge", num(uni(&r) - 0.5));
            }
            set(add(ph, "random"), "strength", num(2));
            if (g != ph)
                set(add(g, "random"), "strength", num(0.5));
            set(add(ph, "drag"), "strength", num(0.1));
            if (ci % 3 == 2)
                set(add(ph, "electrostatic"), "strength", num(1));
            check_threads_124(ph, seed);
            node_release(ph);
        }
    }
}

/* Set state entry P;:[name] (P = 7, physics_node's prefix) to [x]. */
static void set_sym_entry(StateDict *sd, const char *name, double x)
{
    Vec *parts[2] = {num(7), num(symbol_value(name, strlen(name)))};
    Vec *key = vec_compose(parts, 2), *v = num(x);
    state_set(sd, key, v);
    vec_release(v);
    vec_release(key);
    vec_release(parts[0]);
    vec_release(parts[1]);
}

/* A system of [n] discs in 2D on prefix [P], with !random for all of them
 * and a second !random in a group of a third of them, and an all-pairs
 * level of electrostatics that takes the split route (tiles.c) on two
 * threads or more (test_draws_ahead). */
static Node *ahead_system(size_t n, double P, double run, double resolution, uint64_t seed)
{
    Rng r = {seed};
    Node *ph = physics_node(2);
    set(ph, "state", num(P));
    set(ph, "run", num(run));
    set(ph, "resolution", num(resolution));
    Node *g = add(ph, "group");
    for (size_t i = 0; i < n; i++) {
        Node *p = add(i % 3 ? ph : g, "particle");
        set(p, "id", num((double)i));
        set(p, "position", rvec(&r, 2, 20, 0));
        set(p, "radius", num(0.5));
        set(p, "charge", num(uni(&r) - 0.5));
    }
    set(add(ph, "random"), "strength", num(3));
    set(add(g, "random"), "strength", num(1));
    set(add(ph, "drag"), "strength", num(0.1));
    set(add(ph, "electrostatic"), "strength", num(0.5));
    return ph;
}

/* Twelve frames of the systems of test_draws_ahead on [threads] (the
 * reference loop if [naive]), most of them changing what the frame before
 * guessed, with phys_set_ahead([limit]); counts the pairs of draws made
 * ahead (phys_ahead_counts). */
static StateDict *ahead_frames(bool naive, unsigned threads, double resolution, int limit,
                               int split, uint64_t counts[3], uint64_t splits[2])
{
    PhysicsWorld *w = phys_new();
    phys_set_pairs(w, naive);
    phys_set_threads(w, threads);
    phys_set_ahead(w, limit);
    phys_set_split(w, split);
    StateDict *sd = state_new();
    Node *a = ahead_system(200, 7, 0, resolution, 1);
    Node *run1 = ahead_system(200, 7, 1, resolution, 1);
    Node *more = ahead_system(260, 7, 1, resolution, 1);
    Node *fewer = ahead_system(150, 7, 1, resolution, 1);
    Node *other = ahead_system(100, 8, 0, resolution, 2);
    for (int f = 0; f < 12; f++) {
        Node *nodes[2] = {f < 5 ? a : f == 5 ? run1 : f < 8 ? more : fewer, other};
        size_t n = f == 9 || f == 10 ? 2 : 1;
        if (f == 3) {
            /* the next frame's iteration is not this frame's + 1 */
            set_sym_entry(sd, "iteration", 40);
        }
        if (f == 10 && !naive)
            phys_set_threads(w, threads == 2 ? 4 : 2);   /* while a job runs */
        PhysicsFrame fr = {.time = 0.25 * f, .fps = 4, .realtime = false,
                           .performance = 2};
        phys_run_frame(w, nodes, n, sd, &fr);
    }
    phys_ahead_counts(w, counts);
    phys_split_counts(w, splits);
    phys_free(w);
    node_release(a);
    node_release(run1);
    node_release(more);
    node_release(fewer);
    node_release(other);
    return sd;
}

/* The next frame's !random draws, made on the pool's other thread while a
 * frame ends (step.c, "the next frame's draws"), with one step a frame and
 * with five; between frames, what makes the guess wrong: the state's
 * :iteration set, the run changed, particles added (more draws than were
 * made) and removed, a second system (whose pair pass's job ends the
 * first's background job early; the system is freed later while its own
 * job may run), the pool's thread count changed. The draws are made by
 * the split level's two threads while they wait (in AUTO mode and with
 * the pass's thread always waiting for the helper's part, HELPER) and by
 * the background job. On 2 and 4 threads against the reference loop, bit
 * for bit: with the background job ended when the next step needs its
 * draws (how many were made depends on timing), and with at most all the
 * chunks, the first only, or part of each applier's (one applier
 * has 25 chunks of 8 pairs, the other 9) made and the next step waiting
 * for them; with a known count some draws made ahead must have been
 * taken, and not all (the guesses that failed), and with HELPER the
 * split level's helper makes every chunk before the pair pass ends, so
 * some must have been made in the pass. The split route must have run. */
static void test_draws_ahead(void **st)
{
    (void)st;
    static const double resolutions[] = {0.25, 0.05};
    static const int limits[] = {-1, 1000, 1, 5, 30};
    for (size_t ri = 0; ri < 2; ri++) {
        uint64_t none[3], nosplit[2];
        StateDict *ref = ahead_frames(true, 1, resolutions[ri], -1, PHYS_SPLIT_AUTO, none,
                                      nosplit);
        assert_int_equal(none[1], 0);
        static const unsigned threads[] = {2, 4};
        for (size_t ti = 0; ti < 2; ti++) {
            for (size_t li = 0; li < 2 * sizeof limits / sizeof *limits; li++) {
                const int limit = limits[li / 2];
                uint64_t counts[3], splits[2];
                StateDict *sd = ahead_frames(false, threads[ti], resolutions[ri], limit,
                                             li % 2 ? PHYS_SPLIT_HELPER : PHYS_SPLIT_AUTO,
                                             counts, splits);
                assert_same_state(ref, sd, 100 + 20 * ri + li, threads[ti]);
                if (limit >= 0) {
                    assert_true(counts[0] > 0);
                    assert_true(counts[0] < counts[1]);
                    /* with HELPER, the helper made them all in the pass */
                    if (li % 2)
                        assert_true(counts[2] > 0);
                }
                assert_true(splits[0] + splits[1] > 0);
                state_free(sd);
            }
        }
        state_free(ref);
    }
}

/* Clusters of discs far apart: the box of grid cells around them is too
 * large for the dense grid (more than 4 cells per entry + 4096), so the
 * level takes the grid hashed by cell (pairs.c); one cluster alone (the
 * first scene of each D) takes the dense grid. Short-reach appliers only,
 * D = 1..3, 1, 2 and 4 threads against the reference loop. */
static void test_grid_layouts(void **st)
{
    (void)st;
    for (size_t D = 1; D <= 3; D++) {
        for (int clusters = 1; clusters <= 3; clusters += 2) {
            uint64_t seed = 4000 + 10 * D + (uint64_t)clusters;
            Rng r = {seed};
            Scene sc = {.D = D, .box = D == 1 ? 40 : D == 2 ? 8 : 4,
                        .no_random = true};
            Node *ph = physics_node(D);
            for (int c = 0; c < clusters; c++) {
                for (size_t i = 0; i < 300; i++) {
                    Node *p = add(ph, chance(&r, 0.05) ? "anchor" : "particle");
                    set(p, "id", num((double)sc.nids++));
                    double x[4];
                    for (size_t k = 0; k < D; k++)
                        x[k] = 1e5 * c + (uni(&r) - 0.5) * sc.box;
                    set(p, "position", vec_from_nums(x, (uint32_t)D));
                    set(p, "velocity", rvec(&r, D, 4, 0));
                    set(p, "radius", num(chance(&r, 0.1) ? 0 : 0.2 + uni(&r)));
                    set(p, "mass", num(0.5 + uni(&r)));
                }
            }
            set(add(ph, "collision"), "strength", num(7));
            Node *ad = add(ph, "adhesion");
            set(ad, "strength", num(3));
            Node *gv = add(ph, "gravity");
            set(gv, "strength", num(2));
            set(gv, "max_distance", num(2.5));
            check_threads_124(ph, seed);
            node_release(ph);
        }
    }
}

/* Grids large enough for their build to be split into tasks (pairs.c:
 * 4,096 entries a task): 8,500 discs, densely packed, with a few far
 * outside the grid's range (odd entries, which must stay in ascending pool
 * order), a few anchors and eased particles, over 3 frames of one step
 * each, so particles move between cells; the same tree every frame, so
 * the particles are filled from last frame's slots (collect.c, on several
 * threads); 1, 2 and 4 threads against the reference loop. In
 * D = 2 they are one cluster (the dense grid); in D = 3 three clusters far
 * apart (the grid hashed by cell). */
static void test_large_grids(void **st)
{
    (void)st;
    for (size_t D = 2; D <= 3; D++) {
        int clusters = D == 2 ? 1 : 3;
        uint64_t seed = 4500 + 10 * D + (uint64_t)clusters;
        Rng r = {seed};
        Node *ph = physics_node(D);
        set(ph, "resolution", num(0.25));
        double box = D == 2 ? 150 : 30;
        for (size_t i = 0; i < 8500; i++) {
            Node *p = add(ph, chance(&r, 0.02) ? "anchor" : "particle");
            /* in D = 3 one id twice: the later particle's values win */
            set(p, "id", num((double)(D == 3 && i == 8000 ? 10 : i)));
            if (chance(&r, 0.01))
                set(p, "ease", num(0.6));
            double x[3];
            int c = (int)below(&r, (size_t)clusters);
            for (size_t k = 0; k < D; k++)
                x[k] = 1e5 * c + (uni(&r) - 0.5) * box;
            if (chance(&r, 0.002))
                x[below(&r, D)] = chance(&r, 0.5) ? 3e9 : -1e15;
            set(p, "position", vec_from_nums(x, (uint32_t)D));
            set(p, "velocity", rvec(&r, D, 40, 0));
            set(p, "radius", num(0.3 + uni(&r)));
        }
        set(add(ph, "collision"), "strength", num(50));
        check_threads_124(ph, seed);
        /* a collision level is simple: an entry's candidates (from none
         * to past 16 here), from 4 on, go through simple_block in blocks,
         * put in pool order by rank (AVX2, up to 16) or by insertion (the
         * portable copies, and past 16) */
        StateDict *ref = simulate(ph, true, 1, 3);
        for (unsigned t = 1; t <= 2; t++) {
            StateDict *sd = simulate_simd(ph, false, t, 3, PHYS_SIMD_PORTABLE);
            assert_same_state(ref, sd, seed, t);
            state_free(sd);
        }
        state_free(ref);
        node_release(ph);
    }
}

/* The position and velocity writes of a large system (8,192 particles or
 * more) are split over threads when they can go in place (stateio.c); a
 * value someone else also holds (a script that kept it: here every 97th
 * particle's values, retained between frames) must instead be replaced
 * through the dictionary, leaving the held vector as it was. 1, 2 and 4
 * threads give the same dictionaries, and the held vectors keep their
 * numbers. */
static void test_shared_values(void **st)
{
    (void)st;
    Rng r = {4600};
    Node *ph = physics_node(2);
    for (size_t i = 0; i < 8400; i++) {
        Node *p = add(ph, "particle");
        set(p, "id", num((double)i));
        set(p, "position", rvec(&r, 2, 300, 0));
        set(p, "velocity", rvec(&r, 2, 10, 0));
        set(p, "radius", num(1));
    }
    set(add(ph, "collision"), "strength", num(5));
    StateDict *sds[3];
    static const unsigned threads[] = {1, 2, 4};
    for (size_t ti = 0; ti < 3; ti++) {
        PhysicsWorld *w = phys_new();
        phys_set_threads(w, threads[ti]);
        StateDict *sd = state_new();
        Vec *held[2 * 87] = {0};
        double was[2 * 87][2];
        for (int f = 0; f < 4; f++) {
            PhysicsFrame fr = {.time = 0.25 * f, .fps = 4, .performance = 2};
            phys_run_frame(w, &ph, 1, sd, &fr);
            for (size_t h = 0; f > 0 && h < 2 * 87; h++) {   /* frame 0 does not step */
                vec_release(held[h]);
                /* keys P;id (position) and P;id;:velocity */
                Vec *parts[3] = {num(7), num((double)(97 * (h / 2))),
                                 num(symbol_value("velocity", 8))};
                Vec *key = vec_compose(parts, h % 2 ? 3 : 2);
                held[h] = (Vec *)state_get(sd, key);
                assert_non_null(held[h]);
                vec_retain(held[h]);
                memcpy(was[h], vec_cnums(held[h]), sizeof was[h]);
                for (int k = 0; k < 3; k++)
                    vec_release(parts[k]);
                vec_release(key);
            }
        }
        PhysicsFrame fr = {.time = 1.0, .fps = 4, .performance = 2};
        phys_run_frame(w, &ph, 1, sd, &fr);
        for (size_t h = 0; h < 2 * 87; h++) {
            assert_memory_equal(vec_cnums(held[h]), was[h], sizeof was[h]);
            vec_release(held[h]);
        }
        phys_free(w);
        sds[ti] = sd;
    }
    assert_same_state(sds[0], sds[1], 4600, 2);
    assert_same_state(sds[0], sds[2], 4600, 4);
    for (size_t ti = 0; ti < 3; ti++)
        state_free(sds[ti]);
    node_release(ph);
}

/* Levels of unlimited reach (!electrostatic without max_distance, mixed
 * with !gravity with and without it, !collision with and without power,
 * up to four appliers): these take the tiled reference loop of tiles.c
 * with one or two threads (the gather with four), in each of its vector
 * widths (2, 4 and 8 lanes: portable, AVX2 with and without AVX-512VL,
 * AVX-512, as far as the processor has them), whose row blocks and tiles end part-filled unless
 * the sizes are multiples of the width; the two largest have enough pairs
 * for the threaded route of tiles.c (tasks over chunks of partners, the
 * last chunk part-filled). Sizes around the widths, D = 1..3,
 * a nested group (a level whose pool reaches the parent's particles), zero
 * charges and masses, coincident particles, NaN/infinite/far elements. */
static void test_unlimited_levels(void **st)
{
    (void)st;
    static const size_t sizes[] = {2, 3, 4, 5, 7, 8, 9, 16, 17, 40, 131, 390, 517};
    for (size_t D = 1; D <= 3; D++) {
        for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++) {
            uint64_t seed = 3000 + 10 * D + si;
            Rng r = {seed};
            /* every third scene has NaN, infinite and far-out elements */
            Scene sc = {.D = D, .box = 6, .no_random = true,
                        .special = si % 3 == 2 ? 0.05 : 0};
            Node *ph = physics_node(D);
            add_particles(&r, &sc, ph, sizes[si]);
            set(add(ph, "electrostatic"), "strength", num(5 + uni(&r)));
            if (si % 2) {
                Node *gv = add(ph, "gravity");
                set(gv, "strength", num(2));
                if (si % 4 == 1)
                    set(gv, "max_distance", num(1.5));
            }
            Node *c = add(ph, "collision");
            if (si % 3 == 0)
                set(c, "power", num(1.5));
            if (si % 4 == 3)   /* four appliers in one level */
                set(add(ph, "electrostatic"), "strength", num(-1));
            Node *g = add(ph, "group");
            add_particles(&r, &sc, g, 3 + sizes[si] / 2);
            set(add(g, "gravity"), "strength", num(3));
            set(add(g, "electrostatic"), "strength", num(1));
            vec_release(sc.lastpos);
            static const unsigned threads[] = {1, 2, 4};
            assert_widths_match(ph, seed, threads, 3);
            node_release(ph);
        }
    }
}

/* The tile kernels specialised for the common unlimited levels (tiles.c
 * TILE_SPEC_*: !electrostatic or !gravity alone, or either with
 * !collision before or after it, power 1, no max_distance) and levels just
 * outside them (a power, a max_distance, three appliers), D = 1..3, in each
 * vector width on one and two threads, against the reference loop. */
static void test_tile_specs(void **st)
{
    (void)st;
    static const char *const levels[][3] = {
        {"electrostatic"}, {"gravity"},
        {"electrostatic", "collision"}, {"collision", "electrostatic"},
        {"gravity", "collision"}, {"collision", "gravity"},
        {"gravity", "electrostatic"}, {"collision", "gravity", "electrostatic"},
    };
    const size_t nlevels = sizeof levels / sizeof *levels;
    for (size_t D = 1; D <= 3; D++) {
        for (size_t li = 0; li < nlevels + 2; li++) {
            uint64_t seed = 5000 + 20 * D + li;
            Rng r = {seed};
            Scene sc = {.D = D, .box = 5, .no_random = true,
                        .special = li % 4 == 3 ? 0.05 : 0};
            Node *ph = physics_node(D);
            add_particles(&r, &sc, ph, 37 + 11 * li);
            /* the last two: a specialised pair made general by a power
             * or a max_distance */
            const char *const *kinds = levels[li < nlevels ? li : 2];
            for (size_t f = 0; f < 3 && kinds[f]; f++) {
                Node *a = add(ph, kinds[f]);
                set(a, "strength", num(1 + 4 * uni(&r)));
                if (li == nlevels && !strcmp(kinds[f], "collision"))
                    set(a, "power", num(2));
                if (li == nlevels + 1 && strcmp(kinds[f], "collision"))
                    set(a, "max_distance", num(2));
            }
            vec_release(sc.lastpos);
            static const unsigned threads[] = {1, 2};
            assert_widths_match(ph, seed, threads, 2);
            node_release(ph);
        }
    }
}

/* The tiles that tiles_kernel.h takes its fast route for: every lane a
 * partner, every radius, mass and charge nonzero, no max_distance, where
 * !gravity and !electrostatic act in every lane without masks and
 * !collision is left out of the rows where it acts nowhere. Crowded boxes
 * (a few collisions in most tiles, none in some), in sizes around the tile
 * widths with a nested group, D = 1..3, the specialised levels and general
 * ones (a collision power, three appliers), NaN and infinite elements in
 * every third, each vector width, one and two threads, against the
 * reference loop. */
static void test_full_tiles(void **st)
{
    (void)st;
    static const char *const levels[][3] = {
        {"electrostatic", "collision"}, {"collision", "gravity"},
        {"gravity"}, {"collision", "electrostatic", "gravity"},
    };
    static const size_t sizes[] = {8, 9, 16, 23, 64, 150};
    const size_t nlevels = sizeof levels / sizeof *levels;
    for (size_t D = 1; D <= 3; D++) {
        for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++) {
            const size_t li = (D + si) % (nlevels + 1);
            uint64_t seed = 7000 + 20 * D + si;
            Rng r = {seed};
            Scene sc = {.D = D, .box = 1.5 * (double)D * pow((double)sizes[si], 1.0 / (double)D),
                        .no_random = true, .nonzero = true,
                        .special = si % 3 == 2 ? 0.02 : 0};
            Node *ph = physics_node(D);
            add_particles(&r, &sc, ph, sizes[si]);
            const char *const *kinds = levels[li < nlevels ? li : 0];
            for (size_t f = 0; f < 3 && kinds[f]; f++) {
                Node *a = add(ph, kinds[f]);
                set(a, "strength", num(1 + 4 * uni(&r)));
                if (li == nlevels && !strcmp(kinds[f], "collision"))
                    set(a, "power", num(1.5));
            }
            Node *g = add(ph, "group");
            add_particles(&r, &sc, g, 5 + sizes[si] / 3);
            set(add(g, "collision"), "strength", num(2));
            set(add(g, "electrostatic"), "strength", num(1));
            vec_release(sc.lastpos);
            static const unsigned threads[] = {1, 2};
            assert_widths_match(ph, seed, threads, 2);
            node_release(ph);
        }
    }
}

/* simulate() with the tiles and rows routes taking at most [slice] pairs
 * at once (phys_set_slice). */
static StateDict *simulate_sliced(Node *ph, unsigned threads, int simd, double slice)
{
    PhysicsWorld *w = phys_new();
    phys_set_threads(w, threads);
    if (simd >= 0) phys_set_simd(w, simd);
    phys_set_slice(w, slice);
    return run_frames(w, ph, 3);
}

/* A level of more pairs than a slice runs as consecutive slices of its
 * rows (pairs.c, run_slices), each a level of its own: D = 1..3, the tiles
 * route (collision, gravity, electrostatic) and the rows route (with
 * adhesion, which the tiles do not take), slices of one row, of a few
 * rows and of rows that do not divide the level, a nested group whose
 * pool reaches the parent's particles, zero masses and charges, NaN and
 * infinite elements; on one and two threads, in each vector width,
 * against the reference loop, bit for bit. */
static void test_sliced_levels(void **st)
{
    (void)st;
    static const double slices[] = {1, 37, 500, 4000};
    for (size_t D = 1; D <= 3; D++) {
        for (size_t k = 0; k < 4; k++) {
            uint64_t seed = 9100 + 10 * D + k;
            Rng r = {seed};
            Scene sc = {.D = D, .box = 2.0 * (double)D * pow(120.0, 1.0 / (double)D),
                        .no_random = true, .special = k == 3 ? 0.02 : 0};
            Node *ph = physics_node(D);
            add_particles(&r, &sc, ph, 120);
            set(add(ph, "electrostatic"), "strength", num(1 + 4 * uni(&r)));
            set(add(ph, k % 2 ? "adhesion" : "gravity"), "strength", num(1 + uni(&r)));
            Node *g = add(ph, "group");
            add_particles(&r, &sc, g, 30);
            set(add(g, "collision"), "strength", num(2));
            vec_release(sc.lastpos);
            StateDict *ref = simulate(ph, true, 1, 3);
            static const unsigned threads[] = {1, 2};
            for (size_t t = 0; t < 2; t++)
                for (int simd = PHYS_SIMD_PORTABLE; simd <= PHYS_SIMD_AVX512; simd++) {
                    StateDict *sd = simulate_sliced(ph, threads[t], simd, slices[k]);
                    assert_same_state(ref, sd, seed, threads[t]);
                    state_free(sd);
                }
            state_free(ref);
            node_release(ph);
        }
    }
}

/* A copy of [sd]'s entries. */
static StateDict *state_snapshot(const StateDict *sd)
{
    size_t n;
    StateEntry *e = state_entries(sd, &n);
    StateDict *c = state_new();
    for (size_t i = 0; i < n; i++)
        state_set(c, e[i].key, e[i].value);
    free(e);
    return c;
}

/* A step whose pair pass the interrupt flag cuts short is abandoned
 * (step.c) on every route that asks for the flag: the all-pairs gather
 * (four threads), the grid, the reference loop, and a tiles level run in
 * slices (one thread). Run A has the flag set for its third frame (at
 * 0.5 s), before the frame or (phys_set_cut_after) part way through its
 * pair pass: that frame must leave every entry as the frame before left
 * it but P;:last (the frame's time) and P;:iteration (one more). Run B
 * has no such frame: its state is given those two entries by hand
 * instead. From then on both must step alike, bit for bit: nothing of
 * the cut pass's partial sums is left for the next step. */
static void test_interrupted_step(void **st)
{
    (void)st;
    for (int t = 0; t < 8; t++) {
        /* t = 4..7: routes 0..3 cut after 50 polls (after two slices of
         * 100 pairs for route 3) */
        const int route = t % 4;
        const long after = t >= 4 ? (route == 3 ? 3 : 50) : 0;
        uint64_t seed = 9300 + (uint64_t)t;
        Rng r = {seed};
        const size_t D = route == 1 ? 2 : 3;
        Scene sc = {.D = D, .box = 6, .no_random = true, .nonzero = true};
        Node *ph = physics_node(D);
        /* the all-pairs gather takes an unlimited level of 512 entries or
         * more on three threads or more (pairs.c, phys_plan_levels) */
        add_particles(&r, &sc, ph, route == 0 ? 600 : 200);
        set(add(ph, route == 1 ? "collision" : "electrostatic"), "strength", num(3));
        vec_release(sc.lastpos);
        volatile int flag = 0;
        StateDict *sd[2];
        for (int run = 0; run < 2; run++) {
            PhysicsWorld *w = phys_new();
            phys_set_pairs(w, route == 2);
            /* route 3 on one thread: on two, the first pass splits a
             * level of this size between them, and a split level is not
             * sliced */
            phys_set_threads(w, route == 0 ? 4 : route == 3 ? 1 : 2);
            if (route == 3) phys_set_slice(w, 100);
            sd[run] = state_new();
            for (int f = 0; f < 5; f++) {
                PhysicsFrame fr = {.time = 0.25 * f, .fps = 4, .realtime = false,
                                   .performance = 2, .interrupt = &flag};
                if (f == 2) {
                    StateDict *before = state_snapshot(sd[run]);
                    set_sym_entry(before, "last", 0.5);
                    set_sym_entry(before, "iteration", 2);
                    if (run == 0) {
                        flag = !after;
                        phys_set_cut_after(w, after);
                        phys_run_frame(w, &ph, 1, sd[run], &fr);
                        phys_set_cut_after(w, 0);
                        flag = 0;
                        assert_same_state(before, sd[run], seed, 2);
                    } else {
                        set_sym_entry(sd[run], "last", 0.5);
                        set_sym_entry(sd[run], "iteration", 2);
                        assert_same_state(before, sd[run], seed, 2);
                    }
                    state_free(before);
                    continue;
                }
                phys_run_frame(w, &ph, 1, sd[run], &fr);
            }
            phys_free(w);
        }
        assert_same_state(sd[0], sd[1], seed, 2);
        assert_true(state_count(sd[0]) > 400);
        node_release(ph);
        state_free(sd[0]);
        state_free(sd[1]);
    }
}

/* simulate_simd() with the split route in [mode] (PHYS_SPLIT_*), adding
 * the levels it ran to [counts] (phys_split_counts). */
static StateDict *simulate_split(Node *ph, unsigned threads, int simd, int mode,
                                 uint64_t counts[2])
{
    PhysicsWorld *w = phys_new();
    phys_set_threads(w, threads);
    phys_set_simd(w, simd);
    phys_set_split(w, mode);
    /* no draws made ahead between frames: how many the background job
     * would make depends on the threads' timing, and they move the cut
     * (a loaded machine once left a level unsplit) */
    phys_set_ahead(w, 0);
    StateDict *sd = state_new();
    for (int f = 0; f < 3; f++) {
        PhysicsFrame fr = {.time = 0.25 * f, .fps = 4, .realtime = false,
                           .performance = 2};
        phys_run_frame(w, &ph, 1, sd, &fr);
    }
    uint64_t c[2];
    phys_split_counts(w, c);
    counts[0] += c[0];
    counts[1] += c[1];
    phys_free(w);
    return sd;
}

/* The split route of tiles.c ("Two threads for a middle-sized level"):
 * all-pairs levels of 4,096 to 98,303 pairs (from 32,768 only with
 * !random, whose draws the helper makes and which move the cut), D =
 * 1..3, specialised levels and general ones (a max_distance beside an
 * unlimited applier, a collision power, four appliers), rows in part-filled blocks, a nested group whose
 * level has more partners than rows (its pool reaches the parent's
 * particles), zero charges and masses, coincident particles, NaN and
 * infinite elements in every third. On two and four threads, in each
 * vector width, with the helper thread free to take the near part (AUTO),
 * with the pass's thread taking all three parts (ALONE) and with the
 * helper always taking the near part (HELPER), against the reference
 * loop, bit for bit; every scene must have taken the route, in the part
 * each mode says. */
static void test_split_levels(void **st)
{
    (void)st;
    static const size_t sizes[] = {93, 130, 181, 250, 300};
    for (size_t D = 1; D <= 3; D++) {
        for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++) {
            uint64_t seed = 11000 + 20 * D + si;
            Rng r = {seed};
            const bool random = si % 2 == 1 || sizes[si] >= 256;
            Scene sc = {.D = D, .box = 6, .no_random = true,
                        .special = si % 3 == 2 ? 0.05 : 0};
            Node *ph = physics_node(D);
            add_particles(&r, &sc, ph, sizes[si]);
            switch ((D + si) % 4) {
            case 0:
                set(add(ph, "electrostatic"), "strength", num(5));
                set(add(ph, "collision"), "strength", num(3));
                break;
            case 1:
                set(add(ph, "collision"), "strength", num(3));
                Node *gv = add(ph, "gravity");
                set(gv, "strength", num(2));
                set(gv, "max_distance", num(2.5));
                set(add(ph, "electrostatic"), "strength", num(5));   /* the unlimited reach */
                break;
            case 2:
                set(add(ph, "gravity"), "strength", num(4));
                break;
            default:   /* four appliers, the most a tile level takes */
                set(add(ph, "electrostatic"), "strength", num(5));
                Node *c = add(ph, "collision");
                set(c, "strength", num(3));
                set(c, "power", num(1.5));
                set(add(ph, "electrostatic"), "strength", num(-1));
                set(add(ph, "gravity"), "strength", num(2));
                break;
            }
            if (random)
                set(add(ph, "random"), "strength", num(0.5));
            Node *g = add(ph, "group");
            add_particles(&r, &sc, g, 3 + sizes[si] / 4);
            set(add(g, "electrostatic"), "strength", num(1));
            vec_release(sc.lastpos);
            StateDict *ref = simulate(ph, true, 1, 3);
            static const unsigned threads[] = {2, 4};
            for (size_t ti = 0; ti < 2; ti++) {
                for (int simd = PHYS_SIMD_PORTABLE; simd <= PHYS_SIMD_AVX512; simd++) {
                    static const int modes[] = {PHYS_SPLIT_AUTO, PHYS_SPLIT_ALONE, PHYS_SPLIT_HELPER};
                    for (size_t mi = 0; mi < 3; mi++) {
                        uint64_t counts[2] = {0, 0};
                        StateDict *sd = simulate_split(ph, threads[ti], simd, modes[mi], counts);
                        assert_same_state(ref, sd, seed, threads[ti]);
                        state_free(sd);
                        if (counts[0] + counts[1] == 0)
                            fail_msg("seed %llu threads %u: no level took the split route",
                                     (unsigned long long)seed, threads[ti]);
                        if (modes[mi] == PHYS_SPLIT_ALONE && counts[0] != 0)
                            fail_msg("seed %llu: the helper ran a near part when told not to",
                                     (unsigned long long)seed);
                        if (modes[mi] == PHYS_SPLIT_HELPER && counts[1] != 0)
                            fail_msg("seed %llu: the pass's thread ran a near part when told not to",
                                     (unsigned long long)seed);
                    }
                }
            }
            state_free(ref);
            node_release(ph);
        }
    }
}

/* A copy of [n] sharing nothing but attribute values and names. */
static Node *deep_copy(const Node *n)
{
    Node *c = node_new(n->kind);
    for (uint32_t i = 0; i < n->ntags; i++)
        node_add_tag(c, n->tags[i]);
    for (uint32_t i = 0; i < n->nattrs; i++)
        node_set_attr(c, n->attrs[i].name, vec_retain(n->attrs[i].value));
    for (uint32_t i = 0; i < n->nchildren; i++) {
        Node *k = deep_copy(n->children[i]);
        node_append(c, k);
        node_release(k);
    }
    return c;
}

/* simulate(), each frame handed a fresh copy of [ph]: no child of the
 * root is ever the one of the frame before, so every frame walks the tree
 * in full (collect.c). */
static StateDict *simulate_fresh(Node *ph, bool naive, int frames)
{
    PhysicsWorld *w = phys_new();
    phys_set_pairs(w, naive);
    phys_set_threads(w, 1);
    StateDict *sd = state_new();
    for (int f = 0; f < frames; f++) {
        PhysicsFrame fr = {.time = 0.25 * f, .fps = 4, .realtime = false,
                           .performance = 2};
        Node *cp = deep_copy(ph);
        phys_run_frame(w, &cp, 1, sd, &fr);
        node_release(cp);
    }
    phys_free(w);
    return sd;
}

/* A static tree (the same children of the root every frame, as the
 * simplifier hands them) keeps what collection built from it and redoes
 * only what depends on the frame (collect.c): the same bits as a tree
 * collected afresh every frame. Random scenes (groups, every applier kind,
 * distance appliers with missing ends, barriers, anchors, special values)
 * with eased appliers, an eased particle force and a chain of !random
 * appliers added, whose eases run out during the frames; both pair routes. */
static void test_static_tree(void **st)
{
    (void)st;
    for (uint64_t seed = 9000; seed < 9012; seed++) {
        Node *ph = random_scene(seed, 0, false);
        Rng r = {seed};
        const Vec *pos = NULL;
        for (uint32_t i = 0; i < ph->nchildren && !pos; i++)
            pos = node_attr(ph->children[i], "position");
        const size_t D = pos ? pos->len : 1;
        Node *e = add(ph, "electrostatic");
        set(e, "strength", num(3 + uni(&r)));
        set(e, "ease", num(0.6));
        Node *dr = add(ph, "drag");
        set(dr, "strength", num(0.05));
        set(dr, "ease", num(1));
        set(add(ph, "random"), "strength", num(0.2));
        set(add(ph, "random"), "strength", num(0.1));
        Node *p = add(ph, "particle");
        set(p, "id", num(1e6));
        set(p, "position", rvec(&r, D, 2, 0));
        set(p, "force", rvec(&r, D, 5, 0));
        set(p, "ease", num(0.8));
        for (int naive = 0; naive <= 1; naive++) {
            StateDict *ref = simulate_fresh(ph, naive, 7);
            assert_true(state_count(ref) > 4);
            StateDict *sd = simulate(ph, naive, 1, 7);
            assert_same_state(ref, sd, seed, 1);
            state_free(sd);
            state_free(ref);
        }
        node_release(ph);
    }
}

/* The test can fail: a world whose fast route adds one pair twice would
 * differ. Here, a scene that does interact gives different bits from one
 * that starts a hair apart, so bitwise comparison is meaningful. */
static void test_comparison_detects_change(void **st)
{
    (void)st;
    Node *ph = mk("physics");
    set(ph, "state", num(7));
    set(ph, "dimensions", num(2));
    double x[2] = {0, 0}, y[2] = {0.5, 0.25};
    Node *a = add(ph, "particle");
    set(a, "id", num(1));
    set(a, "radius", num(1));
    set(a, "position", vec_from_nums(x, 2));
    Node *b = add(ph, "particle");
    set(b, "id", num(2));
    set(b, "radius", num(1));
    set(b, "position", vec_from_nums(y, 2));
    add(ph, "collision");
    StateDict *s1 = simulate(ph, false, 2, 3);
    y[0] = nextafter(0.5, 1);
    set(b, "position", vec_from_nums(y, 2));
    StateDict *s2 = simulate(ph, false, 2, 3);
    size_t n;
    StateEntry *e = state_entries(s1, &n);
    bool differs = false;
    for (size_t i = 0; i < n; i++) {
        const Vec *v2 = state_get(s2, e[i].key);
        if (!v2 || v2->len != e[i].value->len ||
            memcmp(vec_cnums(v2), vec_cnums(e[i].value), v2->len * sizeof(double)))
            differs = true;
    }
    free(e);
    assert_true(differs);
    state_free(s1);
    state_free(s2);
    node_release(ph);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_comparison_detects_change),
        cmocka_unit_test(test_grid_edge),
        cmocka_unit_test(test_grid_layouts),
        cmocka_unit_test(test_large_grids),
        cmocka_unit_test(test_shared_values),
        cmocka_unit_test(test_unlimited_levels),
        cmocka_unit_test(test_tile_specs),
        cmocka_unit_test(test_full_tiles),
        cmocka_unit_test(test_split_levels),
        cmocka_unit_test(test_sliced_levels),
        cmocka_unit_test(test_interrupted_step),
        cmocka_unit_test(test_static_tree),
        cmocka_unit_test(test_small_scenes),
        cmocka_unit_test(test_large_scenes),
        cmocka_unit_test(test_split_particle_pass),
        cmocka_unit_test(test_draw_chunks),
        cmocka_unit_test(test_draws_ahead),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
