/* fuzz_templates.c: libFuzzer target for the template passes of the
 * simplifier (lib/eval/simplify_template.c). The input is loaded with
 * fl_debug_options.check_templates, which simplifies every templated copy of
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
    static const fl_debug_options check = {.check_templates = true};
    fuzz_run_script(data, size, false, &check);
    fuzz_run_script(data, size, true, NULL);
    return 0;
}
