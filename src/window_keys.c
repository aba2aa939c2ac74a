/* window_keys.c: the table from SDL scan codes (a key's place on the
 * keyboard) to Flitter's key names, which are GLFW's key tokens in lower
 * case (Flitter render/window/__init__.py looks `KEY_` + NAME.upper() up in
 * glfw). Both SDL and GLFW name a key by where it sits on a US keyboard, so
 * the table is one entry per GLFW token; letters, digits and F-keys are
 * computed from their contiguous scan-code ranges. */
#include "window_keys.h"

#include <stddef.h>

static const struct {
    SDL_Scancode sc;
    const char *name;
} named[] = {
    {SDL_SCANCODE_SPACE, "space"},          {SDL_SCANCODE_APOSTROPHE, "apostrophe"},
    {SDL_SCANCODE_COMMA, "comma"},          {SDL_SCANCODE_MINUS, "minus"},
    {SDL_SCANCODE_PERIOD, "period"},        {SDL_SCANCODE_SLASH, "slash"},
    {SDL_SCANCODE_SEMICOLON, "semicolon"},  {SDL_SCANCODE_EQUALS, "equal"},
    {SDL_SCANCODE_LEFTBRACKET, "left_bracket"}, {SDL_SCANCODE_BACKSLASH, "backslash"},
    {SDL_SCANCODE_RIGHTBRACKET, "right_bracket"}, {SDL_SCANCODE_GRAVE, "grave_accent"},
    {SDL_SCANCODE_NONUSBACKSLASH, "world_2"},
    {SDL_SCANCODE_ESCAPE, "escape"},        {SDL_SCANCODE_RETURN, "enter"},
    {SDL_SCANCODE_TAB, "tab"},              {SDL_SCANCODE_BACKSPACE, "backspace"},
    {SDL_SCANCODE_INSERT, "insert"},        {SDL_SCANCODE_DELETE, "delete"},
    {SDL_SCANCODE_RIGHT, "right"},          {SDL_SCANCODE_LEFT, "left"},
    {SDL_SCANCODE_DOWN, "down"},            {SDL_SCANCODE_UP, "up"},
    {SDL_SCANCODE_PAGEUP, "page_up"},       {SDL_SCANCODE_PAGEDOWN, "page_down"},
    {SDL_SCANCODE_HOME, "home"},            {SDL_SCANCODE_END, "end"},
    {SDL_SCANCODE_CAPSLOCK, "caps_lock"},   {SDL_SCANCODE_SCROLLLOCK, "scroll_lock"},
    {SDL_SCANCODE_NUMLOCKCLEAR, "num_lock"}, {SDL_SCANCODE_PRINTSCREEN, "print_screen"},
    {SDL_SCANCODE_PAUSE, "pause"},
    {SDL_SCANCODE_KP_PERIOD, "kp_decimal"}, {SDL_SCANCODE_KP_DIVIDE, "kp_divide"},
    {SDL_SCANCODE_KP_MULTIPLY, "kp_multiply"}, {SDL_SCANCODE_KP_MINUS, "kp_subtract"},
    {SDL_SCANCODE_KP_PLUS, "kp_add"},       {SDL_SCANCODE_KP_ENTER, "kp_enter"},
    {SDL_SCANCODE_KP_EQUALS, "kp_equal"},
    {SDL_SCANCODE_LSHIFT, "left_shift"},    {SDL_SCANCODE_LCTRL, "left_control"},
    {SDL_SCANCODE_LALT, "left_alt"},        {SDL_SCANCODE_LGUI, "left_super"},
    {SDL_SCANCODE_RSHIFT, "right_shift"},   {SDL_SCANCODE_RCTRL, "right_control"},
    {SDL_SCANCODE_RALT, "right_alt"},       {SDL_SCANCODE_RGUI, "right_super"},
    {SDL_SCANCODE_MENU, "menu"},            {SDL_SCANCODE_APPLICATION, "menu"},
};

/* "a".."z", "0".."9", "f1".."f24", "kp_0".."kp_9" */
static const char *const letters[26] = {
    "a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l", "m",
    "n", "o", "p", "q", "r", "s", "t", "u", "v", "w", "x", "y", "z"};
static const char *const digits[10] = {"1", "2", "3", "4", "5", "6", "7", "8", "9", "0"};
static const char *const fkeys[24] = {
    "f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8", "f9", "f10", "f11", "f12",
    "f13", "f14", "f15", "f16", "f17", "f18", "f19", "f20", "f21", "f22", "f23", "f24"};
static const char *const keypad[10] = {"kp_1", "kp_2", "kp_3", "kp_4", "kp_5",
                                       "kp_6", "kp_7", "kp_8", "kp_9", "kp_0"};

const char *winkeys_name(SDL_Scancode sc)
{
    if (sc >= SDL_SCANCODE_A && sc <= SDL_SCANCODE_Z) return letters[sc - SDL_SCANCODE_A];
    /* SDL orders the digit row 1..9 then 0, as the keys sit */
    if (sc >= SDL_SCANCODE_1 && sc <= SDL_SCANCODE_0) return digits[sc - SDL_SCANCODE_1];
    if (sc >= SDL_SCANCODE_F1 && sc <= SDL_SCANCODE_F12) return fkeys[sc - SDL_SCANCODE_F1];
    if (sc >= SDL_SCANCODE_F13 && sc <= SDL_SCANCODE_F24) return fkeys[12 + sc - SDL_SCANCODE_F13];
    if (sc >= SDL_SCANCODE_KP_1 && sc <= SDL_SCANCODE_KP_0) return keypad[sc - SDL_SCANCODE_KP_1];
    for (size_t i = 0; i < sizeof named / sizeof named[0]; i++)
        if (named[i].sc == sc) return named[i].name;
    return NULL;
}
