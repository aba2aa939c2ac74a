/* fuzz_templates.c: libFuzzer target for the template passes of the
 * simplifier (lib/eval/simplify_template.c, issue 24). The input is loaded
 * with FLITTER_TEMPLATE_CHECK=1, which simplifies every templated copy of
 * an unrolled loop also on its own and aborts when the two trees differ:
 * a finding is a loop whose copies the passes got wrong. It is then loaded
 * again without the check, so that runs of copies become loops over hidden
 * names, and three frames are evaluated: any crash, sanitizer report, leak
 * or hang there is a finding too. Syntax and run-time errors are not. */
#include <stdlib.h>

#include "fuzz_run.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_budget_start();
    /* the simplifier reads the variable when a load starts */
    setenv("FLITTER_TEMPLATE_CHECK", "1", 1);
    fuzz_run_script(data, size, false);
    unsetenv("FLITTER_TEMPLATE_CHECK");
    fuzz_run_script(data, size, true);
    return 0;
}
