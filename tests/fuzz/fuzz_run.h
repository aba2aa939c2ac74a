/* fuzz_run.h: what the script targets do with an input: load it as a
 * program and, when it parses, evaluate and simulate three frames and dump
 * the state and node tree (within the time budget, fuzz_budget.h). */
#ifndef FL_FUZZ_RUN_H
#define FL_FUZZ_RUN_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"
#include "node.h"

/* The most numbers (and strings) in a tree's attributes that the targets
 * write out as text: a legitimate script can make millions in one frame
 * (`b=1..0|-0.2u`, five million) and writing them takes seconds (flitter
 * run --dump-tree: 14 s for that one; more under the sanitizers, where it
 * ran past libFuzzer's timeout). Like a state past the time budget, a
 * larger tree is not written: the frames that made it were fuzzed. */
#define FUZZ_DUMP_NUMBERS 1000000

/* The nodes of [root]'s tree and the items in their attributes, counted up to a little
 * past FUZZ_DUMP_NUMBERS (depth-first with a stack of its own: a deep
 * tree cannot exhaust the C stack). */
static size_t fuzz_tree_items(const Node *root)
{
    size_t n = 0, depth = 0, cap = 64;
    const Node **stack = malloc(cap * sizeof *stack);
    if (!stack) return (size_t)-1;
    stack[depth++] = root;
    while (depth > 0 && n <= FUZZ_DUMP_NUMBERS) {
        const Node *nd = stack[--depth];
        n++;   /* (its line) */
        for (uint32_t i = 0; i < nd->nattrs; i++) n += vec_len(nd->attrs[i].value);
        for (uint32_t i = 0; i < nd->nchildren; i++) {
            if (depth == cap) {
                const Node **more = realloc(stack, 2 * cap * sizeof *stack);
                if (!more) {
                    free(stack);
                    return (size_t)-1;
                }
                stack = more;
                cap *= 2;
            }
            stack[depth++] = nd->children[i];
        }
    }
    free(stack);
    return n;
}

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
            if (rt_root(rt) && fuzz_tree_items(rt_root(rt)) <= FUZZ_DUMP_NUMBERS)
                fmt_tree(&out, rt_root(rt), rt_symbols(rt));
        }
    }
    buf_free(&err);
    buf_free(&out);
    fl_free(rt);
}

#endif
