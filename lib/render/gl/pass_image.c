/* pass_image.c: the `!image` pass (Flitter docs/windows.md, "!image";
 * render/window/image.py): the picture in filename= (relative to the
 * script's folder), resized to size= when given, else of its own size,
 * flipped as flip= asks (:horizontal, :vertical, :both), premultiplied and
 * uploaded into an 8-bit sRGB texture, which changes only when the file,
 * the size or the flip does. Decoded pictures are kept by the graph's
 * media cache (media.h). An image pass carries on across frames by kind,
 * tags and id alone (Flitter's Image.similar_to asks the id again). */
#include <stdlib.h>
#include <string.h>

#include "graph_internal.h"
#include "media.h"
#include "mem.h"
#include "rnode.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

typedef struct ImagePass {
    Pass base;
    Buf file;                /* filename= as given ("" when none) */
    uint64_t version;        /* of the picture in the texture */
    bool flip_x, flip_y;     /* of the picture in the texture */
    uint8_t *rows;           /* upload buffer */
    size_t caprows;
} ImagePass;

MediaCache *graph_media(Graph *g)
{
    if (!g->media) g->media = media_cache_new(g->env.budget, g->env.interrupt);
    return g->media;
}

static void render_image(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    (void)cx;
    ImagePass *ip = (ImagePass *)p;
    p->retain = true;
    Buf name = BUF_INIT, path = BUF_INIT, flip = BUF_INIT, err = BUF_INIT;
    if (!canvas_attr_str(n, "filename", g->env.symbols, &name) || name.len == 0) {
        target_release(g->pool, p->target);
        p->target = NULL;
        buf_reset(&ip->file);
        goto done;
    }
    graph_path(g, buf_cstr(&name), &path);
    double s[2];
    int w = 0, h = 0;
    if (canvas_attr_nums(n, "size", 2, s) && s[0] >= 1 && s[1] >= 1 && s[0] <= 16384 && s[1] <= 16384) {
        w = (int)s[0];
        h = (int)s[1];
    }
    bool fresh = false;
    const MediaImage *img = media_image(graph_media(g), buf_cstr(&path), w, h, &err, &fresh);
    if (!img) {
        if (fresh) render_log(&g->env.log, RLOG_ERROR, "image: %s", buf_line(&err));
        target_release(g->pool, p->target);
        p->target = NULL;
        goto done;
    }
    canvas_attr_str(n, "flip", g->env.symbols, &flip);
    const char *f = buf_cstr(&flip);
    bool fx = strcmp(f, "horizontal") == 0 || strcmp(f, "both") == 0;
    bool fy = strcmp(f, "vertical") == 0 || strcmp(f, "both") == 0;
    p->w = img->w;
    p->h = img->h;
    bool same = p->target && p->target->w == img->w && p->target->h == img->h && ip->version == img->version &&
                ip->flip_x == fx && ip->flip_y == fy && strcmp(buf_cstr(&ip->file), buf_cstr(&name)) == 0;
    if (same) goto done;
    if (p->target && (p->target->w != img->w || p->target->h != img->h)) {
        target_release(g->pool, p->target);
        p->target = NULL;
    }
    if (!p->target) p->target = graph_target(g, img->w, img->h, 8, true, false, 0);
    if (!p->target) goto done;
    size_t row = (size_t)img->w * 4, n8 = row * (size_t)img->h;
    if (n8 > ip->caprows) {
        free(ip->rows);
        ip->rows = mem_alloc(n8);
        ip->caprows = n8;
    }
    /* GL's first row is the bottom one: the picture's last row goes first,
     * unless flipped vertically (Flitter image.py); premultiplied (PIL "RGBa") */
    for (int y = 0; y < img->h; y++) {
        const uint8_t *src = img->rgba + (size_t)(fy ? y : img->h - 1 - y) * row;
        uint8_t *dst = ip->rows + (size_t)y * row;
        for (int x = 0; x < img->w; x++) {
            const uint8_t *q = src + (size_t)(fx ? img->w - 1 - x : x) * 4;
            unsigned a = q[3];
            for (int k = 0; k < 3; k++) {
                unsigned t = q[k] * a + 128;
                dst[4 * x + k] = (uint8_t)((t + (t >> 8)) >> 8);
            }
            dst[4 * x + 3] = (uint8_t)a;
        }
    }
    glBindTexture(GL_TEXTURE_2D, p->target->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, img->w, img->h, GL_RGBA, GL_UNSIGNED_BYTE, ip->rows);
    glBindTexture(GL_TEXTURE_2D, 0);
    ip->version = img->version;
    ip->flip_x = fx;
    ip->flip_y = fy;
    buf_reset(&ip->file);
    buf_puts(&ip->file, buf_cstr(&name));
done:
    buf_free(&name);
    buf_free(&path);
    buf_free(&flip);
    buf_free(&err);
}

static void release_image(Graph *g, Pass *p)
{
    (void)g;
    ImagePass *ip = (ImagePass *)p;
    buf_free(&ip->file);
    free(ip->rows);
}

/* its picture stays */
static void keep(Graph *g, Pass *p)
{
    (void)g;
    (void)p;
}

const PassKind pass_image = {.kind = "image", .size = sizeof(ImagePass), .leaf = true,
                             .render = render_image, .release = release_image, .finished = keep};
