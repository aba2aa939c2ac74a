/* test_mem.c: the one allocation-failure path (lib/mem.c): the helpers,
 * and what happens when an allocation fails (in a child process, through
 * the mem_test_fail_after hook): the thread's failure handler receives the
 * message, then the process aborts. */
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#include "buf.h"
#include "mem.h"

static void test_helpers(void **st)
{
    (void)st;
    char *s = mem_asprintf("%s/%d", "dir", 42);
    assert_string_equal(s, "dir/42");
    free(s);
    s = mem_strndup("abcdef", 3);
    assert_string_equal(s, "abc");
    free(s);
    s = mem_strdup("");
    assert_string_equal(s, "");
    free(s);
    unsigned char *z = mem_calloc(10, 3);
    for (int i = 0; i < 30; i++) assert_int_equal(z[i], 0);
    z = mem_realloc_array(z, 100, 4);
    z[399] = 7;
    free(z);
    void *p = mem_alloc(0);   /* never NULL */
    assert_non_null(p);
    free(p);
}

/* handlers nest: mem_enter returns the one it replaced */
/* buf_truncate takes a prefix back; buf_line drops trailing newlines only. */
static void test_buf_error_lines(void **st)
{
    (void)st;
    Buf b = BUF_INIT;
    assert_string_equal(buf_line(&b), "");
    buf_truncate(&b, 0);
    buf_printf(&b, "a.png: ");
    size_t mark = b.len;
    buf_printf(&b, "no such file\n\n");
    assert_string_equal(buf_line(&b), "a.png: no such file");
    assert_int_equal(b.len, 19);
    buf_truncate(&b, mark);
    assert_string_equal(buf_cstr(&b), "a.png: ");
    buf_truncate(&b, 100);
    assert_int_equal(b.len, 7);
    buf_printf(&b, "x\ny\n");
    assert_string_equal(buf_line(&b), "a.png: x\ny");
    buf_free(&b);
}

static void h1(void *ctx, const char *m) { (void)ctx; (void)m; }
static void h2(void *ctx, const char *m) { (void)ctx; (void)m; }
static void test_nesting(void **st)
{
    (void)st;
    int a, b;
    MemHandler outer = mem_enter(h1, &a);
    assert_null(outer.fn);
    MemHandler inner = mem_enter(h2, &b);
    assert_ptr_equal(inner.fn, h1);
    assert_ptr_equal(inner.ctx, &a);
    mem_leave(inner);
    MemHandler again = mem_enter(NULL, NULL);
    assert_ptr_equal(again.fn, h1);
    mem_leave(again);
    mem_leave(outer);
    MemHandler none = mem_enter(NULL, NULL);
    assert_null(none.fn);
    mem_leave(none);
}

/* The child's handler writes "CTX|MESSAGE" to this pipe. */
static int report_fd = -1;
static void report(void *ctx, const char *message)
{
    char line[200];
    int n = snprintf(line, sizeof line, "%s|%s", (const char *)ctx, message);
    if (write(report_fd, line, (size_t)n) != n) _exit(3);
}

/* Run [child] in a forked process with its stderr and the report pipe
 * captured; returns the wait status, the report in [rep], stderr in
 * [err]. */
static int run_child(void (*child)(void), char *rep, size_t nrep, char *err, size_t nerr)
{
    int rp[2], ep[2];
    assert_int_equal(pipe(rp), 0);
    assert_int_equal(pipe(ep), 0);
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(rp[0]);
        close(ep[0]);
        dup2(ep[1], 2);
        report_fd = rp[1];
        /* no core file for the expected abort */
        signal(SIGABRT, SIG_DFL);
        child();
        _exit(0);
    }
    close(rp[1]);
    close(ep[1]);
    ssize_t n = read(rp[0], rep, nrep - 1);
    rep[n > 0 ? n : 0] = '\0';
    size_t got = 0;
    while (got < nerr - 1) {
        ssize_t k = read(ep[0], err + got, nerr - 1 - got);
        if (k <= 0) break;
        got += (size_t)k;
    }
    err[got] = '\0';
    close(rp[0]);
    close(ep[0]);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    return status;
}

/* the third mem_* allocation fails, deep inside a Buf append */
static void child_with_handler(void)
{
    mem_enter(report, "runtime-7");
    mem_test_fail_after(2);
    void *a = mem_alloc(8), *b = mem_calloc(1, 8);
    (void)a;
    (void)b;
    Buf buf = {0};
    buf_printf(&buf, "%s", "this append needs memory");   /* aborts */
    _exit(0);
}

static void child_without_handler(void)
{
    mem_test_fail_after(0);
    free(mem_strdup("x"));   /* aborts */
    _exit(0);
}

static void child_size_overflow(void)
{
    mem_enter(report, "rt");
    free(mem_realloc_array(NULL, SIZE_MAX / 2, 4));   /* aborts */
    _exit(0);
}

static void test_failure_calls_handler_then_aborts(void **st)
{
    (void)st;
    char rep[256], err[256];
    int status = run_child(child_with_handler, rep, sizeof rep, err, sizeof err);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), SIGABRT);
    assert_string_equal(rep, "runtime-7|out of memory");
    assert_null(strstr(err, "flitter: out of memory"));   /* the handler had it */

    status = run_child(child_without_handler, rep, sizeof rep, err, sizeof err);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), SIGABRT);
    assert_string_equal(rep, "");
    assert_non_null(strstr(err, "flitter: out of memory\n"));

    status = run_child(child_size_overflow, rep, sizeof rep, err, sizeof err);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), SIGABRT);
    assert_string_equal(rep, "rt|out of memory");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_helpers),
        cmocka_unit_test(test_buf_error_lines),
        cmocka_unit_test(test_nesting),
        cmocka_unit_test(test_failure_calls_handler_then_aborts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
