/* window_scale.h: the live window's dynamic resolution (window_scale.c):
 * the scale at which the frame loop draws the windows' pictures
 * (fl_set_window_scale), chosen after each picture from what the last
 * pictures cost to draw, so that a frame's simulation and its picture fit
 * in the frame's time (1/fps) and the window keeps its rate; never below
 * the user's floor (--min-scale, a fraction of the pixels).
 *
 * The scale is a linear factor in steps of 1/16 (so that framebuffers of
 * the same few sizes are reused), from 1 down to the least step whose
 * square is at least the floor. Below full size a `!canvas3d` draws with
 * at most 2 samples from 3/4 and 1 below that: multisampling costs as
 * much as pixels do on a CPU rasteriser.
 *
 * The rule, per picture drawn, with [budget] the frame's seconds and
 * [sim] the frame's simulation (evaluation, physics, outputs) seconds,
 * both smoothed over the last pictures: the target is 85% of the budget
 * less the simulation (at least 1 ms). Drawing slower than the target
 * scales down at once, by the square root of the ratio (the cost is taken
 * as proportional to the pixels, which the next pictures correct); a
 * picture drawn in under 60% of the target, eight times in a row, scales
 * up one step. A step up that has to be taken back within as many
 * pictures as it waited for doubles the wait for the next (at most 128
 * pictures), and a step up that holds for twice its wait halves it again
 * (at least 8): under a steady load the scale settles instead of going up
 * and down. The longer wait applies only where the next step's cost (in
 * proportion to its pixels) would be over half the target: when the load
 * ends, the scale comes back after 8 pictures a step. Pure arithmetic: no
 * clock, no GL, no global state. */
#ifndef FL_WINDOW_SCALE_H
#define FL_WINDOW_SCALE_H

#include <stdbool.h>

typedef struct WinScale {
    int floor_step;          /* the least step (1..16) */
    int step;                /* the scale now: step/16 */
    double draw;             /* smoothed seconds to draw a picture at this step (0: none yet) */
    double sim;              /* smoothed seconds of a frame's simulation */
    int calm;                /* pictures in a row drawn well within the target */
    int need;                /* calm pictures that take a step up (8..128) */
    int since_up;            /* pictures since the last step up (-1: none pending) */
    long changes;            /* times the scale changed */
    int least_step;          /* the least step used so far */
} WinScale;

/* A controller at full size with floor [min_area] (a fraction of the
 * pixels, 0 < min_area <= 1; outside that or NaN: 1, no scaling). */
void winscale_init(WinScale *s, double min_area);

/* Count one frame's simulation time [sim] (seconds). */
void winscale_frame(WinScale *s, double sim);

/* Count one picture drawn at the current scale in [draw] seconds, for a
 * frame time of [budget] seconds (1/fps); returns whether the scale
 * changed for the next picture. */
bool winscale_picture(WinScale *s, double draw, double budget);

/* The scale now (linear, 1/16 .. 1) and the cap on samples it goes with
 * (0: none). */
double winscale_scale(const WinScale *s);
int winscale_samples(const WinScale *s);

#endif
