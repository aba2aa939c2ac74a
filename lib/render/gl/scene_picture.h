/* scene_picture.h: a 3D scene given as shapes (canvas3d.h, C3dScene)
 * drawn into a cairo picture: the physics view's 3D panels. Outside any
 * render graph, so it has its own GL context (the library's EGL one),
 * framebuffers and 3D renderer, made by the first drawing. */
#ifndef FL_RENDER_SCENE_PICTURE_H
#define FL_RENDER_SCENE_PICTURE_H

#include <stddef.h>

#include <cairo.h>

#include "buf.h"
#include "canvas3d.h"

typedef struct ScenePicture ScenePicture;

/* A drawer with nothing made yet. */
ScenePicture *scene_picture_new(void);
/* Draw [s] into [pic] (an ARGB32 image surface: the camera's picture),
 * replacing its pixels with the sRGB encoding of the scene's light,
 * clamped to 0..1, premultiplied, transparent where nothing is drawn.
 *   errors: -1 with one line in [err] when there is no OpenGL (said once:
 *           nothing is appended on later calls) or a program does not compile; else 0. */
int scene_picture_draw(ScenePicture *sp, const C3dScene *s, cairo_surface_t *pic, Buf *err);
/* Free everything (NULL is a no-op). */
void scene_picture_free(ScenePicture *sp);

#endif
