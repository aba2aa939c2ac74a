/* outputs.c: windows, --view and --trace after each frame (outputs.h). */
#include "outputs.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "runtime.h"   /* internal: the node tree and symbols for the renderers */
#include "systems.h"
#include "trace.h"
#include "view.h"
#include "window.h"

struct Outputs {
    const RunSpec *spec;
    FILE *log;
    Renderer *ren;
    View *view;
    Trace *trace;
    bool failed;
};

Outputs *outputs_new(const RunSpec *spec, fl_runtime *rt, FILE *log)
{
    Outputs *o = calloc(1, sizeof *o);
    if (!o) abort();
    o->spec = spec;
    o->log = log;
    char err[600];
    if (spec->view) {
        long every = spec->view_every > 0 ? spec->view_every : 1;
        double cs = 100.0 * (double)every / spec->fps;   /* GIF delays are 1..65535 cs */
        int delay = cs >= 65535 ? 65535 : cs <= 1 ? 1 : (int)lround(cs);
        o->view = view_open(spec->view, delay, rt_symbols(rt), err, sizeof err);
        if (!o->view) goto fail;
    }
    if (spec->trace) {
        o->trace = trace_open(spec->trace, rt_symbols(rt), err, sizeof err);
        if (!o->trace) goto fail;
    }
    o->ren = renderer_new(rt_symbols(rt), log, spec->verbosity >= 2 ? log : NULL);
    return o;
fail:
    fprintf(log, "flitter run: %s\n", err);
    view_close(o->view);
    trace_close(o->trace);
    free(o);
    return NULL;
}

static bool due(long frame, long every) { return every <= 1 || frame % every == 0; }

void outputs_frame(Outputs *o, fl_runtime *rt, long frame)
{
    const RunSpec *spec = o->spec;
    renderer_frame(o->ren, rt_root(rt), spec->fps);
    bool gif = o->view && view_animated(o->view) && due(frame, spec->view_every);
    bool trace = o->trace && due(frame, spec->trace_every);
    if (!gif && !trace) return;
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    char err[600];
    if (gif && view_frame(o->view, frame, sys, n, err, sizeof err) != 0) {
        fprintf(o->log, "flitter run: %s\n", err);
        view_close(o->view);
        o->view = NULL;
        o->failed = true;
    }
    if (trace && trace_frame(o->trace, frame, fl_frame_time(rt), sys, n) != 0) {
        fprintf(o->log, "flitter run: %s: cannot write the trace\n", spec->trace);
        trace_close(o->trace);
        o->trace = NULL;
        o->failed = true;
    }
    ps_free(sys, n);
}

int outputs_finish(Outputs *o, fl_runtime *rt, long frames_run)
{
    if (!o) return 0;
    int rc = o->failed ? -1 : 0;
    if (o->view && !view_animated(o->view) && frames_run > 0) {
        PsSystem *sys;
        size_t n;
        char err[600];
        ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
        if (view_frame(o->view, fl_frame_count(rt) - 1, sys, n, err, sizeof err) != 0) {
            fprintf(o->log, "flitter run: %s\n", err);
            rc = -1;
        }
        ps_free(sys, n);
    }
    if (view_close(o->view) != 0) {
        fprintf(o->log, "flitter run: %s: cannot finish the GIF\n", o->spec->view);
        rc = -1;
    }
    if (o->trace && trace_close(o->trace) != 0) {
        fprintf(o->log, "flitter run: %s: cannot write the trace\n", o->spec->trace);
        rc = -1;
    }
    if (renderer_free(o->ren) != 0) rc = -1;
    free(o);
    return rc;
}
