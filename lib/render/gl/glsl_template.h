/* glsl_template.h: the shader templates of `!shader` and the built-in
 * filters, a subset of the Mako template language that Flitter runs its
 * GLSL through (Flitter docs/shaders.md, "Shader templating").
 *
 * What a template may hold:
 *   ${EXPR}             the text of EXPR's value;
 *   % if EXPR: / % elif EXPR: / % else: / % endif
 *   % for NAME in EXPR: / % endfor   (inside: loop.index, loop.first, loop.last)
 *   ## a comment        (the line is dropped)
 *   <%include file="NAME"/>   the text of library file NAME (glsl_library.h:
 *                       composite_functions.glsl, color_functions.glsl,
 *                       filter_functions.glsl, ease_functions.glsl,
 *                       noise_functions.glsl), rendered with the same names
 *   %% at the start of a line for a literal %, a backslash at the end of a
 *   line joins it to the next.
 * A control line is one whose first character that is not a space or tab
 * is `%`. Expressions are Python's: numbers, 'strings', True, False, None,
 * names, tuples and lists, x[i], x.y (loop's only), calls of int, float,
 * str, len, abs, min, max, round and bool, unary - + not, ** * / // % + -,
 * comparisons (== != < <= > >= in, not in), and, or, and `a if c else b`.
 *
 * Values are Flitter vectors (a node attribute's value behaves as
 * Flitter's Vector does in Mako: arithmetic element-wise, `==` whole
 * vectors, str() the language's string conversion), with a style that
 * says how Python would print and treat a value of the engine's own
 * (an int, a float, a bool, a str, a list of strings, None).
 *
 * Errors never abort: a template that does not parse or names an unknown
 * name gives -1 with "line N: MESSAGE" (N of the template's own text).
 */
#ifndef FL_RENDER_GLSL_TEMPLATE_H
#define FL_RENDER_GLSL_TEMPLATE_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"
#include "value.h"

/* How a value prints and behaves where Python and Flitter's Vector
 * differ. */
typedef enum TplStyle {
    TPL_VEC,     /* a Flitter vector (a node attribute) */
    TPL_INT,     /* a Python int */
    TPL_FLOAT,   /* a Python float: printed with a point ("1.0") */
    TPL_BOOL,    /* True / False */
    TPL_STR,     /* a Python str (one string element) */
    TPL_LIST,    /* a list or tuple (of the vector's elements) */
    TPL_NONE,    /* None (the null vector) */
} TplStyle;

typedef struct TplValue {
    Vec *v;          /* one reference (NULL: the null vector) */
    TplStyle style;
} TplValue;

/* The names a template sees: [lookup] fills *[out] with a new reference
 * for [name] ([len] bytes, not NUL-terminated) and returns true, or
 * returns false for a name it does not know. [include] returns the text
 * of a library file, or NULL. [symbols] gives the names of symbols for
 * str() (may be NULL). */
typedef struct TplEnv {
    bool (*lookup)(void *ctx, const char *name, size_t len, TplValue *out);
    void *ctx;
    const char *(*include)(const char *file);
    const SymTab *symbols;
} TplEnv;

/* Render template [src] ([len] bytes) with [env]'s names, appending the
 * text to [out].
 *   errors: -1 with "line N: MESSAGE" appended to [err] when it
 *           does not parse, names an unknown name or include file, or
 *           nests deeper than 64 blocks; [out] then holds part of the
 *           text. Else 0. */
int tpl_render(const char *src, size_t len, const TplEnv *env, Buf *out, Buf *err);

/* Release [v]'s vector (the value itself is left NULL, TPL_NONE). */
void tpl_value_free(TplValue *v);

#endif
