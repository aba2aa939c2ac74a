/* media_cache.c: the MediaCache itself (media.h): made and freed here, with
 * FFmpeg loaded for it the first time a picture or a video needs it. Its
 * pictures are kept by media_image.c, its videos by media_video.c.
 *
 * Each cache loads its own AvLib (avlib.h: the libraries are opened once
 * per process, so a second cache's load is a lookup); when loading fails
 * the reason is kept and given again without trying again. FFmpeg's log
 * level is lowered from its default (AV_LOG_INFO) to AV_LOG_ERROR as
 * render/output/video.c does; a host that chose its own level keeps it. */
#include "media_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "mem.h"

MediaCache *media_cache_new(MemBudget *budget, volatile int *interrupt)
{
    MediaCache *m = mem_calloc(1, sizeof *m);
    m->budget = budget;
    m->interrupt = interrupt;
    m->next_version = 1;
    m->next_video = 1;
    return m;
}

void media_cache_free(MediaCache *m)
{
    if (!m) return;
    media_videos_close_all(m);
    media_images_free(m);
    free(m->L);
    free(m);
}

void media_cache_expire(MediaCache *m, double age)
{
    if (!m || isnan(age)) return;
    media_images_expire(m, media_now() - age);
}

const AvLib *media_lib(MediaCache *m, const char *path, Buf *err)
{
    if (m->L) return m->L;
    if (!m->lib_failure[0]) {
        Buf why = BUF_INIT;
        if ((m->L = avlib_load(&why)) != NULL) {
            buf_free(&why);
            /* FFmpeg's own lines (a decoder's complaint about a bad file)
             * would come beside ours, which carry the reason: only its
             * fatal ones, unless the embedder set a level of its own */
            if (m->L->av_log_get_level() == AV_LOG_INFO) m->L->av_log_set_level(AV_LOG_FATAL);
            return m->L;
        }
        snprintf(m->lib_failure, sizeof m->lib_failure, "%s", buf_line(&why));
        buf_free(&why);
    }
    buf_printf(err, "%s: %s\n", path, m->lib_failure);
    return NULL;
}
