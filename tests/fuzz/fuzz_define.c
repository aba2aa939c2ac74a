/* fuzz_define.c: libFuzzer target for `-D NAME=VALUE` values (issue 13):
 * the input up to its first NUL byte is split at the first '=' as the
 * runner does and given to fl_define (without '=', the whole text is the
 * value of `x`); then a script using `x` runs one frame and its tree is
 * dumped. Rejected names are fine; crashes, leaks and hangs are not. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "runtime.h"
#include "format.h"
#include "fuzz_budget.h"

static const char script[] = "!define value=x n=len(x) s=str(x)\n";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        abort();
    memcpy(text, data, size);
    text[size] = '\0';
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &fuzz_interrupt;
    fl_runtime *rt = fl_new(&o);
    fuzz_budget_start();
    char *eq = strchr(text, '=');
    if (eq) {
        *eq = '\0';
        fl_define(rt, text, eq + 1);
    } else {
        fl_define(rt, "x", text);
    }
    Buf err = BUF_INIT, out = BUF_INIT;
    if (rt_load_text(rt, "define.fl", script, sizeof script - 1, &err) != 0)
        abort();
    fl_step(rt);
    fmt_tree(&out, rt_root(rt), rt_symbols(rt));
    buf_free(&err);
    buf_free(&out);
    fl_free(rt);
    free(text);
    return 0;
}
