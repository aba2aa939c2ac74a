/* glsl_library.h: the GLSL of lib/render/gl/glsl, built into the library
 * (glsl/embed.py makes glsl_sources.c from it): the templates of the
 * screen-space programs (default.vert, default.frag, the built-in filters'
 * NAME.frag, video.vert) and the function files a template may include
 * (composite_functions.glsl, color_functions.glsl, filter_functions.glsl,
 * ease_functions.glsl, noise_functions.glsl, merge.glsl), each written for
 * this project after the behaviour Flitter documents (docs/shaders.md). */
#ifndef FL_RENDER_GLSL_LIBRARY_H
#define FL_RENDER_GLSL_LIBRARY_H

#include <stddef.h>

/* The text of file [name] (e.g. "blur.frag"), NUL-terminated, static; NULL
 * when there is no such file. */
const char *glsl_library(const char *name);

#endif
