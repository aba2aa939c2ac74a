/* systems.c: physics systems read from the node tree and state (systems.h). */
#include "systems.h"

#include <stdlib.h>
#include <string.h>

#include "buf.h"
#include "format.h"
#include "mem.h"
#include "rnode.h"

typedef struct Collect {
    const StateDict *sd;
    PsSystem *s;
    size_t cap_bodies, cap_links, cap_barriers;
    Vec *vsym;            /* :velocity */
} Collect;

/* The state value under prefix;id[;:velocity] (borrowed) or NULL. */
static const Vec *lookup(const Collect *c, const Vec *id, bool velocity)
{
    Vec *parts[3] = {(Vec *)c->s->prefix, (Vec *)id, c->vsym};
    Vec *key = vec_compose(parts, velocity ? 3 : 2);
    const Vec *v = state_get(c->sd, key);
    vec_release(key);
    return vec_is_num(v) ? v : NULL;
}

static double num_attr(const Node *n, const char *name, double dflt)
{
    const Vec *v = rnode_attr(n, name);
    return vec_is_num(v) && vec_len(v) == 1 ? vec_scalar(v) : dflt;
}

static const Vec *num_vec(const Node *n, const char *name)
{
    const Vec *v = rnode_attr(n, name);
    return vec_is_num(v) ? v : NULL;
}

/* The position of the body with [id]: state first, else its node's. */
static const Vec *position_of(const Collect *c, const Vec *id)
{
    if (!id) return NULL;
    const Vec *v = lookup(c, id, false);
    for (size_t i = 0; !v && i < c->s->nbodies; i++)
        if (vec_equal(c->s->bodies[i].id, id)) v = c->s->bodies[i].pos;
    return v;
}

static void walk(Collect *c, const Node *g)
{
    PsSystem *s = c->s;
    for (size_t i = 0; i < rnode_nchildren(g); i++) {
        const Node *n = rnode_child(g, i);
        bool anchor = rnode_is(n, "anchor");
        if (anchor || rnode_is(n, "particle")) {
            const Vec *id = rnode_attr(n, "id");
            if (!id) continue;
            s->bodies = mem_grow(s->bodies, &c->cap_bodies, s->nbodies + 1, sizeof *s->bodies);
            PsBody *b = &s->bodies[s->nbodies++];
            b->anchor = anchor;
            b->id = id;
            b->pos = lookup(c, id, false);
            if (!b->pos) b->pos = num_vec(n, "position");
            b->vel = lookup(c, id, true);
            if (!b->vel) b->vel = num_vec(n, "velocity");
            b->radius = num_attr(n, "radius", 0);
            if (!(b->radius > 0)) b->radius = 0;
            b->charge = num_attr(n, "charge", 0);
        } else if (rnode_is(n, "group")) {
            walk(c, n);
        }
    }
}

/* Links and barriers, after every body is known (ids may come later). */
static void walk_links(Collect *c, const Node *g)
{
    PsSystem *s = c->s;
    for (size_t i = 0; i < rnode_nchildren(g); i++) {
        const Node *n = rnode_child(g, i);
        if (rnode_is(n, "distance")) {
            s->links = mem_grow(s->links, &c->cap_links, s->nlinks + 1, sizeof *s->links);
            s->links[s->nlinks].from = position_of(c, rnode_attr(n, "from"));
            s->links[s->nlinks].to = position_of(c, rnode_attr(n, "to"));
            s->nlinks++;
        } else if (rnode_is(n, "barrier")) {
            s->barriers = mem_grow(s->barriers, &c->cap_barriers, s->nbarriers + 1, sizeof *s->barriers);
            s->barriers[s->nbarriers].pos = num_vec(n, "position");
            s->barriers[s->nbarriers].normal = num_vec(n, "normal");
            s->nbarriers++;
        } else if (rnode_is(n, "group")) {
            walk_links(c, n);
        }
    }
}

void ps_collect(const Node *root, const StateDict *sd, PsSystem **out, size_t *n)
{
    *out = NULL;
    *n = 0;
    size_t cap = 0;
    Vec *vsym = vec_num1(symbol_value("velocity", 8));
    for (size_t i = 0; root && i < rnode_nchildren(root); i++) {
        const Node *p = rnode_child(root, i);
        if (!rnode_is(p, "physics")) continue;
        const Vec *prefix = rnode_attr(p, "state");
        double dims = num_attr(p, "dimensions", 0);
        if (!prefix || !(dims >= 1) || dims > 1 << 20) continue;
        *out = mem_grow(*out, &cap, *n + 1, sizeof **out);
        PsSystem *s = &(*out)[(*n)++];
        memset(s, 0, sizeof *s);
        s->prefix = prefix;
        s->dims = (int)dims;
        Collect c = {.sd = sd, .s = s, .vsym = vsym};
        walk(&c, p);
        walk_links(&c, p);
    }
    vec_release(vsym);
}

void ps_free(PsSystem *systems, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        free(systems[i].bodies);
        free(systems[i].links);
        free(systems[i].barriers);
    }
    free(systems);
}

/* {=====================================================================
 * Frozen copies
 * ===================================================================== */

/* Bytes of a frozen copy of numeric vector [v] (0 for NULL), a multiple
 * of 16 so that every copy's data stays aligned as a Vec's is. */
static size_t frozen_size(const Vec *v)
{
    if (!v) return 0;
    size_t bytes = sizeof(Vec) + (size_t)v->len * sizeof(double);
    return (bytes + 15) & ~(size_t)15;
}

/* Copy numeric vector [v] (or NULL) to the block at *[at], advancing it;
 * the copy, or NULL. */
static const Vec *frozen_copy(const Vec *v, unsigned char **at)
{
    if (!v) return NULL;
    Vec *c = (Vec *)(void *)*at;
    c->refs = 1;
    c->kind = VEC_NUM;
    c->stream = 0;
    c->hashed = 0;
    c->len = v->len;
    c->key = 0;
    memcpy(vec_nums(c), vec_cnums(v), (size_t)v->len * sizeof(double));
    *at += frozen_size(v);
    return c;
}

/* [n] elements of [size] bytes from [src], into the owned array *[dst]
 * (reallocated; NULL when [n] is 0). */
static void *frozen_array(void *dst, const void *src, size_t n, size_t size)
{
    if (!n) {
        free(dst);
        return NULL;
    }
    dst = mem_realloc(dst, n * size);
    memcpy(dst, src, n * size);
    return dst;
}

/* Bytes of the frozen copies of [s]'s vectors (the block ps_freeze
 * allocates for it). */
static size_t vector_bytes(const PsSystem *s)
{
    size_t bytes = 0;
    for (size_t k = 0; k < s->nbodies; k++)
        bytes += frozen_size(s->bodies[k].pos) + frozen_size(s->bodies[k].vel);
    for (size_t k = 0; k < s->nlinks; k++)
        bytes += frozen_size(s->links[k].from) + frozen_size(s->links[k].to);
    for (size_t k = 0; k < s->nbarriers; k++)
        bytes += frozen_size(s->barriers[k].pos) + frozen_size(s->barriers[k].normal);
    return bytes;
}

bool ps_freeze(PsFrozen *into, const PsSystem *systems, size_t n, const SymTab *symbols)
{
    /* the sizes first: the block is allocated once, so the copies stay put;
     * the whole copy is asked of the memory budget before anything changes */
    size_t bytes = 0, arrays = n * sizeof *systems;
    for (size_t i = 0; i < n; i++) {
        const PsSystem *s = &systems[i];
        bytes += vector_bytes(s);
        arrays += s->nbodies * sizeof *s->bodies + s->nlinks * sizeof *s->links +
                  s->nbarriers * sizeof *s->barriers;
    }
    if (!mem_fits(bytes + arrays)) return false;
    Buf titles = BUF_INIT;
    size_t *title_at = n ? mem_alloc(n * sizeof *title_at) : NULL;
    for (size_t i = 0; i < n; i++) {
        const PsSystem *s = &systems[i];
        title_at[i] = titles.len;
        if (s->title) buf_puts(&titles, s->title);
        else fmt_str(&titles, s->prefix, symbols);
        buf_putc(&titles, '\0');
    }
    /* the previous copy's systems: their arrays are reused */
    for (size_t i = n; i < into->n; i++) {
        free(into->sys[i].bodies);
        free(into->sys[i].links);
        free(into->sys[i].barriers);
    }
    if (n > into->n) {
        into->sys = mem_realloc(into->sys, n * sizeof *into->sys);
        memset(into->sys + into->n, 0, (n - into->n) * sizeof *into->sys);
    }
    into->n = n;
    if (bytes > into->cap_block) {
        free(into->block);
        into->block = mem_alloc(bytes);
        into->cap_block = bytes;
    }
    if (titles.len > into->cap_titles) {
        free(into->titles);
        into->titles = mem_alloc(titles.len);
        into->cap_titles = titles.len;
    }
    if (titles.len) memcpy(into->titles, titles.data, titles.len);
    buf_free(&titles);
    unsigned char *at = into->block;
    for (size_t i = 0; i < n; i++) {
        const PsSystem *s = &systems[i];
        PsSystem *d = &into->sys[i];
        d->prefix = NULL;
        d->title = into->titles + title_at[i];
        d->dims = s->dims;
        d->nbodies = s->nbodies;
        d->bodies = frozen_array(d->bodies, s->bodies, s->nbodies, sizeof *s->bodies);
        for (size_t k = 0; k < s->nbodies; k++) {
            d->bodies[k].id = NULL;
            d->bodies[k].pos = frozen_copy(s->bodies[k].pos, &at);
            d->bodies[k].vel = frozen_copy(s->bodies[k].vel, &at);
        }
        d->nlinks = s->nlinks;
        d->links = frozen_array(d->links, s->links, s->nlinks, sizeof *s->links);
        for (size_t k = 0; k < s->nlinks; k++) {
            d->links[k].from = frozen_copy(s->links[k].from, &at);
            d->links[k].to = frozen_copy(s->links[k].to, &at);
        }
        d->nbarriers = s->nbarriers;
        d->barriers = frozen_array(d->barriers, s->barriers, s->nbarriers, sizeof *s->barriers);
        for (size_t k = 0; k < s->nbarriers; k++) {
            d->barriers[k].pos = frozen_copy(s->barriers[k].pos, &at);
            d->barriers[k].normal = frozen_copy(s->barriers[k].normal, &at);
        }
    }
    free(title_at);
    return true;
}

void ps_frozen_free(PsFrozen *f)
{
    ps_free(f->sys, f->n);
    free(f->block);
    free(f->titles);
    *f = (PsFrozen){0};
}

/* }===================================================================== */

double ps_coord(const Vec *v, int k)
{
    if (!vec_is_num(v) || k < 0) return 0;
    if (vec_len(v) == 1) return vec_cnums(v)[0];   /* one number for every axis */
    return (uint32_t)k < vec_len(v) ? vec_cnums(v)[k] : 0;
}
