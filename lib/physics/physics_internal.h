/* physics_internal.h: data structures shared by world.c, forces.c and step.c.
 *
 * One `PhysSystem` per top-level !physics node (matched by order). Everything
 * a frame needs lives in arrays owned by the system and reused from frame to
 * frame (grown, never shrunk), so a steady-state frame allocates nothing per
 * particle except the value vectors it stores into the state dictionary:
 *
 *   particles  struct-of-arrays in *storage order*: the groups in list order
 *              (pre-order, PHYSICS-ENGINE.md §3), each group's particles
 *              contiguous and in declaration order. pos/vel/acc/force/own
 *              hold D doubles per particle (particle p at [p*D, p*D+D)).
 *   appliers   one `PhysApplier` per force applier/barrier node, in tree
 *              pre-order; vector parameters live in `avec` (2*D per applier).
 *   groups     one `PhysGroup` per group (index 0 = the !physics node); each
 *              refers to index lists (into `gidx`) of its own appliers by
 *              category, to the chains "own ++ parent's ++ ..." of particle
 *              appliers and barriers (into `chain`), and to the pair-force
 *              levels and particle pool of §4 (into `levels` and `pool`).
 *   key cache  per storage slot: the particle id and the state keys P;id and
 *              P;id;:velocity built from it (rebuilt only when they change).
 *   prev keys  the particle state keys collected on the previous frame, for
 *              "keys written last frame but not this frame become null".
 */
#ifndef FL_PHYSICS_INTERNAL_H
#define FL_PHYSICS_INTERNAL_H

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "config.h"
#include "physics.h"
#include "workers.h"

/* Python's min(a, b) / max(a, b): the first argument unless the second is
 * strictly smaller / larger (so a NaN first argument is kept). */
static inline double py_min(double a, double b) { return b < a ? b : a; }
static inline double py_max(double a, double b) { return b > a ? b : a; }

/* Copy the [D] doubles of [src] to [dst] (memcpy; inline for D <= 3, the
 * common sizes, where a library call costs more than the copy). */
static inline void phys_copy(double *dst, const double *src, size_t D)
{
    switch (D) {
    case 3: dst[2] = src[2]; /* fall through */
    case 2: dst[1] = src[1]; /* fall through */
    case 1: dst[0] = src[0]; /* fall through */
    case 0: return;
    default: memcpy(dst, src, D * sizeof *dst);
    }
}

/* k = pow(k, power) unless power == 1, then k * strength (§4 distance). */
static inline double phys_shape(double k, double power, double strength)
{
    if (power != 1)
        k = pow(k, power);
    return k * strength;
}

typedef enum PhysApplierKind {
    AP_DISTANCE,        /* explicit pair by id */
    AP_COLLISION,       /* pair ("matrix") appliers ... */
    AP_GRAVITY,
    AP_ELECTROSTATIC,
    AP_ADHESION,
    AP_DRAG,            /* per-particle appliers ... */
    AP_BUOYANCY,
    AP_CONSTANT,
    AP_RANDOM,
    AP_FIELD,
    AP_BARRIER          /* soft distance + hard rebound */
} PhysApplierKind;

/* One force applier or barrier, read once per frame (PHYSICS-ENGINE.md §3). */
typedef struct PhysApplier {
    PhysApplierKind kind;
    uint32_t group;        /* index of the group that declared it */
    double strength;       /* eased strength, fixed for the frame */
    double strength0;      /* the strength attribute, before the ease */
    double ease;           /* the ease attribute (0 = none) */
    double power;          /* distance, collision, barrier */
    double minimum;        /* distance, barrier */
    double maximum;        /* distance, barrier */
    double maxd;           /* pair appliers: max_distance, 0 = unlimited */
    double overlap;        /* adhesion */
    double density;        /* buoyancy */
    double restitution;    /* barrier */
    bool enabled;          /* barrier: false when the normal is zero */
    const Vec *from_id;    /* distance: borrowed from the frame's node */
    const Vec *to_id;
    ptrdiff_t from;        /* distance: resolved storage index, or -1 */
    ptrdiff_t to;
    uint64_t key;          /* random: normal() stream key */
    uint64_t index;        /* random: next draw index (0 at frame start) */
    uint64_t pair_at;      /* random: the even index of the draws in pair
                            * (odd, UINT64_MAX: none yet) */
    double pair[2];        /* ... rng_normal_pair()'s */
    uint64_t pre_at;       /* random: pairs pre_at, pre_at + 2, ... (even
                            * indices) were drawn ahead into PhysSystem.rnd
                            * from offset pre_off, pre_n of them (step.c) */
    uint64_t pre_n;
    size_t pre_off;
    size_t pre_chunk;      /* random: the step's first draw chunk of these
                            * pairs (step.c, phys_draw_chunk) */
    uint64_t pre_done;     /* random: the first pre_done of them were made
                            * during the frame before (DrawsAhead) */
    uint64_t pre_draws;    /* random: the draws a step takes (the
                            * particles of the groups whose chains hold it,
                            * times D) */
    size_t vec;            /* offset of this applier's 2*D doubles in avec:
                            * drag flow | buoyancy gravity | constant force,
                            * acceleration | field direction | barrier
                            * position, unit normal */
} PhysApplier;

/* A group (PHYSICS.md "Groups"); all offsets are into PhysSystem arrays. */
typedef struct PhysGroup {
    ptrdiff_t parent;                 /* -1 for the !physics node itself */
    size_t pstart, npart;             /* storage range of its particles */
    size_t fill;                      /* collection cursor */
    size_t dist_off, dist_n;          /* own distance appliers (gidx) */
    size_t pair_off, pair_n;          /* own pair appliers (gidx) */
    size_t part_off, part_n;          /* own particle appliers (gidx) */
    size_t bar_off, bar_n;            /* own barriers (gidx) */
    size_t pf_off, pf_n;              /* particle-applier chain (chain) */
    size_t b_off, b_n;                /* barrier chain (chain) */
    size_t lvl_off, lvl_n;            /* pair levels (levels) */
    size_t pool_off;                  /* particle pool (pool) */
} PhysGroup;

/* One level of the §4 pair loop: the first `npool` entries of the group's
 * pool against the pair appliers declared by group `group`. */
typedef struct PhysLevel {
    size_t npool;
    size_t group;
    int route;          /* PHYS_ROUTE_*, chosen per frame by phys_plan_levels */
    double reach;       /* no applier of the level acts at dist >= reach */
} PhysLevel;

/* How one pair level is computed (pairs.c). Every route gives the same bits
 * as the reference loop of phys_apply_pair_level. */
enum {
    PHYS_ROUTE_SCATTER,  /* the reference all-pairs loop, one thread */
    PHYS_ROUTE_SKIP,     /* reach 0: no pair can interact */
    PHYS_ROUTE_ALL,      /* per-particle gather over all pairs */
    PHYS_ROUTE_GRID,     /* per-particle gather over a uniform grid */
    PHYS_ROUTE_ROWS,     /* the reference loop, blocks of partners (rows.c) */
    PHYS_ROUTE_TILES     /* the reference loop, W x W tiles (tiles.c) */
};

/* Per-thread scratch of the gather routes: the pair direction and a
 * candidate list (capacity `capcand`). */
typedef struct PhysScratch {
    double *dir;
    size_t capdir;
    uint32_t *cand;
    size_t capcand;
} PhysScratch;

/* The uniform neighbour grid of one pair level, rebuilt every step (pairs.c):
 * dense (below) when the box of the entries' cells is small enough, else
 * pool entries hashed by cell into `nb` buckets (counting sort, each
 * bucket's entries in ascending pool order). Entries whose position is not
 * finite or lies too far out for a 32-bit cell index are in `odd`. */
typedef struct PhysGrid {
    double h;                    /* cell size (>= reach) */
    /* The dense form, used when the box of cells around the entries is
     * small enough: cells numbered x fastest over the box (one cell of
     * padding on every side), the entries laid out cell by cell (within a
     * cell in ascending pool order) with their coordinates copied in that
     * order, so a row of 3 neighbouring cells is one contiguous run. */
    bool dense;
    size_t ext[3];               /* cells along each axis, padding included */
    uint32_t *cellof;            /* per pool entry: dense cell, or UINT32_MAX */
    uint32_t *cstart;            /* ncells + 1 slot starts */
    uint32_t *slotq;             /* pool entry of each slot */
    size_t nslot;                /* entries in the dense layout (not odd) */
    double *sx;                  /* coordinate k of slot i at sx[k*nslot + i] */
    size_t capcellof, capcstart, capslotq, capsx;
    size_t nb;                   /* buckets, a power of two */
    uint32_t *bucket;            /* per pool entry: bucket (0 in the dense
                                  * form), or UINT32_MAX when odd */
    int32_t *cell;               /* per pool entry: 3 cell coordinates */
    uint32_t *start;             /* nb + 1 bucket starts into `ent` */
    uint32_t *ent;               /* pool entries by bucket */
    uint32_t *odd;               /* pool entries outside the grid */
    size_t nodd;
    size_t capbucket, capcell, capstart, capent, capodd;
} PhysGrid;

typedef struct Workers Workers;

/* State keys of one storage slot for this frame (borrowed from the key
 * table). */
typedef struct PhysKeySlot {
    Vec *pkey;            /* P;id */
    Vec *vkey;            /* P;id;:velocity */
    uint64_t phash, vhash;/* vec_hash(key, false) */
    uint32_t ent1;        /* key table entry + 1 of the last particle here */
    bool hit;             /* this frame's particle has last frame's id */
    Vec *pval, *vval;     /* the state's values of pkey/vkey this frame
                           * (numeric, length D; borrowed), or NULL */
    Vec *cp, *cv;         /* retained: pval/vval at the end of last frame */
    Node *node;           /* retained: the particle node whose attributes
                           * fill this slot's radius, mass, charge, anchor
                           * and own force (collect.c), or NULL */
    bool eased;           /* ... and its own force depends on the clock */
} PhysKeySlot;

/* One particle id's state keys, kept while the id is collected every frame
 * (keys.c). */
typedef struct PhysKeyEnt {
    Vec *id;              /* retained */
    Vec *pkey, *vkey;     /* P;id and P;id;:velocity, retained */
    uint64_t idhash, phash, vhash;   /* vec_hash(..., false) */
    uint64_t seen;        /* last frame (kframe) the id was collected */
} PhysKeyEnt;

/* Open-addressing (linear probing) hash index from key vectors (compared
 * with vec_key_equal) to array indices; idx1 = index + 1, 0 = empty slot;
 * the capacity is a power of two at least twice the number of entries. */
typedef struct PhysHashSlot {
    const Vec *key;       /* borrowed */
    uint64_t hash;        /* vec_hash(key, false) */
    size_t idx1;
} PhysHashSlot;

typedef struct PhysHash {
    PhysHashSlot *slot;
    size_t cap;
} PhysHash;

/* A node collected during the tree walk, before storage order is known. */
typedef struct PhysPNode {
    const Node *node;
    const Vec *id;        /* borrowed */
    uint64_t idhash;
    size_t group;
    size_t storage;       /* assigned storage index */
    bool anchor;
} PhysPNode;

/* One !random applier's draws of the next frame (step.c, DrawsAhead):
 * pairs 0 .. n-1 of normal(key), from buf + off, in chunks chunk, ... */
typedef struct AheadSeg {
    uint64_t key, n;
    size_t off, chunk;
} AheadSeg;

/* The next frame's !random draws, made by the threads of the last step's
 * pair pass while they wait, then on the pool's other thread while the
 * calling thread finishes this frame and starts the next (step.c, "the
 * next frame's draws"). The threads making them read seg, nseg, limit,
 * ready and buf, and claim chunks through next; the calling thread
 * changes none of them while the first pass's job or the background job
 * (`running`) runs, and reads next only once both have ended
 * (phys_draws_ahead_settle). */
typedef struct DrawsAhead {
    AheadSeg *seg; size_t nseg, capseg;
    double *buf; size_t capbuf;   /* doubles */
    size_t limit;                 /* chunks the job may make: all the
                                   * segments' or fewer (phys_set_ahead) */
    bool wait;                    /* settling waits for them (no stop) */
    atomic_size_t next;           /* the next chunk to claim */
    atomic_bool stop;             /* set when the job is ended early */
    WorkersJob job;
    Workers *pool;                /* the pool running it */
    bool ready;                   /* segments made ready, chunks claimable
                                   * (phys_ahead_chunk), not yet settled */
    bool running;                 /* the background job started, not yet
                                   * ended */
    size_t done;                  /* once settled: chunks 0 .. done-1 made */
} DrawsAhead;

typedef struct PhysSystem {
    size_t D;                     /* dimensions of the current frame */
    double c;                     /* speed of light, 0 = none */
    const PhysicsFrame *frame;    /* this frame's step limit and interrupt flag */
    atomic_bool cut;              /* the interrupt flag stopped this step's
                                   * pair pass part way (phys_interrupted):
                                   * the step is abandoned (step.c) */
    long cut_after;               /* phys_set_cut_after's polls, or 0 */
    atomic_long polls;            /* this frame's polls, while cut_after */

    /* particles (storage order) */
    size_t n, cap;
    size_t capvec;                            /* doubles in each vector array */
    double *pos, *vel, *acc, *force, *own;    /* D*n used in each */
    double *radius, *mass, *charge;           /* cap each */
    double *ease;                             /* cap: the particles' ease
                                                 attribute (0 = none) */
    unsigned char *anchor;                    /* cap */
    double *dir;                              /* D scratch: pair direction */
    size_t capdir;
    double *dgeo; size_t capdgeo;             /* scratch: the distance
                                                 appliers' pairs, D+1 each */

    /* appliers (pre-order) */
    PhysApplier *ap;
    size_t nap, capap;
    double *avec;                 /* 2*D*capap */
    size_t capavec;

    /* groups and their index lists */
    PhysGroup *groups;
    size_t ngroups, capgroups;
    uint32_t *gidx;  size_t ngidx, capgidx;
    uint32_t *chain; size_t nchain, capchain;
    PhysLevel *levels; size_t nlevels, caplevels;
    uint32_t *pool;  size_t npool, cappool;

    /* PhysicsFrame.upstream of the current frame: Flitter 1.0.0b28's
     * behaviour at the four [doc] places (physics.h) */
    bool upstream;
    /* the particle pass through literal.c instead of step.c's routes */
    bool literal;

    /* pair routes (pairs.c) */
    bool naive;                   /* always the reference loop */
    Workers *workers;         /* borrowed from the world; NULL = 1 thread */
    PhysGrid grid;
    PhysScratch *scratch; size_t capscratch;  /* one per thread */
    double *rows; size_t caprows; /* rows.c: the level in pool order */
    int simd;                     /* PHYS_SIMD_* the tile kernel may use */
    bool simd_auto;               /* tiles.c may take 4 x 4 tiles where they
                                   * run a kind of level faster than AVX-512 */
    struct TileTune *tune;        /* tiles.c: those timings, per kind of
                                   * level (NULL until the first) */
    double *tiles; size_t captiles;   /* tiles.c: the level in pool order,
                                       * 64-byte aligned */
    struct TileTask *ttasks; size_t capttasks;   /* tiles.c: the tasks of a
                                                  * level on two threads */
    struct TileProgress *tprog; size_t captprog; /* tiles.c: their progress,
                                                  * per row block */
    double *trec; size_t captrec; /* tiles.c: the split route's record */
    struct TileSplit *tsplit;     /* tiles.c: its hand-off to the first
                                   * pass's second thread (NULL until the
                                   * first) */
    int split_mode;               /* PHYS_SPLIT_* (physics.h) */
    uint64_t split_near[2];       /* split levels whose near part the
                                   * helper / the pass's thread ran */
    double *rnd; size_t caprnd;   /* step.c: !random draws made ahead, two
                                   * doubles a pair */
    size_t draw_chunks;           /* step.c: the chunks of those draws this
                                   * step (0: none planned) */
    atomic_size_t draw_next;      /* the next chunk a thread may claim */
    DrawsAhead ahead;             /* step.c: the next frame's draws */
    uint64_t seed_now, seed_next; /* world.c: the hash of the seed P;run;
                                   * iteration of this frame's first
                                   * !random and of the next frame's
                                   * (vec_hash, floored) */
    bool seed_ok;                 /* they are computed */
    int ahead_limit;              /* phys_set_ahead's limit */
    double slice_pairs;           /* the most pairs the tiles and rows
                                   * routes take at once (pairs.c,
                                   * run_slices): PHYS_SLICE_PAIRS, or
                                   * phys_set_slice's */
    uint64_t ahead_pairs[3];      /* pairs of draws planned ahead in a step:
                                   * [0] those the frame before made, [1] all;
                                   * [2] chunks of the next frame's made by
                                   * the pair pass's threads
                                   * (phys_ahead_counts) */

    /* names seen in the tree, classified once while the string lives
     * (collect.c): direct-mapped by address, strings retained */
    Str *kcache[16]; signed char kcid[16];     /* node kinds */
    Str *acache[64]; signed char acid[64];     /* attribute names */

    size_t filld;                 /* D the slots' attribute values have */

    /* tree walk scratch */
    PhysPNode *pn; size_t npn, cappn;
    /* per particle of pn: filled on a worker this frame (collect.c) */
    bool *filled; size_t capfilled;
    /* the children of the root collected last (retained; kids_ok when that
     * collection succeeded, with kidsD dimensions): the same children next
     * frame mean the same groups, particles and appliers (collect.c) */
    Node **kids; size_t nkids, capkids, kidsD;
    bool kids_ok;
    /* the nodes below the root when it had the kept children (world.c:
     * the budget check counts them once, not every frame) */
    size_t kids_nodes;
    /* the appliers applier_clock() changes: eased or !random (collect.c) */
    uint32_t *clocked; size_t nclocked, capclocked;
    struct PhysWalk *walk; size_t capwalk;

    /* lookups */
    PhysHash ids;                 /* pre-order particle ids -> pn index */
    PhysHash newkeys;             /* this frame's particle state keys */
    bool dupids;                  /* two particles of this frame share an id */
    /* the slots' cp/cv are the state's values when the state dictionary
     * is the one, with the compound write count and size, seen at the end of the
     * system's last frame (stateio.c) */
    const StateDict *csd;
    unsigned long long csets;
    size_t ccount;
    bool cvalid;                  /* cp/cv were recorded last frame */
    bool cuse;                    /* ... and hold for this frame */

    /* state keys */
    Vec *prefix;                  /* P the cached keys were built from */
    double sym_velocity;          /* the symbol :velocity (keys.c) */
    uint64_t prefix_hash;         /* vec_hash(prefix, false) (keys.c) */
    Vec *kclock, *klast, *krun, *kiter;
    PhysKeySlot *slots; size_t capslots;
    PhysKeyEnt *kent; size_t nkent, capkent;  /* key table (keys.c) */
    uint32_t *kidx; size_t capkidx;           /* its index: entry + 1 */
    uint64_t kframe;                          /* frames swept so far */
    Vec **prev; size_t nprev, capprev;        /* retained */
    Vec **next; uint64_t *nexthash; size_t capnext;  /* borrowed scratch */
} PhysSystem;

/* ---- world.c: systems and the frame driver ---- */

/* Print "out of memory" and abort. */
void phys_oom(void);

/* ---- collect.c: reading the node tree (PHYSICS-ENGINE.md §1, §3) ---- */

/* What collection needs to know about the frame. */
typedef struct PhysCollect {
    const Vec *P;
    int64_t run, iteration;
    double clock;
    Vec *seed;          /* current !random seed vector (lazily built) */
    bool upstream;      /* Flitter 1.0.0b28's eases (PhysicsFrame.upstream) */
    bool same_tree;     /* phys_kids_same() of the root, asked once a frame */
} PhysCollect;

/* Forget (release) the nodes the slots' attribute values came from. */
void phys_slot_nodes_drop(PhysSystem *s);
/* Forget (release) the root's children kept by the last collection, so the
 * next one walks the tree in full. */
void phys_kids_drop(PhysSystem *s);
/* True when [root] has the very children kept by the last full collection
 * (whatever its D): the same subtree, as nodes are immutable. */
bool phys_kids_same(const PhysSystem *s, const Node *root);
/* Release the name caches of [s]. */
void phys_names_free(PhysSystem *s);
/* Empty [h] and size it for [n] entries. */
void phys_hash_reset(PhysHash *h, size_t n);
/* Map [key] (hash vec_hash(key, false)) to [idx], replacing an earlier
 * equal key's index; [key] is borrowed. */
void phys_hash_put(PhysHash *h, const Vec *key, uint64_t hash, size_t idx);
/* The index mapped to [key], or SIZE_MAX. */
size_t phys_hash_get(const PhysHash *h, const Vec *key, uint64_t hash);
/* floor() as a 64-bit integer; NaN and out-of-range values give INT64_MIN. */
int64_t phys_floor_i64(double x);
/* §1 float(name, default) and int(name, default) of node [n]. */
double phys_attr_float(const Node *n, const char *name, double def);
int64_t phys_attr_int(const Node *n, const char *name, int64_t def);
/* §3 in full: walk, lay particles out group-major, fill them (reading
 * their state from [sd]), resolve the distance appliers' ids, build the
 * group lists and plan the pair levels. Returns false when the system is
 * too large to index (more than 2^32-2 particles or appliers). */
bool phys_collect(PhysSystem *s, PhysCollect *c, const Node *root,
                  const StateDict *sd);

/* ---- stateio.c: state keys, read-back and writes (§2) ---- */

/* A state value read back as a single number (§2 step 3). */
bool phys_state_scalar(const StateDict *sd, const Vec *key, double *out);
/* state[key] = x. */
void phys_state_set_num(StateDict *sd, const Vec *key, double x);
/* Release the keys kept from the previous frame. */
void phys_release_prev(PhysSystem *s);
/* Point the system at prefix [P]: rebuild the clock keys and drop the key
 * cache when P changed. */
void phys_set_prefix(PhysSystem *s, const Vec *P);
/* The keys of storage slot [i], holding the particle [pn]; sets
 * s->dupids when another slot of this frame has the same id. */
PhysKeySlot *phys_slot_keys(PhysSystem *s, size_t i, const PhysPNode *pn);
/* §2 step 7: null the keys of last frame not collected now. */
void phys_null_stale_keys(PhysSystem *s, StateDict *sd);
/* §2 step 8: write every particle's position and velocity. */
void phys_write_particles(PhysSystem *s, StateDict *sd);
/* Start of a frame of [s] on [sd], before any state write: may the slots'
 * cached values stand in for state lookups this frame (s->cuse)? */
void phys_cache_check(PhysSystem *s, const StateDict *sd);
/* End of a frame, after the last state write: keep this frame's values
 * of every slot for the next. */
void phys_cache_keep(PhysSystem *s, const StateDict *sd);
/* Drop the cached values of every slot (before the slots are freed). */
void phys_cache_drop(PhysSystem *s);

/* ---- forces.c: force appliers and barriers (PHYSICS-ENGINE.md §4) ---- */

/* pair(a, b) into s->dir; returns dist. */
double phys_pair(PhysSystem *s, size_t a, size_t b);
/* Apply the distance appliers s->ap[list[0 .. n-1]] in that order, each
 * whose ends both exist (§4 "for each distance applier of G"). The pairs
 * are all measured first (pair(), into scratch: positions do not change
 * during the pass, and the measurements are independent, so they overlap
 * instead of waiting on each other's square root and division), then the
 * forces are added in order: the same operations as pair() then distance
 * one applier at a time. */
void phys_apply_distances(PhysSystem *s, const uint32_t *list, size_t n);
/* The pair loop of one level of group [g]: the group's own particles
 * against the first lv->npool of its pool, with lv->group's pair appliers. */
void phys_apply_pair_level(PhysSystem *s, const PhysGroup *g,
                           const PhysLevel *lv);

/* F += dir*k (plus) or F -= dir*k, per element with f = dir_i*k: one side
 * of a push apart or a pull together (forces.c). */
static inline __attribute__((always_inline)) void
phys_add_side(double *F, const double *dir, double k, size_t D, bool plus)
{
    if (plus) {
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] + dir[i] * k;
    } else {
        for (size_t i = 0; i < D; i++)
            F[i] = F[i] - dir[i] * k;
    }
}

/* Gather side of a pair applier: what applier [ap] adds to one particle of
 * the pair (a, b) measured as dist/dir by pair(a, b): to a's force [F] when
 * [to_b] is false, to b's when true (the same conditions, the same k and
 * the same element operations as the reference loop performs on that
 * particle: a push apart subtracts from a and adds to b, a pull together
 * the reverse). [D] is s->D; inline, so that a caller compiled for one D
 * has the element loops unrolled (PHYSICS-ENGINE.md §4, pair appliers). */
static inline __attribute__((always_inline)) void
phys_pair_force_side(const PhysSystem *s, const PhysApplier *ap, size_t a,
                     size_t b, double dist, const double *dir, double *F,
                     bool to_b, const size_t D)
{
    switch (ap->kind) {
    case AP_COLLISION: {
        double ra = s->radius[a], rb = s->radius[b];
        if (ra != 0 && rb != 0) {
            double r = ra + rb;
            if (dist < r)
                phys_add_side(F, dir, phys_shape(r - dist, ap->power, ap->strength), D, to_b);
        }
        break;
    }
    case AP_GRAVITY: {
        double ma = s->mass[a], mb = s->mass[b];
        if (ma != 0 && mb != 0) {
            double m = py_max(s->radius[a] + s->radius[b], dist);
            double k = ap->strength * ma * mb / (m * m);
            phys_add_side(F, dir, k, D, !to_b);
        }
        break;
    }
    case AP_ELECTROSTATIC: {
        double qa = s->charge[a], qb = s->charge[b];
        if (qa != 0 && qb != 0) {
            double m = py_max(s->radius[a] + s->radius[b], dist);
            double k = ap->strength * qa * qb / (m * m);
            phys_add_side(F, dir, k, D, to_b);
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
                phys_add_side(F, dir, k, D, !to_b);
            }
        }
        break;
    }
    default:
        break;
    }
}

/* phys_pair_force_side() for any D, out of line. */
void phys_pair_force_one(const PhysSystem *s, const PhysApplier *ap, size_t a,
                         size_t b, double dist, const double *dir, double *F,
                         bool to_b);

/* ---- keys.c: particle state keys kept while the particle lives ---- */

/* The key entry of particle [id] (hash [idhash] = vec_hash(id, false)),
 * built from s->prefix on first sight; marks it seen this frame (setting
 * *dup when it already was). The pointer is valid until the next
 * phys_keys_get or sweep. */
const PhysKeyEnt *phys_keys_get(PhysSystem *s, const Vec *id, uint64_t idhash,
                                bool *dup);
/* Make room for [n] entries in all (a system's first collection, whose
 * particle count is known): the table and its index are sized once
 * instead of doubling as the entries come. */
void phys_keys_reserve(PhysSystem *s, size_t n);
/* End of collection: drop the entries not seen this frame. */
void phys_keys_sweep(PhysSystem *s);
/* Drop every entry (the prefix changed). */
void phys_keys_clear(PhysSystem *s);
/* Free the table. */
void phys_keys_free(PhysSystem *s);

/* ---- pairs.c: pair routes (neighbour grid, gather, threads) ---- */

/* Choose each level's route for this frame (after collection: radii,
 * appliers and pools are known). */
void phys_plan_levels(PhysSystem *s);
/* Run one pair level of group [g] by its route. */
void phys_run_level(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv);
/* Free the grid and scratch arrays. */
void phys_pairs_free(PhysSystem *s);

/* ---- rows.c: the reference pair loop in blocks of partners ---- */

/* Can phys_run_rows() take this system's levels (D = 1, 2 or 3)? */
bool phys_rows_suits(const PhysSystem *s);
/* Run one pair level of group [g] as phys_apply_pair_level() does, with the
 * same additions in the same order (PHYSICS-ENGINE.md §4), measuring a
 * block of partners of each row at a time so the sqrt and divisions run as
 * vector instructions. Reuses s->rows (grown, never shrunk); aborts with a
 * message if memory runs out. */
void phys_run_rows(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv);
/* Grow s->rows for a level of [npool] pool entries now (at planning, so a
 * frame whose first step comes later allocates nothing then); aborts with
 * a message if memory runs out. */
void phys_rows_reserve(PhysSystem *s, size_t npool);

/* ---- tiles.c: the reference pair loop in W x W tiles ---- */

/* The best PHYS_SIMD_* level this processor runs. */
int phys_simd_best(void);
/* The highest PHYS_SIMD_* level up to [level] this processor runs (0 for
 * a negative one). */
int phys_simd_cap(int level);
/* Can phys_run_tiles() take level [lv] (D = 1..3, at most 4 appliers,
 * each !collision, !gravity or !electrostatic)? */
bool phys_tiles_suits(const PhysSystem *s, const PhysLevel *lv);
/* Run one pair level of group [g] as phys_apply_pair_level() does, with
 * the same additions in the same order (PHYSICS-ENGINE.md §4), W x W pairs
 * at a time in vector instructions of level s->simd. Reuses s->tiles;
 * aborts with a message if memory runs out. */
void phys_run_tiles(PhysSystem *s, const PhysGroup *g, const PhysLevel *lv);
/* Whether level [lv] of group [g] must take the threaded route of tiles.c
 * ("Several threads"), so that the first pass cannot hold it (step.c,
 * pairs_one_thread): TILES_PIPE_PAIRS pairs or more and a pool of two
 * threads or more, except below SPLIT_RANDOM_PAIRS in a system with
 * !random, which the first pass may split ("Two threads for a
 * middle-sized level"). Such a level that the first pass does not take
 * after all still runs threaded (phys_run_tiles). */
bool phys_tiles_threaded(const PhysSystem *s, const PhysGroup *g, const PhysLevel *lv);
/* Grow s->tiles for a level of [npool] pool entries now (at planning). */
void phys_tiles_reserve(PhysSystem *s, size_t npool);
/* The split route (tiles.c, "Two threads for a middle-sized level"): a
 * level of the pair pass run by two threads, this one and a helper that
 * first does [other] pairs of normal draws. phys_tiles_split_wanted():
 * whether some level of [s] would take it. phys_tiles_split_begin(): before
 * a pair pass whose levels may take it (false, with nothing changed, when
 * out of memory: then none does); phys_tiles_split_end() after that pass,
 * on the same thread; phys_tiles_help(), on the helper thread, runs the
 * parts of split levels it can claim until the pass ends. Whichever thread
 * runs a part, the forces are the same bits. */
bool phys_tiles_split_wanted(const PhysSystem *s, double other);
bool phys_tiles_split_begin(PhysSystem *s, double other);
void phys_tiles_split_end(PhysSystem *s);
/* Whether a split first pass is under way (between phys_tiles_split_begin
 * and phys_tiles_split_end). */
bool phys_tiles_split_active(const PhysSystem *s);
void phys_tiles_help(PhysSystem *s);
/* The helper's part of a split level posted now, if any (does not wait). */
void phys_tiles_help_posted(PhysSystem *s);
/* Make one chunk of this step's planned !random draws (step.c, "!random
 * draws made on a second thread"), the next one no thread has claimed;
 * false when every chunk is claimed. Any thread of the first pass's job
 * may call it, in any order: a draw is a function of its key and index
 * alone, so the draws are the same bits whoever makes them. */
bool phys_draw_chunk(PhysSystem *s);
/* End the background job of the next frame's draws of [s], if one runs,
 * and close the draws made ready: `done` counts the chunks made, by the
 * pair pass's threads and the job (step.c). Before [s] or its pool is
 * freed, and before the draws are taken; never while the first pass's
 * job runs. */
void phys_draws_ahead_settle(PhysSystem *s);
/* Make one chunk of the next frame's draws of [s] made ready in this
 * step, if one is left (step.c); false otherwise. For a thread of the
 * first pass's job while it waits (tiles.c): a chunk is a function of its
 * index alone, so the draws are the same bits whoever makes them. */
bool phys_ahead_chunk(PhysSystem *s);

/* ---- literal.c: the literal route of the particle pass ---- */

/* §4's second pass over the particles of group [g] (with particles) for a
 * step of [delta] starting at [clock], written as the spec is (literal.c);
 * [more]: reset each force to the own force for the next step. */
void phys_literal_particle_pass(PhysSystem *s, const PhysGroup *g,
                                double clock, double delta, bool more);

/* ---- step.c: the particle pass (appliers, barriers, step) and the step loop ---- */

/* The §4 loop from [last] up to [time]; returns the advanced clock. */
double phys_run_steps(PhysSystem *s, double time, double last, double clock,
                      double resolution, bool realtime, bool extra);

/* The pairs of the reference loop over [rows] rows and [n] pool entries
 * (a level: its group's particles against its pool). */
static inline double phys_level_pairs(size_t rows, size_t n)
{
    return (double)rows * (double)(n - 1) - (double)rows * (double)(rows - 1) / 2;
}

/* The most pairs the tiles route takes at once (the rows route a quarter
 * of it): about 0.03 s of a step on two threads here (the rows route 0.1 s
 * on its one), a second or so under the sanitizers; a larger level runs as
 * slices of its rows (pairs.c, run_slices). */
#define PHYS_SLICE_PAIRS 0x1p25

/* Whether the frame's interrupt flag (physics.h) is set; the pair routes
 * ask between targets (the all-pairs and grid gathers), rows (the
 * reference loop) or slices (the tiles and rows routes), and on a yes set
 * s->cut and stop, so that a step of a huge system ends soon after an
 * interrupt instead of after all its pairs. */
static inline bool phys_interrupted(PhysSystem *s)
{
    const PhysicsFrame *fr = s->frame;
    /* read as an atomic: worker threads ask, while a signal handler on
     * any thread may write it (the writers store it atomically too) */
    bool set = fr && fr->interrupt && __atomic_load_n(fr->interrupt, __ATOMIC_RELAXED);
    if (!set && s->cut_after)   /* tests (phys_set_cut_after) */
        set = atomic_fetch_add_explicit(&s->polls, 1, memory_order_relaxed) + 1 >= s->cut_after;
    if (set)
        atomic_store_explicit(&s->cut, true, memory_order_relaxed);
    return set;
}

#endif
