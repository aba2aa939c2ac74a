/* physics.h: the !physics particle engine (PHYSICS.md, PHYSICS-ENGINE.md).
 *
 * A PhysicsWorld holds the persistent simulation systems of one runtime. Each
 * frame the runtime hands it the top-level !physics nodes of the frame's node
 * tree, in order; the i-th node drives the i-th system. The engine reads its
 * persistent values back from the state dictionary and writes positions,
 * velocities and clock keys into it (PHYSICS.md "State interaction").
 */
#ifndef FL_PHYSICS_H
#define FL_PHYSICS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "node.h"
#include "state.h"

typedef struct PhysicsWorld PhysicsWorld;

/* What the engine needs to know about the current frame. */
typedef struct PhysicsFrame {
    double time;          /* the frame's `time` name, seconds */
    double fps;           /* target frame rate used for the default resolution */
    bool realtime;        /* false in lockstep: always insert extra steps */
    double performance;   /* engine performance figure (2 in lockstep) */
    /* Bounded work: at most [max_steps] simulation steps per
     * system per frame (0: no limit); past it the system stops stepping and
     * its clock falls behind `time`, as when the reference cannot keep up
     * (PHYSICS.md "The Simulation Clock"). [interrupt] (NULL: none) is
     * polled after every step and, inside a step, by the pair routes
     * between targets, rows or slices of rows: once *interrupt is
     * non-zero the remaining steps of the frame are skipped, and a step
     * cut short is abandoned (the last whole step's positions,
     * velocities and clock stay), leaving a consistent state. Read
     * atomically from any thread: write it with an atomic store (as a
     * signal handler may). */
    long max_steps;
    volatile int *interrupt;
    /* Set to true (when non-NULL) if a system skipped this frame because
     * its `time` or `resolution` was not finite (state left untouched), or
     * stopped stepping at max_steps. */
    bool *nonfinite;
    bool *capped;
    /* false: PHYSICS.md's behaviour (the default). true: the four places
     * that PHYSICS-ENGINE.md marks [doc] behave as Flitter 1.0.0b28
     * published them (--physics=upstream, `%pragma physics :upstream`):
     * an applier's strength *= clock/ease when ease > 0 and ease < clock;
     * a particle's ease scales the step's k = dt/mass by clock/ease while
     * clock < ease, and its own force is not eased; !field adds
     * strength*direction without the charge; a barrier with min <= 0
     * applies no soft force at all (its max is ignored). */
    bool upstream;
} PhysicsFrame;

/* A new world with no systems. */
PhysicsWorld *phys_new(void);
/* Threads for the pair loops of [w]: [n] in all (0 = every available
 * core). The results are the same bits for every n (pairs.c explains why);
 * small systems run on one thread whatever n is. Default: 0. */
void phys_set_threads(PhysicsWorld *w, unsigned n);
/* The world's thread pool (workers.h), made now if it has none yet, for
 * the runtime to lend to other work between physics frames (the
 * evaluator's loop kernels); NULL when the world runs on one thread or the
 * threads cannot be had. Owned by the world: valid until the next
 * phys_set_threads or phys_free. */
struct Workers *phys_workers(PhysicsWorld *w);
/* [naive] true: always use the reference all-pairs loop of
 * PHYSICS-ENGINE.md §4 on one thread (the slow route that the neighbour
 * grid and the threaded gather are checked against). Default: false. */
void phys_set_pairs(PhysicsWorld *w, bool naive);
/* [literal] true: run the particle pass (per-particle appliers, barrier
 * soft forces, the step and the rebounds of PHYSICS-ENGINE.md §4) through
 * the literal route of lib/physics/literal.c, one particle at a time on
 * one thread, written as the spec is, that the specialised route of
 * step.c is checked against; the same bits. Default: false. */
void phys_set_particles(PhysicsWorld *w, bool literal);
/* Vector instruction sets of the pair kernels, in order: the portable
 * copy (the tile kernel's 2 x 2 tiles), AVX2 (4 x 4 tiles, 16 vector
 * registers), the same 4 x 4 tiles with AVX-512VL (its 32 registers: the
 * 3-D kernel keeps its values in them instead of on the stack) and
 * AVX-512 (8 x 8 tiles). */
enum { PHYS_SIMD_PORTABLE, PHYS_SIMD_AVX2, PHYS_SIMD_AVX2_VL, PHYS_SIMD_AVX512 };

/* The vector instructions the pair kernels may use: [level] a
 * PHYS_SIMD_* (PHYS_SIMD_AVX2: up to AVX2, and so on), capped at what the
 * processor runs. Returns the level in force. Every
 * level gives the same bits (lib/physics/tiles.c). Default, without a
 * call of this: the best available, and where the processor has AVX-512
 * each system times the 4 x 4 tiles (with AVX-512VL) against it on the
 * first runs of each kind of pair level and keeps the faster (tiles.c). */
int phys_set_simd(PhysicsWorld *w, int level);
/* The split route of the pair kernels (lib/physics/tiles.c, "Two threads
 * for a middle-sized level"): PHYS_SPLIT_AUTO (the default) lets
 * middle-sized all-pairs levels take it when the world has two threads or
 * more; PHYS_SPLIT_OFF never; PHYS_SPLIT_ALONE takes it where AUTO would
 * but has the pair pass's thread run all three of its parts (the helper
 * thread only draws); PHYS_SPLIT_HELPER takes it where AUTO would and has
 * the pair pass's thread always wait for the helper to run the near part
 * (with two threads or more the helper is another thread, so it comes).
 * Every mode gives the same bits; all but AUTO are for tests. */
enum { PHYS_SPLIT_AUTO, PHYS_SPLIT_OFF, PHYS_SPLIT_ALONE, PHYS_SPLIT_HELPER };
void phys_set_split(PhysicsWorld *w, int mode);
/* How many levels the systems of [w] have run on the split route: [0]
 * those whose near part the helper thread ran, [1] those whose near part
 * the pair pass's own thread ran (tests check that the route was taken). */
void phys_split_counts(const PhysicsWorld *w, uint64_t out[2]);
/* Pairs of !random draws that [w]'s systems planned to make alongside a
 * step's pair pass, over all steps so far: [0] those made ahead, during
 * the frame before (step.c, "the next frame's draws": by the threads of
 * its last step's pair pass while they waited, or by the pool's
 * background job after), [1] all; and [2] the chunks of next frames'
 * draws made by the pair passes' threads (tests check that the routes
 * were taken). */
void phys_ahead_counts(const PhysicsWorld *w, uint64_t out[3]);
/* For tests: [limit] < 0 (the default) has the next step end the
 * background job of the next frame's draws, keeping the chunks made by
 * then (how many depends on the threads' timing); [limit] >= 0 lets at
 * most [limit] chunks (8 pairs each) be made, by the pair pass's threads
 * and the background job together, and has the next step wait for them,
 * so that the count is known; then, with PHYS_SPLIT_HELPER, the helper of
 * a split level makes all of them before the pair pass ends. The bits are
 * the same. */
void phys_set_ahead(PhysicsWorld *w, int limit);
/* For tests: the tiles route runs a level of more than [pairs] pairs
 * (<= 0: the default, 2^25), the rows route one of more than a quarter of
 * that, as consecutive slices of its rows, asking for the interrupt
 * between them. The bits are the same. */
void phys_set_slice(PhysicsWorld *w, double pairs);
/* For tests: in each frame after this call, the pair routes' polls of the
 * interrupt flag find it set from the [polls]-th on (<= 0: never), as if
 * the flag had been set part way through the pair pass. */
void phys_set_cut_after(PhysicsWorld *w, long polls);
/* Free [w] and all its systems (NULL is a no-op). */
void phys_free(PhysicsWorld *w);
/* Simulate one frame.
 *   shapes: [nodes] are the [n] top-level !physics nodes of the frame, in
 *           tree order (borrowed); [state] is updated in place
 *   units:  seconds (or the script's own `time` units), world units
 *   errors: nodes with missing `state` or dimensions < 1 are skipped, and so
 *           are nodes with a non-finite `time` or `resolution` (*nonfinite
 *           set); a catch-up past max_steps is cut short (*capped set)
 *   source: PHYSICS-ENGINE.md §2-4 (order of operations is normative) */
void phys_run_frame(PhysicsWorld *w, Node *const *nodes, size_t n,
                    StateDict *state, const PhysicsFrame *frame);

#endif
