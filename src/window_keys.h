/* window_keys.h: SDL key codes to the key names of Flitter's `!key name=`. */
#ifndef FL_WINDOW_KEYS_H
#define FL_WINDOW_KEYS_H

#include <SDL.h>

/* The Flitter name of the physical key [sc]: GLFW's key token lower-cased
 * without its `KEY_` prefix ("a", "0", "space", "left_shift", "kp_add",
 * "f12"), the names `!key name=` takes.
 *   shapes: a static string, or NULL for a key GLFW has no token for
 *   source: Flitter render/window/__init__.py handle_node ('KEY_' +
 *           name.upper() looked up in glfw); GLFW names keys by their place
 *           on a US keyboard, as SDL scan codes do. */
const char *winkeys_name(SDL_Scancode sc);

#endif
