/* fuzz_statefile.c: libFuzzer target for the saved-state reader (issue 13,
 * statefile.h). The input is written to a scratch file and loaded; a refused
 * file must leave the dictionary and clock untouched. An accepted one must
 * round-trip: saved, loaded again and saved again, the two saved files hold
 * the same lines (entry order is unspecified) and the same entry count. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fileio.h"
#include "statefile.h"

/* A scratch file name in $TMPDIR (or /tmp) unique to this process. */
static void scratch(char *path, size_t n, const char *tag)
{
    const char *dir = getenv("TMPDIR");
    snprintf(path, n, "%s/flitter-fuzz-%ld-%s", dir && *dir ? dir : "/tmp", (long)getpid(), tag);
}

static void check(int ok)
{
    if (!ok)
        __builtin_trap();
}

static int cmp_lines(const void *x, const void *y)
{
    return strcmp(*(char *const *)x, *(char *const *)y);
}

/* The lines of [b] (NUL-separated in place) sorted, in a new array of
 * [*n] pointers into [b]. */
static char **sorted_lines(Buf *b, size_t *n)
{
    char *s = (char *)buf_cstr(b);
    size_t count = 0;
    for (size_t i = 0; i < b->len; i++)
        count += s[i] == '\n';
    char **v = malloc((count + 1) * sizeof *v);
    check(v != NULL);
    *n = 0;
    for (char *p = s, *nl; (nl = strchr(p, '\n')); p = nl + 1) {
        *nl = '\0';
        v[(*n)++] = p;
    }
    qsort(v, *n, sizeof *v, cmp_lines);
    return v;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char in[256], a[256], b[256];
    scratch(in, sizeof in, "in");
    scratch(a, sizeof a, "a");
    scratch(b, sizeof b, "b");
    FILE *f = fopen(in, "wb");
    check(f && fwrite(data, 1, size, f) == size && fclose(f) == 0);

    SymTab *st = symtab_new();
    StateDict *sd = state_new();
    Vec *k = vec_num1(-7), *v = vec_num1(8);
    state_set(sd, k, v);
    StateClock clock = {42, 1, 2, 3, 4, 5, 6}, before = clock;
    Buf err = BUF_INIT, ta = BUF_INIT, tb = BUF_INIT;
    if (statefile_load(sd, st, &clock, NULL, in, &err) != 0) {
        check(err.len > 0 && state_count(sd) == 1 && memcmp(&clock, &before, sizeof clock) == 0);
    } else {
        size_t n = state_count(sd);
        check(clock.frame >= 0);
        check(statefile_save(sd, st, &clock, NULL, a, NULL, &err) == 0);
        StateDict *again = state_new();
        StateClock c2 = {0};
        check(statefile_load(again, st, &c2, NULL, a, &err) == 0);
        check(state_count(again) == n);
        check(statefile_save(again, st, &c2, NULL, b, NULL, &err) == 0);
        check(file_read(a, &ta) && file_read(b, &tb));
        check(ta.len == tb.len);
        size_t na, nb;
        char **la = sorted_lines(&ta, &na), **lb = sorted_lines(&tb, &nb);
        check(na == nb);
        for (size_t i = 0; i < na; i++)
            check(strcmp(la[i], lb[i]) == 0);
        free(la);
        free(lb);
        state_free(again);
    }
    vec_release(k);
    vec_release(v);
    buf_free(&err);
    buf_free(&ta);
    buf_free(&tb);
    state_free(sd);
    symtab_free(st);
    unlink(in);
    unlink(a);
    unlink(b);
    return 0;
}
