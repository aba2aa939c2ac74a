/* test_window_scale.c: the live window's dynamic resolution
 * (src/window_scale.c): the floor's step, the step down in proportion to
 * the pixels, the step up after eight calm pictures, the cap on samples,
 * and pictures drawn whole not counted. Exact values worked by hand from
 * window_scale.h's rule. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "window_scale.h"

static void floor_steps(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);   /* sqrt 0.25 = 0.5 = 8/16 */
    assert_int_equal(s.floor_step, 8);
    winscale_init(&s, 0.3);    /* sqrt 0.3 = 0.548: 9/16 (0.316 of the pixels; 8/16 is 0.25 < 0.3) */
    assert_int_equal(s.floor_step, 9);
    winscale_init(&s, 1);
    assert_int_equal(s.floor_step, 16);
    winscale_init(&s, 0.001);  /* 1/16 at least */
    assert_int_equal(s.floor_step, 1);
    winscale_init(&s, NAN);    /* no scaling */
    assert_int_equal(s.floor_step, 16);
    winscale_init(&s, 0);
    assert_int_equal(s.floor_step, 16);
    winscale_init(&s, 1.5);
    assert_int_equal(s.floor_step, 16);
    assert_true(winscale_scale(&s) == 1);
    assert_int_equal(winscale_samples(&s), 0);
}

static void steps_down_in_proportion(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);
    /* 60 frames/s: 16.67 ms; a frame's simulation 2.67 ms: target
     * 0.85 * 16.67 - 2.67 = 11.5 ms */
    winscale_frame(&s, 0.00266666);
    double budget = 1 / 60.0;
    /* a picture of 46 ms: the pixels by target/46, the scale by its
     * square root: 16 * sqrt(11.5/46) = 8.0 (7.99... or 8 as it rounds):
     * step 8, the floor either way */
    assert_true(winscale_picture(&s, 0.046, budget));
    assert_int_equal(s.step, 8);
    assert_true(winscale_scale(&s) == 0.5);
    assert_int_equal(winscale_samples(&s), 1);   /* below 3/4: one sample */
    /* the smoothed cost carried over to the new step: 46 ms * 64/256 */
    assert_true(fabs(s.draw - 0.046 * 64 / 256) < 1e-12);
    /* at the floor, a slower picture changes nothing */
    assert_false(winscale_picture(&s, 0.1, budget));
    assert_int_equal(s.step, 8);
    assert_int_equal(s.least_step, 8);
    assert_int_equal(s.changes, 1);
}

static void at_least_one_step_down(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);
    /* just over the target: the square root rounds to 16, one step down
     * all the same */
    double budget = 1 / 60.0;
    assert_true(winscale_picture(&s, 0.85 * budget * 1.01, budget));
    assert_int_equal(s.step, 15);
    assert_int_equal(winscale_samples(&s), 2);   /* 15/16 >= 3/4: two samples */
}

static void steps_up_after_calm(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);
    double budget = 1 / 60.0;
    assert_true(winscale_picture(&s, 0.05, budget));   /* 16 * sqrt(14.17/50) = 8.5: step 8 */
    assert_int_equal(s.step, 8);
    /* 2 ms pictures, well within 60% of the target: the smoothed cost
     * halves toward 2 ms; the eighth calm picture steps up */
    int changed_at = -1;
    for (int i = 0; i < 8; i++)
        if (winscale_picture(&s, 0.002, budget) && changed_at < 0) changed_at = i;
    assert_int_equal(changed_at, 7);
    assert_int_equal(s.step, 9);
    /* a picture in between (over 60% of the target, within it) resets the
     * count */
    for (int i = 0; i < 7; i++) assert_false(winscale_picture(&s, 0.002, budget));
    assert_false(winscale_picture(&s, 0.02, budget));   /* smoothed 11 ms: over 0.6 * 14.17, within 14.17 */
    assert_int_equal(s.calm, 0);
    /* back to full size eventually, where the samples are as asked */
    for (int i = 0; i < 200; i++) winscale_picture(&s, 0.002, budget);
    assert_int_equal(s.step, 16);
    assert_true(winscale_scale(&s) == 1);
    assert_int_equal(winscale_samples(&s), 0);
    assert_false(winscale_picture(&s, 0.002, budget));   /* no step past full size */
}

/* A step up taken back within its wait doubles the next wait; one that
 * holds for twice its wait halves it again. */
static void failed_steps_up_wait_longer(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);
    /* target 14.17 ms, calm below 8.5; pictures of 8 ms, whose next step
     * (8 ms x 81/64 = 10.1) would come over half the target (7.08): the
     * long wait applies */
    double budget = 1 / 60.0;
    assert_true(winscale_picture(&s, 0.05, budget));
    assert_int_equal(s.step, 8);
    assert_int_equal(s.need, 8);
    int pictures = 0;
    while (!winscale_picture(&s, 0.008, budget)) pictures++;
    assert_int_equal(s.step, 9);
    assert_int_equal(s.since_up, 0);
    /* taken back at once: 16 calm pictures wanted now */
    assert_true(winscale_picture(&s, 0.03, budget));
    assert_int_equal(s.step, 8);
    assert_int_equal(s.need, 16);
    int calm_at_step = -1;
    for (int i = 0; i < 100 && calm_at_step < 0; i++) {
        int before = s.calm;
        if (winscale_picture(&s, 0.008, budget)) calm_at_step = before + 1;
    }
    assert_int_equal(calm_at_step, 16);
    assert_int_equal(s.step, 9);
    /* taken back again within 16: 32 */
    for (int i = 0; i < 10; i++) assert_false(winscale_picture(&s, 0.008, budget));
    assert_true(winscale_picture(&s, 0.04, budget));
    assert_int_equal(s.need, 32);
    /* at most 128 */
    for (int round = 0; round < 4; round++) {
        while (!winscale_picture(&s, 0.008, budget)) {}
        assert_true(winscale_picture(&s, 0.04, budget));
    }
    assert_int_equal(s.need, 128);
    /* a step up that holds for 2 x 128 pictures halves the wait */
    while (!winscale_picture(&s, 0.008, budget)) {}
    int step = s.step;
    for (int i = 0; i < 2 * 128; i++) winscale_picture(&s, 0.011, budget);   /* within the target, not calm */
    assert_int_equal(s.step, step);
    assert_int_equal(s.need, 64);
    assert_int_equal(s.since_up, -1);
}

/* Far within the target the wait stays 8 pictures whatever failed
 * before: when a load ends the scale comes back at 8 pictures a step. */
static void back_at_once_when_load_ends(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);
    double budget = 1 / 60.0;
    assert_true(winscale_picture(&s, 0.05, budget));
    for (int round = 0; round < 5; round++) {
        while (!winscale_picture(&s, 0.008, budget)) {}
        assert_true(winscale_picture(&s, 0.04, budget));
    }
    assert_int_equal(s.need, 128);
    assert_int_equal(s.step, 8);
    /* 1 ms pictures: 8 steps of 8 pictures each, after the few that bring
     * the smoothed cost down */
    int pictures = 0;
    while (s.step < 16 && pictures < 1000) {
        winscale_picture(&s, 0.001, budget);
        pictures++;
    }
    assert_int_equal(s.step, 16);
    assert_true(pictures <= 8 * 8 + 4);
}

static void bad_input_changes_nothing(void **unused)
{
    (void)unused;
    WinScale s;
    winscale_init(&s, 0.25);
    assert_false(winscale_picture(&s, NAN, 1 / 60.0));
    assert_false(winscale_picture(&s, -1, 1 / 60.0));
    assert_false(winscale_picture(&s, 1, 0));
    assert_false(winscale_picture(&s, 1, NAN));
    winscale_frame(&s, NAN);
    winscale_frame(&s, -1);
    assert_true(s.sim == 0);
    assert_int_equal(s.step, 16);
    /* a frame whose simulation fills the budget: the target is 1 ms */
    winscale_frame(&s, 1);
    assert_true(winscale_picture(&s, 0.004, 1 / 60.0));   /* 16 * sqrt(1/4) = 8 */
    assert_int_equal(s.step, 8);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(floor_steps),
        cmocka_unit_test(steps_down_in_proportion),
        cmocka_unit_test(at_least_one_step_down),
        cmocka_unit_test(steps_up_after_calm),
        cmocka_unit_test(failed_steps_up_wait_longer),
        cmocka_unit_test(back_at_once_when_load_ends),
        cmocka_unit_test(bad_input_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
