/* window_input.c: the input of a run with live windows, as the display
 * resolved it from SDL events (window_display.c), turned into Flitter's
 * on the frame loop's thread: keys by name to the window's `!key` nodes,
 * the pointer as fractions of the shown picture to its `!pointer`, buttons
 * numbered as GLFW numbers them; what no node claims drives the front end
 * itself (quit, pages, overlay, physics view, pause, step). Inputs are
 * applied between frames, so what they write to the state is seen by the
 * next frame. */
#include <string.h>

#include "window_keys.h"
#include "window_loop.h"

/* The front end's own keys, for a key no !key claimed. */
static void own_key(Loop *L, SDL_Scancode sc, bool pressed)
{
    if (pressed) {
        switch (sc) {
        case SDL_SCANCODE_ESCAPE: L->quit = true; break;
        case SDL_SCANCODE_F1:
            L->show_status = !L->show_status;
            L->overlay_changed = true;
            break;
        case SDL_SCANCODE_F2:
            L->show_view = !L->show_view;
            L->redraw = true;
            break;
        case SDL_SCANCODE_F5:
            L->paused = !L->paused;
            fl_clock_pause(L->pages[L->cur].rt, L->paused);   /* `time` stops with the frames */
            L->overlay_changed = true;
            break;
        case SDL_SCANCODE_F6:
            if (L->paused) L->steps++;
            break;
        default: break;
        }
    } else if (sc == SDL_SCANCODE_LEFT && L->cur > 0) {
        L->switch_to = L->cur - 1;   /* Flitter switches on release */
    } else if (sc == SDL_SCANCODE_RIGHT && L->cur + 1 < L->npages) {
        L->switch_to = L->cur + 1;
    }
}

void window_input(Loop *L, const Input *in)
{
    fl_runtime *rt = L->pages[L->cur].rt;
    switch (in->kind) {
    case INPUT_QUIT: L->quit = true; break;
    case INPUT_KEY: {
        const char *name = winkeys_name((SDL_Scancode)in->scancode);
        /* the view window (no !window) passes 0, which claims nothing */
        size_t index = in->index == NO_WINDOW ? 0 : in->index;
        int claimed = name ? fl_key(rt, index, name, in->pressed) : 0;
        if (!claimed) own_key(L, (SDL_Scancode)in->scancode, in->pressed);
        break;
    }
    case INPUT_POINTER:
        if (in->index != NO_WINDOW) fl_pointer(rt, in->index, in->inside, in->fx, in->fy);
        break;
    case INPUT_BUTTON:
        if (in->index != NO_WINDOW) fl_pointer_button(rt, in->index, in->button, in->pressed);
        break;
    case INPUT_RESIZED:
        /* paused, no frame comes to draw the physics view window at its
         * new output size: draw the last frame again */
        if (L->paused) L->redraw = true;
        break;
    }
}
