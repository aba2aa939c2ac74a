/* window.h: `flitter run --window` and Flitter's `flitter SCRIPT...`: the
 * frame loop with live windows (window_main.c). */
#ifndef FL_WINDOW_H
#define FL_WINDOW_H

#include <stddef.h>
#include <stdio.h>

#include "runner.h"

/* window_run()'s result when there is no display to open windows on. */
#define WINDOW_NO_DISPLAY (-1)

/* Run [spec] with windows: each page (spec->scripts) a runtime, each
 * !window of the current page's frame an SDL window showing its picture
 * (fl_draw_window), or one window with the physics view (fl_draw_view)
 * when the frame has no !window; keys, pointer and buttons go to the
 * runtime (fl_key, fl_pointer, fl_pointer_button); saved files reload the
 * page (fl_program_files). The clock is realtime (frames paced to
 * fl_target_fps, late pictures dropped) unless spec->clock_given with
 * --lockstep (every frame shown). Ends at spec->frames, on Escape, when a
 * window is closed, or when *[interrupt] is set; then saves --state and
 * writes --dump-state / --dump-tree of the current page to [out].
 *   errors: WINDOW_NO_DISPLAY, with the reason in [why] ([cap] bytes),
 *           before doing anything when neither DISPLAY nor WAYLAND_DISPLAY
 *           is set or SDL cannot start its video; 1 when a script cannot
 *           be loaded or a window cannot be opened, or --state cannot be
 *           saved; 2 for a bad define; else 0.
 *   source: Flitter engine/control.py EngineController.run (clock, pages),
 *           render/window/__init__.py (windows, keys, pointer). */
int window_run(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, char *why,
               size_t cap);

#endif
