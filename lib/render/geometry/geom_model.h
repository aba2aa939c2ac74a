/* geom_model.h: `!canvas3d`'s models beyond the primitives' own path:
 * model files and vectors, constructive solid geometry and signed distance
 * fields (Flitter docs/canvas3d.md, sections Models, Custom Models,
 * Constructive Solid Geometry, Signed Distance Fields), each a node of a
 * model tree made from the node tree and kept in a cache.
 *
 * A model is hash-consed: the same kind with the same attributes and the
 * same child models is the same GeomModel object, frame after frame, so its
 * mesh is built once and found again while the scene does not change that
 * part (an animated scene rebuilds only the models whose attributes
 * changed, as Flitter's model cache does). A model not used for
 * `max_age` seconds (`--modelcache`, Flitter's default 300) is dropped,
 * unless a model still kept uses it.
 *
 * Kinds (Flitter render/window/canvas3d.pyx, get_model, for behaviour):
 * `!box`, `!sphere`, `!cylinder`, `!cone`; `!model filename=` (a file,
 * read again when it changes on disk) or `vertices=` `faces=` `uv=`;
 * `!union`, `!intersect`, `!difference` (nested ones of the same operation
 * and blend are one operation; a repeated child counts once); `!trim` and
 * `!slice` (`origin`, `normal`); `!sdf` (`minimum`/`min`, `maximum`/`max`,
 * `resolution`, and `function=` or its children); `!mix` (`weights`, only
 * inside an `!sdf`); `!transform` inside another model. Below the top,
 * a model node's `position`, `rotation`, `size` (or `start`, `end`,
 * `radius`) transform it. Blends (`smooth`, `fillet`, `chamfer`) act on
 * signed distances, so inside an `!sdf`; a mesh boolean ignores them, as
 * Flitter's does. */
#ifndef FL_RENDER_GEOM_MODEL_H
#define FL_RENDER_GEOM_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "geom_mesh.h"
#include "mem.h"
#include "node.h"
#include "value.h"

/* What the models need from the renderer, fixed at geom_models_new. */
typedef struct GeomEnv {
    const SymTab *symbols;       /* names symbol attributes such as :repeat (may be NULL) */
    MemBudget *budget;           /* every kept mesh charged to it (may be NULL) */
    volatile int *interrupt;     /* polled while meshes are built (may be NULL) */
    /* one error line (the models report each failure once per model) */
    void (*error)(void *error_ctx, const char *line);
    void *error_ctx;
    /* distances (negative inside) of Flitter function [fn] at [n] points
     * (xyz: 3n doubles) into out (a result that is not one number: NaN);
     * false to stop (interrupted). NULL: `function=` gives no model. */
    bool (*distance)(void *ctx, const Vec *fn, const double *xyz, size_t n, double *out);
    /* a key that is the same for two function values exactly when they
     * compute the same (their definition and captured values) */
    uint64_t (*function_key)(void *ctx, const Vec *fn);
    void *ctx;                   /* distance's and function_key's */
} GeomEnv;

typedef struct GeomModels GeomModels;
typedef struct GeomModel GeomModel;

GeomModels *geom_models_new(const GeomEnv *env);
/* Free the cache and every model (NULL is a no-op). */
void geom_models_free(GeomModels *c);

/* Begin a frame: relative file names are taken from [folder] (NULL or "":
 * the working directory); models unused for more than [max_age] seconds of
 * [now] (a monotonic clock) are dropped first. */
void geom_models_frame(GeomModels *c, const char *folder, double now, double max_age);

/* Whether [n] is one of the kinds the models make (primitives included). */
bool geom_is_model_kind(const Node *n);

/* The model of node [n] ([top]: the node drawn, whose own position,
 * rotation and size are its instance's, not the model's), or NULL when [n]
 * gives none (not a model kind, no children, an empty difference). The
 * pointer stays valid until geom_models_frame drops it. */
GeomModel *geom_model_of(GeomModels *c, const Node *n, bool top);

/* [m]'s mesh, built the first time it is asked for (model files are
 * checked for changes once per frame), or NULL when it has none: the
 * reason (`FILE: cannot load model: ...`, `!union: mesh 2 of 3 is not a
 * volume`, `!sdf: resolution 0.001 gives N points, more than the budget
 * of M`) logged once per model. Building polls the interrupt. */
const GeomMesh *geom_model_mesh(GeomModels *c, GeomModel *m);

/* A number that names [m] for the life of the cache (never reused), for
 * the renderer's own caches of what it made from the mesh. */
uint64_t geom_model_serial(const GeomModel *m);
/* The snap_edges= [m] is drawn with when the node gives none
 * (geom_shading.h): 0.05 turn for the solids a boolean or trim makes (as
 * Flitter snaps a manifold's edges by default), 0.5 (the mesh's own
 * normals) for the rest; an SDF's mesh carries its field's gradient as
 * its normals, smoother than Flitter's snapped faces of the same
 * surface, so it too keeps its own. */
double geom_model_snap(const GeomModel *m);
/* Models kept, and the bytes of their meshes (charged to the budget). */
size_t geom_models_count(const GeomModels *c);
size_t geom_models_bytes(const GeomModels *c);

#endif
