/* world.c: physics systems, attribute reading, collection, state I/O and the
 * frame driver.
 *
 * A PhysicsWorld is an array of PhysSystem pointers, the i-th driven by the
 * i-th top-level !physics node of the frame (systems beyond the frame's
 * count are freed, as the reference destroys surplus renderers). A
 * PhysSystem (physics_internal.h) keeps every per-frame array (particles in
 * struct-of-arrays storage, appliers, groups and their index lists, hash
 * indexes, the tree-walk stack) and only grows them, so a steady frame
 * allocates nothing per particle except the position/velocity vectors it
 * stores in the state dictionary. The state keys P;id and P;id;:velocity are
 * cached per storage slot and rebuilt only when the id or prefix changes.
 *
 * Implements PHYSICS-ENGINE.md §1 (reading attributes), §2 (one frame: run
 * reset, read-back of :clock/:last/:run/:iteration, nulling of keys not
 * written again, the final writes), §3 (collecting groups, particles,
 * anchors and appliers, including the [doc] eases) and the !random seed
 * chain of §5; the steps themselves are in step.c, the appliers in forces.c.
 * PHYSICS.md "State interaction" and "Groups" describe the behaviour.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics_internal.h"
#include "workers.h"

struct PhysicsWorld {
    PhysSystem **sys;
    size_t n, cap;
    bool naive;             /* --pairs naive: the reference pair loop only */
    unsigned threads;       /* wanted threads; the pool is made on first use */
    PhysWorkers *workers;   /* NULL until needed or when threads == 1 */
    int simd;               /* PHYS_SIMD_* level of the tile kernel */
};

/* One level of the explicit tree-walk stack (§3 is recursive over groups). */
struct PhysWalk {
    const Node *node;
    size_t next;      /* next child to visit */
    size_t group;     /* group the children belong to */
};

/* ------------------------------------------------------------------ */
/* Allocation                                                          */
/* ------------------------------------------------------------------ */

static void oom(void)
{
    fputs("flitter: out of memory\n", stderr);
    abort();
}

/* [p] reallocated to hold at least [need] elements of [size] bytes (its
 * capacity in *[cap], grown geometrically; contents kept). */
static void *grow_buf(void *p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return p;
    size_t n = *cap ? *cap : 8;
    while (n < need) {
        if (n > SIZE_MAX / 2)
            oom();
        n *= 2;
    }
    if (n > SIZE_MAX / size)
        oom();
    void *q = realloc(p, n * size);
    if (!q)
        oom();
    *cap = n;
    return q;
}

/* Grow array [ptr] (capacity variable [cap]) to at least [need] elements. */
#define GROW(ptr, cap, need) \
    ((ptr) = grow_buf((ptr), &(cap), (need), sizeof *(ptr)))

/* ------------------------------------------------------------------ */
/* Hash index                                                          */
/* ------------------------------------------------------------------ */

static void hash_reset(PhysHash *h, size_t n)
{
    size_t need = 16;
    while (need < 2 * n) {
        if (need > SIZE_MAX / 4)
            oom();
        need *= 2;
    }
    if (h->cap < need) {
        free(h->slot);
        h->slot = malloc(need * sizeof *h->slot);
        if (!h->slot)
            oom();
        h->cap = need;
    }
    memset(h->slot, 0, h->cap * sizeof *h->slot);
}

/* The slot holding [key], or the empty slot where it would go. */
static PhysHashSlot *hash_slot(const PhysHash *h, const Vec *key,
                               uint64_t hash)
{
    size_t mask = h->cap - 1;
    for (size_t i = (size_t)hash & mask;; i = (i + 1) & mask) {
        PhysHashSlot *e = &h->slot[i];
        if (!e->idx1 || (e->hash == hash && vec_key_equal(e->key, key)))
            return e;
    }
}

/* Map [key] to [idx], replacing an earlier equal key's index. */
static void hash_put(PhysHash *h, const Vec *key, uint64_t hash, size_t idx)
{
    PhysHashSlot *e = hash_slot(h, key, hash);
    e->key = key;
    e->hash = hash;
    e->idx1 = idx + 1;
}

/* The index mapped to [key], or SIZE_MAX. */
static size_t hash_get(const PhysHash *h, const Vec *key, uint64_t hash)
{
    const PhysHashSlot *e = hash_slot(h, key, hash);
    return e->idx1 ? e->idx1 - 1 : SIZE_MAX;
}

/* ------------------------------------------------------------------ */
/* Attributes (PHYSICS-ENGINE.md §1)                                   */
/* ------------------------------------------------------------------ */

static inline double py_min(double a, double b) { return b < a ? b : a; }
static inline double py_max(double a, double b) { return b > a ? b : a; }

/* floor() as a 64-bit integer; NaN and out-of-range values give INT64_MIN,
 * the x86 "integer indefinite" the reference's C cast produces there (a
 * plain cast would be undefined behaviour). */
static int64_t floor_i64(double x)
{
    double f = floor(x);
    if (f >= -9223372036854775808.0 && f < 9223372036854775808.0)
        return (int64_t)f;
    return INT64_MIN;
}

/* §1 float(name, default) of an attribute value [v] (NULL: missing). */
static double float_of(const Vec *v, double def)
{
    return vec_is_scalar(v) ? vec_scalar(v) : def;
}

/* §1 float(name, default). */
static double attr_float(const Node *n, const char *name, double def)
{
    return float_of(node_attr(n, name), def);
}

/* §1 int(name, default). */
static int64_t attr_int(const Node *n, const char *name, int64_t def)
{
    const Vec *v = node_attr(n, name);
    return vec_is_scalar(v) ? floor_i64(vec_scalar(v)) : def;
}

/* §1 fvec(name): writes D doubles to [out] and returns true, or returns
 * false (out untouched) when the default applies. */
static bool fvec_of(const Vec *v, size_t D, double *out)
{
    if (!vec_is_num(v))
        return false;
    const double *x = vec_cnums(v);
    if (v->len == 1 && D > 1) {
        for (size_t i = 0; i < D; i++)
            out[i] = x[0];
        return true;
    }
    if (v->len == D) {
        memcpy(out, x, D * sizeof *out);
        return true;
    }
    return false;
}

static bool attr_fvec(const Node *n, const char *name, size_t D, double *out)
{
    return fvec_of(node_attr(n, name), D, out);
}

/* fvec of attribute value [v] with the zero-vector default. */
static void fvec0_of(const Vec *v, size_t D, double *out)
{
    if (!fvec_of(v, D, out))
        memset(out, 0, D * sizeof *out);
}

/* A state value read back as a single number (§2 step 3). */
static bool state_scalar(const StateDict *sd, const Vec *key, double *out)
{
    const Vec *v = state_get(sd, key);
    if (!vec_is_scalar(v))
        return false;
    *out = vec_scalar(v);
    return true;
}

static void state_set_num(StateDict *sd, const Vec *key, double x)
{
    Vec *v = vec_num1(x);
    state_set(sd, key, v);
    vec_release(v);
}

static Vec *compose2(const Vec *a, const Vec *b)
{
    Vec *parts[2] = {(Vec *)a, (Vec *)b};
    return vec_compose(parts, 2);
}

static Vec *compose_sym(const Vec *a, const char *sym)
{
    Vec *s = vec_num1(symbol_value(sym, strlen(sym)));
    Vec *r = compose2(a, s);
    vec_release(s);
    return r;
}

/* ------------------------------------------------------------------ */
/* Systems                                                             */
/* ------------------------------------------------------------------ */

static PhysSystem *system_new(void)
{
    PhysSystem *s = calloc(1, sizeof *s);
    if (!s)
        oom();
    return s;
}

/* Forget every cached particle key (the slots only borrow them). */
static void release_slots(PhysSystem *s)
{
    phys_keys_clear(s);
    if (s->capslots)
        memset(s->slots, 0, s->capslots * sizeof *s->slots);
}

static void release_prev(PhysSystem *s)
{
    for (size_t i = 0; i < s->nprev; i++)
        vec_release(s->prev[i]);
    s->nprev = 0;
}

static void system_free(PhysSystem *s)
{
    if (!s)
        return;
    phys_keys_free(s);
    release_prev(s);
    vec_release(s->prefix);
    vec_release(s->kclock);
    vec_release(s->klast);
    vec_release(s->krun);
    vec_release(s->kiter);
    free(s->pos); free(s->vel); free(s->acc); free(s->force); free(s->own);
    free(s->radius); free(s->mass); free(s->charge); free(s->anchor);
    free(s->dir);
    free(s->ap); free(s->avec);
    free(s->groups); free(s->gidx); free(s->chain); free(s->levels);
    free(s->pool);
    free(s->pn); free(s->walk);
    free(s->ids.slot); free(s->newkeys.slot);
    free(s->slots); free(s->prev); free(s->next); free(s->nexthash);
    phys_pairs_free(s);
    free(s);
}

/* Point the system at prefix [P]: rebuild the clock keys and drop the key
 * cache when P changed. */
static void set_prefix(PhysSystem *s, const Vec *P)
{
    if (s->prefix && vec_key_equal(s->prefix, P))
        return;
    release_slots(s);
    vec_release(s->prefix);
    vec_release(s->kclock);
    vec_release(s->klast);
    vec_release(s->krun);
    vec_release(s->kiter);
    s->prefix = vec_retain((Vec *)P);
    s->kclock = compose_sym(P, "clock");
    s->klast = compose_sym(P, "last");
    s->krun = compose_sym(P, "run");
    s->kiter = compose_sym(P, "iteration");
}

/* The keys of storage slot [i], holding the particle [pn] (§2 step 8
 * keys), from the system's key table (keys.c). */
static PhysKeySlot *slot_keys(PhysSystem *s, size_t i, const PhysPNode *pn)
{
    const PhysKeyEnt *e = phys_keys_get(s, pn->id, pn->idhash);
    PhysKeySlot *k = &s->slots[i];
    *k = (PhysKeySlot){e->pkey, e->vkey, e->phash, e->vhash};
    return k;
}

/* ------------------------------------------------------------------ */
/* Collecting (PHYSICS-ENGINE.md §3)                                   */
/* ------------------------------------------------------------------ */

typedef struct Collect {
    const Vec *P;
    int64_t run, iteration;
    double clock;
    Vec *seed;          /* current !random seed vector (lazily built) */
} Collect;

static size_t new_group(PhysSystem *s, ptrdiff_t parent)
{
    GROW(s->groups, s->capgroups, s->ngroups + 1);
    PhysGroup *g = &s->groups[s->ngroups];
    memset(g, 0, sizeof *g);
    g->parent = parent;
    return s->ngroups++;
}

/* §3 "every other child": a force applier or barrier of group [group]. */
static void collect_applier(PhysSystem *s, Collect *c, const Node *child,
                            size_t group)
{
    PhysApplierKind kind;
    if (node_is(child, "distance")) kind = AP_DISTANCE;
    else if (node_is(child, "drag")) kind = AP_DRAG;
    else if (node_is(child, "buoyancy")) kind = AP_BUOYANCY;
    else if (node_is(child, "constant")) kind = AP_CONSTANT;
    else if (node_is(child, "random")) kind = AP_RANDOM;
    else if (node_is(child, "field")) kind = AP_FIELD;
    else if (node_is(child, "collision")) kind = AP_COLLISION;
    else if (node_is(child, "gravity")) kind = AP_GRAVITY;
    else if (node_is(child, "electrostatic")) kind = AP_ELECTROSTATIC;
    else if (node_is(child, "adhesion")) kind = AP_ADHESION;
    else if (node_is(child, "barrier")) kind = AP_BARRIER;
    else return;
    const Vec *from = NULL, *to = NULL;
    if (kind == AP_DISTANCE) {
        from = node_attr(child, "from");
        to = node_attr(child, "to");
        if (!from || !to)
            return;
    }
    const size_t D = s->D;
    GROW(s->ap, s->capap, s->nap + 1);
    GROW(s->avec, s->capavec, 2 * D * (s->nap + 1));
    PhysApplier *ap = &s->ap[s->nap];
    memset(ap, 0, sizeof *ap);
    ap->kind = kind;
    ap->group = (uint32_t)group;
    ap->vec = 2 * D * s->nap;
    ap->from = ap->to = -1;
    s->nap++;
    double *x = s->avec + ap->vec, *y = x + D;
    memset(x, 0, 2 * D * sizeof *x);

    /* strength, and the [doc] ease: if e > 0 and clock < e, scale by
     * clock / e (fixed for the whole frame) */
    double strength = attr_float(child, "strength", 1);
    double e = attr_float(child, "ease", 0);
    if (e > 0 && c->clock < e)
        strength = strength * (c->clock / e);
    ap->strength = strength;

    switch (kind) {
    case AP_DISTANCE: {
        ap->from_id = from;
        ap->to_id = to;
        ap->power = py_max(0, attr_float(child, "power", 1));
        double fixed = attr_float(child, "fixed", 0);
        if (fixed != 0) {
            ap->minimum = ap->maximum = fixed;
        } else {
            ap->minimum = attr_float(child, "minimum", attr_float(child, "min", 0));
            ap->maximum = attr_float(child, "maximum", attr_float(child, "max", 0));
        }
        break;
    }
    case AP_DRAG:
        attr_fvec(child, "flow", D, x);
        break;
    case AP_BUOYANCY:
        ap->density = attr_float(child, "density", 1);
        if (!attr_fvec(child, "gravity", D, x))
            x[D - 1] = -1;
        break;
    case AP_CONSTANT:
        attr_fvec(child, "force", D, x);
        attr_fvec(child, "acceleration", D, y);
        break;
    case AP_RANDOM: {
        /* §3/§5: source normal(seed), seed = P;run;iteration for the first
         * !random of the frame and seed;0 for each further one */
        Vec *seed = c->seed;
        if (!seed) {
            Vec *parts[3] = {(Vec *)c->P, vec_num1((double)c->run),
                             vec_num1((double)c->iteration)};
            seed = vec_compose(parts, 3);
            vec_release(parts[1]);
            vec_release(parts[2]);
        } else {
            Vec *zero = vec_num1(0);
            Vec *next = compose2(seed, zero);
            vec_release(zero);
            vec_release(seed);
            seed = next;
        }
        c->seed = seed;
        ap->key = vec_hash(seed, true);
        ap->index = 0;
        break;
    }
    case AP_FIELD:
        attr_fvec(child, "direction", D, x);
        break;
    case AP_COLLISION:
        ap->power = py_max(0, attr_float(child, "power", 1));
        ap->maxd = py_max(0, attr_float(child, "max_distance", 0));
        break;
    case AP_GRAVITY:
    case AP_ELECTROSTATIC:
        ap->maxd = py_max(0, attr_float(child, "max_distance", 0));
        break;
    case AP_ADHESION:
        ap->maxd = py_max(0, attr_float(child, "max_distance", 0));
        ap->overlap = py_min(py_max(0, attr_float(child, "overlap", 0.25)), 1);
        break;
    case AP_BARRIER: {
        /* position, unit normal n_i = m_i / sqrt(sum m_j*m_j); a zero
         * normal disables the barrier */
        attr_fvec(child, "position", D, x);
        double sum = 0;
        if (attr_fvec(child, "normal", D, y)) {
            for (size_t i = 0; i < D; i++)
                sum += y[i] * y[i];
        }
        ap->enabled = sum != 0;
        if (ap->enabled) {
            double len = sqrt(sum);
            for (size_t i = 0; i < D; i++)
                y[i] = y[i] / len;
        }
        ap->restitution = py_min(py_max(0, attr_float(child, "restitution", 1)), 1);
        ap->power = py_max(0, attr_float(child, "power", 1));
        ap->minimum = attr_float(child, "minimum", attr_float(child, "min", 0));
        ap->maximum = attr_float(child, "maximum", attr_float(child, "max", 0));
        break;
    }
    }
}

/* §3 tree walk: groups in pre-order, particle nodes (to be laid out once
 * the group sizes are known) and appliers, all in declaration order. */
static void walk(PhysSystem *s, Collect *c, const Node *root)
{
    size_t depth = 0;
    GROW(s->walk, s->capwalk, 1);
    s->walk[depth++] = (struct PhysWalk){root, 0, new_group(s, -1)};
    while (depth) {
        struct PhysWalk *top = &s->walk[depth - 1];
        if (top->next >= top->node->nchildren) {
            depth--;
            continue;
        }
        const Node *child = top->node->children[top->next++];
        size_t group = top->group;
        bool anchor = node_is(child, "anchor");
        if (anchor || node_is(child, "particle")) {
            const Vec *id = node_attr(child, "id");
            if (!id)
                continue;
            GROW(s->pn, s->cappn, s->npn + 1);
            s->pn[s->npn++] = (PhysPNode){child, id, vec_hash(id, false),
                                          group, 0, anchor};
            s->groups[group].npart++;
        } else if (node_is(child, "group")) {
            size_t g = new_group(s, (ptrdiff_t)group);
            GROW(s->walk, s->capwalk, depth + 1);
            s->walk[depth++] = (struct PhysWalk){child, 0, g};
        } else {
            collect_applier(s, c, child, group);
        }
    }
}

/* Make room for [n] particles of [D] dimensions. */
static void ensure_particles(PhysSystem *s, size_t n, size_t D)
{
    if (n == 0)
        n = 1;      /* keep every array allocated */
    if (n > s->cap) {
        size_t cap = s->cap;
        GROW(s->radius, cap, n);
        cap = s->cap;
        GROW(s->mass, cap, n);
        cap = s->cap;
        GROW(s->charge, cap, n);
        cap = s->cap;
        GROW(s->anchor, cap, n);
        s->cap = cap;
    }
    if (n > s->capslots) {
        size_t old = s->capslots;
        GROW(s->slots, s->capslots, n);
        memset(s->slots + old, 0, (s->capslots - old) * sizeof *s->slots);
    }
    if (D > SIZE_MAX / (n ? n : 1))
        oom();
    size_t need = n * D;
    if (need > s->capvec) {
        size_t cap = s->capvec;
        GROW(s->pos, cap, need);
        cap = s->capvec;
        GROW(s->vel, cap, need);
        cap = s->capvec;
        GROW(s->acc, cap, need);
        cap = s->capvec;
        GROW(s->force, cap, need);
        cap = s->capvec;
        GROW(s->own, cap, need);
        s->capvec = cap;
    }
    GROW(s->dir, s->capdir, D);
}

/* The attributes §3 reads from a particle, found in one pass over the
 * node's attributes (the first of each name, as node_attr() would). */
enum { PA_POSITION, PA_VELOCITY, PA_FORCE, PA_RADIUS, PA_MASS, PA_CHARGE,
       PA_EASE, PA_COUNT };

static void particle_attrs(const Node *n, const Vec *out[PA_COUNT])
{
    static const char *const names[PA_COUNT] = {
        "position", "velocity", "force", "radius", "mass", "charge", "ease"};
    static const unsigned char lens[PA_COUNT] = {8, 8, 5, 6, 4, 6, 4};
    for (int k = 0; k < PA_COUNT; k++)
        out[k] = NULL;
    for (uint32_t a = 0; a < n->nattrs; a++) {
        const Str *name = n->attrs[a].name;
        for (int k = 0; k < PA_COUNT; k++) {
            if (!out[k] && name->len == lens[k] &&
                memcmp(name->bytes, names[k], lens[k]) == 0) {
                out[k] = n->attrs[a].value;
                break;
            }
        }
    }
}

/* §3 particle/anchor: fill storage slot [pn->storage]. */
static void fill_particle(PhysSystem *s, const Collect *c, const StateDict *sd,
                          const PhysPNode *pn)
{
    const size_t D = s->D, i = pn->storage;
    const Vec *at[PA_COUNT];
    particle_attrs(pn->node, at);
    const PhysKeySlot *k = slot_keys(s, i, pn);
    double *pos = s->pos + i * D, *vel = s->vel + i * D;
    double *own = s->own + i * D;
    s->anchor[i] = pn->anchor;
    const Vec *v = NULL;
    if (!pn->anchor && c->iteration > 0)
        v = state_get(sd, k->pkey);
    if (vec_is_num(v) && v->len == D)
        memcpy(pos, vec_cnums(v), D * sizeof *pos);
    else
        fvec0_of(at[PA_POSITION], D, pos);
    v = NULL;
    if (!pn->anchor && c->iteration > 0)
        v = state_get(sd, k->vkey);
    if (vec_is_num(v) && v->len == D)
        memcpy(vel, vec_cnums(v), D * sizeof *vel);
    else
        fvec0_of(at[PA_VELOCITY], D, vel);
    fvec0_of(at[PA_FORCE], D, own);
    s->radius[i] = py_max(0, float_of(at[PA_RADIUS], 0));
    s->mass[i] = py_max(0, float_of(at[PA_MASS], 1));
    s->charge[i] = float_of(at[PA_CHARGE], 0);
    /* [doc] the particle's own force is eased: if e > 0 and clock < e,
     * own[i] = own[i] * (clock / e) */
    double e = float_of(at[PA_EASE], 0);
    if (e > 0 && c->clock < e) {
        double q = c->clock / e;
        for (size_t j = 0; j < D; j++)
            own[j] = own[j] * q;
    }
    memcpy(s->force + i * D, own, D * sizeof *own);
    memset(s->acc + i * D, 0, D * sizeof(double));
}

/* Category of an applier in its group's own lists. */
static int category(PhysApplierKind k)
{
    switch (k) {
    case AP_DISTANCE: return 0;
    case AP_COLLISION: case AP_GRAVITY: case AP_ELECTROSTATIC:
    case AP_ADHESION: return 1;
    case AP_BARRIER: return 3;
    default: return 2;
    }
}

static size_t *cat_off(PhysGroup *g, int cat)
{
    switch (cat) {
    case 0: return &g->dist_off;
    case 1: return &g->pair_off;
    case 2: return &g->part_off;
    default: return &g->bar_off;
    }
}

static size_t *cat_n(PhysGroup *g, int cat)
{
    switch (cat) {
    case 0: return &g->dist_n;
    case 1: return &g->pair_n;
    case 2: return &g->part_n;
    default: return &g->bar_n;
    }
}

/* Build the per-group index lists: own appliers by category (declaration
 * order), the particle-applier and barrier chains (own, parent's, ...) and
 * the pair levels with their pools (§4). */
static void build_lists(PhysSystem *s)
{
    /* at least one element each, so offsets never apply to NULL */
    GROW(s->gidx, s->capgidx, s->nap + 1);
    GROW(s->chain, s->capchain, 1);
    GROW(s->pool, s->cappool, 1);
    GROW(s->levels, s->caplevels, 1);
    size_t off = 0;
    for (int cat = 0; cat < 4; cat++) {
        for (size_t a = 0; a < s->nap; a++) {
            if (category(s->ap[a].kind) == cat)
                (*cat_n(&s->groups[s->ap[a].group], cat))++;
        }
        for (size_t g = 0; g < s->ngroups; g++) {
            PhysGroup *G = &s->groups[g];
            *cat_off(G, cat) = off;
            off += *cat_n(G, cat);
            *cat_n(G, cat) = 0;
        }
        for (size_t a = 0; a < s->nap; a++) {
            if (category(s->ap[a].kind) == cat) {
                PhysGroup *G = &s->groups[s->ap[a].group];
                s->gidx[*cat_off(G, cat) + (*cat_n(G, cat))++] = (uint32_t)a;
            }
        }
    }
    s->ngidx = off;

    s->nchain = s->nlevels = s->npool = 0;
    for (size_t g = 0; g < s->ngroups; g++) {
        PhysGroup *G = &s->groups[g];
        if (!G->npart)
            continue;
        G->pf_off = s->nchain;
        for (ptrdiff_t A = (ptrdiff_t)g; A >= 0; A = s->groups[A].parent) {
            const PhysGroup *GA = &s->groups[A];
            GROW(s->chain, s->capchain, s->nchain + GA->part_n);
            if (GA->part_n)
                memcpy(s->chain + s->nchain, s->gidx + GA->part_off,
                       GA->part_n * sizeof *s->chain);
            s->nchain += GA->part_n;
        }
        G->pf_n = s->nchain - G->pf_off;
        G->b_off = s->nchain;
        for (ptrdiff_t A = (ptrdiff_t)g; A >= 0; A = s->groups[A].parent) {
            const PhysGroup *GA = &s->groups[A];
            GROW(s->chain, s->capchain, s->nchain + GA->bar_n);
            if (GA->bar_n)
                memcpy(s->chain + s->nchain, s->gidx + GA->bar_off,
                       GA->bar_n * sizeof *s->chain);
            s->nchain += GA->bar_n;
        }
        G->b_n = s->nchain - G->b_off;
        /* pool = G.particles ++ parent's ++ ...; a level wherever that
         * ancestor declares pair appliers */
        G->pool_off = s->npool;
        G->lvl_off = s->nlevels;
        size_t npool = 0;
        for (ptrdiff_t A = (ptrdiff_t)g; A >= 0; A = s->groups[A].parent) {
            const PhysGroup *GA = &s->groups[A];
            GROW(s->pool, s->cappool, s->npool + GA->npart);
            for (size_t q = 0; q < GA->npart; q++)
                s->pool[s->npool++] = (uint32_t)(GA->pstart + q);
            npool += GA->npart;
            if (GA->pair_n) {
                GROW(s->levels, s->caplevels, s->nlevels + 1);
                s->levels[s->nlevels++] = (PhysLevel){.npool = npool, .group = (size_t)A};
            }
        }
        G->lvl_n = s->nlevels - G->lvl_off;
        if (!G->lvl_n)
            s->npool = G->pool_off;
    }
}

/* §3 in full: walk, lay particles out group-major, fill them, resolve the
 * distance appliers' ids and build the group lists. Returns false when the
 * system is too large to index (more than 2^32-2 particles or appliers). */
static bool collect(PhysSystem *s, Collect *c, const Node *root,
                    const StateDict *sd)
{
    s->ngroups = s->nap = s->npn = 0;
    walk(s, c, root);
    if (s->npn >= UINT32_MAX || s->nap >= UINT32_MAX)
        return false;
    size_t off = 0;
    for (size_t g = 0; g < s->ngroups; g++) {
        s->groups[g].pstart = off;
        s->groups[g].fill = 0;
        off += s->groups[g].npart;
    }
    s->n = off;
    ensure_particles(s, s->n, s->D);
    hash_reset(&s->ids, s->npn);
    for (size_t i = 0; i < s->npn; i++) {
        PhysPNode *pn = &s->pn[i];
        PhysGroup *G = &s->groups[pn->group];
        pn->storage = G->pstart + G->fill++;
        fill_particle(s, c, sd, pn);
        /* particles are found by id across all groups; a later duplicate
         * replaces the earlier */
        hash_put(&s->ids, pn->id, pn->idhash, pn->storage);
    }
    for (size_t a = 0; a < s->nap; a++) {
        PhysApplier *ap = &s->ap[a];
        if (ap->kind != AP_DISTANCE)
            continue;
        size_t f = hash_get(&s->ids, ap->from_id, vec_hash(ap->from_id, false));
        size_t t = hash_get(&s->ids, ap->to_id, vec_hash(ap->to_id, false));
        ap->from = f == SIZE_MAX ? -1 : (ptrdiff_t)f;
        ap->to = t == SIZE_MAX ? -1 : (ptrdiff_t)t;
    }
    phys_keys_sweep(s);
    build_lists(s);
    phys_plan_levels(s);
    return true;
}

/* ------------------------------------------------------------------ */
/* State keys                                                          */
/* ------------------------------------------------------------------ */

/* §2 step 7: every key collected on the previous frame (the particle
 * position and velocity keys, as in the reference) that is not collected
 * this frame is set to null; this frame's keys become the new list. */
static void null_stale_keys(PhysSystem *s, StateDict *sd)
{
    const size_t nk = 2 * s->n;
    bool same = s->nprev == nk;
    for (size_t i = 0; same && i < s->n; i++)
        same = s->prev[2 * i] == s->slots[i].pkey &&
               s->prev[2 * i + 1] == s->slots[i].vkey;
    if (same)
        return;
    size_t capn = s->capnext;
    GROW(s->next, capn, nk);
    capn = s->capnext;
    GROW(s->nexthash, capn, nk);
    s->capnext = capn;
    for (size_t i = 0; i < s->n; i++) {
        s->next[2 * i] = s->slots[i].pkey;
        s->nexthash[2 * i] = s->slots[i].phash;
        s->next[2 * i + 1] = s->slots[i].vkey;
        s->nexthash[2 * i + 1] = s->slots[i].vhash;
    }
    hash_reset(&s->newkeys, nk);
    for (size_t i = 0; i < nk; i++)
        hash_put(&s->newkeys, s->next[i], s->nexthash[i], i);
    for (size_t i = 0; i < s->nprev; i++) {
        Vec *k = s->prev[i];
        if (hash_get(&s->newkeys, k, vec_hash(k, false)) == SIZE_MAX)
            state_set(sd, k, NULL);
    }
    release_prev(s);
    GROW(s->prev, s->capprev, nk);
    for (size_t i = 0; i < nk; i++)
        s->prev[i] = vec_retain(s->next[i]);
    s->nprev = nk;
}

/* state[key] = the [D] numbers [x]. When the stored value is already a
 * numeric vector of length D referenced by the state alone (refs == 1, so
 * nothing else can see it change; the copy-on-write rule eval.c also
 * uses), its numbers are overwritten in place: the same effect as storing a
 * new vector, without allocating one per particle per frame. */
static void store_nums(StateDict *sd, const Vec *key, const double *x, size_t D)
{
    Vec *cur = state_get(sd, key);
    if (cur && cur->refs == 1 && cur->kind == VEC_NUM && cur->len == D) {
        memcpy(vec_nums(cur), x, D * sizeof *x);
        return;
    }
    Vec *v = vec_from_nums(x, (uint32_t)D);
    state_set(sd, key, v);
    vec_release(v);
}

/* §2 step 8 writes: position and velocity of every particle (anchors too)
 * in group order, each only when all its elements are finite. */
static void write_particles(PhysSystem *s, StateDict *sd)
{
    const size_t D = s->D;
    for (size_t i = 0; i < s->n; i++) {
        const PhysKeySlot *k = &s->slots[i];
        const double *vecs[2] = {s->pos + i * D, s->vel + i * D};
        const Vec *keys[2] = {k->pkey, k->vkey};
        for (int j = 0; j < 2; j++) {
            bool finite = true;
            for (size_t d = 0; d < D && finite; d++)
                finite = isfinite(vecs[j][d]);
            if (finite)
                store_nums(sd, keys[j], vecs[j], D);
        }
    }
}

/* ------------------------------------------------------------------ */
/* One frame of one system (PHYSICS-ENGINE.md §2)                      */
/* ------------------------------------------------------------------ */

static void system_frame(PhysSystem *s, const Node *node, StateDict *sd,
                         const PhysicsFrame *fr)
{
    /* §2.1: run, dimensions and the prefix P; skip unusable nodes */
    int64_t run = attr_int(node, "run", 0);
    int64_t D = attr_int(node, "dimensions", 0);
    if (D < 1 || D > (int64_t)PHYS_MAX_DIMENSIONS)
        return;
    const Vec *P = node_attr(node, "state");
    if (!P)
        return;
    /* §2.2: time, resolution (default 1/fps), speed of light */
    double time = attr_float(node, "time", fr->time);
    double resolution = attr_float(node, "resolution", 1 / fr->fps);
    if (!isfinite(time) || !isfinite(resolution)) {
        if (fr->nonfinite)
            *fr->nonfinite = true;
        return;
    }
    if (resolution <= 0)
        return;
    s->frame = fr;
    s->D = (size_t)D;
    s->c = py_max(0, attr_float(node, "speed_of_light", 0));
    set_prefix(s, P);
    /* §2.3: read back :clock, :last, :run, :iteration */
    double clock = 0, last = time, x;
    if (!state_scalar(sd, s->kclock, &clock))
        clock = 0;
    if (!state_scalar(sd, s->klast, &last))
        last = time;
    int64_t last_run = state_scalar(sd, s->krun, &x) ? floor_i64(x) : run;
    int64_t iteration = state_scalar(sd, s->kiter, &x) ? floor_i64(x) + 1 : 0;
    /* §2.4: a new run nulls our keys and restarts clock and iteration
     * (`last` is not reset) */
    if (run != last_run) {
        for (size_t i = 0; i < s->nprev; i++)
            state_set(sd, s->prev[i], NULL);
        release_prev(s);
        state_set_num(sd, P, time);
        clock = 0;
        iteration = 0;
    }
    /* §2.5 */
    state_set_num(sd, s->krun, (double)run);
    state_set_num(sd, s->kiter, (double)iteration);
    /* §2.6: collect (the !random seed is P;run;iteration) */
    Collect c = {P, run, iteration, clock, NULL};
    bool ok = collect(s, &c, node, sd);
    vec_release(c.seed);
    if (!ok)
        return;
    /* §2.7: null last frame's keys not collected now; ensure state[P] */
    null_stale_keys(s, sd);
    if (!vec_is_scalar(state_get(sd, P)))
        state_set_num(sd, P, time);
    /* §2.8: step, then write positions and velocities. Spare performance
     * (realtime only) is the reference's `performance > 1.5`, which buys
     * at most one extra step per frame. */
    if (time > last) {
        clock = phys_run_steps(s, time, last, clock, resolution,
                               fr->realtime, fr->performance > 1.5);
        write_particles(s, sd);
    }
    /* §2.9 */
    state_set_num(sd, s->klast, time);
    state_set_num(sd, s->kclock, clock);
}

/* ------------------------------------------------------------------ */
/* Public interface                                                    */
/* ------------------------------------------------------------------ */

/* A new world with no systems; FLITTER_THREADS and FLITTER_PAIRS give the
 * defaults of phys_set_threads() and phys_set_pairs(). */
PhysicsWorld *phys_new(void)
{
    PhysicsWorld *w = calloc(1, sizeof *w);
    if (!w)
        oom();
    const char *e = getenv("FLITTER_THREADS");
    char *end;
    long n = e ? strtol(e, &end, 10) : 0;
    phys_set_threads(w, e && *e && !*end && n > 0 && n <= 1024 ? (unsigned)n : 0);
    e = getenv("FLITTER_PAIRS");
    phys_set_pairs(w, e && !strcmp(e, "naive"));
    e = getenv("FLITTER_SIMD");
    phys_set_simd(w, !e ? 2 : !strcmp(e, "portable") ? 0 : !strcmp(e, "avx2") ? 1 : 2);
    return w;
}

void phys_set_threads(PhysicsWorld *w, unsigned n)
{
    if (n == 0)
        n = phys_available_cores();
    if (n != w->threads) {
        phys_workers_free(w->workers);
        w->workers = NULL;
    }
    w->threads = n;
}

void phys_set_pairs(PhysicsWorld *w, bool naive)
{
    w->naive = naive;
}

int phys_set_simd(PhysicsWorld *w, int level)
{
    int best = phys_simd_best();
    w->simd = level < 0 ? 0 : level < best ? level : best;
    return w->simd;
}

/* Free [w] and all its systems (NULL is a no-op). */
void phys_free(PhysicsWorld *w)
{
    if (!w)
        return;
    for (size_t i = 0; i < w->n; i++)
        system_free(w->sys[i]);
    free(w->sys);
    phys_workers_free(w->workers);
    free(w);
}

/* Simulate one frame: the i-th node drives the i-th system (created on
 * first use; systems beyond [n] are freed). PHYSICS-ENGINE.md §2-4. */
void phys_run_frame(PhysicsWorld *w, Node *const *nodes, size_t n,
                    StateDict *state, const PhysicsFrame *frame)
{
    while (w->n > n)
        system_free(w->sys[--w->n]);
    GROW(w->sys, w->cap, n);
    while (w->n < n)
        w->sys[w->n++] = system_new();
    if (w->threads > 1 && !w->workers && !w->naive)
        w->workers = phys_workers_new(w->threads);
    for (size_t i = 0; i < n; i++) {
        PhysSystem *s = w->sys[i];
        s->naive = w->naive;
        s->simd = w->simd;
        s->workers = w->naive ? NULL : w->workers;
        system_frame(s, nodes[i], state, frame);
    }
}
