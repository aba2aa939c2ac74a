/* collect.c: reading a !physics node into its system's arrays.
 *
 * Implements PHYSICS-ENGINE.md §1 (reading attributes) and §3 (collecting
 * groups, particles, anchors and appliers in tree order, including the
 * [doc] eases and the !random seed chain of §5): the tree walk, the
 * group-major storage layout, the per-group index lists and pair levels,
 * and the id index that resolves the !distance appliers. Also the hash
 * index (PhysHash) the state I/O uses for its key sets.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics_internal.h"
#include "workers.h"

/* Grow array [ptr] (capacity variable [cap]) to at least [need] elements. */
#define GROW(ptr, cap, need) \
    ((ptr) = mem_grow((ptr), &(cap), (need), sizeof *(ptr)))

/* One level of the explicit tree-walk stack (§3 is recursive over groups). */
struct PhysWalk {
    const Node *node;
    size_t next;      /* next child to visit */
    size_t group;     /* group the children belong to */
};

/* ------------------------------------------------------------------ */
/* Hash index                                                          */
/* ------------------------------------------------------------------ */

void phys_hash_reset(PhysHash *h, size_t n)
{
    size_t need = 16;
    while (need < 2 * n) {
        if (need > SIZE_MAX / 4)
            phys_oom();
        need *= 2;
    }
    if (h->cap < need) {
        free(h->slot);
        h->slot = malloc(need * sizeof *h->slot);
        if (!h->slot)
            phys_oom();
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
void phys_hash_put(PhysHash *h, const Vec *key, uint64_t hash, size_t idx)
{
    PhysHashSlot *e = hash_slot(h, key, hash);
    e->key = key;
    e->hash = hash;
    e->idx1 = idx + 1;
}

/* The index mapped to [key], or SIZE_MAX. */
size_t phys_hash_get(const PhysHash *h, const Vec *key, uint64_t hash)
{
    const PhysHashSlot *e = hash_slot(h, key, hash);
    return e->idx1 ? e->idx1 - 1 : SIZE_MAX;
}
/* ------------------------------------------------------------------ */
/* Attributes (PHYSICS-ENGINE.md §1)                                   */
/* ------------------------------------------------------------------ */


/* floor() as a 64-bit integer; NaN and out-of-range values give INT64_MIN,
 * the x86 "integer indefinite" the reference's C cast produces there (a
 * plain cast would be undefined behaviour). */
int64_t phys_floor_i64(double x)
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
double phys_attr_float(const Node *n, const char *name, double def)
{
    return float_of(node_attr(n, name), def);
}

/* §1 int(name, default). */
int64_t phys_attr_int(const Node *n, const char *name, int64_t def)
{
    const Vec *v = node_attr(n, name);
    return vec_is_scalar(v) ? phys_floor_i64(vec_scalar(v)) : def;
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

/* fvec of attribute value [v] with the zero-vector default. */
static void fvec0_of(const Vec *v, size_t D, double *out)
{
    if (!fvec_of(v, D, out))
        memset(out, 0, D * sizeof *out);
}

/* A state value read back as a single number (§2 step 3). */
/* ------------------------------------------------------------------ */
/* Collecting (PHYSICS-ENGINE.md §3)                                   */
/* ------------------------------------------------------------------ */

/* ------------------------------------------------------------------ */
/* Names, classified once per node or attribute                        */
/* ------------------------------------------------------------------ */

/* The node kinds collection knows: the applier kinds, then these. */
enum { KIND_PARTICLE = AP_BARRIER + 1, KIND_ANCHOR, KIND_GROUP, KIND_OTHER };

/* The kind of a child of a !physics node or group: a scan of the kind
 * names' table, comparing the length and first byte before the name (the
 * result is cached per kind symbol: cached_class). */
static int child_kind_of(const Str *k)
{
    static const struct { const char *name; unsigned char len, kind; } t[] = {
        {"drag", 4, AP_DRAG}, {"field", 5, AP_FIELD}, {"group", 5, KIND_GROUP},
        {"random", 6, AP_RANDOM}, {"anchor", 6, KIND_ANCHOR},
        {"gravity", 7, AP_GRAVITY}, {"barrier", 7, AP_BARRIER},
        {"particle", 8, KIND_PARTICLE}, {"distance", 8, AP_DISTANCE},
        {"buoyancy", 8, AP_BUOYANCY}, {"constant", 8, AP_CONSTANT},
        {"adhesion", 8, AP_ADHESION}, {"collision", 9, AP_COLLISION},
        {"electrostatic", 13, AP_ELECTROSTATIC},
    };
    for (size_t i = 0; i < sizeof t / sizeof *t; i++) {
        if (t[i].len == k->len && t[i].name[0] == k->bytes[0] &&
            memcmp(t[i].name, k->bytes, k->len) == 0)
            return t[i].kind;
    }
    return KIND_OTHER;
}

/* The attributes collection reads (PHYSICS.md), found for one node in one
 * pass over its attributes: the first of each name, as node_attr() finds. */
enum { AN_POSITION, AN_VELOCITY, AN_FORCE, AN_RADIUS, AN_MASS, AN_CHARGE,
       AN_EASE, AN_STRENGTH, AN_POWER, AN_FIXED, AN_MINIMUM, AN_MIN,
       AN_MAXIMUM, AN_MAX, AN_FROM, AN_TO, AN_FLOW, AN_DENSITY, AN_GRAVITY,
       AN_ACCELERATION, AN_DIRECTION, AN_MAX_DISTANCE, AN_OVERLAP, AN_NORMAL,
       AN_RESTITUTION, AN_COUNT };

static int attr_id_of(const Str *name);

/* The class of [name] by [classify], through the direct-mapped cache
 * [cache]/[ids] of [size] entries: a string held by the cache cannot be
 * freed and reused, so the same address means the same name. */
static int cached_class(Str **cache, signed char *ids, size_t size, Str *name,
                        int (*classify)(const Str *))
{
    uintptr_t a = (uintptr_t)name;
    size_t h = (size_t)((a >> 4) ^ (a >> 12)) & (size - 1);
    if (cache[h] == name)
        return ids[h];
    int id = classify(name);
    str_release(cache[h]);
    cache[h] = str_retain(name);
    ids[h] = (signed char)id;
    return id;
}

static int child_kind(PhysSystem *s, Str *k)
{
    return cached_class(s->kcache, s->kcid, 16, k, child_kind_of);
}

void phys_names_free(PhysSystem *s)
{
    for (size_t i = 0; i < 16; i++)
        str_release(s->kcache[i]);
    for (size_t i = 0; i < 64; i++)
        str_release(s->acache[i]);
}

static void node_attrs(PhysSystem *s, const Node *n, const Vec *out[AN_COUNT])
{
    memset(out, 0, AN_COUNT * sizeof *out);
    for (uint32_t a = 0; a < n->nattrs; a++) {
        int id = cached_class(s->acache, s->acid, 64, n->attrs[a].name,
                              attr_id_of);
        if (id >= 0 && !out[id])
            out[id] = n->attrs[a].value;
    }
}

/* The AN_* of attribute [name], or -1. */
static int attr_id_of(const Str *name)
{
    static const char *const names[AN_COUNT] = {
        "position", "velocity", "force", "radius", "mass", "charge", "ease",
        "strength", "power", "fixed", "minimum", "min", "maximum", "max",
        "from", "to", "flow", "density", "gravity", "acceleration",
        "direction", "max_distance", "overlap", "normal", "restitution"};
    /* the names of each length, as indexes into names[], -1 ended */
    static const signed char bylen[13][6] = {
        {-1}, {-1}, {AN_TO, -1}, {AN_MIN, AN_MAX, -1},
        {AN_MASS, AN_EASE, AN_FROM, AN_FLOW, -1},
        {AN_FORCE, AN_POWER, AN_FIXED, -1},
        {AN_RADIUS, AN_CHARGE, AN_NORMAL, -1},
        {AN_MINIMUM, AN_MAXIMUM, AN_DENSITY, AN_GRAVITY, AN_OVERLAP, -1},
        {AN_POSITION, AN_VELOCITY, AN_STRENGTH, -1},
        {AN_DIRECTION, -1}, {-1}, {AN_RESTITUTION, -1},
        {AN_ACCELERATION, AN_MAX_DISTANCE, -1},
    };
    if (name->len > 12)
        return -1;
    for (const signed char *id = bylen[name->len]; *id >= 0; id++) {
        if (names[*id][0] == name->bytes[0] &&
            memcmp(names[*id], name->bytes, name->len) == 0)
            return *id;
    }
    return -1;
}

static Vec *compose2(const Vec *a, const Vec *b)
{
    Vec *parts[2] = {(Vec *)a, (Vec *)b};
    return vec_compose(parts, 2);
}

static size_t new_group(PhysSystem *s, ptrdiff_t parent)
{
    GROW(s->groups, s->capgroups, s->ngroups + 1);
    PhysGroup *g = &s->groups[s->ngroups];
    memset(g, 0, sizeof *g);
    g->parent = parent;
    return s->ngroups++;
}

/* What of applier [ap] depends on the frame ([c]): its strength, with the
 * [doc] ease (if e > 0 and clock < e, scaled by clock / e, fixed for the
 * whole frame; c->upstream: Flitter 1.0.0b28's, physics.h), and a !random's source: normal(seed), seed = P;run;iteration
 * for the first !random of the frame and seed;0 for each further one
 * (§3/§5), its draws from index 0. Called in collection order for every
 * applier of a fresh walk, and for those with an ease or a !random source
 * (s->clocked) when the tree is the same as last frame's. */
static void applier_clock(PhysApplier *ap, PhysCollect *c)
{
    double strength = ap->strength0, e = ap->ease;
    if (c->upstream) {
        /* Flitter 1.0.0b28: `if ease > 0 and ease < clock: strength *=
         * clock/ease` (the strength grows once the ease is over) */
        if (e > 0 && e < c->clock)
            strength = strength * (c->clock / e);
    } else if (e > 0 && c->clock < e) {
        strength = strength * (c->clock / e);
    }
    ap->strength = strength;
    if (ap->kind != AP_RANDOM)
        return;
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
    ap->pair_at = UINT64_MAX;
    ap->pre_n = 0;
}

/* §3 "every other child": a force applier or barrier of group [group],
 * of applier kind [kind]. */
static void collect_applier(PhysSystem *s, PhysCollect *c, const Node *child,
                            size_t group, PhysApplierKind kind)
{
    const Vec *at[AN_COUNT];
    node_attrs(s, child, at);
    const Vec *from = NULL, *to = NULL;
    if (kind == AP_DISTANCE) {
        from = at[AN_FROM];
        to = at[AN_TO];
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

    ap->strength0 = float_of(at[AN_STRENGTH], 1);
    ap->ease = float_of(at[AN_EASE], 0);
    applier_clock(ap, c);

    switch (kind) {
    case AP_DISTANCE: {
        ap->from_id = from;
        ap->to_id = to;
        ap->power = py_max(0, float_of(at[AN_POWER], 1));
        double fixed = float_of(at[AN_FIXED], 0);
        if (fixed != 0) {
            ap->minimum = ap->maximum = fixed;
        } else {
            ap->minimum = float_of(at[AN_MINIMUM], float_of(at[AN_MIN], 0));
            ap->maximum = float_of(at[AN_MAXIMUM], float_of(at[AN_MAX], 0));
        }
        break;
    }
    case AP_DRAG:
        fvec_of(at[AN_FLOW], D, x);
        break;
    case AP_BUOYANCY:
        ap->density = float_of(at[AN_DENSITY], 1);
        if (!fvec_of(at[AN_GRAVITY], D, x))
            x[D - 1] = -1;
        break;
    case AP_CONSTANT:
        fvec_of(at[AN_FORCE], D, x);
        fvec_of(at[AN_ACCELERATION], D, y);
        break;
    case AP_RANDOM:
        break;          /* applier_clock() */
    case AP_FIELD:
        fvec_of(at[AN_DIRECTION], D, x);
        break;
    case AP_COLLISION:
        ap->power = py_max(0, float_of(at[AN_POWER], 1));
        ap->maxd = py_max(0, float_of(at[AN_MAX_DISTANCE], 0));
        break;
    case AP_GRAVITY:
    case AP_ELECTROSTATIC:
        ap->maxd = py_max(0, float_of(at[AN_MAX_DISTANCE], 0));
        break;
    case AP_ADHESION:
        ap->maxd = py_max(0, float_of(at[AN_MAX_DISTANCE], 0));
        ap->overlap = py_min(py_max(0, float_of(at[AN_OVERLAP], 0.25)), 1);
        break;
    case AP_BARRIER: {
        /* position, unit normal n_i = m_i / sqrt(sum m_j*m_j); a zero
         * normal disables the barrier */
        fvec_of(at[AN_POSITION], D, x);
        double sum = 0;
        if (fvec_of(at[AN_NORMAL], D, y)) {
            for (size_t i = 0; i < D; i++)
                sum += y[i] * y[i];
        }
        ap->enabled = sum != 0;
        if (ap->enabled) {
            double len = sqrt(sum);
            for (size_t i = 0; i < D; i++)
                y[i] = y[i] / len;
        }
        ap->restitution = py_min(py_max(0, float_of(at[AN_RESTITUTION], 1)), 1);
        ap->power = py_max(0, float_of(at[AN_POWER], 1));
        ap->minimum = float_of(at[AN_MINIMUM], float_of(at[AN_MIN], 0));
        ap->maximum = float_of(at[AN_MAXIMUM], float_of(at[AN_MAX], 0));
        break;
    }
    }
}

/* §3 tree walk: groups in pre-order, particle nodes (to be laid out once
 * the group sizes are known) and appliers, all in declaration order. */
static void walk(PhysSystem *s, PhysCollect *c, const Node *root)
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
        int kind = child_kind(s, child->kind);
        bool anchor = kind == KIND_ANCHOR;
        if (anchor || kind == KIND_PARTICLE) {
            const Vec *id = node_attr(child, "id");
            if (!id)
                continue;
            GROW(s->pn, s->cappn, s->npn + 1);
            s->pn[s->npn++] = (PhysPNode){child, id, vec_key_hash(id),
                                          group, 0, anchor};
            s->groups[group].npart++;
        } else if (kind == KIND_GROUP) {
            size_t g = new_group(s, (ptrdiff_t)group);
            GROW(s->walk, s->capwalk, depth + 1);
            s->walk[depth++] = (struct PhysWalk){child, 0, g};
        } else if (kind != KIND_OTHER) {
            collect_applier(s, c, child, group, (PhysApplierKind)kind);
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
        GROW(s->ease, cap, n);
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
        phys_oom();
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

void phys_slot_nodes_drop(PhysSystem *s)
{
    for (size_t i = 0; i < s->capslots; i++) {
        node_release(s->slots[i].node);
        s->slots[i].node = NULL;
    }
}

/* §3 particle/anchor: fill storage slot [pn->storage]. A slot whose arrays
 * were filled from this very node (a static tree hands the same nodes
 * every frame; the slot retains it, so the address cannot be reused, and
 * nodes are immutable) keeps its radius, mass, charge, anchor flag and own
 * force unless that force is eased (it then depends on the clock); only
 * the position and velocity are read again. */
static void fill_particle(PhysSystem *s, const PhysCollect *c, const StateDict *sd,
                          const PhysPNode *pn)
{
    const size_t D = s->D, i = pn->storage;
    PhysKeySlot *k = phys_slot_keys(s, i, pn);
    const bool same = k->node == pn->node && !k->eased;
    const Vec *at[AN_COUNT];
    if (!same)
        node_attrs(s, pn->node, at);
    double *pos = s->pos + i * D, *vel = s->vel + i * D;
    double *own = s->own + i * D;
    const Vec *v = NULL;
    if (!pn->anchor && c->iteration > 0)
        v = s->cuse && k->hit && k->cp ? k->cp : state_get(sd, k->pkey);
    if (vec_is_num(v) && v->len == D) {
        phys_copy(pos, vec_cnums(v), D);
        k->pval = (Vec *)v;
    } else
        fvec0_of(same ? node_attr(pn->node, "position") : at[AN_POSITION], D, pos);
    v = NULL;
    if (!pn->anchor && c->iteration > 0)
        v = s->cuse && k->hit && k->cv ? k->cv : state_get(sd, k->vkey);
    if (vec_is_num(v) && v->len == D) {
        phys_copy(vel, vec_cnums(v), D);
        k->vval = (Vec *)v;
    } else
        fvec0_of(same ? node_attr(pn->node, "velocity") : at[AN_VELOCITY], D, vel);
    if (!same) {
        s->anchor[i] = pn->anchor;
        fvec0_of(at[AN_FORCE], D, own);
        s->radius[i] = py_max(0, float_of(at[AN_RADIUS], 0));
        s->mass[i] = py_max(0, float_of(at[AN_MASS], 1));
        s->charge[i] = float_of(at[AN_CHARGE], 0);
        /* [doc] the particle's own force is eased: if e > 0 and clock < e,
         * own[i] = own[i] * (clock / e). Upstream, the ease scales the
         * step's k instead (step.c), so the own force is kept as given. */
        double e = float_of(at[AN_EASE], 0);
        s->ease[i] = e;
        if (!c->upstream && e > 0 && c->clock < e) {
            double q = c->clock / e;
            for (size_t j = 0; j < D; j++)
                own[j] = own[j] * q;
        }
        node_release(k->node);
        k->node = node_retain((Node *)pn->node);
        k->eased = e > 0;
    }
    phys_copy(s->force + i * D, own, D);
    for (size_t j = 0; j < D; j++)
        s->acc[i * D + j] = 0;
}

/* fill_particle() of a particle that is last frame's in every respect:
 * the same id in its slot (its key entry found without hashing), the same
 * node (not eased), and its position and velocity read back from the
 * slot's retained values (PhysKeySlot cp/cv, usable this frame). Such a
 * fill reads nothing shared but the node's fields and its key entry, and
 * writes only its slot, so fills run on any thread with the bits of
 * fill_particle(); the key entry is claimed afterwards, on one thread
 * (fill_all). Returns false, having changed nothing, for any other
 * particle. */
static bool fill_same(PhysSystem *s, const PhysCollect *c, const PhysPNode *pn)
{
    const size_t D = s->D, i = pn->storage;
    PhysKeySlot *k = &s->slots[i];
    if (pn->anchor || c->iteration == 0 || !s->cuse || k->node != pn->node || k->eased ||
        !k->ent1 || k->ent1 > s->nkent || s->kent[k->ent1 - 1].id != pn->id)
        return false;
    const Vec *cp = k->cp, *cv = k->cv;
    if (!vec_is_num(cp) || cp->len != D || !vec_is_num(cv) || cv->len != D)
        return false;
    const PhysKeyEnt *e = &s->kent[k->ent1 - 1];
    k->hit = true;
    k->pkey = e->pkey;
    k->vkey = e->vkey;
    k->phash = e->phash;
    k->vhash = e->vhash;
    phys_copy(s->pos + i * D, vec_cnums(cp), D);
    k->pval = (Vec *)cp;
    phys_copy(s->vel + i * D, vec_cnums(cv), D);
    k->vval = (Vec *)cv;
    phys_copy(s->force + i * D, s->own + i * D, D);
    for (size_t j = 0; j < D; j++)
        s->acc[i * D + j] = 0;
    return true;
}

/* Particles per task of the parallel fill, and half the fewest that are
 * split over threads. */
#define FILL_CHUNK 512

typedef struct FillRun {
    PhysSystem *s;
    const PhysCollect *c;
    size_t chunk;
    size_t left[WORKERS_MAX_TASKS];   /* per task: particles fill_same() left */
} FillRun;

static void fill_task(void *ctx, size_t t, unsigned thread)
{
    (void)thread;
    FillRun *r = ctx;
    /* counted here, stored once: the tasks' entries of [r] share cache
     * lines, which per-particle stores would pass between the cores */
    size_t left = 0;
    for (size_t i = t * r->chunk, i1 = workers_task_end(t, r->chunk, r->s->npn); i < i1; i++) {
        bool done = fill_same(r->s, r->c, &r->s->pn[i]);
        r->s->filled[i] = done;
        left += !done;
    }
    r->left[t] = left;
}

/* fill_particle() of every particle of an unchanged tree, in collection
 * order. A large system fills the particles that are last frame's on all
 * threads first (fill_same) and claims their key entries on this thread
 * (`seen`: a second claim in one frame means two particles share an id;
 * an atomic claim on the threads, a locked instruction waiting for the
 * fill's stores each time, made the fills cost twice as much); the rest,
 * which may add key entries, read the state or the node's attributes, are
 * then filled in order on this thread. The key entries added are the same
 * and in the same order, as fill_same() never adds one. */
static void fill_all(PhysSystem *s, const PhysCollect *c, const StateDict *sd)
{
    const size_t n = s->npn;
    if (!s->workers || n < 2 * FILL_CHUNK) {
        for (size_t i = 0; i < n; i++)
            fill_particle(s, c, sd, &s->pn[i]);
        return;
    }
    GROW(s->filled, s->capfilled, n);
    FillRun r = {.s = s, .c = c};
    size_t ntasks = workers_split(n, FILL_CHUNK, &r.chunk);
    workers_run(s->workers, ntasks, fill_task, &r);
    for (size_t i = 0; i < n; i++) {
        if (!s->filled[i])
            continue;
        PhysKeyEnt *e = &s->kent[s->slots[s->pn[i].storage].ent1 - 1];
        if (e->seen == s->kframe)
            s->dupids = true;
        e->seen = s->kframe;
    }
    for (size_t t = 0; t < ntasks; t++) {
        if (!r.left[t])
            continue;
        for (size_t i = t * r.chunk, i1 = workers_task_end(t, r.chunk, n); i < i1; i++)
            if (!s->filled[i])
                fill_particle(s, c, sd, &s->pn[i]);
    }
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

void phys_kids_drop(PhysSystem *s)
{
    for (size_t i = 0; i < s->nkids; i++)
        node_release(s->kids[i]);
    s->nkids = 0;
    s->kids_ok = false;
}

/* Keep the children of [root] (retained: their addresses cannot be reused
 * while kept, and nodes are immutable), collected with D dimensions. */
static void keep_kids(PhysSystem *s, const Node *root)
{
    phys_kids_drop(s);
    GROW(s->kids, s->capkids, root->nchildren + 1);
    for (size_t i = 0; i < root->nchildren; i++)
        s->kids[i] = node_retain(root->children[i]);
    s->nkids = root->nchildren;
    s->kidsD = s->D;
    s->kids_ok = true;
    s->kids_nodes = SIZE_MAX;
}

bool phys_kids_same(const PhysSystem *s, const Node *root)
{
    return s->kids_ok && root->nchildren == s->nkids &&
           (s->nkids == 0 ||
            memcmp(root->children, s->kids, s->nkids * sizeof *s->kids) == 0);
}

/* True when the root has the very children of the last collection
 * (c->same_tree), with the same D: then the walk would find the same
 * groups, particles, anchors and appliers with the same attributes, and
 * lay them out the same. */
static bool same_kids(const PhysSystem *s, const PhysCollect *c)
{
    return s->kidsD == s->D && c->same_tree;
}

/* §3 in full: walk, lay particles out group-major, fill them, resolve the
 * distance appliers' ids and build the group lists. Returns false when the
 * system is too large to index (more than 2^32-2 particles or appliers).
 *
 * A tree whose root has the same children as last frame's (a static tree:
 * the simplifier builds it once and every frame's !physics node shares its
 * children) keeps everything the walk built; only what depends on the frame
 * is done again: the eases and !random sources of the appliers that have
 * them (the others' strengths cannot change), in collection order, and the
 * particles' fill (positions and velocities from the state,
 * keys), then the key sweep and the level plan (which reads the thread
 * count). */
bool phys_collect(PhysSystem *s, PhysCollect *c, const Node *root,
                    const StateDict *sd)
{
    if (same_kids(s, c)) {
        for (size_t i = 0; i < s->nclocked; i++)
            applier_clock(&s->ap[s->clocked[i]], c);
        s->dupids = false;
        fill_all(s, c, sd);
        phys_keys_sweep(s);
        phys_plan_levels(s);
        return true;
    }
    phys_kids_drop(s);
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
    if (s->filld != s->D) {
        phys_slot_nodes_drop(s);
        s->filld = s->D;
    }
    /* the id index only serves the !distance appliers */
    bool by_id = false;
    for (size_t a = 0; a < s->nap && !by_id; a++)
        by_id = s->ap[a].kind == AP_DISTANCE;
    if (by_id)
        phys_hash_reset(&s->ids, s->npn);
    /* a system's first particles: their key entries all new */
    if (!s->nkent)
        phys_keys_reserve(s, s->npn);
    s->dupids = false;
    for (size_t i = 0; i < s->npn; i++) {
        PhysPNode *pn = &s->pn[i];
        PhysGroup *G = &s->groups[pn->group];
        pn->storage = G->pstart + G->fill++;
        fill_particle(s, c, sd, pn);
        /* particles are found by id across all groups; a later duplicate
         * replaces the earlier */
        if (by_id)
            phys_hash_put(&s->ids, pn->id, pn->idhash, pn->storage);
    }
    for (size_t a = 0; a < s->nap; a++) {
        PhysApplier *ap = &s->ap[a];
        if (ap->kind != AP_DISTANCE)
            continue;
        size_t f = phys_hash_get(&s->ids, ap->from_id, vec_key_hash(ap->from_id));
        size_t t = phys_hash_get(&s->ids, ap->to_id, vec_key_hash(ap->to_id));
        ap->from = f == SIZE_MAX ? -1 : (ptrdiff_t)f;
        ap->to = t == SIZE_MAX ? -1 : (ptrdiff_t)t;
    }
    phys_keys_sweep(s);
    build_lists(s);
    phys_plan_levels(s);
    keep_kids(s, root);
    /* the rest keep the strength applier_clock() gave them */
    s->nclocked = 0;
    for (size_t a = 0; a < s->nap; a++) {
        if (s->ap[a].ease > 0 || s->ap[a].kind == AP_RANDOM) {
            GROW(s->clocked, s->capclocked, s->nclocked + 1);
            s->clocked[s->nclocked++] = (uint32_t)a;
        }
    }
    return true;
}
