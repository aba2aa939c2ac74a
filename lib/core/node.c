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

Node *node_new(Str *kind) { return node_new_sized(kind, 0); }

Node *node_new_sized(Str *kind, uint32_t cap)
{
    /* node_new_room without children slots: the nodes a frame builds by
     * the thousand come here, so its two checks and stores are spared */
    if (cap > NODE_INLINE_MAX) cap = 0;
    Node *n = pool_alloc(sizeof *n + (size_t)cap * sizeof(Attr));
    memset(n, 0, sizeof *n);
    n->refs = 1;
    n->kind = str_retain(kind);
    n->inline_attrs = (uint16_t)cap;
    if (cap) {
        n->attrs = node_inline_attrs(n);
        n->cap_attrs = cap;
    }
    return n;
}

Node *node_new_room(Str *kind, uint32_t attrs, uint32_t kids)
{
    if (attrs > NODE_INLINE_MAX) attrs = 0;
    if (kids > NODE_INLINE_MAX) kids = 0;
    Node *n = pool_alloc(sizeof *n + (size_t)attrs * sizeof(Attr) + (size_t)kids * sizeof(Node *));
    memset(n, 0, sizeof *n);
    n->refs = 1;
    n->kind = str_retain(kind);
    n->inline_attrs = (uint16_t)attrs;
    n->inline_kids = (uint16_t)kids;
    if (attrs) {
        n->attrs = node_inline_attrs(n);
        n->cap_attrs = attrs;
    }
    if (kids) {
        n->children = node_inline_kids(n);
        n->cap_children = kids;
    }
    return n;
}

/* Room for [need] attributes in unshared [n]: pool_grow() for the attribute
 * array, which may be the node's inline slots (not a block of its own). */
static void attrs_reserve(Node *n, uint32_t need)
{
    if (need <= n->cap_attrs) return;
    if (n->attrs && n->attrs == node_inline_attrs(n)) {
        uint32_t cap = n->cap_attrs;
        Attr *q = pool_grow(NULL, &cap, need, sizeof(Attr));
        memcpy(q, n->attrs, (size_t)n->nattrs * sizeof(Attr));
        n->attrs = q;
        n->cap_attrs = cap;
    } else {
        n->attrs = pool_grow(n->attrs, &n->cap_attrs, need, sizeof(Attr));
    }
}

/* Room for [need] children in unshared [n]: pool_grow() for the children
 * array, which may be the node's inline slots (not a block of its own). */
static void kids_reserve(Node *n, uint32_t need)
{
    if (need <= n->cap_children) return;
    if (n->children && n->children == node_inline_kids(n)) {
        uint32_t cap = n->cap_children;
        Node **q = pool_grow(NULL, &cap, need, sizeof(Node *));
        memcpy(q, n->children, (size_t)n->nchildren * sizeof(Node *));
        n->children = q;
        n->cap_children = cap;
    } else {
        n->children = pool_grow(n->children, &n->cap_children, need, sizeof(Node *));
    }
}

/* Free unshared [n] (its last reference is gone) and release what it
 * holds. */
static void node_free(Node *n)
{
    str_release(n->kind);
    for (uint32_t i = 0; i < n->ntags; i++) str_release(n->tags[i]);
    for (uint32_t i = 0; i < n->nattrs; i++) {
        str_release(n->attrs[i].name);
        vec_release(n->attrs[i].value);
    }
    /* A released tree is usually cold (built a frame ago, megabytes of
     * other memory touched since): walking it is a chase of dependent
     * cache misses, child -> its attributes -> their values. Software-
     * pipeline the chase over the children: while child i is freed, the
     * attribute values of child i+D3 are fetched (its attribute array
     * asked for D2-D3 children earlier, itself D1-D2 earlier still), so
     * that each level has arrived by the time the next one is read. A
     * child held elsewhere too (refs > 1: a static subtree shared with the
     * program, say) is only decremented, so its attributes are left
     * alone. */
    enum { D1 = 30, D2 = 18, D3 = 8 };
    Node **ch = n->children;
    uint32_t nc = n->nchildren;
    for (uint32_t i = 0; i < nc; i++) {
        if (i + D1 < nc) __builtin_prefetch(ch[i + D1], 1);
        if (i + D2 < nc && ch[i + D2]->refs == 1 && ch[i + D2]->nattrs) {
            const Node *c = ch[i + D2];
            __builtin_prefetch(c->attrs, 1);
            __builtin_prefetch((const char *)(c->attrs + c->nattrs) - 1, 1);
        }
        if (i + D3 < nc && ch[i + D3]->refs == 1) {
            const Node *c = ch[i + D3];
            for (uint32_t k = 0; k < c->nattrs; k++) __builtin_prefetch(c->attrs[k].value, 1);
        }
        node_release(ch[i]);
    }
    if (n->tags) pool_release(n->tags, (size_t)n->cap_tags * sizeof(Str *));
    if (n->attrs && n->attrs != node_inline_attrs(n))
        pool_release(n->attrs, (size_t)n->cap_attrs * sizeof(Attr));
    if (n->children && n->children != node_inline_kids(n))
        pool_release(n->children, (size_t)n->cap_children * sizeof(Node *));
    pool_release(n, node_block_bytes(n));
}

void node_release(Node *n)
{
    if (n && --n->refs == 0) node_free(n);
}

/* node_mut_room and node_mut_children: the copy of a shared [n] with room
 * in its block for its attributes and [extra] more, and for its children
 * and [kids] more (none: no children slots, node_new_sized). */
static Node *node_copy_room(Node *n, uint32_t extra, uint32_t kids)
{
    uint32_t nk = n->nchildren + kids;
    Node *c = nk ? node_new_room(n->kind, n->nattrs + extra, nk) : node_new_sized(n->kind, n->nattrs + extra);
    if (n->ntags) {
        c->tags = pool_grow(NULL, &c->cap_tags, n->ntags, sizeof(Str *));
        for (uint32_t i = 0; i < n->ntags; i++) c->tags[i] = str_retain(n->tags[i]);
        c->ntags = n->ntags;
    }
    if (n->nattrs) {
        for (uint32_t i = 0; i < n->nattrs; i++) {
            c->attrs[i].name = str_retain(n->attrs[i].name);
            c->attrs[i].value = vec_retain(n->attrs[i].value);
        }
        c->nattrs = n->nattrs;
    }
    if (n->nchildren || kids) {
        kids_reserve(c, n->nchildren + kids);
        for (uint32_t i = 0; i < n->nchildren; i++) c->children[i] = node_retain(n->children[i]);
        c->nchildren = n->nchildren;
    }
    node_release(n);
    return c;
}

Node *node_mut(Node *n) { return node_mut_room(n, 0); }

Node *node_mut_room(Node *n, uint32_t extra)
{
    return n->refs == 1 ? n : node_copy_room(n, extra, 0);
}

Node *node_mut_children(Node *n, uint32_t kids)
{
    return n->refs == 1 ? n : node_copy_room(n, 0, kids);
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
    attrs_reserve(n, n->nattrs + 1);
    n->attrs[n->nattrs].name = str_retain(name);
    n->attrs[n->nattrs].value = value;
    n->nattrs++;
}

Node *node_copy_deep(const Node *n)
{
    Str *kind = str_new(n->kind->bytes, n->kind->len);
    Node *c = node_new_room(kind, n->nattrs, n->nchildren);
    str_release(kind);
    for (uint32_t i = 0; i < n->ntags; i++) {
        Str *tag = str_new(n->tags[i]->bytes, n->tags[i]->len);
        node_add_tag(c, tag);
        str_release(tag);
    }
    for (uint32_t i = 0; i < n->nattrs; i++) {
        Str *name = str_new(n->attrs[i].name->bytes, n->attrs[i].name->len);
        node_add_new_attr(c, name, vec_copy_deep(n->attrs[i].value));
        str_release(name);
    }
    if (n->nchildren) node_reserve_children(c, n->nchildren);
    for (uint32_t i = 0; i < n->nchildren; i++) node_append_take(c, node_copy_deep(n->children[i]));
    return c;
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
    n->tags = pool_grow(n->tags, &n->cap_tags, n->ntags + 1, sizeof(Str *));
    memmove(&n->tags[lo + 1], &n->tags[lo], (n->ntags - lo) * sizeof(Str *));
    n->tags[lo] = str_retain(tag);
    n->ntags++;
}

void node_append(Node *n, Node *child) { node_append_take(n, node_retain(child)); }

void node_append_take(Node *n, Node *child)
{
    kids_reserve(n, n->nchildren + 1);
    n->children[n->nchildren++] = child;
}

void node_reserve_children(Node *n, uint32_t need) { kids_reserve(n, need); }

const Vec *node_attr_n(const Node *n, const char *name, size_t len)
{
    for (uint32_t i = 0; i < n->nattrs; i++) {
        const Str *s = n->attrs[i].name;
        if (s->len == len && s->bytes[0] == name[0] && memcmp(s->bytes, name, len) == 0)
            return n->attrs[i].value;
    }
    return NULL;
}

/* Whether [v] holds a function, in itself or in a node it holds. */
static bool vec_has_function(const Vec *v)
{
    if (!vec_is_obj(v)) return false;
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < v->len; i++) {
        if (e[i].kind == EL_FUNC) return true;
        if (e[i].kind == EL_NODE && node_has_function(e[i].node)) return true;
    }
    return false;
}

bool node_has_function(const Node *n)
{
    for (uint32_t i = 0; i < n->nattrs; i++)
        if (vec_has_function(n->attrs[i].value)) return true;
    for (uint32_t i = 0; i < n->nchildren; i++)
        if (node_has_function(n->children[i])) return true;
    return false;
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
