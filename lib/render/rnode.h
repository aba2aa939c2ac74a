/* rnode.h: the renderer's read-only view of a node: kind, ordered
 * attributes and children. The only place in lib/render that knows how
 * node.h lays a node out, so a change of representation is mended here. */
#ifndef FL_RNODE_H
#define FL_RNODE_H

#include <string.h>

#include "node.h"

/* The kind of [n] without '!' (NUL-terminated, borrowed). */
static inline const char *rnode_kind(const Node *n) { return n->kind->bytes; }
static inline bool rnode_is(const Node *n, const char *kind) { return node_is(n, kind); }
/* Children, in order (borrowed). */
static inline size_t rnode_nchildren(const Node *n) { return n->nchildren; }
static inline const Node *rnode_child(const Node *n, size_t i) { return n->children[i]; }
/* Attributes in first-binding order: name (borrowed C string) and value. */
static inline size_t rnode_nattrs(const Node *n) { return n->nattrs; }
static inline const char *rnode_attr_name(const Node *n, size_t i) { return n->attrs[i].name->bytes; }
static inline const Vec *rnode_attr_value(const Node *n, size_t i) { return n->attrs[i].value; }
/* The value of attribute [name] (borrowed) or NULL. */
static inline const Vec *rnode_attr(const Node *n, const char *name) { return node_attr(n, name); }

/* [count] numbers of attribute [name] of [n] into [out] (a single number
 * is repeated, as Flitter's Vector.match); false when absent or of
 * another length. */
static inline bool rnode_nums(const Node *n, const char *name, int count, double *out)
{
    const Vec *v = rnode_attr(n, name);
    if (!vec_is_num(v)) return false;
    uint32_t len = vec_len(v);
    if (len != (uint32_t)count && len != 1) return false;
    const double *x = vec_cnums(v);
    for (int i = 0; i < count; i++) out[i] = x[len == 1 ? 0 : i];
    return true;
}

#endif
