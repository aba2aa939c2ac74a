/* node.h: Flitter node values (LANGUAGE.md §3.12, §4.10).
 *
 * A node has a kind, a set of tags (kept sorted by bytes, no duplicates), an
 * ordered attribute map (name -> non-empty vector; re-binding keeps the
 * original position) and an ordered list of children.
 *
 * Nodes are values and therefore immutable once shared. The mutating
 * functions below require a node with refs == 1; obtain one with node_mut(),
 * which copies a shared node (copy-on-write). The ownership rule of value.h
 * applies.
 */
#ifndef FL_NODE_H
#define FL_NODE_H

#include <string.h>

#include "value.h"

typedef struct Attr {
    Str *name;     /* attribute name */
    Vec *value;    /* non-empty value (one reference) */
} Attr;

struct Node {
    uint32_t refs;        /* reference count */
    uint32_t ntags;       /* number of tags */
    uint32_t nattrs;      /* number of attributes */
    uint32_t nchildren;   /* number of children */
    uint32_t cap_tags, cap_attrs, cap_children; /* allocated capacities */
    Str *kind;            /* node kind without the '!' */
    Str **tags;           /* sorted by bytes, unique */
    Attr *attrs;          /* in first-binding order */
    Node **children;      /* in order */
};

/* A new node of [kind] (retained) with no tags, attributes or children. */
Node *node_new(Str *kind);
static inline Node *node_retain(Node *n) { if (n) n->refs++; return n; }
void node_release(Node *n);
/* Consumes [n]; returns a node with refs == 1 and the same content (n itself
 * when it was unshared, else a shallow copy). */
Node *node_mut(Node *n);
/* Set attribute [name] of unshared [n] to [value] (consumes [value]); an
 * empty [value] removes the attribute. */
void node_set_attr(Node *n, Str *name, Vec *value);
/* Give unshared [n], which has no attributes yet, the attributes
 * names[i] = values[i] for i < [count] in that order, as node_set_attr
 * would one by one; the names must be pairwise different. Consumes the
 * values (empty ones are dropped). */
void node_init_attrs(Node *n, uint32_t count, Str *const *names, Vec **values);
/* Add tag [tag] to unshared [n] (no-op when present). */
void node_add_tag(Node *n, Str *tag);
/* Append [child] (retained) to unshared [n]. */
void node_append(Node *n, Node *child);
/* The value of attribute [name] ([len] bytes; borrowed), or NULL when
 * absent. */
const Vec *node_attr_n(const Node *n, const char *name, size_t len);
/* The same for the NUL-terminated [name] (its length folds away for a
 * string literal). */
static inline const Vec *node_attr(const Node *n, const char *name)
{
    return node_attr_n(n, name, strlen(name));
}
/* True when [n] has kind [kind]. */
static inline bool node_is(const Node *n, const char *kind)
{
    size_t len = strlen(kind);
    return n->kind->len == len && memcmp(n->kind->bytes, kind, len) == 0;
}
/* Structural equality (§3.12): kind, tag set, attribute map regardless of
 * order, children in order. */
bool node_equal(const Node *a, const Node *b);
/* Structural hash consistent with node_equal. */
uint64_t node_hash(const Node *n);

#endif
