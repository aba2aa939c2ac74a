/* graph_internal.h: the render graph's passes, shared by graph.c (the
 * tree of passes, references, the frame) and the pass kinds' files:
 * pass_program.c (shader programs: `!window`, `!offscreen`, `!record`,
 * `!shader` and the built-in filters), pass_canvas.c, pass_canvas3d.c,
 * pass_image.c and pass_video.c. Internal to lib/render/gl; graph.h is
 * the interface.
 *
 * A pass kind is a table row (PassKind): the node kind it draws, whether
 * its children are passes too, how it matches a node to the pass of the
 * last frame, how it draws and what it frees. graph.c walks the node tree
 * as Flitter's WindowNode.update does (render/window/__init__.py): the
 * pass registers its id, takes its size (its own, else its parent's),
 * updates its children, draws, then lets its children release their
 * framebuffers (unless they must keep them: an id, or a `last` sampler).
 */
#ifndef FL_RENDER_GRAPH_INTERNAL_H
#define FL_RENDER_GRAPH_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include <epoxy/gl.h>

#include "buf.h"
#include "canvas.h"
#include "gl_context.h"
#include "gl_target.h"
#include "graph.h"
#include "node.h"
#include "value.h"

typedef struct Pass Pass;
typedef struct PassKind PassKind;
typedef struct Programs Programs;
typedef struct Recorder Recorder;
typedef struct Canvas3D Canvas3D;
typedef struct MediaCache MediaCache;

/* What a pass inherits from its ancestors while the tree is walked. */
typedef struct PassCtx {
    int w, h;                /* the parent's size: the default size */
    int colorbits;           /* the window's colorbits= (8, 16 or 32; 16 by default) */
    bool write;              /* !record nodes write their files */
} PassCtx;

struct PassKind {
    const char *kind;                    /* node kind, without '!' */
    const void *data;                    /* the kind's own description (a filter's) */
    size_t size;                         /* bytes of the pass (a Pass first) */
    bool leaf;                           /* its children are not passes */
    bool refers;                         /* its id= names another pass (!reference): not registered */
    /* before its children are drawn: what they inherit (may be NULL) */
    void (*enter)(Graph *g, Pass *p, const Node *n, PassCtx *cx);
    /* whether [p] can carry on as the pass of node [n] (same kind, tags
     * and id already checked); NULL: yes */
    bool (*similar)(const Pass *p, const Node *n, Graph *g);
    /* draw [p] for node [n], its children drawn already */
    void (*render)(Graph *g, Pass *p, const Node *n, const PassCtx *cx);
    /* the output texture, or 0; NULL: the target's */
    GLuint (*texture)(Graph *g, Pass *p, int *w, int *h);
    /* free what the kind holds besides the target (may be NULL) */
    void (*release)(Graph *g, Pass *p);
    /* after the parent drew: NULL for the default (give the target back
     * to the pool unless [retain]) */
    void (*finished)(Graph *g, Pass *p);
};

struct Pass {
    const PassKind *kind;
    Buf id;                  /* its id= as text ("" when it has none) */
    bool has_id;
    uint64_t tags;           /* a hash of its node's tags */
    int w, h;                /* its framebuffer's size: its size= at the frame's scale */
    int lw, lh;              /* its size= (Flitter's pixels, before the scale) */
    bool hidden;             /* hidden=true: not one of its parent's textures */
    bool retain;             /* keep [target] after the parent drew */
    GlTarget *target;        /* its output, or NULL */
    Pass **children;
    size_t nchildren, cap;
    bool seen;               /* matched this frame */
    bool busy;               /* being drawn (its descendants are) */
};

/* A picture handed to a canvas this frame (graph_canvas_images), kept
 * for the frame's other canvases. */
typedef struct CanvasPic {
    char *key;               /* the id, or the file's path */
    bool file, linear;
    long frame;
    void *surface;           /* a cairo_surface_t */
} CanvasPic;

/* One id's entry: the pass that registered it, and for a !canvas3d's
 * secondary camera which one (-1: the pass's own output). */
typedef struct Ref {
    char *id;
    Pass *pass;
    int camera;
} Ref;

struct Graph {
    GraphEnv env;
    SkipLog skips;
    RenderLog skiplog;       /* env.log with skipped-kind warnings always on */
    GlContext *gl;
    bool failed;             /* no context could be made: draw nothing again */
    bool show;               /* composite top-level windows (graph_show_windows) */
    bool composited;         /* this frame's windows were drawn with [show] */
    double scale;            /* graph_set_scale's scale of shown windows (1: none) */
    int max_samples;         /* and its cap on a !canvas3d's samples (0: none) */
    double draw_scale;       /* the scale of the frame being drawn (1 when a file is written) */
    int draw_samples;        /* its cap on samples (0: none) */
    TargetPool *pool;
    Programs *programs;      /* compiled programs by source (pass_program.c) */
    GLuint quad_vao, quad_vbo;     /* the screen-space quad of every program pass */
    GLuint zero_tex;         /* a 1x1 transparent texture for unbound samplers */
    GLuint nearest;          /* a sampler of nearest texels (copies, program_copy) */
    Pass **windows;          /* the top-level passes */
    size_t nwindows, capwindows;
    Ref *refs;
    size_t nrefs, caprefs;
    Recorder *rec;           /* the !record files open across frames */
    char *record_first;      /* graph_record_first's file, or NULL */
    long frame;              /* the frame number last drawn (-1: none) */
    double beat;             /* its beat */
    const GraphFrame *f;     /* the frame being drawn */
    Canvas3D *c3d;           /* the !canvas3d renderer (pass_canvas3d.c) */
    struct GeomModels *models;   /* its models: files, vectors, CSG, SDF (pass_canvas3d.c) */
    MediaCache *media;       /* decoded images and videos (pass_image.c, pass_video.c) */
    int write_failures;      /* files that could not be written this frame */
    char *reported[64];      /* files whose write error was logged */
    int nreported;
    char *noted[64];         /* one-off messages already logged */
    int nnoted;
    double expire_at;        /* when the pool is next trimmed */
    int ref_depth;           /* references being followed (a loop of them has no picture) */
    CanvasImages images;     /* what canvases draw !image and !pattern from */
    CanvasPic *pics;         /* the pictures canvases took this frame */
    size_t npics, cappics;
};

/* The pass kinds' table rows (each kind's file). */
extern const PassKind pass_window, pass_offscreen, pass_record, pass_shader, pass_canvas, pass_canvas3d,
    pass_image, pass_video, pass_reference;
/* The built-in filters: pass_shader with their own program and defaults
 * (pass_program.c). */
extern const PassKind pass_filters[];
extern const size_t pass_nfilters;

/* {===== graph.c, for the kinds */

/* Log [fmt] once per graph (the same text is not logged again). */
void graph_note(Graph *g, int kind, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* A file's write failure: counted, logged the first time for the file. */
void graph_write_failed(Graph *g, const char *path, const char *line);
/* The output texture of [p] and its size (0 when it has none). */
GLuint graph_pass_texture(Graph *g, Pass *p, int *w, int *h);
/* The texture of the pass registered as [id] (its text), or 0. */
GLuint graph_ref_texture(Graph *g, const char *id, int *w, int *h);
/* Register [id] as [p]'s (camera: a !canvas3d's camera index, or -1). */
void graph_register(Graph *g, const char *id, Pass *p, int camera);
/* [name]'s path relative to the script's folder (absolute names as they
 * are) into [out]. */
void graph_path(Graph *g, const char *name, Buf *out);
/* A target of [w] x [h] for [p] from the pool, or NULL (logged once). */
GlTarget *graph_target(Graph *g, int w, int h, int colorbits, bool srgb, bool depth, int samples);
/* [n] pixels of Flitter's at the frame's scale: round(n * scale), at
 * least 1 (n itself at scale 1). */
int graph_scaled(const Graph *g, int n);
/* Draw the screen-space quad (the program and its uniforms already set). */
void graph_draw_quad(Graph *g);
/* Give [env] the graph's pictures for !image and !pattern: the output of
 * any pass by id (read back, converted to the canvas's light) and picture
 * files (the media cache). */
void graph_canvas_images(Graph *g, CanvasEnv *env);

/* }===== */

/* {===== the kinds' files, for graph.c */

/* The graph's compiled programs (pass_program.c), made with its objects. */
Programs *programs_new(void);
void programs_free(Programs *p);
/* The texture of secondary camera [camera] of !canvas3d pass [p], or 0
 * (pass_canvas3d.c). */
GLuint pass_canvas3d_camera(Graph *g, Pass *p, int camera, int *w, int *h);
/* Free the graph's 3D renderer (pass_canvas3d.c). */
void pass_canvas3d_free(Graph *g);
/* The graph's media cache, made the first time (pass_image.c). */
MediaCache *graph_media(Graph *g);
/* Free the graph's decoded images and videos (media.h). */
void media_cache_free(MediaCache *m);
/* Write target [t] (an 8-bit sRGB framebuffer) as record [s] asks
 * (pass_record.c): read back once, handed to the recorder.
 *   errors: -1 with the message in [err]; else 0. */
struct RecordSpec;
int record_target(Graph *g, GlTarget *t, const struct RecordSpec *s, Buf *err);

/* }===== */

#endif
