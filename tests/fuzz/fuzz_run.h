/* fuzz_run.h: what the script targets do with an input: load it as a
 * program and, when it parses, evaluate and simulate three frames and dump
 * the state and node tree (within the time budget, fuzz_budget.h). */
#ifndef FL_FUZZ_RUN_H
#define FL_FUZZ_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"

/* One runtime for [data], on the routes of [debug] (NULL: the defaults):
 * loaded, then (when [frames]) three frames and the dumps; errors are the
 * script's, not findings. */
static void fuzz_run_script(const uint8_t *data, size_t size, bool frames, const fl_debug_options *debug)
{
    fl_options o = fl_default_options();
    if (debug) o.debug = *debug;
    o.frames = 3;
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &fuzz_interrupt;
    /* a memory budget well inside run.sh's -malloc_limit_mb and
     * -rss_limit_mb (4 GB, with the sanitizers' own on top): a system too
     * large for it is refused with a physics error, which is what the
     * budget is for, rather than taking the fuzzer's limit as a finding */
    o.max_memory = (size_t)1 << 30;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, out = BUF_INIT;
    if (rt_load_text(rt, "fuzz.fl", (const char *)data, size, &err) == 0 && frames) {
        for (int i = 0; i < 3 && !fuzz_interrupt; i++)
            fl_step(rt);
        /* the dumps of what the frames made, unless the budget ran out:
         * a state of a huge system (40 particles in a million dimensions)
         * takes seconds to write as text, and a dump, as a save after
         * Ctrl-C, writes everything */
        if (!fuzz_interrupt) {
            fmt_state_dump(&out, rt_state(rt), fl_frame_count(rt) - 1, fl_frame_time(rt),
                           rt_symbols(rt));
            if (rt_root(rt))
                fmt_tree(&out, rt_root(rt), rt_symbols(rt));
        }
    }
    buf_free(&err);
    buf_free(&out);
    fl_free(rt);
}

#endif
