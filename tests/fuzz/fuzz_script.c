/* fuzz_script.c: libFuzzer target for script text (issue 13): the input is
 * loaded as a program; when it parses, three frames are evaluated and
 * simulated and the state and node tree are dumped. Any crash, sanitizer
 * report, leak or hang is a finding; syntax and run-time errors are not. */
#include <stddef.h>
#include <stdint.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fl_options o = fl_default_options();
    o.frames = 3;
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &fuzz_interrupt;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, out = BUF_INIT;
    fuzz_budget_start();
    if (rt_load_text(rt, "fuzz.fl", (const char *)data, size, &err) == 0) {
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
    return 0;
}
