/* node.c: node values (LANGUAGE.md §3.12).
 *
 * A node owns growable arrays of tags (sorted by bytes, unique), attributes
 * (first-binding order; each value non-empty) and children. Nodes are
 * immutable once shared: node_mut() gives an unshared node, copying the
 * arrays (and retaining their contents) when the node has other owners, so
 * that evaluating `!a x=1` on a node held by a name never changes the name.
 */
#include "node.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pool.h"

/* [p] (of *cap elements of [size] bytes, pooled) grown to hold [need]. */
static void *grow(void *p, uint32_t *cap, uint32_t need, size_t size)
{
    if (need <= *cap) return p;
    uint32_t c = *cap ? *cap * 2 : 4;
    while (c < need) c *= 2;
    void *q = pool_alloc((size_t)c * size);
    if (p) {
        memcpy(q, p, (size_t)*cap * size);
        pool_release(p, (size_t)*cap * size);
    }
    *cap = c;
    return q;
}

Node *node_new(Str *kind)
{
    Node *n = pool_calloc(sizeof *n);
    n->refs = 1;
    n->kind = str_retain(kind);
    return n;
}

void node_release(Node *n)
{
    if (!n || --n->refs) return;
    str_release(n->kind);
    for (uint32_t i = 0; i < n->ntags; i++) str_release(n->tags[i]);
    /* a released tree is usually cold (built a frame ago): ask for the
     * memory a few steps ahead of the loops that touch it */
    for (uint32_t i = 0; i < n->nattrs; i++) __builtin_prefetch(n->attrs[i].value, 1);
    for (uint32_t i = 0; i < n->nattrs; i++) {
        str_release(n->attrs[i].name);
        vec_release(n->attrs[i].value);
    }
    for (uint32_t i = 0; i < n->nchildren; i++) {
        if (i + 8 < n->nchildren) __builtin_prefetch(n->children[i + 8], 1);
        if (i + 4 < n->nchildren) __builtin_prefetch(n->children[i + 4]->attrs, 0);
        node_release(n->children[i]);
    }
    if (n->tags) pool_release(n->tags, (size_t)n->cap_tags * sizeof(Str *));
    if (n->attrs) pool_release(n->attrs, (size_t)n->cap_attrs * sizeof(Attr));
    if (n->children) pool_release(n->children, (size_t)n->cap_children * sizeof(Node *));
    pool_release(n, sizeof *n);
}

Node *node_mut(Node *n)
{
    if (n->refs == 1) return n;
    Node *c = node_new(n->kind);
    if (n->ntags) {
        c->tags = grow(NULL, &c->cap_tags, n->ntags, sizeof(Str *));
        for (uint32_t i = 0; i < n->ntags; i++) c->tags[i] = str_retain(n->tags[i]);
        c->ntags = n->ntags;
    }
    if (n->nattrs) {
        c->attrs = grow(NULL, &c->cap_attrs, n->nattrs, sizeof(Attr));
        for (uint32_t i = 0; i < n->nattrs; i++) {
            c->attrs[i].name = str_retain(n->attrs[i].name);
            c->attrs[i].value = vec_retain(n->attrs[i].value);
        }
        c->nattrs = n->nattrs;
    }
    if (n->nchildren) {
        c->children = grow(NULL, &c->cap_children, n->nchildren, sizeof(Node *));
        for (uint32_t i = 0; i < n->nchildren; i++) c->children[i] = node_retain(n->children[i]);
        c->nchildren = n->nchildren;
    }
    node_release(n);
    return c;
}

void node_set_attr(Node *n, Str *name, Vec *value)
{
    for (uint32_t i = 0; i < n->nattrs; i++) {
        if (!str_eq(n->attrs[i].name, name)) continue;
        vec_release(n->attrs[i].value);
        if (vec_len(value) == 0) {
            vec_release(value);
            str_release(n->attrs[i].name);
            memmove(&n->attrs[i], &n->attrs[i + 1], (n->nattrs - i - 1) * sizeof(Attr));
            n->nattrs--;
        } else {
            n->attrs[i].value = value;
        }
        return;
    }
    if (vec_len(value) == 0) {
        vec_release(value);
        return;
    }
    n->attrs = grow(n->attrs, &n->cap_attrs, n->nattrs + 1, sizeof(Attr));
    n->attrs[n->nattrs].name = str_retain(name);
    n->attrs[n->nattrs].value = value;
    n->nattrs++;
}

void node_init_attrs(Node *n, uint32_t count, Str *const *names, Vec **values)
{
    n->attrs = grow(n->attrs, &n->cap_attrs, count, sizeof(Attr));
    uint32_t k = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (vec_len(values[i]) == 0) {
            vec_release(values[i]);
            continue;
        }
        n->attrs[k].name = str_retain(names[i]);
        n->attrs[k].value = values[i];
        k++;
    }
    n->nattrs = k;
}

void node_add_tag(Node *n, Str *tag)
{
    uint32_t lo = 0, hi = n->ntags;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        int c = str_cmp(n->tags[mid], tag);
        if (c == 0) return;
        if (c < 0) lo = mid + 1;
        else hi = mid;
    }
    n->tags = grow(n->tags, &n->cap_tags, n->ntags + 1, sizeof(Str *));
    memmove(&n->tags[lo + 1], &n->tags[lo], (n->ntags - lo) * sizeof(Str *));
    n->tags[lo] = str_retain(tag);
    n->ntags++;
}

void node_append(Node *n, Node *child)
{
    n->children = grow(n->children, &n->cap_children, n->nchildren + 1, sizeof(Node *));
    n->children[n->nchildren++] = node_retain(child);
}

const Vec *node_attr_n(const Node *n, const char *name, size_t len)
{
    for (uint32_t i = 0; i < n->nattrs; i++) {
        const Str *s = n->attrs[i].name;
        if (s->len == len && s->bytes[0] == name[0] && memcmp(s->bytes, name, len) == 0)
            return n->attrs[i].value;
    }
    return NULL;
}

bool node_equal(const Node *a, const Node *b)
{
    if (a == b) return true;
    if (!str_eq(a->kind, b->kind) || a->ntags != b->ntags || a->nattrs != b->nattrs ||
        a->nchildren != b->nchildren)
        return false;
    for (uint32_t i = 0; i < a->ntags; i++)
        if (!str_eq(a->tags[i], b->tags[i])) return false;
    for (uint32_t i = 0; i < a->nattrs; i++) {
        bool found = false;
        for (uint32_t j = 0; j < b->nattrs && !found; j++) {
            if (!str_eq(a->attrs[i].name, b->attrs[j].name)) continue;
            if (!vec_equal(a->attrs[i].value, b->attrs[j].value)) return false;
            found = true;
        }
        if (!found) return false;
    }
    for (uint32_t i = 0; i < a->nchildren; i++)
        if (!node_equal(a->children[i], b->children[i])) return false;
    return true;
}

uint64_t node_hash(const Node *n)
{
    uint64_t h = hash_update(HASH_START, fnv1a_utf8(n->kind->bytes, n->kind->len));
    for (uint32_t i = 0; i < n->ntags; i++)
        h = hash_update(h, fnv1a_utf8(n->tags[i]->bytes, n->tags[i]->len));
    /* attributes are unordered for equality: combine their hashes commutatively */
    uint64_t attrs = 0;
    for (uint32_t i = 0; i < n->nattrs; i++) {
        const Str *s = n->attrs[i].name;
        attrs += hash_update(fnv1a_utf8(s->bytes, s->len), vec_hash(n->attrs[i].value, false));
    }
    h = hash_update(h, attrs);
    for (uint32_t i = 0; i < n->nchildren; i++) h = hash_update(h, node_hash(n->children[i]));
    return h;
}
