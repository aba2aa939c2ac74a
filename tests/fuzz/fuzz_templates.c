/* fuzz_templates.c: libFuzzer target for the template passes of the
 * simplifier (lib/eval/simplify_template.c, issue 24). The input is loaded
 * with FLITTER_TEMPLATE_CHECK=1, which simplifies every templated copy of
 * an unrolled loop also on its own and aborts when the two trees differ:
 * a finding is a loop whose copies the passes got wrong. It is then loaded
 * again without the check, so that runs of copies become loops over hidden
 * names, and three frames are evaluated: any crash, sanitizer report, leak
 * or hang there is a finding too. Syntax and run-time errors are not. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"

/* One load of [data] (with [check] copies compared), three frames when
 * [frames], then the state and tree dumps. */
static void run(const uint8_t *data, size_t size, bool check, bool frames)
{
    /* the simplifier reads the variable when a load starts */
    if (check) setenv("FLITTER_TEMPLATE_CHECK", "1", 1);
    else unsetenv("FLITTER_TEMPLATE_CHECK");
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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_budget_start();
    run(data, size, true, false);
    run(data, size, false, true);
    return 0;
}
