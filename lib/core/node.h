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
    uint16_t inline_attrs; /* Attr slots allocated right after the node, in
                              its own block (node_new_room); [attrs] points
                              there until it outgrows them */
    uint16_t inline_kids;  /* child slots allocated after those, in the same
                              block; [children] points there until it
                              outgrows them */
    Str *kind;            /* node kind without the '!' */
    Str **tags;           /* sorted by bytes, unique */
    Attr *attrs;          /* in first-binding order */
    Node **children;      /* in order */
};

/* A new node of [kind] (retained) with no tags, attributes or children. */
Node *node_new(Str *kind);
/* The same with room for [cap] attributes allocated in the node's own block
 * (one block to build and to free instead of two; node_add_new_attr fills
 * them). */
Node *node_new_sized(Str *kind, uint32_t cap);
/* The same with room for [attrs] attributes and [kids] children in the
 * node's own block (a copy of a literal node about to get its children:
 * one block instead of two). A room of more than NODE_INLINE_MAX is left
 * out of the block (the array is allocated as it grows). */
Node *node_new_room(Str *kind, uint32_t attrs, uint32_t kids);
#define NODE_INLINE_MAX 65535u
/* The Attr slots allocated with [n] (node_new_room). */
static inline Attr *node_inline_attrs(Node *n) { return (Attr *)(void *)(n + 1); }
/* The child slots allocated with [n], after its Attr slots. */
static inline Node **node_inline_kids(Node *n) { return (Node **)(void *)(node_inline_attrs(n) + n->inline_attrs); }
/* The bytes of [n]'s own block: the node and its inline slots. */
static inline size_t node_block_bytes(const Node *n)
{
    return sizeof *n + (size_t)n->inline_attrs * sizeof(Attr) + (size_t)n->inline_kids * sizeof(Node *);
}
static inline Node *node_retain(Node *n) { if (n) n->refs++; return n; }
void node_release(Node *n);
/* A copy of [n] and all below it that shares no memory with it (its
 * kind, tags, attribute names and values, children: vec_copy_deep). */
Node *node_copy_deep(const Node *n);
/* Consumes [n]; returns a node with refs == 1 and the same content (n itself
 * when it was unshared, else a shallow copy). */
Node *node_mut(Node *n);
/* node_mut, with room in the node for [extra] more attributes without a
 * block of their own when it copies (an attribute setter about to add
 * that many). */
Node *node_mut_room(Node *n, uint32_t extra);
/* node_mut, with room in the copy's own block for its children and
 * [kids] more (an append about to add that many): their array is moved
 * out only when they outgrow it. */
Node *node_mut_children(Node *n, uint32_t kids);
/* Set attribute [name] of unshared [n] to [value] (consumes [value]); an
 * empty [value] removes the attribute. */
void node_set_attr(Node *n, Str *name, Vec *value);
/* Set attribute [name] of unshared [n], which has no attribute of that
 * name yet, to [value] (consumes [value]): node_set_attr without the search
 * for the name. An empty [value] is dropped, as node_set_attr does. */
static inline void node_add_new_attr(Node *n, Str *name, Vec *value)
{
    if (n->nattrs < n->cap_attrs && value && value->len) {
        n->attrs[n->nattrs].name = str_retain(name);
        n->attrs[n->nattrs].value = value;
        n->nattrs++;
    } else {
        node_set_attr(n, name, value);
    }
}
/* Add tag [tag] to unshared [n] (no-op when present). */
void node_add_tag(Node *n, Str *tag);
/* Append [child] (retained) to unshared [n]. */
void node_append(Node *n, Node *child);
/* Append [child] to unshared [n], consuming the caller's reference. */
void node_append_take(Node *n, Node *child);
/* Make room for [need] children in unshared [n], so that appending up to
 * that many reallocates nothing. */
void node_reserve_children(Node *n, uint32_t need);
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
/* Whether a function value lies anywhere in [n]: an element of one of its
 * attributes (or of the attributes of a node held there), or in a child,
 * at any depth. */
bool node_has_function(const Node *n);
/* Structural hash consistent with node_equal. */
uint64_t node_hash(const Node *n);

#endif
