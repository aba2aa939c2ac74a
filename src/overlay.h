/* overlay.h: the text drawn over a window's picture (status, load errors). */
#ifndef FL_OVERLAY_H
#define FL_OVERLAY_H

#include <stddef.h>
#include <stdint.h>

/* Paint the overlay of a window into [pixels] ([width] x [height] pixels,
 * rows [stride] bytes apart, each a native-endian 0xAARRGGBB with straight,
 * not premultiplied, alpha, ready for an SDL_PIXELFORMAT_ARGB8888 texture
 * blended with SDL_BLENDMODE_BLEND): transparent, then the lines of
 * [status] (or nothing when NULL) in white on a translucent black box at
 * the top left, and the lines of [error] (NULL: none) in white on a
 * translucent red box along the bottom, in a monospaced face so that the
 * caret under a source line lines up. [scale] is the output pixels per
 * window point (HiDPI), which the text size follows (13 points).
 *   errors: none; lines too long or too many for the picture are clipped.
 *   source: the text is drawn with cairo (cairo is the library's own
 *           dependency; SDL2 has no text). */
void overlay_paint(uint32_t *pixels, int width, int height, size_t stride, double scale,
                   const char *status, const char *error);

#endif
