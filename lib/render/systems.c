/* systems.c: physics systems read from the node tree and state (systems.h). */
#include "systems.h"

#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "rnode.h"

typedef struct Collect {
    const StateDict *sd;
    PsSystem *s;
    size_t cap_bodies, cap_links, cap_barriers;
    Vec *vsym;            /* :velocity */
} Collect;

static void *grow(void *p, size_t *cap, size_t n, size_t size)
{
    if (n < *cap) return p;
    *cap = *cap ? 2 * *cap : 16;
    p = realloc(p, *cap * size);
    if (!p) mem_oom();
    return p;
}

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
            s->bodies = grow(s->bodies, &c->cap_bodies, s->nbodies, sizeof *s->bodies);
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
            s->links = grow(s->links, &c->cap_links, s->nlinks, sizeof *s->links);
            s->links[s->nlinks].from = position_of(c, rnode_attr(n, "from"));
            s->links[s->nlinks].to = position_of(c, rnode_attr(n, "to"));
            s->nlinks++;
        } else if (rnode_is(n, "barrier")) {
            s->barriers = grow(s->barriers, &c->cap_barriers, s->nbarriers, sizeof *s->barriers);
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
        *out = grow(*out, &cap, *n, sizeof **out);
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

double ps_coord(const Vec *v, int k)
{
    if (!vec_is_num(v) || k < 0) return 0;
    if (vec_len(v) == 1) return vec_cnums(v)[0];   /* one number for every axis */
    return (uint32_t)k < vec_len(v) ? vec_cnums(v)[k] : 0;
}
