/* window_input.c: SDL events of a run with live windows, turned into
 * Flitter's input: keys by name to the window's `!key` nodes, the pointer
 * as fractions of the shown picture to its `!pointer`, buttons numbered as
 * GLFW numbers them; what no node claims drives the front end itself
 * (quit, pages, overlay, physics view, pause, step). Events arrive between
 * frames, so what they write to the state is seen by the next frame. */
#include <string.h>

#include "window_keys.h"
#include "window_loop.h"

/* The slot of the SDL window [id], or NULL (a window already closed). */
static Slot *slot_of(Loop *L, Uint32 id)
{
    for (size_t i = 0; i < L->nslots; i++)
        if (L->slots[i].view.id == id) return &L->slots[i];
    return NULL;
}

/* The fl_windows index input of slot [s] goes to: the view window (no
 * !window) has none. */
static bool input_index(const Slot *s, size_t *index)
{
    if (!s || s->index == NO_WINDOW) return false;
    *index = s->index;
    return true;
}

/* The front end's own keys, for a key no !key claimed. */
static void own_key(Loop *L, SDL_Scancode sc, bool pressed)
{
    if (pressed) {
        switch (sc) {
        case SDL_SCANCODE_ESCAPE: L->quit = true; break;
        case SDL_SCANCODE_F1:
            L->show_status = !L->show_status;
            L->overlay_gen++;
            L->represent = true;
            break;
        case SDL_SCANCODE_F2:
            L->show_view = !L->show_view;
            L->redraw = true;
            break;
        case SDL_SCANCODE_F5:
            L->paused = !L->paused;
            fl_clock_pause(L->pages[L->cur].rt, L->paused);   /* `time` stops with the frames */
            L->overlay_gen++;
            L->represent = true;
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

static void key_event(Loop *L, const SDL_KeyboardEvent *k)
{
    if (k->repeat) return;
    bool pressed = k->type == SDL_KEYDOWN;
    fl_runtime *rt = L->pages[L->cur].rt;
    const char *name = winkeys_name(k->keysym.scancode);
    size_t index = 0;   /* the view window (no !window) passes 0, which claims nothing */
    input_index(slot_of(L, k->windowID), &index);
    int claimed = name ? fl_key(rt, index, name, pressed) : 0;
    if (!claimed) own_key(L, k->keysym.scancode, pressed);
}

/* SDL button numbers to GLFW's: left 0, right 1, middle 2, then 3, 4. */
static int glfw_button(Uint8 b)
{
    switch (b) {
    case SDL_BUTTON_LEFT: return 0;
    case SDL_BUTTON_RIGHT: return 1;
    case SDL_BUTTON_MIDDLE: return 2;
    default: return b - 1;   /* SDL_BUTTON_X1 (4) -> 3, X2 (5) -> 4 */
    }
}

void window_event(Loop *L, const SDL_Event *ev)
{
    fl_runtime *rt = L->pages[L->cur].rt;
    size_t index;
    switch (ev->type) {
    case SDL_QUIT: L->quit = true; break;
    case SDL_KEYDOWN:
    case SDL_KEYUP: key_event(L, &ev->key); break;
    case SDL_MOUSEMOTION: {
        Slot *s = slot_of(L, ev->motion.windowID);
        double fx, fy;
        if (input_index(s, &index)) {
            bool inside = winview_pointer(&s->view, ev->motion.x, ev->motion.y, &fx, &fy);
            fl_pointer(rt, index, inside, fx, fy);
        }
        break;
    }
    case SDL_MOUSEBUTTONDOWN:
    case SDL_MOUSEBUTTONUP:
        if (input_index(slot_of(L, ev->button.windowID), &index))
            fl_pointer_button(rt, index, glfw_button(ev->button.button),
                              ev->type == SDL_MOUSEBUTTONDOWN);
        break;
    case SDL_WINDOWEVENT:
        switch (ev->window.event) {
        case SDL_WINDOWEVENT_CLOSE: L->quit = true; break;
        case SDL_WINDOWEVENT_LEAVE:
            if (input_index(slot_of(L, ev->window.windowID), &index))
                fl_pointer(rt, index, false, 0, 0);
            break;
        case SDL_WINDOWEVENT_EXPOSED:
        case SDL_WINDOWEVENT_SIZE_CHANGED:
            L->represent = true;
            /* paused, no frame comes to draw the physics view window at its
             * new output size: draw the last frame again */
            if (L->paused) L->redraw = true;
            break;
        default: break;
        }
        break;
    default: break;
    }
}
