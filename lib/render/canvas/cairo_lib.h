/* cairo_lib.h: cairo, loaded with dlopen the first time something is drawn,
 * not linked.
 *
 * Why: libcairo.so.2 brings about twenty libraries with it on Debian 12
 * (pixman, fontconfig, freetype, libpng, X11 and xcb); mapping and
 * relocating them cost every process a noticeable share of a short
 * physics run (bench/PROFILE.md, "lib/render/canvas/cairo_lib.h: cairo
 * opened on first use"). Loaded on first use, only a run that draws a
 * picture pays for it. The headers (libcairo2-dev) are still needed to
 * build; at run time the library of the same major version is opened by
 * soname.
 *
 * The render files call cairo by its usual names: this header, included
 * after <cairo.h>, makes each name used in lib/ a call through the table
 * of entry points (FL_CAIRO_FUNCTIONS is that list: a function missing
 * from it fails to link, as the library no longer links cairo). The table
 * is process-wide, like the dynamic linker's own: it is filled once (dynload.h,
 * under a mutex) and never changes; every runtime in the process shares the
 * one loaded libcairo, as it would if it were linked.
 *
 * Every path that draws starts at a function that calls cairo_lib_ready
 * (renderer_frame, renderer_draw_window, view_new, pictures), so no call
 * goes through the table before it is filled. */
#ifndef FL_RENDER_CAIRO_LIB_H
#define FL_RENDER_CAIRO_LIB_H

#include <stdbool.h>
#include <stddef.h>

#include <cairo-svg.h>
#include <cairo.h>

#include "buf.h"

#define FL_CAIRO_FUNCTIONS(X)                                                                           \
    X(cairo_arc) X(cairo_arc_negative) X(cairo_clip) X(cairo_clip_extents) X(cairo_close_path)          \
    X(cairo_create) X(cairo_curve_to) X(cairo_destroy) X(cairo_device_to_user_distance)                 \
    X(cairo_fill_preserve) X(cairo_get_current_point) X(cairo_get_matrix) X(cairo_get_source)           \
    X(cairo_has_current_point) X(cairo_identity_matrix) X(cairo_image_surface_create)                   \
    X(cairo_image_surface_create_for_data) X(cairo_image_surface_get_data)                              \
    X(cairo_image_surface_get_format) X(cairo_image_surface_get_height)                                 \
    X(cairo_image_surface_get_stride) X(cairo_image_surface_get_width) X(cairo_line_to)                 \
    X(cairo_matrix_init) X(cairo_matrix_init_scale) X(cairo_matrix_init_translate)                      \
    X(cairo_matrix_init_identity) X(cairo_matrix_init_rotate) X(cairo_matrix_invert) X(cairo_matrix_multiply) X(cairo_matrix_rotate) X(cairo_matrix_scale)        \
    X(cairo_matrix_translate) X(cairo_move_to) X(cairo_new_path) X(cairo_new_sub_path) X(cairo_paint)   \
    X(cairo_paint_with_alpha) X(cairo_pattern_add_color_stop_rgba) X(cairo_pattern_create_for_surface) X(cairo_pattern_create_linear)       \
    X(cairo_pattern_create_radial) X(cairo_pattern_create_rgba) X(cairo_pattern_destroy)                \
    X(cairo_pattern_reference) X(cairo_pattern_set_extend) X(cairo_pattern_set_filter)                  \
    X(cairo_pattern_set_matrix) X(cairo_pop_group) X(cairo_pop_group_to_source) X(cairo_push_group) X(cairo_rectangle)     \
    X(cairo_reference) X(cairo_restore) X(cairo_rotate) X(cairo_save) X(cairo_scale) X(cairo_select_font_face)             \
    X(cairo_set_antialias) X(cairo_set_dash) X(cairo_set_fill_rule) X(cairo_set_font_size)              \
    X(cairo_set_line_cap) X(cairo_set_line_join) X(cairo_set_line_width) X(cairo_set_matrix)            \
    X(cairo_set_miter_limit) X(cairo_set_operator) X(cairo_set_source) X(cairo_set_source_rgb)          \
    X(cairo_set_source_rgba) X(cairo_set_source_surface) X(cairo_show_text) X(cairo_status_to_string)   \
    X(cairo_stroke) X(cairo_stroke_preserve) X(cairo_surface_destroy) X(cairo_surface_finish)           \
    X(cairo_surface_flush) X(cairo_surface_get_reference_count) X(cairo_surface_get_type) X(cairo_surface_mark_dirty) X(cairo_surface_reference) X(cairo_surface_status) \
    X(cairo_surface_write_to_png) X(cairo_surface_write_to_png_stream) X(cairo_svg_surface_create)      \
    X(cairo_text_extents) X(cairo_text_path) X(cairo_transform) X(cairo_translate)                      \
    X(cairo_user_to_device_distance)

/* cairo's entry points: f_NAME for each NAME of FL_CAIRO_FUNCTIONS. */
typedef struct CairoLib {
#define FL_CAIRO_FIELD(name) __typeof__(&name) f_##name;
    FL_CAIRO_FUNCTIONS(FL_CAIRO_FIELD)
#undef FL_CAIRO_FIELD
} CairoLib;

/* The filled table (NULL before cairo_lib_ready succeeds). */
extern const void *fl_cairo;
#define FL_CAIRO ((const CairoLib *)fl_cairo)

/* Load cairo if it is not loaded yet (thread-safe; only the first call
 * does any work) and say whether its entry points can be called.
 *   errors: false with one line appended to [why] (may be NULL): the library or
 *           one of its functions missing; the same answer every time. */
bool cairo_lib_ready(Buf *why);

/* The names the render files call (FL_CAIRO_FUNCTIONS). */
#define cairo_arc (FL_CAIRO->f_cairo_arc)
#define cairo_arc_negative (FL_CAIRO->f_cairo_arc_negative)
#define cairo_clip (FL_CAIRO->f_cairo_clip)
#define cairo_clip_extents (FL_CAIRO->f_cairo_clip_extents)
#define cairo_close_path (FL_CAIRO->f_cairo_close_path)
#define cairo_create (FL_CAIRO->f_cairo_create)
#define cairo_curve_to (FL_CAIRO->f_cairo_curve_to)
#define cairo_destroy (FL_CAIRO->f_cairo_destroy)
#define cairo_device_to_user_distance (FL_CAIRO->f_cairo_device_to_user_distance)
#define cairo_fill_preserve (FL_CAIRO->f_cairo_fill_preserve)
#define cairo_get_current_point (FL_CAIRO->f_cairo_get_current_point)
#define cairo_get_matrix (FL_CAIRO->f_cairo_get_matrix)
#define cairo_get_source (FL_CAIRO->f_cairo_get_source)
#define cairo_has_current_point (FL_CAIRO->f_cairo_has_current_point)
#define cairo_identity_matrix (FL_CAIRO->f_cairo_identity_matrix)
#define cairo_image_surface_create (FL_CAIRO->f_cairo_image_surface_create)
#define cairo_image_surface_create_for_data (FL_CAIRO->f_cairo_image_surface_create_for_data)
#define cairo_image_surface_get_data (FL_CAIRO->f_cairo_image_surface_get_data)
#define cairo_image_surface_get_format (FL_CAIRO->f_cairo_image_surface_get_format)
#define cairo_image_surface_get_height (FL_CAIRO->f_cairo_image_surface_get_height)
#define cairo_image_surface_get_stride (FL_CAIRO->f_cairo_image_surface_get_stride)
#define cairo_image_surface_get_width (FL_CAIRO->f_cairo_image_surface_get_width)
#define cairo_line_to (FL_CAIRO->f_cairo_line_to)
#define cairo_matrix_init (FL_CAIRO->f_cairo_matrix_init)
#define cairo_matrix_init_identity (FL_CAIRO->f_cairo_matrix_init_identity)
#define cairo_matrix_init_rotate (FL_CAIRO->f_cairo_matrix_init_rotate)
#define cairo_matrix_init_scale (FL_CAIRO->f_cairo_matrix_init_scale)
#define cairo_matrix_init_translate (FL_CAIRO->f_cairo_matrix_init_translate)
#define cairo_matrix_invert (FL_CAIRO->f_cairo_matrix_invert)
#define cairo_matrix_multiply (FL_CAIRO->f_cairo_matrix_multiply)
#define cairo_matrix_rotate (FL_CAIRO->f_cairo_matrix_rotate)
#define cairo_matrix_scale (FL_CAIRO->f_cairo_matrix_scale)
#define cairo_matrix_translate (FL_CAIRO->f_cairo_matrix_translate)
#define cairo_move_to (FL_CAIRO->f_cairo_move_to)
#define cairo_new_path (FL_CAIRO->f_cairo_new_path)
#define cairo_new_sub_path (FL_CAIRO->f_cairo_new_sub_path)
#define cairo_paint (FL_CAIRO->f_cairo_paint)
#define cairo_paint_with_alpha (FL_CAIRO->f_cairo_paint_with_alpha)
#define cairo_pattern_add_color_stop_rgba (FL_CAIRO->f_cairo_pattern_add_color_stop_rgba)
#define cairo_pattern_create_for_surface (FL_CAIRO->f_cairo_pattern_create_for_surface)
#define cairo_pattern_create_linear (FL_CAIRO->f_cairo_pattern_create_linear)
#define cairo_pattern_create_radial (FL_CAIRO->f_cairo_pattern_create_radial)
#define cairo_pattern_create_rgba (FL_CAIRO->f_cairo_pattern_create_rgba)
#define cairo_pattern_destroy (FL_CAIRO->f_cairo_pattern_destroy)
#define cairo_pattern_reference (FL_CAIRO->f_cairo_pattern_reference)
#define cairo_pattern_set_extend (FL_CAIRO->f_cairo_pattern_set_extend)
#define cairo_pattern_set_filter (FL_CAIRO->f_cairo_pattern_set_filter)
#define cairo_pattern_set_matrix (FL_CAIRO->f_cairo_pattern_set_matrix)
#define cairo_pop_group (FL_CAIRO->f_cairo_pop_group)
#define cairo_pop_group_to_source (FL_CAIRO->f_cairo_pop_group_to_source)
#define cairo_push_group (FL_CAIRO->f_cairo_push_group)
#define cairo_rectangle (FL_CAIRO->f_cairo_rectangle)
#define cairo_reference (FL_CAIRO->f_cairo_reference)
#define cairo_restore (FL_CAIRO->f_cairo_restore)
#define cairo_rotate (FL_CAIRO->f_cairo_rotate)
#define cairo_save (FL_CAIRO->f_cairo_save)
#define cairo_scale (FL_CAIRO->f_cairo_scale)
#define cairo_select_font_face (FL_CAIRO->f_cairo_select_font_face)
#define cairo_set_antialias (FL_CAIRO->f_cairo_set_antialias)
#define cairo_set_dash (FL_CAIRO->f_cairo_set_dash)
#define cairo_set_fill_rule (FL_CAIRO->f_cairo_set_fill_rule)
#define cairo_set_font_size (FL_CAIRO->f_cairo_set_font_size)
#define cairo_set_line_cap (FL_CAIRO->f_cairo_set_line_cap)
#define cairo_set_line_join (FL_CAIRO->f_cairo_set_line_join)
#define cairo_set_line_width (FL_CAIRO->f_cairo_set_line_width)
#define cairo_set_matrix (FL_CAIRO->f_cairo_set_matrix)
#define cairo_set_miter_limit (FL_CAIRO->f_cairo_set_miter_limit)
#define cairo_set_operator (FL_CAIRO->f_cairo_set_operator)
#define cairo_set_source (FL_CAIRO->f_cairo_set_source)
#define cairo_set_source_rgb (FL_CAIRO->f_cairo_set_source_rgb)
#define cairo_set_source_rgba (FL_CAIRO->f_cairo_set_source_rgba)
#define cairo_set_source_surface (FL_CAIRO->f_cairo_set_source_surface)
#define cairo_show_text (FL_CAIRO->f_cairo_show_text)
#define cairo_status_to_string (FL_CAIRO->f_cairo_status_to_string)
#define cairo_stroke (FL_CAIRO->f_cairo_stroke)
#define cairo_stroke_preserve (FL_CAIRO->f_cairo_stroke_preserve)
#define cairo_surface_destroy (FL_CAIRO->f_cairo_surface_destroy)
#define cairo_surface_finish (FL_CAIRO->f_cairo_surface_finish)
#define cairo_surface_flush (FL_CAIRO->f_cairo_surface_flush)
#define cairo_surface_get_reference_count (FL_CAIRO->f_cairo_surface_get_reference_count)
#define cairo_surface_get_type (FL_CAIRO->f_cairo_surface_get_type)
#define cairo_surface_mark_dirty (FL_CAIRO->f_cairo_surface_mark_dirty)
#define cairo_surface_reference (FL_CAIRO->f_cairo_surface_reference)
#define cairo_surface_status (FL_CAIRO->f_cairo_surface_status)
#define cairo_surface_write_to_png (FL_CAIRO->f_cairo_surface_write_to_png)
#define cairo_surface_write_to_png_stream (FL_CAIRO->f_cairo_surface_write_to_png_stream)
#define cairo_svg_surface_create (FL_CAIRO->f_cairo_svg_surface_create)
#define cairo_text_extents (FL_CAIRO->f_cairo_text_extents)
#define cairo_text_path (FL_CAIRO->f_cairo_text_path)
#define cairo_transform (FL_CAIRO->f_cairo_transform)
#define cairo_translate (FL_CAIRO->f_cairo_translate)
#define cairo_user_to_device_distance (FL_CAIRO->f_cairo_user_to_device_distance)

#endif
