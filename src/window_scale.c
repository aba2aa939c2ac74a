/* window_scale.c: the live window's dynamic resolution (see
 * window_scale.h for the rule). */
#include "window_scale.h"

#include <math.h>

#define STEPS 16
#define CALM_PICTURES 8
#define CALM_MOST 128

void winscale_init(WinScale *s, double min_area)
{
    *s = (WinScale){.floor_step = STEPS, .step = STEPS, .least_step = STEPS, .need = CALM_PICTURES, .since_up = -1};
    if (!(min_area > 0 && min_area <= 1)) return;
    /* the least step whose square is at least the floor */
    int k = 1;
    while (k < STEPS && ((double)k / STEPS) * ((double)k / STEPS) < min_area) k++;
    s->floor_step = k;
}

void winscale_frame(WinScale *s, double sim)
{
    if (!(sim >= 0)) return;
    s->sim = s->sim > 0 ? 0.75 * s->sim + 0.25 * sim : sim;
}

/* Change to step [k]; the smoothed cost is carried over in proportion to
 * the pixels. */
static bool go_to(WinScale *s, int k)
{
    if (k < s->floor_step) k = s->floor_step;
    if (k > STEPS) k = STEPS;
    if (k == s->step) return false;
    s->draw *= ((double)k * k) / ((double)s->step * s->step);
    s->step = k;
    s->calm = 0;
    s->changes++;
    if (k < s->least_step) s->least_step = k;
    return true;
}

bool winscale_picture(WinScale *s, double draw, double budget)
{
    if (!(draw >= 0) || !(budget > 0)) return false;
    s->draw = s->draw > 0 ? 0.5 * s->draw + 0.5 * draw : draw;
    double target = 0.85 * budget - s->sim;
    if (target < 0.001) target = 0.001;
    if (s->since_up >= 0 && ++s->since_up >= 2 * s->need) {
        /* the last step up held: the next may come sooner */
        if (s->need > CALM_PICTURES) s->need /= 2;
        s->since_up = -1;
    }
    if (s->draw > target) {
        /* the pixels in proportion to the time: the linear scale by the
         * square root of it, at least one step down */
        int k = (int)floor(s->step * sqrt(target / s->draw));
        if (k >= s->step) k = s->step - 1;
        bool changed = go_to(s, k);
        if (changed && s->since_up >= 0 && s->since_up <= s->need && s->need < CALM_MOST) s->need *= 2;
        if (changed) s->since_up = -1;
        return changed;
    }
    if (s->draw < 0.6 * target && s->step < STEPS) {
        /* the longer wait only where the next step would come near the
         * target (its cost taken in proportion to the pixels): after the
         * load has gone, the scale comes back at once */
        double next = s->draw * ((double)(s->step + 1) * (s->step + 1)) / ((double)s->step * s->step);
        int wait = next < 0.5 * target ? CALM_PICTURES : s->need;
        if (++s->calm >= wait && go_to(s, s->step + 1)) {
            s->since_up = 0;
            return true;
        }
        return false;
    }
    s->calm = 0;
    return false;
}

double winscale_scale(const WinScale *s) { return (double)s->step / STEPS; }

int winscale_samples(const WinScale *s)
{
    if (s->step >= STEPS) return 0;
    return s->step * 4 >= STEPS * 3 ? 2 : 1;
}
