/* builtins.c: the built-in function registry (LANGUAGE.md §5, §5.13) and
 * the one error helper every builtin uses (§4.16, Appendix B).
 *
 * The registry is the union of the family tables (vector, maths, random,
 * noise, colour, text, file), each ending with a {NULL} entry. Names are
 * unique across tables; lookup is a linear scan, done when names are bound,
 * not per call. bi_error formats `Error calling INTERNAL: DETAIL` and hands
 * it to the evaluator's per-frame error set; with no evaluator (ev == NULL,
 * as in unit tests) it records nothing.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "context.h"
#include "mem.h"

static const Builtin *const families[] = {
    bi_vector_table, bi_maths_table, bi_random_table, bi_noise_table,
    bi_colour_table, bi_text_table, bi_file_table,
};

const Builtin *bi_lookup(const char *name, size_t len)
{
    if (!name || len == 0)
        return NULL;
    /* the first byte rules out nearly every entry without a strlen */
    for (size_t f = 0; f < sizeof families / sizeof families[0]; f++)
        for (const Builtin *b = families[f]; b->name; b++)
            if (b->name[0] == name[0] && strlen(b->name) == len && memcmp(b->name, name, len) == 0)
                return b;
    return NULL;
}

Vec *bi_error(Eval *ev, const Builtin *bi, const char *fmt, ...)
{
    if (!ev)
        return NULL;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0)
        n = 0;
    const char *who = bi && bi->internal ? bi->internal : "?";
    size_t head = strlen("Error calling ") + strlen(who) + strlen(": ");
    char *msg = malloc(head + (size_t)n + 1);
    if (!msg)
        mem_oom();
    snprintf(msg, head + 1, "Error calling %s: ", who);
    va_start(ap, fmt);
    vsnprintf(msg + head, (size_t)n + 1, fmt, ap);
    va_end(ap);
    eval_error(ev, msg);
    free(msg);
    return NULL;
}
