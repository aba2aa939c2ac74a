/* pass_video.c: the `!video` pass (Flitter docs/windows.md, "!video";
 * render/window/video.py): a program pass whose two inputs are the frames
 * around position= (media.h maps it with loop=, back_and_forth= and
 * trim=), uploaded into two 8-bit sRGB textures that are swapped rather
 * than uploaded again when playback moves on by one frame, mixed by the
 * fraction between them with interpolate=true, and placed by aspect=
 * (:fit, :fill; else stretched). In a live window (a realtime clock) a
 * frame the decoding thread has not reached yet is not waited for: the
 * nearest decoded one is shown; recording on the lockstep clock waits for
 * every exact frame. */
#include <string.h>
#include <sys/stat.h>

#include "graph_internal.h"
#include "media.h"
#include "pass_program.h"
#include "rnode.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

typedef struct VideoPass {
    ProgramPass prog;
    MediaVideo *video;
    Buf path;                /* the file [video] reads */
    bool threads;            /* thread= it was opened with */
    GLuint tex[2];           /* frame0, frame1 */
    int tw, th;              /* their size */
    uint64_t serial[2];      /* the frames they hold (0: none) */
    /* the file that failed to open, as it was then: not opened again
     * (every frame) until it changes */
    Buf failed;
    struct stat failed_st;
    bool failed_exists;
} VideoPass;

/* Whether [path] is the file that failed to open last, unchanged. */
static bool failed_before(const VideoPass *vp, const char *path)
{
    if (!vp->failed.len || strcmp(vp->failed.data, path) != 0) return false;
    struct stat st;
    bool exists = stat(path, &st) == 0;
    if (exists != vp->failed_exists) return false;
    return !exists || (st.st_mtim.tv_sec == vp->failed_st.st_mtim.tv_sec &&
                       st.st_mtim.tv_nsec == vp->failed_st.st_mtim.tv_nsec && st.st_size == vp->failed_st.st_size &&
                       st.st_ino == vp->failed_st.st_ino);
}

static bool attr_flag(const Node *n, const char *name)
{
    const Vec *v = rnode_attr(n, name);
    return v && vec_truthy(v);
}

/* Frame [f] into texture [k] unless it holds it already. */
static void upload(VideoPass *vp, int k, const MediaFrame *f)
{
    if (!f || vp->serial[k] == f->serial) return;
    glBindTexture(GL_TEXTURE_2D, vp->tex[k]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f->w, f->h, GL_RGBA, GL_UNSIGNED_BYTE, f->rgba);
    glBindTexture(GL_TEXTURE_2D, 0);
    vp->serial[k] = f->serial;
}

static void drop_textures(VideoPass *vp)
{
    if (vp->tex[0]) glDeleteTextures(2, vp->tex);
    vp->tex[0] = vp->tex[1] = 0;
    vp->serial[0] = vp->serial[1] = 0;
    vp->tw = vp->th = 0;
}

static void no_picture(Graph *g, Pass *p)
{
    target_release(g->pool, p->target);
    p->target = NULL;
}

static void render_video(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    VideoPass *vp = (VideoPass *)p;
    Buf name = BUF_INIT, path = BUF_INIT, aspect = BUF_INIT, err = BUF_INIT;
    if (!canvas_attr_str(n, "filename", g->env.symbols, &name) || name.len == 0) {
        no_picture(g, p);
        goto done;
    }
    graph_path(g, buf_cstr(&name), &path);
    bool threads = attr_flag(n, "thread");
    if (vp->video && (strcmp(buf_cstr(&vp->path), buf_cstr(&path)) != 0 || vp->threads != threads ||
                      !media_video_current(vp->video, buf_cstr(&path)))) {
        media_video_close(vp->video);
        vp->video = NULL;
    }
    if (!vp->video && failed_before(vp, buf_cstr(&path))) {
        no_picture(g, p);
        goto done;
    }
    if (!vp->video) {
        vp->video = media_video_open(graph_media(g), buf_cstr(&path), threads, &err);
        if (!vp->video) {
            graph_note(g, RLOG_ERROR, "video: %s", buf_line(&err));
            buf_reset(&vp->failed);
            buf_puts(&vp->failed, buf_cstr(&path));
            vp->failed_exists = stat(buf_cstr(&path), &vp->failed_st) == 0;
            no_picture(g, p);
            goto done;
        }
        buf_reset(&vp->failed);
        buf_reset(&vp->path);
        buf_puts(&vp->path, buf_cstr(&path));
        vp->threads = threads;
        vp->serial[0] = vp->serial[1] = 0;
    }
    double position = 0, trim[2] = {0, 0}, ratio = 0;
    canvas_attr_nums(n, "position", 1, &position);
    canvas_attr_nums(n, "trim", 2, trim);
    const MediaFrame *f0 = NULL, *f1 = NULL;
    bool wait = !(g->f && g->f->realtime);
    if (!media_video_frames(vp->video, position, attr_flag(n, "loop"), attr_flag(n, "back_and_forth"), trim[0],
                            trim[1], wait, &ratio, &f0, &f1, &err)) {
        if (err.len) graph_note(g, RLOG_ERROR, "video: %s", buf_line(&err));
        if (!f0) {
            no_picture(g, p);
            goto done;
        }
    }
    if (!f0) {
        no_picture(g, p);
        goto done;
    }
    if (vp->tw != f0->w || vp->th != f0->h) {
        drop_textures(vp);
        glGenTextures(2, vp->tex);
        for (int k = 0; k < 2; k++) {
            glBindTexture(GL_TEXTURE_2D, vp->tex[k]);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, f0->w, f0->h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        }
        glBindTexture(GL_TEXTURE_2D, 0);
        vp->tw = f0->w;
        vp->th = f0->h;
    }
    /* playback moving on by a frame: the textures change places */
    if ((f0->serial == vp->serial[1] && vp->serial[1]) || (f1 && f1->serial == vp->serial[0] && vp->serial[0])) {
        GLuint t = vp->tex[0];
        vp->tex[0] = vp->tex[1];
        vp->tex[1] = t;
        uint64_t s = vp->serial[0];
        vp->serial[0] = vp->serial[1];
        vp->serial[1] = s;
    }
    upload(vp, 0, f0);
    upload(vp, 1, f1 && f1->w == f0->w && f1->h == f0->h ? f1 : f0);
    canvas_attr_str(n, "aspect", g->env.symbols, &aspect);
    int mode = strcmp(buf_cstr(&aspect), "fit") == 0 ? 1 : strcmp(buf_cstr(&aspect), "fill") == 0 ? 2 : 0;
    double frame_size[2] = {f0->w, f0->h};
    Kw kw[3] = {{"frame_size", {vec_from_nums(frame_size, 2), TPL_LIST}},
                {"aspect_mode", {vec_num1(mode), TPL_INT}},
                {"ratio", {vec_num1(attr_flag(n, "interpolate") ? ratio : 0), TPL_FLOAT}}};
    ChildTex kids[2] = {{"frame0", vp->tex[0], 0, 0}, {"frame1", vp->tex[1], 0, 0}};
    ProgramParams pr = {.fragment = "video.frag", .vertex = "video.vert", .kwargs = kw, .nkwargs = 3,
                        .children = kids, .nchildren = 2};
    program_render(g, &vp->prog, n, cx, &pr);
    for (int k = 0; k < 3; k++) tpl_value_free(&kw[k].value);
done:
    buf_free(&name);
    buf_free(&path);
    buf_free(&aspect);
    buf_free(&err);
}

static void release_video(Graph *g, Pass *p)
{
    VideoPass *vp = (VideoPass *)p;
    media_video_close(vp->video);
    vp->video = NULL;
    drop_textures(vp);
    buf_free(&vp->path);
    buf_free(&vp->failed);
    program_pass_release(g, p);
}

/* Flitter Video.similar_to: the same file too. */
static bool similar_video(const Pass *p, const Node *n, Graph *g)
{
    const VideoPass *vp = (const VideoPass *)p;
    Buf name = BUF_INIT, path = BUF_INIT;
    bool same = false;
    if (canvas_attr_str(n, "filename", g->env.symbols, &name)) {
        graph_path(g, buf_cstr(&name), &path);
        same = strcmp(buf_cstr(&path), buf_cstr((Buf *)&vp->path)) == 0;
    } else {
        same = vp->path.len == 0;
    }
    buf_free(&name);
    buf_free(&path);
    return same;
}

const PassKind pass_video = {.kind = "video", .size = sizeof(VideoPass), .leaf = true, .similar = similar_video,
                             .render = render_video, .release = release_video};
