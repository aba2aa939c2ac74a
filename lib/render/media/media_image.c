/* media_image.c: pictures read from files (media.h, media_image): decoded
 * with FFmpeg's image decoders into RGBA, kept in the MediaCache by path
 * with their resized copies, and decoded again when the file changes.
 *
 * Each path has one entry in the cache's hash table: the file's identity
 * when it was read (device, inode, size, modification time, or why stat
 * failed), the picture at the file's size (or why the file is no
 * picture), and up to MAX_COPIES resized copies, the least recently asked
 * one replaced first. A failure that depends on the file (missing, not a
 * picture, damaged) is kept until the file changes; one that does not
 * (the memory budget, an interrupt) is tried again on the next call. The
 * last message given for a path is kept too, so that *fresh says whether
 * the caller has seen it.
 *
 * Resizing is swscale's bilinear filter on premultiplied pixels (then
 * straight again), as Pillow resizes RGBA pictures for Flitter's !image:
 * the colour of transparent pixels does not bleed into their neighbours.
 * A picture without alpha is filtered as it is. */
#include "media_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "mem.h"

/* Resized copies kept per picture. */
#define MAX_COPIES 4

typedef struct Copy {
    MediaImage img;       /* img.rgba == pixels */
    uint8_t *pixels;      /* NULL: none */
    size_t bytes;         /* charged to the budget */
    double used;          /* media_now() when last asked for */
} Copy;

struct ImageEntry {
    ImageEntry *next;     /* in its bucket */
    char *path;
    uint64_t hash;
    bool known;           /* the identity below was taken */
    int stat_errno;       /* 0: the file was there; else why stat failed */
    dev_t dev;
    ino_t ino;
    off_t size;
    struct timespec mtime;
    double used;          /* media_now() when last asked for */
    char *failure;        /* why this file is no picture (until it changes), or NULL */
    char *last_message;   /* the last failure given for this path, or NULL */
    Copy full;            /* the picture at the file's size */
    Copy copies[MAX_COPIES];
    int ncopies;
};

static uint64_t hash_path(const char *s)
{
    uint64_t h = 0xcbf29ce484222325u;   /* FNV-1a */
    for (; *s; s++) h = (h ^ (unsigned char)*s) * 0x100000001b3u;
    return h;
}

static void copy_free(MediaCache *m, Copy *c)
{
    free(c->pixels);
    mem_budget_release(m->budget, c->bytes);
    *c = (Copy){0};
}

/* Forget what [e] holds of its file (pixels, copies, failure), not its
 * last message. */
static void entry_clear(MediaCache *m, ImageEntry *e)
{
    copy_free(m, &e->full);
    for (int i = 0; i < e->ncopies; i++) copy_free(m, &e->copies[i]);
    e->ncopies = 0;
    free(e->failure);
    e->failure = NULL;
}

static void entry_free(MediaCache *m, ImageEntry *e)
{
    entry_clear(m, e);
    free(e->last_message);
    free(e->path);
    free(e);
}

void media_images_free(MediaCache *m)
{
    for (size_t b = 0; b < m->nbuckets; b++) {
        for (ImageEntry *e = m->buckets[b], *next; e; e = next) {
            next = e->next;
            entry_free(m, e);
        }
    }
    free(m->buckets);
    m->buckets = NULL;
    m->nbuckets = m->nentries = 0;
}

void media_images_expire(MediaCache *m, double before)
{
    for (size_t b = 0; b < m->nbuckets; b++) {
        ImageEntry **link = &m->buckets[b];
        while (*link) {
            ImageEntry *e = *link;
            if (e->used < before) {
                *link = e->next;
                entry_free(m, e);
                m->nentries--;
                continue;
            }
            for (int i = 0; i < e->ncopies;) {
                if (e->copies[i].used < before) {
                    copy_free(m, &e->copies[i]);
                    e->copies[i] = e->copies[--e->ncopies];
                    e->copies[e->ncopies] = (Copy){0};
                } else {
                    i++;
                }
            }
            link = &e->next;
        }
    }
}

/* [m]'s entry for [path], made (empty) when there is none. */
static ImageEntry *entry_for(MediaCache *m, const char *path)
{
    uint64_t h = hash_path(path);
    if (m->nbuckets) {
        for (ImageEntry *e = m->buckets[h & (m->nbuckets - 1)]; e; e = e->next)
            if (e->hash == h && strcmp(e->path, path) == 0) return e;
    }
    if (m->nentries >= m->nbuckets) {   /* grow: at most one entry per bucket on average */
        size_t n = m->nbuckets ? m->nbuckets * 2 : 16;
        ImageEntry **nb = mem_calloc(n, sizeof *nb);
        for (size_t b = 0; b < m->nbuckets; b++) {
            for (ImageEntry *e = m->buckets[b], *next; e; e = next) {
                next = e->next;
                e->next = nb[e->hash & (n - 1)];
                nb[e->hash & (n - 1)] = e;
            }
        }
        free(m->buckets);
        m->buckets = nb;
        m->nbuckets = n;
    }
    ImageEntry *e = mem_calloc(1, sizeof *e);
    e->path = mem_strdup(path);
    e->hash = h;
    e->next = m->buckets[h & (m->nbuckets - 1)];
    m->buckets[h & (m->nbuckets - 1)] = e;
    m->nentries++;
    return e;
}

/* Whether the file as [serr]/[sb] found it is what [e] read. */
static bool same_file(const ImageEntry *e, int serr, const struct stat *sb)
{
    if (!e->known || e->stat_errno != serr) return false;
    if (serr) return true;
    return e->dev == sb->st_dev && e->ino == sb->st_ino && e->size == sb->st_size &&
           e->mtime.tv_sec == sb->st_mtim.tv_sec && e->mtime.tv_nsec == sb->st_mtim.tv_nsec;
}

static size_t rgba_bytes(int w, int h) { return (size_t)w * (size_t)h * 4; }

static void budget_message(const char *path, int w, int h, Buf *msg)
{
    buf_printf(msg, "%s: out of memory for a %dx%d picture (past the memory budget, --max-memory)\n", path, w, h);
}

/* The results of decode_file. */
enum { DECODED, FILE_FAILED, TRY_AGAIN };

/* Decode [e]'s file into e->full: DECODED; FILE_FAILED (the file's fault,
 * kept until it changes) or TRY_AGAIN (the budget, an interrupt) with
 * the reason appended to [msg]. */
static int decode_file(MediaCache *m, const AvLib *L, ImageEntry *e, Buf *msg)
{
    MediaStop stop = {m->interrupt, NULL};
    MediaInput in;
    if (!media_input_open(L, e->path, true, false, &stop, &in, msg))
        return media_stopped(&stop) ? TRY_AGAIN : FILE_FAILED;
    /* the decoder's own frame, charged while it lives (its size as the
     * file says; checked again on the frame) */
    int cw = in.cc->width, ch = in.cc->height;
    size_t transient = cw > 0 && ch > 0 ? rgba_bytes(cw, ch) : 0;
    if (!mem_budget_reserve(m->budget, transient)) {
        budget_message(e->path, cw, ch, msg);
        media_input_close(L, &in);
        return TRY_AGAIN;
    }
    AVPacket *pkt = L->av_packet_alloc();
    AVFrame *f = L->av_frame_alloc();
    if (!pkt || !f) mem_oom();
    int why = 0, result = FILE_FAILED;
    char reason[AV_ERROR_MAX_STRING_SIZE];
    int rc = media_decode_next(L, &in, pkt, f, &stop, &why);
    if (rc == MEDIA_FRAME) {
        int w = f->width, h = f->height;
        struct SwsContext *sws = NULL;
        if (w <= 0 || h <= 0 || w > MEDIA_MAX_SIDE || h > MEDIA_MAX_SIDE) {
            buf_printf(msg, "%s: %dx%d pixels, past %d a side\n", e->path, w, h, MEDIA_MAX_SIDE);
        } else if (!mem_budget_reserve(m->budget, rgba_bytes(w, h))) {
            budget_message(e->path, w, h, msg);
            result = TRY_AGAIN;
        } else if (!(sws = media_scaler(L, f, w, h))) {
            mem_budget_release(m->budget, rgba_bytes(w, h));
            buf_printf(msg, "%s: cannot convert its %s pixels\n", e->path, L->av_get_pix_fmt_name(f->format));
        } else {
            Copy *c = &e->full;
            c->bytes = rgba_bytes(w, h);
            c->pixels = mem_alloc(c->bytes);
            uint8_t *dst[4] = {c->pixels, NULL, NULL, NULL};
            int stride[4] = {w * 4, 0, 0, 0};
            L->sws_scale(sws, (const uint8_t *const *)f->data, f->linesize, 0, h, dst, stride);
            L->sws_freeContext(sws);
            c->img = (MediaImage){w, h, c->pixels, m->next_version++};
            result = DECODED;
        }
    } else if (rc == MEDIA_STOP) {
        buf_printf(msg, "%s: interrupted\n", e->path);
        result = TRY_AGAIN;
    } else {
        int code = rc == MEDIA_DAMAGED ? why : in.last_error;
        if (code) {
            media_av_error(L, code, reason, sizeof reason);
            buf_printf(msg, "%s: cannot decode the picture (%s)\n", e->path, reason);
        } else {
            buf_printf(msg, "%s: not a picture (no frame in it)\n", e->path);
        }
    }
    L->av_frame_free(&f);
    L->av_packet_free(&pkt);
    media_input_close(L, &in);
    mem_budget_release(m->budget, transient);
    return result;
}

/* Split the [w] x [h] RGBA pixels of [src] into the planes G, B, R, A of
 * [planes] (swscale's GBRAP), rows [stride] bytes apart, premultiplying
 * the colours by alpha when [premultiply]. */
static void to_planes(uint8_t *const planes[4], size_t stride, const uint8_t *src, int w, int h, bool premultiply)
{
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++, src += 4) {
            size_t i = (size_t)y * stride + (size_t)x;
            unsigned a = src[3];
            for (int k = 0; k < 3; k++) {
                unsigned c = premultiply ? (src[k] * a + 127) / 255 : src[k];
                planes[(k + 2) % 3][i] = (uint8_t)c;   /* R, G, B to planes 2, 0, 1 */
            }
            planes[3][i] = (uint8_t)a;
        }
    }
}

/* Join the [w] x [h] GBRAP [planes] (rows [stride] bytes apart) into RGBA
 * at [dst], undoing premultiplication when [premultiplied]. */
static void from_planes(uint8_t *dst, uint8_t *const planes[4], size_t stride, int w, int h, bool premultiplied)
{
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++, dst += 4) {
            size_t i = (size_t)y * stride + (size_t)x;
            unsigned a = planes[3][i];
            for (int k = 0; k < 3; k++) {
                unsigned c = planes[(k + 2) % 3][i];
                if (premultiplied && a != 255) c = a ? (c * 255u + a / 2) / a : 0;
                dst[k] = (uint8_t)(c > 255 ? 255 : c);
            }
            dst[3] = (uint8_t)a;
        }
    }
}

/* A plane's row length for [w] pixels, and its size for [h] rows: rows
 * aligned and padded, as swscale's vector code reads and writes past a
 * row's last pixel. */
static size_t plane_stride(int w) { return ((size_t)w + 63) / 64 * 64; }
static size_t plane_bytes(int w, int h) { return plane_stride(w) * (size_t)(h + 1) + 64; }

static bool has_alpha(const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (p[i * 4 + 3] != 255) return true;
    return false;
}

/* [e]'s picture resized to [w] x [h] (made and kept when new); NULL with
 * the reason appended to [msg] (the budget). The scaling is done on
 * planes (GBRAP): swscale filters packed RGBA through YUV, which does not
 * even keep a flat alpha of 128 at 128. */
static const MediaImage *resized(MediaCache *m, const AvLib *L, ImageEntry *e, int w, int h, double now, Buf *msg)
{
    for (int i = 0; i < e->ncopies; i++) {
        if (e->copies[i].img.w == w && e->copies[i].img.h == h) {
            e->copies[i].used = now;
            return &e->copies[i].img;
        }
    }
    const Copy *src = &e->full;
    int sw = src->img.w, sh = src->img.h;
    size_t sn = plane_bytes(sw, sh), dn = plane_bytes(w, h), ss = plane_stride(sw), ds = plane_stride(w);
    size_t bytes = rgba_bytes(w, h), scratch = 4 * (sn + dn);   /* the copy; both sizes' planes */
    if (!mem_budget_reserve(m->budget, bytes)) {
        budget_message(e->path, w, h, msg);
        return NULL;
    }
    if (!mem_budget_reserve(m->budget, scratch)) {
        mem_budget_release(m->budget, bytes);
        budget_message(e->path, w, h, msg);
        return NULL;
    }
    struct SwsContext *sws = L->sws_getContext(sw, sh, AV_PIX_FMT_GBRAP, w, h, AV_PIX_FMT_GBRAP,
                                               SWS_BILINEAR | SWS_ACCURATE_RND, NULL, NULL, NULL);
    if (!sws) {
        mem_budget_release(m->budget, bytes + scratch);
        buf_printf(msg, "%s: cannot resize the picture to %dx%d\n", e->path, w, h);
        return NULL;
    }
    bool alpha = has_alpha(src->pixels, (size_t)sw * (size_t)sh);
    uint8_t *planes = mem_alloc(scratch);
    uint8_t *in[4] = {planes, planes + sn, planes + 2 * sn, planes + 3 * sn};
    uint8_t *out[4] = {planes + 4 * sn, planes + 4 * sn + dn, planes + 4 * sn + 2 * dn, planes + 4 * sn + 3 * dn};
    int in_stride[4] = {(int)ss, (int)ss, (int)ss, (int)ss}, out_stride[4] = {(int)ds, (int)ds, (int)ds, (int)ds};
    to_planes(in, ss, src->pixels, sw, sh, alpha);
    L->sws_scale(sws, (const uint8_t *const *)in, in_stride, 0, sh, out, out_stride);
    L->sws_freeContext(sws);
    /* the slot: a free one, else the least recently asked copy's */
    int slot = e->ncopies;
    if (slot == MAX_COPIES) {
        slot = 0;
        for (int i = 1; i < MAX_COPIES; i++)
            if (e->copies[i].used < e->copies[slot].used) slot = i;
        copy_free(m, &e->copies[slot]);
    } else {
        e->ncopies++;
    }
    Copy *c = &e->copies[slot];
    c->bytes = bytes;
    c->pixels = mem_alloc(bytes);
    from_planes(c->pixels, out, ds, w, h, alpha);
    free(planes);
    mem_budget_release(m->budget, scratch);
    c->img = (MediaImage){w, h, c->pixels, m->next_version++};
    c->used = now;
    return &c->img;
}

const MediaImage *media_image(MediaCache *m, const char *path, int w, int h, Buf *err, bool *fresh)
{
    if (fresh) *fresh = false;
    if (!m || !path || !*path) {
        if (err) buf_printf(err, "%s: no such file\n", path && *path ? path : "(no file name)");
        if (fresh) *fresh = true;
        return NULL;
    }
    double now = media_now();
    ImageEntry *e = entry_for(m, path);
    e->used = now;
    struct stat sb;
    int serr = stat(path, &sb) == 0 ? 0 : errno;
    if (!same_file(e, serr, &sb)) {   /* new, changed, gone or back: read again */
        entry_clear(m, e);
        e->known = true;
        e->stat_errno = serr;
        if (!serr) {
            e->dev = sb.st_dev;
            e->ino = sb.st_ino;
            e->size = sb.st_size;
            e->mtime = sb.st_mtim;
        }
        free(e->last_message);   /* the file changed: its failures are news again */
        e->last_message = NULL;
        if (serr)
            e->failure = mem_asprintf("%s: %s", path, serr == ENOENT ? "no such file" : strerror(serr));
        else if (S_ISDIR(sb.st_mode))
            e->failure = mem_asprintf("%s: not a picture (a folder)", path);
    }
    const MediaImage *result = NULL;
    const AvLib *L = NULL;
    Buf msg = BUF_INIT;   /* why there is no picture */
    if (e->failure) {
        buf_puts(&msg, e->failure);
    } else if (w > MEDIA_MAX_SIDE || h > MEDIA_MAX_SIDE) {
        buf_printf(&msg, "%s: size %dx%d past %d a side\n", path, w, h, MEDIA_MAX_SIDE);
    } else if (!(L = media_lib(m, path, &msg))) {
        /* msg says why */
    } else if (!e->full.pixels) {
        int rc = decode_file(m, L, e, &msg);
        if (rc == FILE_FAILED) e->failure = mem_strdup(buf_line(&msg));
    }
    if (L && e->full.pixels) {
        if (w > 0 && h > 0 && (w != e->full.img.w || h != e->full.img.h)) {
            result = resized(m, L, e, w, h, now, &msg);
        } else {
            e->full.used = now;
            result = &e->full.img;
        }
    }
    if (result) {
        buf_free(&msg);
        return result;
    }
    const char *text = buf_line(&msg);
    if (err) buf_printf(err, "%s\n", text);
    bool news = !e->last_message || strcmp(e->last_message, text) != 0;
    if (news) {
        free(e->last_message);
        e->last_message = mem_strdup(text);
    }
    if (fresh) *fresh = news;
    buf_free(&msg);
    return NULL;
}
