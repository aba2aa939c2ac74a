/* outputs.c: the pictures and trajectories a run writes after its frames
 * (flitter.h, "Pictures and trajectories"): the windows' !record files
 * (the runtime's render graph, pictures.h), the --view picture or
 * animation of the !physics systems (render/view/view.h) and the --trace
 * rows (render/view/trace.h).
 */
#include "runtime.h"

#include <math.h>
#include <stdlib.h>

#include "mem.h"
#include "outfile.h"
#include "systems.h"
#include "trace.h"
#include "view.h"
#include "canvas.h"
#include "pictures.h"

_Static_assert((int)RLOG_ERROR == (int)FL_LOG_ERROR && (int)RLOG_WARNING == (int)FL_LOG_WARNING,
               "the renderer's log kinds are flitter.h's");

struct fl_outputs {
    char *view_path, *trace_path;
    long view_every, trace_every;
    long frames;           /* fl_outputs_frame calls so far */
    View *view;
    Trace *trace;
    bool failed;
    bool record_failed;    /* a window's !record file could not be written */
};

/* The GIF frame delay of a picture every [every] frames at [fps], in
 * hundredths of a second (GIF delays are 1..65535). */
static int gif_delay(long every, double fps)
{
    double cs = 100.0 * (double)(every > 0 ? every : 1) / fps;
    return cs >= 65535 ? 65535 : cs <= 1 ? 1 : (int)lround(cs);
}

fl_outputs *fl_outputs_open(fl_runtime *rt, const fl_output_options *opts)
{
    if (!rt) return NULL;
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    fl_output_options none = {0};
    const fl_output_options *o = opts ? opts : &none;
    fl_outputs *out = mem_calloc(1, sizeof *out);
    Buf err = BUF_INIT;
    RenderLog log = {NULL, NULL, o->debug};
    rt_log_target(rt, &log.fn, &log.ctx);
    if (o->view) {
        out->view_path = mem_strdup(o->view);
        out->view_every = o->view_every;
        out->view = view_open(o->view, gif_delay(o->view_every, fl_target_fps(rt)),
                              rt_symbols(rt), &err);
        if (!out->view) goto fail;
        view_set_style(out->view, rt_options(rt)->view_axes, &log);
    }
    if (o->trace) {
        out->trace_path = mem_strdup(o->trace);
        out->trace_every = o->trace_every;
        out->trace = trace_open(o->trace, rt_symbols(rt), &err);
        if (!out->trace) goto fail;
    }
    pictures_record_first(rt_pictures(rt), o->record);
    buf_free(&err);
    mem_leave(prev);
    return out;
fail:
    rt_fail(rt, "%s", buf_line(&err));
    buf_free(&err);
    view_close(out->view);
    trace_close(out->trace);
    free(out->view_path);
    free(out->trace_path);
    free(out);
    mem_leave(prev);
    return NULL;
}

static bool due(long frame, long every) { return every <= 1 || frame % every == 0; }

int fl_outputs_frame(fl_outputs *out, fl_runtime *rt)
{
    if (!rt) return -1;
    if (!out) return rt_fail(rt, "fl_outputs_frame: [out] is NULL");
    MemHandler prev = rt_enter(rt);
    long frame = fl_frame_count(rt) - 1;
    out->frames++;
    int rc = 0;
    /* (the graph is touched only when the frame is drawn for its files:
     * otherwise a drawing thread may be drawing it, fl_outputs_draws) */
    if (pictures_draws_for_files(rt_pictures(rt), rt_root(rt)) && rt_render(rt, false) > 0)
        out->record_failed = true;
    bool gif = out->view && view_animated(out->view) && due(frame, out->view_every);
    bool trace = out->trace && due(frame, out->trace_every);
    if (gif || trace) {
        PsSystem *sys;
        size_t n;
        ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
        Buf err = BUF_INIT;
        if (gif && view_frame(out->view, frame, sys, n, &err) != 0) {
            rt_fail(rt, "%s", buf_line(&err));
            view_close(out->view);
            out->view = NULL;
            out->failed = true;
            rc = -1;
        }
        buf_free(&err);
        if (trace && trace_frame(out->trace, frame, fl_frame_time(rt), sys, n) != 0) {
            rt_fail(rt, "%s: cannot write the trace", out->trace_path);
            trace_close(out->trace);
            out->trace = NULL;
            out->failed = true;
            rc = -1;
        }
        ps_free(sys, n);
    }
    mem_leave(prev);
    return rc;
}

bool fl_outputs_draws(const fl_outputs *out, fl_runtime *rt)
{
    if (!out || !rt) return false;
    /* the --view animation's frame may draw a 3D system through OpenGL */
    long frame = fl_frame_count(rt) - 1;
    if (frame >= 0 && out->view && view_animated(out->view) && due(frame, out->view_every)) return true;
    return pictures_draws_for_files(rt_pictures(rt), rt_root(rt)) && !rt_no_draw(rt);
}

/* Draw [rt]'s systems now into [v] as frame [frame]; -1 with [err] set on
 * failure. */
static int view_now(fl_runtime *rt, View *v, long frame, size_t *nsystems, Buf *err)
{
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    int rc = view_frame(v, frame, sys, n, err);
    ps_free(sys, n);
    if (nsystems) *nsystems = n;
    return rc;
}

int fl_outputs_close(fl_outputs *out, fl_runtime *rt)
{
    if (!out) return 0;
    if (!rt) {
        /* no runtime: no final picture, no message; close and free the rest */
        view_close(out->view);
        trace_close(out->trace);
        free(out->view_path);
        free(out->trace_path);
        free(out);
        return -1;
    }
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    int rc = out->failed ? -1 : 0;
    Buf err = BUF_INIT;
    if (out->view && !view_animated(out->view) && out->frames > 0 &&
        view_now(rt, out->view, fl_frame_count(rt) - 1, NULL, &err) != 0) {
        rt_fail(rt, "%s", buf_line(&err));
        rc = -1;
    }
    buf_free(&err);
    if (view_close(out->view) != 0) {
        rt_fail(rt, "%s: cannot finish the GIF", out->view_path);
        rc = -1;
    }
    if (out->trace && trace_close(out->trace) != 0) {
        rt_fail(rt, "%s: cannot write the trace", out->trace_path);
        rc = -1;
    }
    pictures_record_first(rt_pictures(rt), NULL);
    if (pictures_finish_records(rt_pictures(rt)) != 0) rc = -1;
    if (out->record_failed && rc == 0) {
        /* each file's first error was logged as it happened */
        rt_fail(rt, "a !record file could not be written (the error is above)");
        rc = -1;
    }
    free(out->view_path);
    free(out->trace_path);
    free(out);
    mem_leave(prev);
    return rc;
}

int fl_view(fl_runtime *rt, const char *path, size_t *nsystems)
{
    if (!rt) return -1;
    if (!path) return rt_fail(rt, "fl_view: [path] is NULL");
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    Buf err = BUF_INIT;
    int rc = 0;
    View *v = view_open(path, 10, rt_symbols(rt), &err);
    if (!v) {
        rt_fail(rt, "%s", buf_line(&err));
        rc = -1;
    } else {
        RenderLog log = {NULL, NULL, false};
        rt_log_target(rt, &log.fn, &log.ctx);
        view_set_style(v, rt_options(rt)->view_axes, &log);
        rc = view_now(rt, v, fl_frame_count(rt) - 1, nsystems, &err);
        if (rc != 0) rt_fail(rt, "%s", buf_line(&err));
        if (view_close(v) != 0 && rc == 0) {
            rt_fail(rt, "%s: cannot finish the file", path);
            rc = -1;
        }
    }
    buf_free(&err);
    mem_leave(prev);
    return rc;
}

int fl_check_output(const char *path, char *err, size_t cap)
{
    Buf msg = BUF_INIT;
    bool ok = path && outfile_check(path, &msg);
    if (err && cap) snprintf(err, cap, "%s", ok ? "" : path ? buf_line(&msg) : "no file name");
    buf_free(&msg);
    return ok ? 0 : -1;
}

bool fl_parse_view_axes(const char *text, int out[2])
{
    return out && view_parse_axes(text, out);
}
