/* overlay.c: a window's overlay picture, drawn with cairo: the F1 status
 * box (frame rate, clock, per-frame costs) and the text of a load error
 * that keeps the last good program running. cairo draws premultiplied
 * ARGB32; the pixels are turned to straight alpha at the end, because
 * SDL_BLENDMODE_BLEND (the blend every SDL renderer has) expects that. */
#include "overlay.h"

#include <cairo.h>
#include <stdbool.h>
#include <string.h>

enum { MAX_LINES = 40 };

/* Split [text] into at most MAX_LINES lines (pointers and lengths into the
 * text, without the newlines); a trailing newline ends the last line. */
static int split_lines(const char *text, const char **line, int *len)
{
    int n = 0;
    while (*text && n < MAX_LINES) {
        const char *nl = strchr(text, '\n');
        size_t l = nl ? (size_t)(nl - text) : strlen(text);
        line[n] = text;
        len[n++] = (int)(l > 4000 ? 4000 : l);
        text += l + (nl ? 1 : 0);
    }
    return n;
}

/* Draw the lines of [text] in a box of colour [r,g,b,a] at the top left,
 * or along the bottom (the whole width) when [from_bottom], in [cr]'s
 * current font, made smaller when the lines are wider than the picture. */
static void text_box(cairo_t *cr, const char *text, int width, int height, double scale,
                     bool from_bottom, double r, double g, double b, double a)
{
    const char *line[MAX_LINES];
    int len[MAX_LINES];
    int n = split_lines(text, line, len);
    if (n == 0) return;
    double pad = 6 * scale, box_w = 0;
    char buf[4001];
    for (int i = 0; i < n; i++) {
        memcpy(buf, line[i], (size_t)len[i]);
        buf[len[i]] = '\0';
        cairo_text_extents_t te;
        cairo_text_extents(cr, buf, &te);
        if (te.x_advance > box_w) box_w = te.x_advance;
    }
    /* a small window gets smaller text (down to 55%) before lines are clipped */
    if (box_w + 2 * pad > width && box_w > 0) {
        double f = (width - 2 * pad) / box_w;
        if (f < 0.55) f = 0.55;
        cairo_set_font_size(cr, 13 * scale * f);
        box_w *= f;
    }
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    double lh = fe.height, box_h = n * lh + 2 * pad;
    box_w += 2 * pad;
    if (from_bottom) box_w = width;
    double y0 = from_bottom ? height - box_h : 0;
    if (y0 < 0) y0 = 0;
    cairo_set_source_rgba(cr, r, g, b, a);
    cairo_rectangle(cr, 0, y0, box_w, box_h);
    cairo_fill(cr);
    cairo_set_source_rgba(cr, 1, 1, 1, 1);
    for (int i = 0; i < n; i++) {
        memcpy(buf, line[i], (size_t)len[i]);
        buf[len[i]] = '\0';
        cairo_move_to(cr, pad, y0 + pad + fe.ascent + i * lh);
        cairo_show_text(cr, buf);
    }
}

void overlay_paint(uint32_t *pixels, int width, int height, size_t stride, double scale,
                   const char *status, const char *error)
{
    cairo_surface_t *s = cairo_image_surface_create_for_data(
        (unsigned char *)pixels, CAIRO_FORMAT_ARGB32, width, height, (int)stride);
    cairo_t *cr = cairo_create(s);
    cairo_set_operator(cr, CAIRO_OPERATOR_CLEAR);
    cairo_paint(cr);
    cairo_set_operator(cr, CAIRO_OPERATOR_OVER);
    cairo_select_font_face(cr, "monospace", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 13 * scale);
    if (status) text_box(cr, status, width, height, scale, false, 0, 0, 0, 0.7);
    cairo_set_font_size(cr, 13 * scale);
    if (error) text_box(cr, error, width, height, scale, true, 0.6, 0, 0, 0.85);
    cairo_destroy(cr);
    cairo_surface_flush(s);
    cairo_surface_destroy(s);
    /* premultiplied to straight alpha */
    for (int y = 0; y < height; y++) {
        uint32_t *row = (uint32_t *)((unsigned char *)pixels + (size_t)y * stride);
        for (int x = 0; x < width; x++) {
            uint32_t p = row[x], a = p >> 24;
            if (a == 0 || a == 255) continue;
            uint32_t r = ((p >> 16) & 255) * 255 / a, g = ((p >> 8) & 255) * 255 / a,
                     b = (p & 255) * 255 / a;
            row[x] = a << 24 | (r > 255 ? 255 : r) << 16 | (g > 255 ? 255 : g) << 8 |
                     (b > 255 ? 255 : b);
        }
    }
}
