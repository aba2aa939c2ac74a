/* input.h: keyboard and pointer input of the windows a front end shows
 * (flitter.h fl_key, fl_pointer, fl_pointer_button), written into the
 * state dictionary as Flitter's window does (`!key` and `!pointer`,
 * Flitter 1.0.0b28 render/window/__init__.py, Window.handle_node,
 * key_callback, pointer_movement_callback, pointer_button_callback).
 */
#ifndef FL_INPUT_H
#define FL_INPUT_H

#include "node.h"
#include "state.h"
#include "value.h"

/* A runtime's input: which keys are held in which window. */
typedef struct Input Input;

Input *input_new(void);
/* Free [in] (NULL is a no-op). */
void input_free(Input *in);

/* After a frame is evaluated into [root]: each `!key name=NAME state=S`
 * directly under a top-level `!window` or `!offscreen` node (index i in
 * tree order), with NAME a GLFW key name, whose S is not in [state] gets
 * S = 1, S;:pushed = 1, S;:released = 0 when that key is held in window i
 * (per the earlier fl_key calls), else 0, 0, 1 (Flitter's
 * Window.handle_node, which runs for off-screen windows too). Symbol
 * names (name=:space) are read from [st]. */
void input_frame(Input *in, const Node *root, StateDict *state, const SymTab *st);

/* The GLFW key code (GLFW_KEY_*) of key name [name] (GLFW's names, any
 * case, e.g. "space", "left_shift", "kp_0"; "last" is "menu"), or -1. */
int input_key_code(const char *name, size_t len);

/* Key [code] (GLFW_KEY_*) pressed or released in window [window] (index
 * in tree order) of the frame [root] (may be NULL): held in [in] from now
 * on (or no longer); when a `!key` of that window claims the key, its
 * state S gets S = 1 or 0 and S;:pushed;:beat or S;:released;:beat =
 * [beat] (Flitter's Window.key_callback). Returns whether one claimed it. */
bool input_key(Input *in, const Node *root, size_t window, int code, bool pressed,
               StateDict *state, const SymTab *st, double beat);
/* The pointer at ([x], [y]) in window [window] of [root] ([inside]), or
 * gone from it: the state of a `!pointer` of that window gets x;y, or
 * loses its entry (Flitter's pointer_movement_callback). */
void input_pointer(const Node *root, size_t window, bool inside, double x, double y,
                   StateDict *state);
/* Pointer [button] pressed or released in window [window] of [root]: the
 * state S of a `!pointer` of that window gets S;button = 1 or 0
 * (Flitter's pointer_button_callback). */
void input_pointer_button(const Node *root, size_t window, int button, bool pressed,
                          StateDict *state);

#endif
