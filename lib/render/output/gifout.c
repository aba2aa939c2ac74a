/* gifout.c: animated GIF output through giflib (see gifout.h).
 *
 * An animated GIF grows frame by frame during the run: it is written to a
 * temporary next to the target (outfile.h) and renamed into place by
 * gifout_close, so the file appears, complete, at the end of the run (a
 * reader never sees a GIF without its trailer).
 */
#include <stddef.h>

#include "gifout.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gif_lib.h>

#include "mem.h"
#include "outfile.h"

struct GifOut {
    GifFileType *f;
    OutFile out;   /* the temporary; giflib owns (and closes) out.fd */
    int w, h, delay, frames;
    bool failed;   /* a write failed: the temporary is discarded at close */
    unsigned char *r, *g, *b, *idx;   /* planes for quantisation, w*h each */
};

GifOut *gifout_open(const char *path, int width, int height, int delay_cs, Buf *err)
{
    OutFile out;
    if (!outfile_open(&out, path, err)) return NULL;
    int code = 0;
    GifFileType *f = EGifOpenFileHandle(out.fd, &code);
    if (!f) {
        buf_printf(err, "%s: cannot create GIF: %s\n", path, GifErrorString(code));
        outfile_discard(&out);
        return NULL;
    }
    out.fd = -1;   /* giflib's now: closed by EGifCloseFile */
    EGifSetGifVersion(f, true);
    GifOut *g = calloc(1, sizeof *g);
    size_t n = (size_t)width * (size_t)height;
    if (!g || !(g->r = malloc(n)) || !(g->g = malloc(n)) || !(g->b = malloc(n)) || !(g->idx = malloc(n)))
        mem_oom();
    g->f = f;
    g->out = out;
    g->w = width;
    g->h = height;
    g->delay = delay_cs < 1 ? 1 : delay_cs > 65535 ? 65535 : delay_cs;   /* a 16-bit field */
    if (EGifPutScreenDesc(f, width, height, 8, 0, NULL) == GIF_ERROR) {
        buf_printf(err, "%s: cannot write GIF header\n", path);
        g->failed = true;
        gifout_close(g);
        return NULL;
    }
    /* NETSCAPE2.0 application extension: loop forever */
    static const unsigned char app[] = "NETSCAPE2.0", loop[] = {1, 0, 0};
    if (EGifPutExtensionLeader(f, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
        EGifPutExtensionBlock(f, 11, app) == GIF_ERROR ||
        EGifPutExtensionBlock(f, 3, loop) == GIF_ERROR || EGifPutExtensionTrailer(f) == GIF_ERROR) {
        buf_printf(err, "%s: cannot write GIF header\n", path);
        g->failed = true;
        gifout_close(g);
        return NULL;
    }
    return g;
}

int gifout_frame(GifOut *g, const unsigned char *argb, int stride)
{
    size_t k = 0;
    for (int y = 0; y < g->h; y++) {
        const uint32_t *row = (const uint32_t *)(const void *)(argb + (size_t)y * (size_t)stride);
        for (int x = 0; x < g->w; x++, k++) {
            uint32_t p = row[x];   /* premultiplied over black = the colour bytes */
            g->r[k] = (unsigned char)(p >> 16);
            g->g[k] = (unsigned char)(p >> 8);
            g->b[k] = (unsigned char)p;
        }
    }
    GifColorType pal[256];
    memset(pal, 0, sizeof pal);
    int ncolors = 256;
    if (GifQuantizeBuffer((unsigned)g->w, (unsigned)g->h, &ncolors, g->r, g->g, g->b, g->idx, pal) == GIF_ERROR)
        return -1;
    ColorMapObject *map = GifMakeMapObject(256, pal);
    if (!map) mem_oom();
    GraphicsControlBlock gcb = {.DisposalMode = DISPOSE_DO_NOT, .UserInputFlag = false,
                                .DelayTime = g->delay, .TransparentColor = NO_TRANSPARENT_COLOR};
    GifByteType ext[4];
    size_t elen = EGifGCBToExtension(&gcb, ext);
    int rc = 0;
    if (EGifPutExtension(g->f, GRAPHICS_EXT_FUNC_CODE, (int)elen, ext) == GIF_ERROR ||
        EGifPutImageDesc(g->f, 0, 0, g->w, g->h, false, map) == GIF_ERROR)
        rc = -1;
    for (int y = 0; rc == 0 && y < g->h; y++)
        if (EGifPutLine(g->f, g->idx + (size_t)y * (size_t)g->w, g->w) == GIF_ERROR) rc = -1;
    GifFreeMapObject(map);
    if (rc == 0) g->frames++;
    else g->failed = true;
    return rc;
}

int gifout_frames(const GifOut *g) { return g->frames; }

int gifout_close(GifOut *g)
{
    if (!g) return 0;
    int code = 0, rc = EGifCloseFile(g->f, &code) == GIF_ERROR || g->failed ? -1 : 0;
    Buf err = BUF_INIT;   /* the caller reports the failure by the file's name */
    if (rc == 0) rc = outfile_commit(&g->out, true, &err) ? 0 : -1;
    else outfile_discard(&g->out);
    free(g->r);
    free(g->g);
    free(g->b);
    free(g->idx);
    free(g);
    buf_free(&err);
    return rc;
}
