/* fuzz_script.c: libFuzzer target for script text (issue 13): the input is
 * loaded as a program; when it parses, three frames are evaluated and
 * simulated and the state and node tree are dumped. Any crash, sanitizer
 * report, leak or hang is a finding; syntax and run-time errors are not. */
#include "fuzz_run.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_budget_start();
    fuzz_run_script(data, size, true, NULL);
    return 0;
}
