/* pass_program.h: the shader-program passes (Flitter docs/windows.md,
 * "program nodes", and docs/shaders.md): `!window`, `!offscreen`,
 * `!record`, `!shader`, `!video` and the built-in filters all draw a
 * screen-space quad through a program made from templates
 * (glsl_template.h), one or more passes a frame, into framebuffers of
 * their size. This is what they share: the programs compiled by source,
 * the uniforms set from attributes and defaults, the samplers, and the
 * multi-pass loop of Flitter's ProgramNode.render. */
#ifndef FL_RENDER_PASS_PROGRAM_H
#define FL_RENDER_PASS_PROGRAM_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"
#include "glsl_template.h"
#include "graph_internal.h"

typedef struct Program Program;

/* A default a program kind gives one of its names (a uniform and a
 * template name; Flitter's keyword arguments to ProgramNode.render). */
typedef struct Kw {
    const char *name;
    TplValue value;          /* one reference */
} Kw;

/* A texture a program samples under a name (texture0, frame0 ...). */
typedef struct ChildTex {
    char name[24];
    GLuint tex;
    int w, h;                    /* its size in texels (0: not known) */
} ChildTex;

/* How a program pass draws this frame (its kind's defaults; a node's own
 * attributes override those Flitter lets it: composite=, passes=,
 * downsample=, downsample_passes=, colorbits=, border=, repeat=,
 * nearest=, fragment=, vertex=). */
typedef struct ProgramParams {
    bool srgb;                   /* an 8-bit sRGB framebuffer (!record) */
    int colorbits;               /* 0: the window's */
    int passes;                  /* default 1 */
    int downsample;              /* default 2 */
    const int *downsample_passes;
    size_t ndownsample;
    bool clamp;                  /* default sampling: the edge colour (else transparent) */
    const char *fragment;        /* the default fragment template (glsl_library name) */
    const char *vertex;          /* the default vertex template */
    const Kw *kwargs;
    size_t nkwargs;
    const ChildTex *children;    /* the textures to sample; NULL: the pass's children */
    size_t nchildren;
    /* a pass of the default programs that may take over its one child's
     * framebuffer instead of copying it (pass_program.c, pass_through):
     * with [keep_format], only a framebuffer of the pass's own format */
    bool pass_through, keep_format;
    /* at a scale below 1 (graph_set_scale): the `size` uniform in
     * Flitter's pixels (a filter that works in pixel positions: noise,
     * feedback, transform, kaleid), else the framebuffer's; and the name
     * of a uniform in pixels that is scaled with the picture (a blur's
     * radius, counted in texels), or NULL */
    bool logical_size;
    const char *pixel_uniform;
    /* the default program reads each texture either at the centres of
     * its texels, where it has the pass's size, or filtered, where it
     * has another (a blur's taps, `size` texels apart): a texture of the
     * pass's size is then sampled nearest, which reads what bilinear
     * filtering reads there and costs a CPU rasteriser half as much
     * (bench/PROFILE.md, issue 58, "texels at their centres"); not with
     * a fragment= or vertex= of the node's own */
    bool texel_centres;
} ProgramParams;

/* A program pass: a Pass, the program it drew with last, and its
 * sources of this frame. */
typedef struct ProgramPass {
    Pass base;
    Program *program;            /* last frame's, or NULL */
    Buf vsrc, fsrc;              /* this frame's rendered sources */
    Buf good_vsrc, good_fsrc;    /* those of the last program that compiled (empty: none yet) */
    const struct FilterKind *filter;
} ProgramPass;

/* Draw program pass [pp] for node [n] as [pr] says: its output ends in
 * pp->base.target (NULL when nothing could be drawn: a template or
 * program error, logged once each). */
void program_render(Graph *g, ProgramPass *pp, const Node *n, const PassCtx *cx, const ProgramParams *pr);
/* The textures of [p]'s children a program samples (those with a
 * picture, hidden ones left out), as texture0, texture1, ... into [out]
 * (at most [cap]); returns how many. */
size_t program_children(Graph *g, Pass *p, ChildTex *out, size_t cap);
/* Free [pp]'s sources (the program stays in the graph's cache). */
void program_pass_release(Graph *g, Pass *p);
/* Draw texture [tex], of [t]'s size, alone into [t] through the
 * compositing program, [t] bound and cleared by the caller: a copy, texel
 * for texel, sRGB-encoded when [t] is. */
bool program_copy(Graph *g, GLuint tex, GlTarget *t);

/* Python's hash of Flitter's Vector [v] (the seed of !noise, Flitter
 * shaders.py Noise.render: hash(seed) / 2^48). */
double program_seed_hash(const Vec *v);

#endif
