/* systems.h: the `!physics` systems of a frame as an onlooker sees them,
 * read from the frame's node tree and the state dictionary only (never from
 * the engine's internals), for pictures (view.h) and trajectories (trace.h).
 *
 * For each top-level `!physics state=P dimensions=D` node: its particles and
 * anchors (also inside `!group`s) with the position and velocity the engine
 * stored under P;id and P;id;:velocity (PHYSICS.md "State interaction"),
 * falling back to the node's `position` / `velocity` attributes before the
 * first step; `radius` and `charge`; the `!distance from= to=` links; and
 * the `!barrier position= normal=` nodes.
 */
#ifndef FL_RENDER_SYSTEMS_H
#define FL_RENDER_SYSTEMS_H

#include <stdbool.h>
#include <stddef.h>

#include "node.h"
#include "state.h"
#include "value.h"

typedef struct PsBody {
    bool anchor;          /* an !anchor (else a !particle) */
    const Vec *id;        /* borrowed from the node */
    const Vec *pos;       /* D numbers (borrowed: state or node), or NULL */
    const Vec *vel;       /* D numbers (borrowed), or NULL */
    double radius;        /* clamped to >= 0 */
    double charge;
} PsBody;

typedef struct PsLink {
    const Vec *from, *to; /* positions (borrowed), either may be NULL */
} PsLink;

typedef struct PsBarrier {
    const Vec *pos, *normal;   /* borrowed from the node (NULL: absent) */
} PsBarrier;

typedef struct PsSystem {
    const Vec *prefix;    /* the `state` attribute (borrowed); NULL in a
                             frozen copy (ps_freeze), which has [title] */
    const char *title;    /* the prefix as text (a frozen copy), or NULL:
                             the view formats [prefix] itself */
    int dims;             /* `dimensions` (>= 1) */
    PsBody *bodies;
    size_t nbodies;
    PsLink *links;
    size_t nlinks;
    PsBarrier *barriers;
    size_t nbarriers;
} PsSystem;

/* The systems of [root] (a frame's !root node) in tree order, into [*out]
 * ([*n] of them; free with ps_free). Nodes without `state` or with
 * dimensions < 1 are left out, as the engine skips them. The borrowed
 * vectors stay valid until [sd] or the tree changes.
 *   errors: none (aborts when out of memory). */
void ps_collect(const Node *root, const StateDict *sd, PsSystem **out, size_t *n);
/* Free what ps_collect returned. */
void ps_free(PsSystem *systems, size_t n);
/* A copy of [n] systems from ps_collect that owns everything it points
 * to, so that it can be drawn (view.h) on another thread after the state
 * and the tree have moved on: positions, velocities, links and barriers
 * are copied into one block of numeric vectors of its own, each prefix is
 * written as text with [symbols] into `title`, and body ids are left out
 * (NULL; the view does not show them). [into] is filled, its storage
 * reused from a previous ps_freeze; free it with ps_frozen_free. The
 * vectors of a frozen copy are never retained or released.
 *   errors: false, [into] left as it was, when the copy (its vectors,
 *           bodies, links and barriers) does not fit the memory budget
 *           (mem.h mem_fits); aborts when really out of memory. */
typedef struct PsFrozen {
    PsSystem *sys;        /* the copies (bodies, links and barriers owned) */
    size_t n;
    unsigned char *block; /* the copied vectors */
    size_t cap_block;
    char *titles;         /* the prefixes' text, NUL after each */
    size_t cap_titles;
} PsFrozen;
bool ps_freeze(PsFrozen *into, const PsSystem *systems, size_t n, const SymTab *symbols);
/* Free the storage of [f] (its systems, vectors and titles); it is left
 * empty, ready for another ps_freeze. */
void ps_frozen_free(PsFrozen *f);

/* Coordinate [k] of the numeric vector [v]: a single number stands for
 * every coordinate (as Flitter matches a `position=0` attribute to any
 * dimension); 0 when absent or short. */
double ps_coord(const Vec *v, int k);

#endif
