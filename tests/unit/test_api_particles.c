/* test_api_particles.c: fl_particles (lib/runtime/api_particles.c) through the
 * public interface only: the particles and the anchor of a !physics system
 * in state-dump order with their positions and velocities bit for bit as
 * the state holds them, keys that are not particles left out, a system
 * prefix of two parts, string ids, stopping early, and the error for an
 * empty prefix. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "flitter.h"

typedef struct Seen {
    char ids[8][32];
    double pos[8][3], vel[8][3];
    size_t dims[8];
    int n, stop_after;
} Seen;

static int collect(void *ctx, const char *id, const double *p, const double *v, size_t dims)
{
    Seen *s = ctx;
    assert_true(s->n < 8 && dims <= 3);
    snprintf(s->ids[s->n], sizeof s->ids[0], "%s", id);
    memcpy(s->pos[s->n], p, dims * sizeof *p);
    memcpy(s->vel[s->n], v, dims * sizeof *v);
    s->dims[s->n] = dims;
    s->n++;
    return s->stop_after && s->n == s->stop_after;
}

static void test_state_entries(void **unused)
{
    (void)unused;
    fl_runtime *rt = fl_new(NULL);
    /* written by hand, as a !physics system writes them */
    fl_state_set(rt, ":dish", "0");
    fl_state_set(rt, ":dish;:clock", "1.5");
    fl_state_set(rt, ":dish;10", "1;2");
    fl_state_set(rt, ":dish;10;:velocity", "0.1;-0.2");
    fl_state_set(rt, ":dish;2", "3;4");
    fl_state_set(rt, ":dish;2;:velocity", "5;6");
    fl_state_set(rt, ":dish;:centre", "0;0");
    fl_state_set(rt, ":dish;:centre;:velocity", "0;0");
    fl_state_set(rt, ":dish;7", "1;1");                 /* no velocity: not a particle */
    fl_state_set(rt, ":dish;8", "1;1");
    fl_state_set(rt, ":dish;8;:velocity", "1;1;1");     /* another length: not one */
    fl_state_set(rt, ":other;1", "9;9");
    fl_state_set(rt, ":other;1;:velocity", "9;9");
    fl_state_set(rt, "s;:t;cell", "1;2;3");
    fl_state_set(rt, "s;:t;cell;:velocity", "4;5;6");

    Seen s = {0};
    assert_int_equal(fl_particles(rt, ":dish", collect, &s), 3);
    assert_int_equal(s.n, 3);
    /* the dump's order: by key text bytes, `:dish;10` < `:dish;2` < `:dish;:centre` */
    assert_string_equal(s.ids[0], "10");
    assert_string_equal(s.ids[1], "2");
    assert_string_equal(s.ids[2], ":centre");
    assert_int_equal(s.dims[0], 2);
    assert_true(s.pos[0][0] == 1 && s.pos[0][1] == 2);
    assert_true(s.vel[0][0] == 0.1 && s.vel[0][1] == -0.2);
    assert_true(s.pos[1][0] == 3 && s.vel[1][1] == 6);

    assert_int_equal(fl_particles(rt, ":dish", NULL, NULL), 3);
    Seen t = {.stop_after = 1};
    assert_int_equal(fl_particles(rt, ":dish", collect, &t), 1);
    assert_int_equal(t.n, 1);

    Seen u = {0};
    assert_int_equal(fl_particles(rt, "s;:t", collect, &u), 1);
    assert_string_equal(u.ids[0], "\"cell\"");
    assert_int_equal(u.dims[0], 3);
    assert_true(u.pos[0][2] == 3 && u.vel[0][2] == 6);

    assert_int_equal(fl_particles(rt, ":none", collect, &u), 0);
    assert_int_equal(fl_particles(rt, "", collect, &u), -1);
    assert_non_null(strstr(fl_error(rt), "prefix"));
    fl_free(rt);
}

/* A stepped system: the numbers are the state's, bit for bit. */
static void test_stepped_system(void **unused)
{
    (void)unused;
    static const char src[] =
        "!physics state=:p dimensions=2 time=time resolution=1/60\n"
        "    !particle id=0 position=1;0 velocity=0;2\n"
        "    !particle id=:b position=0;0\n"
        ;
    fl_runtime *rt = fl_new(NULL);
    assert_int_equal(fl_load_text(rt, "p.fl", src, strlen(src)), 0);
    for (int i = 0; i < 5; i++) assert_int_equal(fl_step(rt), 0);
    Seen s = {0};
    assert_int_equal(fl_particles(rt, ":p", collect, &s), 2);
    assert_string_equal(s.ids[0], "0");
    assert_string_equal(s.ids[1], ":b");
    double want[2];
    assert_int_equal(fl_state_get_numbers(rt, ":p;0", want, 2), 2);
    assert_memory_equal(s.pos[0], want, sizeof want);
    assert_int_equal(fl_state_get_numbers(rt, ":p;:b;:velocity", want, 2), 2);
    assert_memory_equal(s.vel[1], want, sizeof want);
    assert_true(s.pos[0][1] > 0.0); /* it moved with its velocity */
    fl_free(rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state_entries),
        cmocka_unit_test(test_stepped_system),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
