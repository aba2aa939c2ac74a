/* runscript.h: what the evaluation-route tests (test_fastroute.c,
 * test_kernel.c) share: a script run through a fresh runtime for a few
 * frames, with its last frame's node tree and its log as text. The
 * caller sets the environment that picks the route first (FLITTER_NOFAST,
 * FLITTER_NOKERNEL, FLITTER_THREADS: read when the runtime is made and
 * the script compiled). Header-only, a static function; the test files
 * include cmocka.h before it. */
#ifndef FL_TEST_RUNSCRIPT_H
#define FL_TEST_RUNSCRIPT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "format.h"
#include "runtime.h"

/* The memory budget of the runs (fl_options.max_memory; 0: the default). */
static size_t run_script_budget;
/* fl_options.transient_tree of the runs. */
static bool run_script_transient;
/* fl_options.threads and fl_options.debug of the runs (the routes). */
static int run_script_threads;
static fl_debug_options run_script_debug;
/* The last run_script's iterations run as straight bodies
 * (rt_kernel_straight). */
static uint64_t run_script_straight;

/* A new runtime with [src] (named [name]) loaded, with or without the
 * simplifier, under run_script_budget, logging to [streams] (which must
 * outlive it). */
static fl_runtime *script_runtime(const char *name, const char *src, bool simplify, RtStreams *streams)
{
    fl_options o = fl_default_options();
    rt_log_to_files(&o, streams);
    o.no_simplify = !simplify;
    o.max_memory = run_script_budget;
    o.transient_tree = run_script_transient;
    o.threads = run_script_threads;
    o.debug = run_script_debug;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT;
    assert_int_equal(rt_load_text(rt, name, src, strlen(src), &err), 0);
    buf_free(&err);
    return rt;
}

/* The tree dump of the last of [frames] frames of [src] (named [name]),
 * with or without the simplifier; the log in *[log_out] and, when
 * [kiters] is not NULL, the loop iterations run with kernels
 * (rt_kernel_iterations) in *[kiters]. Both strings are the caller's to
 * free. */
static char *run_script(const char *name, const char *src, int frames, bool simplify, char **log_out,
                        uint64_t *kiters)
{
    char *log = NULL;
    size_t loglen;
    FILE *lf = open_memstream(&log, &loglen);
    RtStreams streams = {lf, lf};
    fl_runtime *rt = script_runtime(name, src, simplify, &streams);
    for (int i = 0; i < frames; i++) fl_step(rt);
    Buf t = BUF_INIT;
    fmt_tree(&t, rt_root(rt), rt_symbols(rt));
    char *tree = strdup(buf_cstr(&t));
    buf_free(&t);
    if (kiters) *kiters = rt_kernel_iterations(rt);
    run_script_straight = rt_kernel_straight(rt);
    fl_free(rt);
    fclose(lf);
    *log_out = log;
    return tree;
}

#endif
