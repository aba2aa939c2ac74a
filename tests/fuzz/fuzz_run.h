/* fuzz_run.h: what the script targets do with an input: load it as a
 * program and, when it parses, evaluate and simulate three frames and dump
 * the state and node tree. */
#ifndef FL_FUZZ_RUN_H
#define FL_FUZZ_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"

/* One runtime for [data]: loaded, then (when [frames]) three frames and
 * the dumps; errors are the script's, not findings. */
static void fuzz_run_script(const uint8_t *data, size_t size, bool frames)
{
    fl_options o = fl_default_options();
    o.frames = 3;
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &fuzz_interrupt;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, out = BUF_INIT;
    if (rt_load_text(rt, "fuzz.fl", (const char *)data, size, &err) == 0 && frames) {
        for (int i = 0; i < 3 && !fuzz_interrupt; i++)
            fl_step(rt);
        fmt_state_dump(&out, rt_state(rt), fl_frame_count(rt) - 1, fl_frame_time(rt),
                       rt_symbols(rt));
        if (rt_root(rt))
            fmt_tree(&out, rt_root(rt), rt_symbols(rt));
    }
    buf_free(&err);
    buf_free(&out);
    fl_free(rt);
}

#endif
