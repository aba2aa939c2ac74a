/* fuzz_repl.c: libFuzzer target for REPL input (issue 13): a runtime runs a
 * small script for one frame, then every line of the input is evaluated with
 * fl_eval as `flitter repl` does (a line that ends early is continued by
 * the next); afterwards the runtime must still step. Bad lines may fail but
 * never crash, leak or hang. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"

static const char script[] =
    "%pragma tempo 90\n"
    "let xs = 1;2;3\n"
    "func f(x, y=2)\n"
    "    x * y\n"
    "!window size=640;480\n"
    "    !physics state=:p dimensions=2\n"
    "        !particle id=:a position=f(xs[0])\n"
    "        !drag strength=0.1\n";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &fuzz_interrupt;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, out = BUF_INIT, pending = BUF_INIT;
    fuzz_budget_start();
    if (rt_load_text(rt, "repl.fl", script, sizeof script - 1, &err) != 0)
        abort();
    fl_step(rt);
    const char *p = (const char *)data, *end = p + size;
    while (p < end && !fuzz_interrupt) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *stop = nl ? nl + 1 : end;
        buf_add(&pending, p, (size_t)(stop - p));
        p = stop;
        buf_reset(&out);
        buf_reset(&err);
        if (rt_eval(rt, pending.data, pending.len, &out, &err) != 1)
            buf_reset(&pending);
    }
    fl_step(rt);
    fl_eval_reset(rt);
    buf_free(&err);
    buf_free(&out);
    buf_free(&pending);
    fl_free(rt);
    return 0;
}
