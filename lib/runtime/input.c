/* input.c: keys and the pointer of the shown windows, into the state
 * dictionary (see input.h; flitter.h fl_key, fl_pointer,
 * fl_pointer_button).
 *
 * Nothing about the windows is kept between frames but the keys held: as
 * Flitter's window rebuilds its key map from the `!key` children at each
 * frame, the claims of a key or of the pointer are looked up in the last
 * frame's tree when the event arrives. The held keys are a small list of
 * (window index, GLFW key code) pairs, as GLFW's glfw.get_key answers per
 * window. Key names are GLFW's (`'KEY_' + name.upper()` in Flitter), so a
 * name GLFW does not define claims nothing. The public functions that
 * deliver the events are api_windows.c's.
 */
#include "input.h"

#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "graph.h"

typedef struct Held {
    size_t window;   /* index of the window in tree order */
    int key;         /* GLFW key code */
} Held;

struct Input {
    Held *held;      /* keys down now */
    size_t nheld, cap;
};

Input *input_new(void) { return mem_calloc(1, sizeof(Input)); }

void input_free(Input *in)
{
    if (!in) return;
    free(in->held);
    free(in);
}

/* {=====================================================================
 * GLFW's key names (glfw3.h GLFW_KEY_*, as pyGLFW exposes them)
 * ===================================================================== */

typedef struct KeyName {
    const char *name;   /* upper case, as after Flitter's name.upper() */
    int code;
} KeyName;

static const KeyName keys[] = {
    {"SPACE", 32}, {"APOSTROPHE", 39}, {"COMMA", 44}, {"MINUS", 45}, {"PERIOD", 46},
    {"SLASH", 47}, {"0", 48}, {"1", 49}, {"2", 50}, {"3", 51}, {"4", 52}, {"5", 53},
    {"6", 54}, {"7", 55}, {"8", 56}, {"9", 57}, {"SEMICOLON", 59}, {"EQUAL", 61},
    {"A", 65}, {"B", 66}, {"C", 67}, {"D", 68}, {"E", 69}, {"F", 70}, {"G", 71}, {"H", 72},
    {"I", 73}, {"J", 74}, {"K", 75}, {"L", 76}, {"M", 77}, {"N", 78}, {"O", 79}, {"P", 80},
    {"Q", 81}, {"R", 82}, {"S", 83}, {"T", 84}, {"U", 85}, {"V", 86}, {"W", 87}, {"X", 88},
    {"Y", 89}, {"Z", 90}, {"LEFT_BRACKET", 91}, {"BACKSLASH", 92}, {"RIGHT_BRACKET", 93},
    {"GRAVE_ACCENT", 96}, {"WORLD_1", 161}, {"WORLD_2", 162}, {"ESCAPE", 256},
    {"ENTER", 257}, {"TAB", 258}, {"BACKSPACE", 259}, {"INSERT", 260}, {"DELETE", 261},
    {"RIGHT", 262}, {"LEFT", 263}, {"DOWN", 264}, {"UP", 265}, {"PAGE_UP", 266},
    {"PAGE_DOWN", 267}, {"HOME", 268}, {"END", 269}, {"CAPS_LOCK", 280},
    {"SCROLL_LOCK", 281}, {"NUM_LOCK", 282}, {"PRINT_SCREEN", 283}, {"PAUSE", 284},
    {"F1", 290}, {"F2", 291}, {"F3", 292}, {"F4", 293}, {"F5", 294}, {"F6", 295},
    {"F7", 296}, {"F8", 297}, {"F9", 298}, {"F10", 299}, {"F11", 300}, {"F12", 301},
    {"F13", 302}, {"F14", 303}, {"F15", 304}, {"F16", 305}, {"F17", 306}, {"F18", 307},
    {"F19", 308}, {"F20", 309}, {"F21", 310}, {"F22", 311}, {"F23", 312}, {"F24", 313},
    {"F25", 314}, {"KP_0", 320}, {"KP_1", 321}, {"KP_2", 322}, {"KP_3", 323},
    {"KP_4", 324}, {"KP_5", 325}, {"KP_6", 326}, {"KP_7", 327}, {"KP_8", 328},
    {"KP_9", 329}, {"KP_DECIMAL", 330}, {"KP_DIVIDE", 331}, {"KP_MULTIPLY", 332},
    {"KP_SUBTRACT", 333}, {"KP_ADD", 334}, {"KP_ENTER", 335}, {"KP_EQUAL", 336},
    {"LEFT_SHIFT", 340}, {"LEFT_CONTROL", 341}, {"LEFT_ALT", 342}, {"LEFT_SUPER", 343},
    {"RIGHT_SHIFT", 344}, {"RIGHT_CONTROL", 345}, {"RIGHT_ALT", 346},
    {"RIGHT_SUPER", 347}, {"MENU", 348}, {"LAST", 348},
};

int input_key_code(const char *name, size_t len)
{
    char up[16];
    if (len == 0 || len >= sizeof up) return -1;
    for (size_t i = 0; i < len; i++) {
        char c = name[i];
        if (c == '\0') return -1;
        up[i] = c >= 'a' && c <= 'z' ? (char)(c - 'a' + 'A') : c;
    }
    up[len] = '\0';
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(keys[i].name, up) == 0) return keys[i].code;
    return -1;
}

/* }===================================================================== */

/* The key code of a `!key` node's name= (a string, or a symbol by its
 * name: Flitter's node.get('name', 1, str)), or -1. */
static int node_key_code(const Node *n, const SymTab *st)
{
    const Vec *v = node_attr(n, "name");
    if (vec_len(v) != 1) return -1;
    if (vec_is_num(v)) {
        const Str *s = symtab_name(st, vec_cnums(v)[0]);
        return s ? input_key_code(s->bytes, s->len) : -1;
    }
    const Elem *e = &vec_celems(v)[0];
    return e->kind == EL_STR ? input_key_code(e->str->bytes, e->str->len) : -1;
}

/* The `state` of node [n] when it has one (not null), else NULL. */
static const Vec *state_of(const Node *n)
{
    const Vec *s = node_attr(n, "state");
    return vec_len(s) ? s : NULL;
}

/* Top-level window [index] of [root] (tree order), or NULL. */
static const Node *window_at(const Node *root, size_t index)
{
    for (uint32_t i = 0; root && i < root->nchildren; i++)
        if (graph_is_window(root->children[i]) && index-- == 0) return root->children[i];
    return NULL;
}

static bool is_held(const Input *in, size_t window, int key)
{
    for (size_t i = 0; i < in->nheld; i++)
        if (in->held[i].window == window && in->held[i].key == key) return true;
    return false;
}

static void set_held(Input *in, size_t window, int key, bool down)
{
    for (size_t i = 0; i < in->nheld; i++)
        if (in->held[i].window == window && in->held[i].key == key) {
            if (!down) in->held[i] = in->held[--in->nheld];
            return;
        }
    if (!down) return;
    if (in->nheld == in->cap) {
        in->cap = in->cap ? in->cap * 2 : 8;
        in->held = mem_realloc(in->held, in->cap * sizeof *in->held);
    }
    in->held[in->nheld++] = (Held){window, key};
}

/* Store number [x] under [prefix] followed by the symbols [sym1] and
 * [sym2] (either may be NULL: not appended). */
static void put(StateDict *sd, const Vec *prefix, const char *sym1, const char *sym2, double x)
{
    Vec *parts[3] = {(Vec *)prefix, NULL, NULL};
    size_t n = 1;
    if (sym1) parts[n++] = vec_num1(symbol_value(sym1, strlen(sym1)));
    if (sym2) parts[n++] = vec_num1(symbol_value(sym2, strlen(sym2)));
    Vec *key = vec_compose(parts, n);
    Vec *val = vec_num1(x);
    state_set(sd, key, val);
    vec_release(val);
    vec_release(key);
    for (size_t i = 1; i < n; i++) vec_release(parts[i]);
}

/* S, S;:pushed, S;:released for a key down ([down]) or up. */
static void put_key(StateDict *sd, const Vec *s, bool down)
{
    put(sd, s, NULL, NULL, down ? 1 : 0);
    put(sd, s, "pushed", NULL, down ? 1 : 0);
    put(sd, s, "released", NULL, down ? 0 : 1);
}

/* The state prefix of the last `!key` directly under [win] whose name is
 * key [code] (the key map Flitter's window rebuilds each frame, where a
 * later !key of the same key replaces an earlier one), or NULL. */
static const Vec *key_claim(const Node *win, int code, const SymTab *st)
{
    const Vec *found = NULL, *s;
    for (uint32_t j = 0; j < win->nchildren; j++) {
        const Node *k = win->children[j];
        if (node_is(k, "key") && (s = state_of(k)) && node_key_code(k, st) == code) found = s;
    }
    return found;
}

/* The state prefix of the last `!pointer state=P` directly under [win], or
 * NULL (Flitter's Window.handle_node). */
static const Vec *pointer_claim(const Node *win)
{
    const Vec *found = NULL, *s;
    for (uint32_t j = 0; j < win->nchildren; j++)
        if (node_is(win->children[j], "pointer") && (s = state_of(win->children[j]))) found = s;
    return found;
}

void input_frame(Input *in, const Node *root, StateDict *state, const SymTab *st)
{
    size_t index = 0;
    for (uint32_t i = 0; root && i < root->nchildren; i++) {
        const Node *win = root->children[i];
        if (!graph_is_window(win)) continue;
        for (uint32_t j = 0; j < win->nchildren; j++) {
            const Node *k = win->children[j];
            const Vec *s;
            int code;
            if (!node_is(k, "key") || !(s = state_of(k)) || (code = node_key_code(k, st)) < 0)
                continue;
            if (!state_get(state, s)) put_key(state, s, is_held(in, index, code));
        }
        index++;
    }
}

/* {=====================================================================
 * Events
 * ===================================================================== */

bool input_key(Input *in, const Node *root, size_t window, int code, bool pressed,
               StateDict *state, const SymTab *st, double beat)
{
    set_held(in, window, code, pressed);
    const Node *win = window_at(root, window);
    const Vec *s = win ? key_claim(win, code, st) : NULL;
    if (s) {
        put_key(state, s, pressed);
        put(state, s, pressed ? "pushed" : "released", "beat", beat);
    }
    return s != NULL;
}

void input_pointer(const Node *root, size_t window, bool inside, double x, double y,
                   StateDict *state)
{
    const Node *win = window_at(root, window);
    const Vec *p = win ? pointer_claim(win) : NULL;
    if (p) {
        double xy[2] = {x, y};
        Vec *val = inside ? vec_from_nums(xy, 2) : NULL;
        state_set(state, p, val);   /* null: the entry goes */
        vec_release(val);
    }
}

void input_pointer_button(const Node *root, size_t window, int button, bool pressed,
                          StateDict *state)
{
    const Node *win = window_at(root, window);
    const Vec *p = win ? pointer_claim(win) : NULL;
    if (p) {
        Vec *b = vec_num1(button);
        Vec *parts[2] = {(Vec *)p, b};
        Vec *key = vec_compose(parts, 2);
        Vec *val = vec_num1(pressed ? 1 : 0);
        state_set(state, key, val);
        vec_release(val);
        vec_release(key);
        vec_release(b);
    }
}

/* }===================================================================== */
