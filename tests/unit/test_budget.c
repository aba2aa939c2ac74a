/* test_budget.c: the memory budget (lib/core/mem.h MemBudget, issue 23
 * item 5, issue 28 item 5): size parsing, the charging rules (the pool
 * charges the blocks it mallocs and gives back those it frees; requests
 * past the limit are refused and marked), and what an embedding host sees
 * through flitter.h: error codes and log lines, never an abort, and a
 * runtime that goes on working afterwards. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "flitter.h"
#include "mem.h"
#include "value.h"

static void test_parse_size(void **st)
{
    (void)st;
    size_t n = 7;
    assert_true(mem_parse_size("1", &n));
    assert_int_equal(n, 1);
    assert_true(mem_parse_size("64k", &n));
    assert_int_equal(n, 65536);
    assert_true(mem_parse_size("200M", &n));
    assert_int_equal(n, (size_t)200 << 20);
    assert_true(fl_parse_memory("2G", &n));
    assert_int_equal(n, (size_t)2 << 30);
    n = 7;
    const char *badv[] = {"", "0", "-1", "1.5G", "12X", "G", " 1", "1 ", "1MB",
                          "99999999999999999999", "17179869184G", NULL};
    for (int i = 0; badv[i]; i++) assert_false(mem_parse_size(badv[i], &n));
    assert_false(mem_parse_size(NULL, &n));
    assert_int_equal(n, 7);   /* left alone */
}

static void test_charging(void **st)
{
    (void)st;
    MemBudget b = {.limit = 300000};   /* blocks are charged by their pool class size */
    MemHandler prev = mem_enter_budget(NULL, NULL, &b);
    assert_true(mem_fits(300000));
    assert_false(mem_take_refusal());
    assert_false(mem_fits(300001));
    assert_true(mem_take_refusal());
    assert_false(mem_take_refusal());
    assert_true(mem_reserve(200000));
    assert_int_equal(b.used, 200000);
    assert_false(mem_reserve(150000));
    assert_int_equal(b.used, 200000);
    mem_take_refusal();
    mem_unreserve(200000);
    assert_int_equal(b.used, 0);
    mem_unreserve(5);   /* never below 0 */
    assert_int_equal(b.used, 0);
    /* the pool (no pool active: straight to malloc/free) charges blocks */
    Vec *v = vec_new_num(1000);
    assert_true(b.used >= 8000 && b.used < 8200);
    vec_release(v);
    assert_int_equal(b.used, 0);
    /* composition and ranges past the budget: null and marked */
    Vec *big = vec_new_num(10000);   /* 80 KB: a 128 KiB block */
    assert_int_equal(b.used, 131072);
    for (int i = 0; i < 10000; i++) vec_nums(big)[i] = i;
    Vec *parts[3] = {big, big, big};
    assert_null(vec_compose(parts, 3));
    assert_true(mem_take_refusal());
    Vec *two = vec_compose(parts, 1);   /* the part itself: nothing new */
    assert_ptr_equal(two, big);
    vec_release(two);
    Vec *stop = vec_num1(30000);
    bool too_long = false;
    assert_null(vec_range(NULL, stop, NULL, UINT64_C(1) << 26, &too_long));
    assert_true(too_long && mem_take_refusal());
    vec_release(stop);
    stop = vec_num1(100);
    too_long = false;
    Vec *r = vec_range(NULL, stop, NULL, UINT64_C(1) << 26, &too_long);
    assert_false(too_long || mem_take_refusal());
    assert_int_equal(vec_len(r), 100);
    vec_release(r);
    vec_release(stop);
    vec_release(big);
    assert_int_equal(b.used, 0);
    /* entering again clears the mark: each public call starts afresh */
    assert_false(mem_fits(SIZE_MAX));
    mem_enter_budget(NULL, NULL, &b);
    assert_false(mem_take_refusal());
    mem_leave(prev);
    /* without a budget everything fits */
    assert_true(mem_fits(SIZE_MAX));
    assert_false(mem_take_refusal());
}

typedef struct Log {
    char text[4096];
} Log;

static void collect(void *ctx, int kind, const char *line)
{
    (void)kind;
    Log *log = ctx;
    size_t n = strlen(log->text);
    snprintf(log->text + n, sizeof log->text - n, "%s\n", line);
}

/* One thread's share of test_threads: charges and gives back [n] blocks
 * of 1..64 bytes, explicitly and through its own handler, marks a refusal
 * of its own and adds symbols to the shared table. */
typedef struct Charger {
    MemBudget *b;
    SymTab *syms;
    int id;
    bool refused_seen, stranger_refusal;
} Charger;

static void *charge(void *arg)
{
    Charger *c = arg;
    MemHandler prev = mem_enter_budget(NULL, NULL, c->b);
    for (int i = 0; i < 200000; i++) {
        size_t n = (size_t)(i % 64) + 1;
        if (!mem_budget_reserve(c->b, n)) return NULL;
        mem_charge(n);
        mem_budget_release(c->b, n);
        mem_unreserve(n);
    }
    for (int i = 0; i < 2000; i++) {
        char name[32];
        int len = snprintf(name, sizeof name, "t%d_%d", c->id, i % 500);
        (void)symtab_add(c->syms, name, (size_t)len);
        if (!symtab_name(c->syms, symbol_value(name, (size_t)len))) return NULL;
    }
    /* a refusal marks the thread that met it, not the other */
    if (c->id == 0) {
        c->refused_seen = !mem_fits(SIZE_MAX) && mem_take_refusal();
    } else {
        c->stranger_refusal = mem_take_refusal();
    }
    mem_leave(prev);
    return c;
}

/* Two threads charge one budget (a runtime's frame loop and its drawing
 * thread, fl_picture_draw) and share a symbol table: no charge is lost
 * (the count comes back to exactly what it was), and each thread sees its
 * own refusals alone. Run under ThreadSanitizer by tests/tsan.sh. */
static void test_threads(void **st)
{
    (void)st;
    MemBudget b = {.limit = 1 << 20, .used = 1000};
    SymTab *syms = symtab_new();
    Charger c[2] = {{&b, syms, 0, false, false}, {&b, syms, 1, false, false}};
    pthread_t t[2];
    for (int i = 0; i < 2; i++) assert_int_equal(pthread_create(&t[i], NULL, charge, &c[i]), 0);
    void *res[2];
    for (int i = 0; i < 2; i++) assert_int_equal(pthread_join(t[i], &res[i]), 0);
    assert_ptr_equal(res[0], &c[0]);
    assert_ptr_equal(res[1], &c[1]);
    assert_true(c[0].refused_seen);
    assert_false(c[1].stranger_refusal);
    const Str *name = symtab_name(syms, symbol_value("t1_499", 6));
    assert_non_null(name);
    assert_string_equal(name->bytes, "t1_499");
    /* the table's names were charged as they were made: freed, they give
     * every byte back */
    MemHandler prev = mem_enter_budget(NULL, NULL, &b);
    symtab_free(syms);
    mem_leave(prev);
    assert_int_equal(b.used, 1000);
}

static void test_api(void **st)
{
    (void)st;
    Log log = {{0}};
    fl_options o = fl_default_options();
    o.max_memory = (size_t)1 << 20;   /* 1 MiB */
    o.log = collect;
    o.ctx = &log;
    fl_runtime *rt = fl_new(&o);
    assert_non_null(rt);
    /* folded at load: an error code and the message, no abort */
    const char *huge = "let a=..1000000\n!foo n=len(a)\n";
    assert_int_not_equal(fl_load_text(rt, "huge.fl", huge, strlen(huge)), 0);
    assert_non_null(strstr(fl_error(rt), "huge.fl:1:1: error: out of memory"));
    /* at run time: null and a logged execution error; the frame goes on */
    const char *run = "!foo n=len(..(frame+1000000)) m=1\n";
    assert_int_equal(fl_load_text(rt, "run.fl", run, strlen(run)), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_non_null(strstr(log.text, "Out of memory"));
    /* the state: an error code past the budget, fine below it */
    static double xs[1 << 18];
    size_t n0 = fl_state_count(rt);
    assert_int_equal(fl_state_set_numbers(rt, ":big", xs, 1 << 18), -1);
    assert_non_null(strstr(fl_error(rt), "out of memory"));
    assert_int_equal(fl_state_count(rt), n0);
    assert_int_equal(fl_state_set_numbers(rt, ":small", xs, 10), 0);
    assert_int_equal(fl_state_count(rt), n0 + 1);
    assert_int_equal(fl_step(rt), 0);
    fl_free(rt);
}

/* Appends what fl_dump_tree writes to a Log. */
static void tree_into(void *ctx, const char *text, size_t len)
{
    Log *log = ctx;
    size_t n = strlen(log->text);
    snprintf(log->text + n, sizeof log->text - n, "%.*s", (int)len, text);
}

/* A loop whose body is a compiled expression gathers its numbers into its
 * result (eval.c LoopNums), in one vector made for them: under a budget
 * of 8 MiB, 400,000 iterations of 4 numbers (12.8 MB) are refused room,
 * the result is null with the execution error and the rest of the frame
 * goes on; in another runtime, 100,000 of 2 (1.6 MB) fit, as they do
 * without the compiled expressions (FLITTER_NOFAST). */
static void test_loop_numbers(void **st)
{
    (void)st;
    const char *srcs[2] = {"!foo n=len((i;i;i;i) for i in ..(frame+400000)) m=1\n",
                           "!foo m=len((i;i) for i in ..(frame+100000)) k=sum((i;i) for i in ..(frame+4))\n"};
    const char *trees[2] = {"!root\n !foo n=0 m=1\n", "!root\n !foo m=200000 k=12\n"};
    for (int i = 0; i < 2; i++) {
        Log log = {{0}}, tree = {{0}};
        fl_options o = fl_default_options();
        o.max_memory = (size_t)8 << 20;
        o.log = collect;
        o.ctx = &log;
        fl_runtime *rt = fl_new(&o);
        assert_non_null(rt);
        assert_int_equal(fl_load_text(rt, "loop.fl", srcs[i], strlen(srcs[i])), 0);
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(strstr(log.text, "Out of memory") != NULL, i == 0);
        assert_int_equal(fl_dump_tree(rt, tree_into, &tree), 0);
        assert_string_equal(tree.text, trees[i]);
        fl_free(rt);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_size),
        cmocka_unit_test(test_charging),
        cmocka_unit_test(test_threads),
        cmocka_unit_test(test_api),
        cmocka_unit_test(test_loop_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
