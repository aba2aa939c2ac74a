/* canvas3d_backface.h: the back-face target of `!canvas3d` translucency.
 *
 * Flitter (render/window/canvas3d.pyx, render; docs/canvas3d.md, Instance
 * Ordering) draws the back faces of a render group's translucent
 * instances into an auxiliary framebuffer before the group's transparent
 * and translucent instances: a 16-bit float colour buffer the size of the
 * camera's picture, single-sampled, with a depth buffer of its own, read
 * back by the translucent shader with nearest-texel filtering and
 * repeating edges. This module owns that framebuffer; canvas3d.c draws
 * into it.
 */
#ifndef FL_RENDER_CANVAS3D_BACKFACE_H
#define FL_RENDER_CANVAS3D_BACKFACE_H

#include <stdbool.h>

typedef struct C3dBackface {
    unsigned fbo;        /* the framebuffer (0: none made yet) */
    unsigned texture;    /* its RGBA16F colour texture: light in (rgb), eye distance (a) */
    unsigned depth;      /* its 24-bit depth renderbuffer */
    int w, h;            /* its size in pixels */
    int previous_fbo;    /* the draw framebuffer bound when the pass began */
    int previous_viewport[4];
} C3dBackface;

/* Bind [b]'s framebuffer at [w] x [h] pixels (made, or remade when the
 * size changed), set the viewport to it and clear it: colour 0 (no back
 * face: distance 0) and depth 1. The framebuffer and viewport bound
 * before are kept for c3d_backface_end. A GL context must be current.
 *   errors: false when the framebuffer cannot be made (then the previous
 *           one stays bound and nothing is kept). */
bool c3d_backface_begin(C3dBackface *b, int w, int h);
/* Rebind the framebuffer and viewport of before c3d_backface_begin and
 * bind [b]'s texture to texture unit 0 for the translucent shader. */
void c3d_backface_end(C3dBackface *b);
/* Delete [b]'s GL objects (its context current) and zero it. */
void c3d_backface_free(C3dBackface *b);

#endif
