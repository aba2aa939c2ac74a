/* geom_model.c: the model tree, its cache, signed distances and meshes
 * (see geom_model.h).
 *
 * Each model is found by a hash of its kind, its attributes' numbers (bit
 * for bit), its children's serial numbers, its vectors' contents, its
 * file name and its function's key, and confirmed by comparing them all:
 * a hash collision can cost a lookup, never a wrong mesh. Models hold
 * their children, so a child stays while a parent does. */
#include "geom_model.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "buf.h"
#include "format.h"
#include "geom_csg.h"
#include "geom_model_file.h"
#include "geom_primitives.h"
#include "geom_sdf_mesh.h"
#include "mat4.h"
#include "rnode.h"
#include "transform3d.h"

enum Kind {
    K_PRIMITIVE, K_FILE, K_VECTOR, K_TRANSFORM, K_UNION, K_INTERSECT, K_DIFFERENCE, K_TRIM, K_SDF, K_MIX, K_REPAIR,
};
static const char *const kind_names[] = {"primitive", "model", "model", "transform", "union", "intersect",
                                         "difference", "trim", "sdf", "mix", "model"};

#define NPARAMS 16
#define DEFAULT_SEGMENTS 64
/* Bytes a kept vertex and triangle cost (positions, normals, texture
 * coordinates, indices, with the GL copy), for the budget's estimate. */
#define VERTEX_BYTES 64
#define TRIANGLE_BYTES 24

struct GeomModel {
    uint64_t hash, serial;
    int kind;
    MeshKey prim;                 /* K_PRIMITIVE */
    bool solid;                   /* K_PRIMITIVE: an operand inside a model tree (geom_primitive_solid) */
    double p[NPARAMS];            /* transform: matrix; trim: origin, normal, blends; sdf: min, max, resolution; booleans: blends */
    char *path;                   /* K_FILE: the file, as opened */
    Vec *vertices, *faces, *uv;   /* K_VECTOR (faces, uv may be NULL) */
    Vec *weights;                 /* K_MIX */
    Vec *fn;                      /* K_SDF with function= */
    uint64_t fn_key;
    GeomModel **kids;
    int nkids;
    /* the mesh */
    int built;                    /* 0 not yet, 1 built, -1 failed (reported) */
    GeomMesh mesh;
    size_t charged;
    struct timespec mtime;        /* K_FILE: the file as read */
    off_t fsize;
    long checked;                 /* K_FILE: the frame its file was last looked at */
    /* distances (K_TRANSFORM) */
    bool have_inverse;
    M4 inverse;
    double scale;
    /* the cache */
    double touched;
    int users;                    /* models that hold this one */
    GeomModel *next;              /* hash chain */
};

struct GeomModels {
    GeomEnv env;
    GeomModel **table;
    size_t cap, count, bytes;
    uint64_t serials;
    double now;
    long frame;
    Buf folder, text;
};

GeomModels *geom_models_new(const GeomEnv *env)
{
    GeomModels *c = mem_calloc(1, sizeof *c);
    c->env = *env;
    c->cap = 256;
    c->table = mem_calloc(c->cap, sizeof *c->table);
    c->folder = (Buf)BUF_INIT;
    c->text = (Buf)BUF_INIT;
    return c;
}

/* Free [m]; [alone]: its children stay, and hold one user less (when the
 * whole cache goes, they may be gone already). */
static void model_free(GeomModels *c, GeomModel *m, bool alone)
{
    for (int i = 0; alone && i < m->nkids; i++) m->kids[i]->users--;
    free(m->kids);
    free(m->path);
    vec_release(m->vertices);
    vec_release(m->faces);
    vec_release(m->uv);
    vec_release(m->weights);
    vec_release(m->fn);
    geom_mesh_free(&m->mesh);
    mem_budget_release(c->env.budget, m->charged);
    c->bytes -= m->charged;
    free(m);
}

void geom_models_free(GeomModels *c)
{
    if (!c) return;
    for (size_t i = 0; i < c->cap; i++)
        for (GeomModel *m = c->table[i], *next; m; m = next) {
            next = m->next;
            model_free(c, m, false);
        }
    free(c->table);
    buf_free(&c->folder);
    buf_free(&c->text);
    free(c);
}

void geom_models_frame(GeomModels *c, const char *folder, double now, double max_age)
{
    c->now = now;
    c->frame++;
    buf_reset(&c->folder);
    if (folder) buf_puts(&c->folder, folder);
    /* drop models unused for max_age that nothing kept holds; a parent
     * dropped may free its children for the next pass */
    bool dropped = true;
    while (dropped) {
        dropped = false;
        for (size_t i = 0; i < c->cap; i++)
            for (GeomModel **pp = &c->table[i]; *pp;) {
                GeomModel *m = *pp;
                if (m->users == 0 && now - m->touched > max_age) {
                    *pp = m->next;
                    model_free(c, m, true);
                    c->count--;
                    dropped = true;
                } else {
                    pp = &m->next;
                }
            }
    }
}

size_t geom_models_count(const GeomModels *c) { return c->count; }
size_t geom_models_bytes(const GeomModels *c) { return c->bytes; }
uint64_t geom_model_serial(const GeomModel *m) { return m->serial; }

double geom_model_snap(const GeomModel *m)
{
    if (m->kind == K_SDF) return 0.5;
    bool solid = m->kind == K_UNION || m->kind == K_INTERSECT || m->kind == K_DIFFERENCE || m->kind == K_TRIM;
    return solid ? 0.05 : 0.5;
}

static void report(GeomModels *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void report(GeomModels *c, const char *fmt, ...)
{
    if (!c->env.error) return;
    char line[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    c->env.error(c->env.error_ctx, line);
}

/* {===== attributes */

static bool nums(const Node *n, const char *name, int count, double *out)
{
    return rnode_nums(n, name, count, out);
}

static double num(const Node *n, const char *name, double dflt)
{
    double x;
    return nums(n, name, 1, &x) ? x : dflt;
}

/* Attribute [name] as text (symbols by name), or NULL; valid until the next call. */
static const char *text(GeomModels *c, const Node *n, const char *name)
{
    const Vec *v = rnode_attr(n, name);
    if (!v) return NULL;
    buf_reset(&c->text);
    fmt_str(&c->text, v, c->env.symbols);
    return buf_cstr(&c->text);
}

/* A numeric attribute of any length, or NULL. */
static const Vec *numvec(const Node *n, const char *name)
{
    const Vec *v = rnode_attr(n, name);
    return vec_is_num(v) && vec_len(v) > 0 ? v : NULL;
}

/* }===== */

/* {===== hash-consing */

static uint64_t hash_vec(uint64_t h, const Vec *v)
{
    return hash_update(h, v ? vec_hash(v, false) : 0);
}

static uint64_t model_hash(const GeomModel *m)
{
    uint64_t h = hash_update(HASH_START, (uint64_t)m->kind);
    if (m->kind == K_PRIMITIVE) {
        h = hash_update(h, (uint64_t)m->prim.kind);
        h = hash_update(h, (uint64_t)m->prim.segments);
        h = hash_update(h, (uint64_t)m->prim.uv_repeat);
        h = hash_update(h, (uint64_t)m->solid);
    }
    for (int i = 0; i < NPARAMS; i++) h = hash_update(h, num_bits(m->p[i]));
    for (const char *s = m->path; s && *s; s++) h = hash_update(h, (unsigned char)*s);
    h = hash_vec(h, m->vertices);
    h = hash_vec(h, m->faces);
    h = hash_vec(h, m->uv);
    h = hash_vec(h, m->weights);
    h = hash_update(h, m->fn_key);
    for (int i = 0; i < m->nkids; i++) h = hash_update(h, m->kids[i]->serial);
    return h;
}

static bool same_vec(const Vec *a, const Vec *b)
{
    if (!a || !b) return a == b;
    return vec_equal(a, b);
}

static bool same_model(const GeomModel *a, const GeomModel *b)
{
    if (a->kind != b->kind || a->nkids != b->nkids || a->fn_key != b->fn_key) return false;
    if (a->kind == K_PRIMITIVE && (a->prim.kind != b->prim.kind || a->prim.segments != b->prim.segments ||
                                   a->prim.uv_repeat != b->prim.uv_repeat || a->solid != b->solid))
        return false;
    for (int i = 0; i < NPARAMS; i++)
        if (num_bits(a->p[i]) != num_bits(b->p[i])) return false;
    if ((a->path || b->path) && (!a->path || !b->path || strcmp(a->path, b->path) != 0)) return false;
    if (!same_vec(a->vertices, b->vertices) || !same_vec(a->faces, b->faces) || !same_vec(a->uv, b->uv) ||
        !same_vec(a->weights, b->weights))
        return false;
    for (int i = 0; i < a->nkids; i++)
        if (a->kids[i] != b->kids[i]) return false;
    return true;
}

/* The kept model equal to [proto] (whose path, kids and function it then
 * takes), or [proto] itself made a kept model. [proto] is on the stack;
 * its vertices, faces, uv and weights are borrowed (the tree's), and a
 * new kept model keeps copies of them (vec_copy_deep): the cache never
 * holds a reference to a value of the tree, whose counts the frame
 * loop's thread may be changing while a drawing thread draws
 * (fl_picture_draw). */
static GeomModel *intern(GeomModels *c, GeomModel *proto)
{
    proto->hash = model_hash(proto);
    size_t slot = proto->hash & (c->cap - 1);
    for (GeomModel *m = c->table[slot]; m; m = m->next)
        if (m->hash == proto->hash && same_model(m, proto)) {
            m->touched = c->now;
            free(proto->kids);
            free(proto->path);
            vec_release(proto->fn);
            return m;
        }
    if (c->count >= c->cap) {
        size_t cap = c->cap * 2;
        GeomModel **t = mem_calloc(cap, sizeof *t);
        for (size_t i = 0; i < c->cap; i++)
            for (GeomModel *m = c->table[i], *next; m; m = next) {
                next = m->next;
                m->next = t[m->hash & (cap - 1)];
                t[m->hash & (cap - 1)] = m;
            }
        free(c->table);
        c->table = t;
        c->cap = cap;
        slot = proto->hash & (c->cap - 1);
    }
    GeomModel *m = mem_alloc(sizeof *m);
    *m = *proto;
    m->vertices = vec_copy_deep(proto->vertices);
    m->faces = vec_copy_deep(proto->faces);
    m->uv = vec_copy_deep(proto->uv);
    m->weights = vec_copy_deep(proto->weights);
    m->serial = ++c->serials;
    m->touched = c->now;
    for (int i = 0; i < m->nkids; i++) m->kids[i]->users++;
    m->next = c->table[slot];
    c->table[slot] = m;
    c->count++;
    return m;
}

/* }===== */

/* {===== the model tree */

bool geom_is_model_kind(const Node *n)
{
    static const char *const kinds[] = {"box", "sphere", "cylinder", "cone", "model", "union", "intersect",
                                        "difference", "trim", "slice", "sdf", "mix"};
    for (size_t i = 0; i < sizeof kinds / sizeof *kinds; i++)
        if (rnode_is(n, kinds[i])) return true;
    return false;
}

static GeomModel *model_of(GeomModels *c, const Node *n, bool top);

/* A model of [kind] over [kids] (taken), interned. */
static GeomModel *make(GeomModels *c, GeomModel *proto, GeomModel **kids, int nkids)
{
    proto->kids = kids;
    proto->nkids = nkids;
    return intern(c, proto);
}

/* A model [proto] over the one child [kid], interned. */
static GeomModel *make_one(GeomModels *c, GeomModel *proto, GeomModel *kid)
{
    GeomModel **one = mem_alloc(sizeof *one);
    one[0] = kid;
    return make(c, proto, one, 1);
}

/* Flitter BooleanOperation._get: children flattened where they are the
 * same operation with the same blends (not for difference), a repeated
 * child once, a difference whose later child is its first nothing, one
 * child itself. */
static GeomModel *boolean(GeomModels *c, int kind, GeomModel **in, int nin, const double blend[3])
{
    GeomModel **kids = mem_alloc(sizeof *kids * (size_t)(nin ? nin : 1));
    int n = 0, cap = nin ? nin : 1;
    /* a stack of the children still to look at, first on top */
    GeomModel **stack = mem_alloc(sizeof *stack * (size_t)cap);
    int top = 0, scap = cap;
    for (int i = nin - 1; i >= 0; i--) stack[top++] = in[i];
    GeomModel *first = NULL;
    bool none = false;
    while (top > 0) {
        GeomModel *m = stack[--top];
        if (!m) continue;
        if (m->kind == kind && kind != K_DIFFERENCE && m->p[0] == blend[0] && m->p[1] == blend[1] &&
            m->p[2] == blend[2]) {
            if (top + m->nkids > scap) {
                scap = (top + m->nkids) * 2;
                stack = mem_realloc_array(stack, (size_t)scap, sizeof *stack);
            }
            for (int k = m->nkids - 1; k >= 0; k--) stack[top++] = m->kids[k];
            continue;
        }
        if (!first) {
            first = m;
        } else if (kind == K_DIFFERENCE && m == first) {
            none = true;
            break;
        }
        bool seen = false;
        for (int k = 0; k < n && !seen; k++) seen = kids[k] == m;
        if (seen) continue;
        if (n == cap) {
            cap *= 2;
            kids = mem_realloc_array(kids, (size_t)cap, sizeof *kids);
        }
        kids[n++] = m;
    }
    free(stack);
    if (none || n == 0) {
        free(kids);
        return NULL;
    }
    if (n == 1) {
        GeomModel *only = kids[0];
        free(kids);
        return only;
    }
    GeomModel proto = {.kind = kind};
    memcpy(proto.p, blend, 3 * sizeof *blend);
    return make(c, &proto, kids, n);
}

static GeomModel *transformed(GeomModels *c, GeomModel *m, const M4 *t)
{
    if (!m) return NULL;
    GeomModel proto = {.kind = K_TRANSFORM};
    memcpy(proto.p, t->m, sizeof t->m);
    return make_one(c, &proto, m);
}

/* The models of [n]'s children (NULLs included), in a new array. */
static GeomModel **children(GeomModels *c, const Node *n, int *count)
{
    size_t k = rnode_nchildren(n);
    GeomModel **out = mem_alloc(sizeof *out * (k ? k : 1));
    for (size_t i = 0; i < k; i++) out[i] = model_of(c, rnode_child(n, i), false);
    *count = (int)k;
    return out;
}

static void blends(const Node *n, double out[3])
{
    out[0] = num(n, "smooth", 0);
    out[1] = num(n, "fillet", 0);
    out[2] = num(n, "chamfer", 0);
}

/* A primitive; [solid]: an operand inside a model tree, not the model drawn. */
static GeomModel *primitive(GeomModels *c, const Node *n, int kind, bool solid)
{
    GeomModel proto = {.kind = K_PRIMITIVE, .solid = solid};
    proto.prim.kind = kind;
    double seg = num(n, "segments", DEFAULT_SEGMENTS);
    proto.prim.segments = mesh_segments(kind, seg > 1e6 ? 1000000 : seg < 0 ? 0 : (int)seg);
    if (kind == MESH_BOX) {
        const char *uv = text(c, n, "uv_map");
        proto.prim.uv_repeat = uv && strcmp(uv, "repeat") == 0;
    }
    return intern(c, &proto);
}

/* The path a model file name opens: relative names from the frame's folder. */
static char *model_path(GeomModels *c, const char *name)
{
    Buf b = BUF_INIT;
    if (name[0] != '/' && c->folder.len) {
        buf_puts(&b, buf_cstr(&c->folder));
        if (b.data[b.len - 1] != '/') buf_puts(&b, "/");
    }
    buf_puts(&b, name);
    char *s = mem_alloc(b.len + 1);
    memcpy(s, buf_cstr(&b), b.len + 1);
    buf_free(&b);
    return s;
}

/* `!model`: a file or vectors, repaired (geom_mesh_repair) with repair=true. */
static GeomModel *model_node(GeomModels *c, const Node *n)
{
    const char *name = text(c, n, "filename");
    GeomModel *m;
    if (name && name[0]) {
        GeomModel proto = {.kind = K_FILE, .path = model_path(c, name)};
        m = intern(c, &proto);
    } else {
        const Vec *v = numvec(n, "vertices");
        if (!v) return NULL;
        const Vec *f = numvec(n, "faces"), *uv = numvec(n, "uv");
        GeomModel proto = {.kind = K_VECTOR, .vertices = (Vec *)v, .faces = (Vec *)f, .uv = (Vec *)uv};
        m = intern(c, &proto);
    }
    const Vec *repair = rnode_attr(n, "repair");
    if (!m || !repair || !vec_truthy(repair)) return m;
    GeomModel proto = {.kind = K_REPAIR};
    return make_one(c, &proto, m);
}

/* [m] trimmed (Flitter Model._trim): an intersection or difference
 * without blends has its first part trimmed instead, so the plane cuts a
 * primitive rather than a boolean's result. */
static GeomModel *trimmed(GeomModels *c, GeomModel *m, const double origin[3], const double normal[3],
                          const double b[3])
{
    bool unblended = b[0] == 0 && b[1] == 0 && b[2] == 0 && m->p[0] == 0 && m->p[1] == 0 && m->p[2] == 0;
    if (unblended && (m->kind == K_INTERSECT || m->kind == K_DIFFERENCE)) {
        GeomModel **kids = mem_alloc(sizeof *kids * (size_t)m->nkids);
        memcpy(kids, m->kids, sizeof *kids * (size_t)m->nkids);
        kids[0] = trimmed(c, kids[0], origin, normal, b);
        GeomModel *r = boolean(c, m->kind, kids, m->nkids, b);
        free(kids);
        return r;
    }
    GeomModel proto = {.kind = K_TRIM};
    for (int i = 0; i < 3; i++) proto.p[i] = origin[i], proto.p[3 + i] = normal[i];
    memcpy(proto.p + 6, b, 3 * sizeof *b);
    return make_one(c, &proto, m);
}

static GeomModel *trim_node(GeomModels *c, const Node *n)
{
    int k;
    GeomModel **kids = children(c, n, &k);
    double none[3] = {0, 0, 0};
    GeomModel *m = k == 1 ? kids[0] : boolean(c, K_UNION, kids, k, none);
    free(kids);
    double normal[3], origin[3] = {0, 0, 0};
    if (!m || !nums(n, "normal", 3, normal) || (normal[0] == 0 && normal[1] == 0 && normal[2] == 0)) return m;
    nums(n, "origin", 3, origin);
    double len = sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (int i = 0; i < 3; i++) normal[i] /= len;
    double b[3];
    blends(n, b);
    return trimmed(c, m, origin, normal, b);
}

static GeomModel *sdf_node(GeomModels *c, const Node *n)
{
    GeomModel proto = {.kind = K_SDF};
    double *mn = proto.p, *mx = proto.p + 3;
    mx[0] = mx[1] = mx[2] = 1;
    if (!nums(n, "maximum", 3, mx)) nums(n, "max", 3, mx);
    for (int i = 0; i < 3; i++) mn[i] = -mx[i];
    if (!nums(n, "minimum", 3, mn)) nums(n, "min", 3, mn);
    double span = fmax(mx[0] - mn[0], fmax(mx[1] - mn[1], mx[2] - mn[2]));
    proto.p[6] = num(n, "resolution", span / 64);
    const Vec *fn = rnode_attr(n, "function");
    if (fn && vec_len(fn) == 1 && vec_is_obj(fn) && vec_celems(fn)[0].kind == EL_FUNC) {
        if (!c->env.distance || !c->env.function_key) return NULL;
        proto.fn = vec_retain((Vec *)fn);
        proto.fn_key = c->env.function_key(c->env.ctx, fn) | 1;   /* never 0, which is "none" */
        return intern(c, &proto);
    }
    int k;
    GeomModel **kids = children(c, n, &k);
    double b[3];
    blends(n, b);
    GeomModel *u = boolean(c, K_UNION, kids, k, b);
    free(kids);
    if (!u) return NULL;
    return make_one(c, &proto, u);
}

static GeomModel *mix_node(GeomModels *c, const Node *n)
{
    int k;
    GeomModel **kids = children(c, n, &k);
    int m = 0;
    for (int i = 0; i < k; i++)
        if (kids[i]) kids[m++] = kids[i];
    if (m <= 1) {
        GeomModel *only = m ? kids[0] : NULL;
        free(kids);
        return only;
    }
    const Vec *w = numvec(n, "weights");
    double one = 1;
    Vec *ones = w ? NULL : vec_from_nums(&one, 1);
    GeomModel proto = {.kind = K_MIX, .weights = w ? (Vec *)w : ones};
    GeomModel *mix = make(c, &proto, kids, m);
    vec_release(ones);
    return mix;
}

static GeomModel *model_of(GeomModels *c, const Node *n, bool top)
{
    GeomModel *m = NULL;
    int k;
    if (rnode_is(n, "box")) m = primitive(c, n, MESH_BOX, !top);
    else if (rnode_is(n, "sphere")) m = primitive(c, n, MESH_SPHERE, !top);
    else if (rnode_is(n, "cylinder")) m = primitive(c, n, MESH_CYLINDER, !top);
    else if (rnode_is(n, "cone")) m = primitive(c, n, MESH_CONE, !top);
    else if (rnode_is(n, "model")) m = model_node(c, n);
    else if (!top && rnode_is(n, "transform")) {
        /* Flitter: each child through the transform, then their union */
        M4 t = transform3d_update(n, m4_identity());
        GeomModel **kids = children(c, n, &k);
        for (int i = 0; i < k; i++) kids[i] = transformed(c, kids[i], &t);
        double none[3] = {0, 0, 0};
        m = boolean(c, K_UNION, kids, k, none);
        free(kids);
        return m;
    } else if (rnode_is(n, "trim") || rnode_is(n, "slice")) m = trim_node(c, n);
    else if (rnode_is(n, "union") || rnode_is(n, "intersect") || rnode_is(n, "difference")) {
        int kind = rnode_is(n, "union") ? K_UNION : rnode_is(n, "intersect") ? K_INTERSECT : K_DIFFERENCE;
        GeomModel **kids = children(c, n, &k);
        double b[3];
        blends(n, b);
        m = boolean(c, kind, kids, k, b);
        free(kids);
    } else if (rnode_is(n, "sdf")) m = sdf_node(c, n);
    else if (rnode_is(n, "mix")) m = mix_node(c, n);
    if (m && !top) {
        bool moved;
        M4 t = transform3d_model(n, m4_identity(), &moved);
        if (moved) m = transformed(c, m, &t);
    }
    return m;
}

GeomModel *geom_model_of(GeomModels *c, const Node *n, bool top)
{
    return model_of(c, n, top);
}

/* }===== */

/* {===== signed distances (Flitter models.pyx, signed_distance of each
 * kind), over [n] points at a time */

#define ROOT_HALF 0.7071067811865476

static double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

/* The blend of distances [a] (the result so far) and [d] (the next
 * child) for a boolean of [kind] with blends [b] (Flitter
 * BooleanOperation.signed_distance, term for term). */
static double combine(int kind, const double b[3], double a, double d)
{
    double smooth = b[0], fillet = b[1], chamfer = b[2], g, h;
    if (kind == K_UNION) {
        if (smooth) {
            g = clamp01(0.5 + 0.5 * (d - a) / smooth);
            h = 1 - g;
            return g * a + h * d - smooth * g * h;
        }
        if (fillet) {
            g = fmax(0, fillet - a);
            h = fmax(0, fillet - d);
            return fmax(fillet, fmin(a, d)) - sqrt(g * g + h * h);
        }
        if (chamfer) return fmin(fmin(a, d), (a - chamfer + d) * ROOT_HALF);
        return fmin(a, d);
    }
    if (kind == K_INTERSECT) {
        if (smooth) {
            g = clamp01(0.5 + 0.5 * (d - a) / smooth);
            h = 1 - g;
            a = g * d + h * a + smooth * g * h;
        }
        if (fillet) {
            g = fmax(0, fillet + a);
            h = fmax(0, fillet + d);
            return fmin(-fillet, fmax(a, d)) + sqrt(g * g + h * h);
        }
        if (chamfer) return fmax(fmax(a, d), (a + chamfer + d) * ROOT_HALF);
        return fmax(a, d);
    }
    /* difference */
    if (smooth) {
        g = clamp01(0.5 + 0.5 * (-d - a) / smooth);
        h = 1 - g;
        a = -g * d + h * a + smooth * g * h;
    }
    if (fillet) {
        g = fmax(0, fillet + a);
        h = fmax(0, fillet - d);
        return fmin(-fillet, fmax(a, -d)) + sqrt(g * g + h * h);
    }
    if (chamfer) return fmax(fmax(a, -d), (a + chamfer - d) * ROOT_HALF);
    return fmax(a, -d);
}

static double prim_distance(int kind, double x, double y, double z)
{
    switch (kind) {
    case MESH_SPHERE: return sqrt(x * x + y * y + z * z) - 1;
    case MESH_CYLINDER: return fmax(sqrt(x * x + y * y) - 1, fabs(z) - 0.5);
    case MESH_CONE: return fmax(sqrt(x * x + y * y) + z, fabs(z)) - 0.5;
    default: {
        double xp = fabs(x) - 0.5, yp = fabs(y) - 0.5, zp = fabs(z) - 0.5;
        double xm = fmax(xp, 0), ym = fmax(yp, 0), zm = fmax(zp, 0);
        return sqrt(xm * xm + ym * ym + zm * zm) + fmin(0, fmax(xp, fmax(yp, zp)));
    }
    }
}

static bool distances(GeomModels *c, GeomModel *m, const double *xyz, size_t n, double *out);

static bool transform_distances(GeomModels *c, GeomModel *m, const double *xyz, size_t n, double *out)
{
    if (!m->have_inverse) {
        M4 t;
        memcpy(t.m, m->p, sizeof t.m);
        if (!m4_inverse(&t, &m->inverse)) memset(&m->inverse, 0, sizeof m->inverse);
        double s = INFINITY;
        for (int col = 0; col < 3; col++) {
            const double *v = t.m + col * 4;
            s = fmin(s, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        }
        m->scale = s;
        m->have_inverse = true;
    }
    double *p = mem_alloc(sizeof(double) * 3 * (n ? n : 1));
    for (size_t i = 0; i < n; i++) m4_point(&m->inverse, xyz + i * 3, p + i * 3);
    bool ok = distances(c, m->kids[0], p, n, out);
    free(p);
    for (size_t i = 0; i < n; i++) out[i] *= m->scale;
    return ok;
}

static bool distances(GeomModels *c, GeomModel *m, const double *xyz, size_t n, double *out)
{
    switch (m->kind) {
    case K_PRIMITIVE:
        for (size_t i = 0; i < n; i++) out[i] = prim_distance(m->prim.kind, xyz[i * 3], xyz[i * 3 + 1], xyz[i * 3 + 2]);
        return true;
    case K_TRANSFORM: return transform_distances(c, m, xyz, n, out);
    case K_SDF:
        if (m->fn) return c->env.distance(c->env.ctx, m->fn, xyz, n, out);
        return distances(c, m->kids[0], xyz, n, out);
    case K_UNION:
    case K_INTERSECT:
    case K_DIFFERENCE: {
        if (!distances(c, m->kids[0], xyz, n, out)) return false;
        double *d = mem_alloc(sizeof(double) * (n ? n : 1));
        for (int k = 1; k < m->nkids; k++) {
            if (!distances(c, m->kids[k], xyz, n, d)) {
                free(d);
                return false;
            }
            for (size_t i = 0; i < n; i++) out[i] = combine(m->kind, m->p, out[i], d[i]);
        }
        free(d);
        return true;
    }
    case K_TRIM: {
        if (!distances(c, m->kids[0], xyz, n, out)) return false;
        const double *o = m->p, *nm = m->p + 3;
        double smooth = m->p[6], fillet = m->p[7], chamfer = m->p[8];
        for (size_t i = 0; i < n; i++) {
            double dist = out[i];
            double d = (xyz[i * 3] - o[0]) * nm[0] + (xyz[i * 3 + 1] - o[1]) * nm[1] + (xyz[i * 3 + 2] - o[2]) * nm[2];
            if (smooth) {
                double h = clamp01(0.5 + 0.5 * (d - dist) / smooth);
                dist = h * d + (1 - h) * dist + smooth * h * (1 - h);
            }
            if (fillet) {
                double g = fmax(0, fillet + dist), h = fmax(0, fillet + d);
                dist = fmin(-fillet, fmax(dist, d)) + sqrt(g * g + h * h);
            } else if (chamfer) {
                dist = fmax(fmax(dist, d), (dist + chamfer + d) * ROOT_HALF);
            } else {
                dist = fmax(dist, d);
            }
            out[i] = dist;
        }
        return true;
    }
    case K_MIX: {
        double *d = mem_alloc(sizeof(double) * (n ? n : 1));
        const double *w = vec_cnums(m->weights);
        uint32_t nw = vec_len(m->weights);
        double total = 0;
        for (size_t i = 0; i < n; i++) out[i] = 0;
        for (int k = 0; k < m->nkids; k++) {
            if (!distances(c, m->kids[k], xyz, n, d)) {
                free(d);
                return false;
            }
            double wk = w[(uint32_t)k % nw];
            for (size_t i = 0; i < n; i++) out[i] += d[i] * wk;
            total += wk;
        }
        for (size_t i = 0; i < n; i++) out[i] /= total;
        free(d);
        return true;
    }
    default:
        /* a mesh's distance field: not computed here (said once by the caller) */
        for (size_t i = 0; i < n; i++) out[i] = NAN;
        return true;
    }
}

/* Whether [m]'s distances reach a mesh model (a file or vectors). */
static bool has_mesh_distance(const GeomModel *m)
{
    if (m->kind == K_FILE || m->kind == K_VECTOR) return true;
    if (m->kind == K_SDF && m->fn) return false;
    for (int i = 0; i < m->nkids; i++)
        if (has_mesh_distance(m->kids[i])) return true;
    return false;
}

typedef struct DistCtx {
    GeomModels *c;
    GeomModel *m;
} DistCtx;

static bool dist_fn(void *ctx, const double *xyz, size_t n, double *out)
{
    DistCtx *d = ctx;
    if (d->c->env.interrupt && *d->c->env.interrupt) return false;
    return distances(d->c, d->m, xyz, n, out);
}

/* }===== */

/* {===== meshes */

/* Points or vertices the budget still has room for (at VERTEX_BYTES each). */
static size_t room_vertices(GeomModels *c)
{
    size_t lo = 0, hi = (size_t)1 << 40;
    /* the largest count mem_budget_reserve would accept, by halving */
    if (!c->env.budget) return (size_t)1 << 32;
    while (lo < hi) {
        size_t mid = lo + (hi - lo + 1) / 2;
        if (mem_budget_reserve(c->env.budget, mid * VERTEX_BYTES)) {
            mem_budget_release(c->env.budget, mid * VERTEX_BYTES);
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    return lo;
}

static bool vector_mesh(GeomModel *m, GeomMesh *out, Buf *err)
{
    uint32_t nv = vec_len(m->vertices);
    if (nv % 3 != 0) {
        buf_printf(err, "bad vertices vector length %u (not a multiple of 3)\n", nv);
        return false;
    }
    nv /= 3;
    if (!m->faces) {
        /* Flitter: the convex hull of the vertices (as floats) */
        double *p = mem_alloc(sizeof(double) * 3 * (nv ? nv : 1));
        const double *v = vec_cnums(m->vertices);
        for (uint32_t i = 0; i < nv * 3; i++) p[i] = (float)v[i];
        int rc = geom_csg_hull(p, nv, out, err);
        free(p);
        return rc == 0;
    }
    uint32_t nf = vec_len(m->faces);
    if (nf % 3 != 0) {
        buf_printf(err, "bad faces vector length %u (not a multiple of 3)\n", nf);
        return false;
    }
    if (m->uv && vec_len(m->uv) != nv * 2) {
        buf_printf(err, "bad uv vector length %u (not 2 per vertex)\n", vec_len(m->uv));
        return false;
    }
    const double *v = vec_cnums(m->vertices), *f = vec_cnums(m->faces);
    memset(out, 0, sizeof *out);
    out->pos = mem_alloc(sizeof(double) * 3 * (nv ? nv : 1));
    memcpy(out->pos, v, sizeof(double) * 3 * nv);
    for (uint32_t i = 0; i < nv * 3; i++) out->pos[i] = (float)out->pos[i];   /* Flitter keeps them as floats */
    out->npos = nv;
    if (m->uv) {
        out->uv = mem_alloc(sizeof(float) * 2 * (nv ? nv : 1));
        const double *u = vec_cnums(m->uv);
        for (uint32_t i = 0; i < nv * 2; i++) out->uv[i] = (float)u[i];
    }
    out->tri = mem_alloc(sizeof(uint32_t) * (nf ? nf : 1));
    for (uint32_t i = 0; i < nf; i++) {
        double x = floor(f[i]);
        if (!(x >= 0 && x < nv)) {
            buf_printf(err, "bad vertex index %g in faces (%u vertices)\n", f[i], nv);
            geom_mesh_free(out);
            return false;
        }
        out->tri[i] = (uint32_t)x;
    }
    out->ntri = nf / 3;
    return true;
}

/* Positions through [m]'s matrix, normals through its cofactor, winding
 * reversed when it mirrors (so a transformed volume still faces out). */
static void transform_mesh(const double *mat, const GeomMesh *in, GeomMesh *out)
{
    geom_mesh_copy(in, out);
    M4 t;
    memcpy(t.m, mat, sizeof t.m);
    double cof[9];
    m4_cofactor3(&t, cof);
    for (uint32_t i = 0; i < out->npos; i++) {
        double p[3];
        m4_point(&t, in->pos + (size_t)i * 3, p);
        memcpy(out->pos + (size_t)i * 3, p, sizeof p);
        if (out->normal) {
            const float *nm = in->normal + (size_t)i * 3;
            double r[3];
            for (int k = 0; k < 3; k++) r[k] = cof[k] * nm[0] + cof[3 + k] * nm[1] + cof[6 + k] * nm[2];
            double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            for (int k = 0; k < 3; k++) out->normal[(size_t)i * 3 + k] = (float)(len > 0 ? r[k] / len : 0);
        }
    }
    double det = t.m[0] * (t.m[5] * t.m[10] - t.m[9] * t.m[6]) - t.m[4] * (t.m[1] * t.m[10] - t.m[9] * t.m[2]) +
                 t.m[8] * (t.m[1] * t.m[6] - t.m[5] * t.m[2]);
    if (det < 0)
        for (uint32_t f = 0; f < out->ntri; f++) {
            uint32_t s = out->tri[(size_t)f * 3 + 1];
            out->tri[(size_t)f * 3 + 1] = out->tri[(size_t)f * 3 + 2];
            out->tri[(size_t)f * 3 + 2] = s;
        }
}

static bool file_changed(GeomModels *c, GeomModel *m)
{
    if (m->checked == c->frame) return false;
    m->checked = c->frame;
    struct stat st;
    if (stat(m->path, &st) != 0) return m->built == 1;
    bool changed = st.st_mtim.tv_sec != m->mtime.tv_sec || st.st_mtim.tv_nsec != m->mtime.tv_nsec ||
                   st.st_size != m->fsize;
    m->mtime = st.st_mtim;
    m->fsize = st.st_size;
    return changed && m->built != 0;
}

/* Drop [m]'s mesh and every kept model's that was made from it. */
static void invalidate(GeomModels *c, GeomModel *m)
{
    if (m->built == 0) return;
    geom_mesh_free(&m->mesh);
    mem_budget_release(c->env.budget, m->charged);
    c->bytes -= m->charged;
    m->charged = 0;
    m->built = 0;
    for (size_t i = 0; i < c->cap; i++)
        for (GeomModel *p = c->table[i]; p; p = p->next)
            for (int k = 0; k < p->nkids; k++)
                if (p->kids[k] == m) invalidate(c, p);
}

/* Whether [m] or a model under it is a file changed on disk (each file
 * looked at once a frame); changed ones are invalidated with their users. */
static void check_files(GeomModels *c, GeomModel *m)
{
    if (m->kind == K_FILE && file_changed(c, m)) invalidate(c, m);
    for (int i = 0; i < m->nkids; i++) check_files(c, m->kids[i]);
}

/* [mesh]'s normals from the gradient of [m]'s field at its vertices
 * (central differences a quarter of the grid step apart, batched): the
 * surface's own normals, smoother than its marching tetrahedra's faces.
 * False when interrupted. */
static bool gradient_normals(GeomModels *c, GeomModel *m, GeomMesh *mesh)
{
    double h = m->p[6] / 4;
    size_t n = mesh->npos, batch = 4096;
    double *xyz = mem_alloc(sizeof(double) * 3 * 6 * batch), *d = mem_alloc(sizeof(double) * 6 * batch);
    mesh->normal = mem_alloc(sizeof(float) * 3 * (n ? n : 1));
    DistCtx ctx = {c, m};
    bool ok = true;
    for (size_t at = 0; at < n && ok; at += batch) {
        size_t k = n - at < batch ? n - at : batch;
        for (size_t i = 0; i < k; i++)
            for (int q = 0; q < 6; q++) {
                double *p = xyz + (i * 6 + (size_t)q) * 3;
                memcpy(p, mesh->pos + (at + i) * 3, 3 * sizeof *p);
                p[q / 2] += q % 2 ? -h : h;
            }
        ok = dist_fn(&ctx, xyz, k * 6, d);
        for (size_t i = 0; ok && i < k; i++) {
            double g[3], len = 0;
            for (int a = 0; a < 3; a++) g[a] = d[i * 6 + (size_t)a * 2] - d[i * 6 + (size_t)a * 2 + 1], len += g[a] * g[a];
            len = sqrt(len);
            for (int a = 0; a < 3; a++)
                mesh->normal[(at + i) * 3 + (size_t)a] = len > 0 && isfinite(len) ? (float)(g[a] / len) : 0;
        }
    }
    free(xyz);
    free(d);
    return ok;
}

static const GeomMesh *mesh_of(GeomModels *c, GeomModel *m);

static bool build(GeomModels *c, GeomModel *m, GeomMesh *out, Buf *err)
{
    memset(out, 0, sizeof *out);
    switch (m->kind) {
    case K_PRIMITIVE:
        if (m->solid) geom_primitive_solid(&m->prim, out);
        else geom_primitive_mesh(&m->prim, out);
        return true;
    case K_FILE: {
        if (geom_model_file_read(m->path, room_vertices(c), out, err) != 0) return false;
        return true;
    }
    case K_VECTOR: return vector_mesh(m, out, err);
    case K_REPAIR: {
        const GeomMesh *in = mesh_of(c, m->kids[0]);
        if (!in) return false;
        geom_mesh_copy(in, out);
        geom_mesh_repair(out);
        if (out->ntri == 0) {
            buf_printf(err, "no triangle is left once repaired\n");
            geom_mesh_free(out);
            return false;
        }
        return true;
    }
    case K_TRANSFORM: {
        const GeomMesh *in = mesh_of(c, m->kids[0]);
        if (!in) return false;
        transform_mesh(m->p, in, out);
        return true;
    }
    case K_UNION:
    case K_INTERSECT:
    case K_DIFFERENCE: {
        /* Flitter BooleanOperation.build_manifold: a child without a mesh
         * is left out of a union or a later place of a difference; an
         * intersection, or a difference without its first, has none */
        const GeomMesh **in = mem_alloc(sizeof *in * (size_t)m->nkids);
        size_t n = 0;
        for (int k = 0; k < m->nkids; k++) {
            const GeomMesh *g = mesh_of(c, m->kids[k]);
            if (!g && (m->kind == K_INTERSECT || (m->kind == K_DIFFERENCE && k == 0))) {
                free(in);
                buf_printf(err, "part %d has no mesh\n", k + 1);
                return false;
            }
            if (g) in[n++] = g;
        }
        if (n == 0) {
            free(in);
            buf_printf(err, "no part has a mesh\n");
            return false;
        }
        GeomBoolOp op = m->kind == K_UNION ? GEOM_UNION : m->kind == K_INTERSECT ? GEOM_INTERSECT : GEOM_DIFFERENCE;
        int rc = geom_csg_boolean(op, in, n, out, c->env.interrupt, err);
        free(in);
        if (rc == 0 && out->ntri == 0) {
            buf_printf(err, "the result is empty\n");
            geom_mesh_free(out);
            return false;
        }
        return rc == 0;
    }
    case K_TRIM: {
        const GeomMesh *in = mesh_of(c, m->kids[0]);
        if (!in) return false;
        if (geom_csg_trim(in, m->p, m->p + 3, out, err) != 0) return false;
        if (out->ntri == 0) {
            buf_printf(err, "the result is empty\n");
            geom_mesh_free(out);
            return false;
        }
        return true;
    }
    case K_SDF: {
        if (!m->fn && has_mesh_distance(m->kids[0])) {
            buf_printf(err, "the signed distance of a !model mesh is not computed here\n");
            return false;
        }
        DistCtx d = {c, m};
        size_t room = room_vertices(c);
        if (geom_sdf_mesh(dist_fn, &d, m->p, m->p + 3, m->p[6], room, c->env.interrupt, out, err) != 0)
            return false;
        if (out->ntri == 0) {
            buf_printf(err, "the result is empty\n");
            geom_mesh_free(out);
            return false;
        }
        if (!gradient_normals(c, m, out)) {
            geom_mesh_free(out);
            buf_printf(err, "interrupted\n");
            return false;
        }
        return true;
    }
    case K_MIX: buf_printf(err, "a !mix is drawn only inside an !sdf\n"); return false;
    default: buf_printf(err, "no mesh\n"); return false;
    }
}

static const char *model_name(const GeomModel *m)
{
    return m->kind == K_FILE ? m->path : kind_names[m->kind];
}

static const GeomMesh *mesh_of(GeomModels *c, GeomModel *m)
{
    if (m->built == 1) return &m->mesh;
    if (m->built == -1) return NULL;
    if (c->env.interrupt && *c->env.interrupt) return NULL;   /* not marked: tried again next time */
    Buf err = BUF_INIT;
    GeomMesh out;
    bool ok = build(c, m, &out, &err);
    if (!ok && c->env.interrupt && *c->env.interrupt) {
        buf_free(&err);
        return NULL;
    }
    size_t bytes = ok ? (size_t)out.npos * VERTEX_BYTES + (size_t)out.ntri * TRIANGLE_BYTES : 0;
    if (ok && !mem_budget_reserve(c->env.budget, bytes)) {
        buf_printf(&err, "its mesh (%u vertices, %u triangles) does not fit in the memory budget\n", out.npos,
                   out.ntri);
        geom_mesh_free(&out);
        ok = false;
    }
    if (!ok) {
        m->built = -1;
        if (err.len) report(c, m->kind == K_FILE ? "%s: %s" : "!%s: %s", model_name(m), buf_line(&err));
        buf_free(&err);
        return NULL;
    }
    buf_free(&err);
    m->mesh = out;
    m->charged = bytes;
    c->bytes += bytes;
    m->built = 1;
    return &m->mesh;
}

const GeomMesh *geom_model_mesh(GeomModels *c, GeomModel *m)
{
    check_files(c, m);
    m->touched = c->now;
    return mesh_of(c, m);
}

/* }===== */
