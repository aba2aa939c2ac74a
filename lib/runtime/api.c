/* api.c: the public functions of flitter.h that have an internal twin in
 * runtime.h: they turn Buf results into fl_error() text and writer
 * callbacks, value text into vectors (state keys and values), and install
 * the runtime's error callback as the allocation-failure handler (mem.h)
 * for the length of each call.
 */
#include "runtime.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "config.h"
#include "format.h"
#include "mem.h"

const char *fl_version(void) { return FL_VERSION_STRING; }

/* Copy [b]'s text into [buf] ([cap] bytes, truncated, NUL-terminated). */
static void copy_out(const Buf *b, char *buf, size_t cap)
{
    if (!cap) return;
    size_t k = b->len < cap - 1 ? b->len : cap - 1;
    if (k) memcpy(buf, b->data, k);
    buf[k] = '\0';
}

size_t fl_number_text(double x, char *buf, size_t cap)
{
    if (!buf) cap = 0;   /* a NULL [buf] receives nothing */
    Buf b = BUF_INIT;
    fmt_double(&b, x);
    copy_out(&b, buf, cap);
    size_t n = b.len;
    buf_free(&b);
    return n;
}

const char *fl_builtin_name(size_t i)
{
    static const Builtin *const families[] = {
        bi_vector_table, bi_maths_table, bi_random_table, bi_noise_table,
        bi_colour_table, bi_text_table, bi_file_table,
    };
    for (size_t f = 0; f < sizeof families / sizeof families[0]; f++)
        for (const Builtin *b = families[f]; b->name; b++)
            if (i-- == 0) return b->name;
    return NULL;
}

const char *fl_error(const fl_runtime *rt)
{
    if (!rt) return "no runtime: the fl_runtime pointer is NULL (did fl_new fail?)\n";
    Buf *b = rt_error_buf((fl_runtime *)rt);
    return b->len ? b->data : "";
}

/* Start a call that can fail: clear the error text, enter the handler. */
static MemHandler begin(fl_runtime *rt)
{
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    return prev;
}

/* Hand [b]'s text to [fn] (nothing when it is empty). */
static void deliver(const Buf *b, fl_write_fn fn, void *ctx)
{
    if (b->len && fn) fn(ctx, b->data, b->len);
}

int fl_load(fl_runtime *rt, const char *path)
{
    if (!rt) return -1;
    if (!path) return rt_fail(rt, "fl_load: [path] is NULL");
    MemHandler prev = begin(rt);
    int rc = rt_load(rt, path, rt_error_buf(rt));
    mem_leave(prev);
    return rc;
}

int fl_load_text(fl_runtime *rt, const char *name, const char *text, size_t len)
{
    if (!rt) return -1;
    if (!name) return rt_fail(rt, "fl_load_text: [name] is NULL");
    if (!text && len) return rt_fail(rt, "fl_load_text: [text] is NULL for %zu bytes", len);
    if (len > FILE_READ_MAX)
        return rt_fail(rt, "%s: program text of %zu bytes: over the %zu-byte limit of a script",
                       name, len, FILE_READ_MAX);
    if (!text) text = "";
    MemHandler prev = begin(rt);
    int rc = rt_load_text(rt, name, text, len, rt_error_buf(rt));
    mem_leave(prev);
    return rc;
}

int fl_save_state(fl_runtime *rt, const char *path)
{
    if (!rt) return -1;
    if (!path) return rt_fail(rt, "fl_save_state: [path] is NULL");
    MemHandler prev = begin(rt);
    int rc = rt_save_state(rt, path, rt_error_buf(rt));
    mem_leave(prev);
    return rc;
}

int fl_restore_state(fl_runtime *rt, const char *path)
{
    if (!rt) return -1;
    if (!path) return rt_fail(rt, "fl_restore_state: [path] is NULL");
    MemHandler prev = begin(rt);
    int rc = rt_restore_state(rt, path, rt_error_buf(rt));
    mem_leave(prev);
    return rc;
}

int fl_eval(fl_runtime *rt, const char *text, size_t len, fl_write_fn fn, void *ctx)
{
    if (!rt) return -1;
    if (!text && len) return rt_fail(rt, "fl_eval: [text] is NULL for %zu bytes", len);
    if (len > FILE_READ_MAX)
        return rt_fail(rt, "fl_eval: text of %zu bytes: over the %zu-byte limit of a script",
                       len, FILE_READ_MAX);
    if (!text) text = "";
    MemHandler prev = begin(rt);
    Buf out = BUF_INIT;
    int rc = rt_eval(rt, text, len, &out, rt_error_buf(rt));
    deliver(&out, fn, ctx);
    buf_free(&out);
    mem_leave(prev);
    return rc;
}

int fl_state_set_expr(fl_runtime *rt, const char *key_expr, const char *value_expr,
                      fl_write_fn fn, void *ctx)
{
    if (!rt) return -1;
    if (!key_expr) return rt_fail(rt, "fl_state_set_expr: [key_expr] is NULL");
    if (!value_expr) return rt_fail(rt, "fl_state_set_expr: [value_expr] is NULL");
    MemHandler prev = begin(rt);
    Buf out = BUF_INIT;
    int rc = rt_state_set_expr(rt, key_expr, value_expr, &out, rt_error_buf(rt));
    deliver(&out, fn, ctx);
    buf_free(&out);
    mem_leave(prev);
    return rc;
}

int fl_dump_program(fl_runtime *rt, fl_write_fn fn, void *ctx)
{
    if (!rt) return -1;
    if (!fn) return rt_fail(rt, "fl_dump_program: [fn] is NULL");
    MemHandler prev = rt_enter(rt);
    Buf out = BUF_INIT;
    int rc = rt_dump_program(rt, &out);
    if (rc < 0) rt_fail(rt, "fl_dump_program: no program is loaded");
    deliver(&out, fn, ctx);
    buf_free(&out);
    mem_leave(prev);
    return rc;
}

static int dump_syntax(fl_runtime *rt, const char *path, bool ast, fl_write_fn fn, void *ctx)
{
    const char *name = ast ? "fl_dump_ast" : "fl_dump_tokens";
    if (!rt) return -1;
    if (!path) return rt_fail(rt, "%s: [path] is NULL", name);
    if (!fn) return rt_fail(rt, "%s: [fn] is NULL", name);
    MemHandler prev = begin(rt);
    Buf out = BUF_INIT;
    int rc = rt_dump_syntax(rt, path, ast, &out, rt_error_buf(rt));
    deliver(&out, fn, ctx);
    buf_free(&out);
    mem_leave(prev);
    return rc;
}

int fl_dump_tokens(fl_runtime *rt, const char *path, fl_write_fn fn, void *ctx)
{
    return dump_syntax(rt, path, false, fn, ctx);
}

int fl_dump_ast(fl_runtime *rt, const char *path, fl_write_fn fn, void *ctx)
{
    return dump_syntax(rt, path, true, fn, ctx);
}

int fl_dump_tree(fl_runtime *rt, fl_write_fn fn, void *ctx)
{
    if (!rt) return -1;
    if (!fn) return rt_fail(rt, "fl_dump_tree: [fn] is NULL");
    const Node *root = rt_root(rt);
    if (!root) return rt_fail(rt, "fl_dump_tree: no frame has been evaluated yet");
    MemHandler prev = rt_enter(rt);
    Buf out = BUF_INIT;
    fmt_tree(&out, root, rt_symbols(rt));
    deliver(&out, fn, ctx);
    buf_free(&out);
    mem_leave(prev);
    return 0;
}

void fl_dump_state(fl_runtime *rt, fl_write_fn fn, void *ctx)
{
    if (!rt) return;
    if (!fn) {
        rt_fail(rt, "fl_dump_state: [fn] is NULL");
        return;
    }
    MemHandler prev = rt_enter(rt);
    Buf out = BUF_INIT;
    fmt_state_dump(&out, rt_state(rt), fl_frame_count(rt) - 1, fl_frame_time(rt), rt_symbols(rt));
    deliver(&out, fn, ctx);
    buf_free(&out);
    mem_leave(prev);
}

size_t fl_scope_names(fl_runtime *rt, int (*fn)(void *ctx, const char *name), void *ctx)
{
    if (!rt) return 0;
    if (!fn) {
        rt_fail(rt, "fl_scope_names: [fn] is NULL");
        return 0;
    }
    MemHandler prev = rt_enter(rt);
    size_t n, i;
    const Str *const *names = rt_scope_names(rt, &n);
    for (i = 0; i < n;)
        if (fn(ctx, names[i++]->bytes)) break;
    mem_leave(prev);
    return i;
}

/* {=====================================================================
 * The state dictionary through value text
 * ===================================================================== */

/* The value stored under [key_text] (borrowed), or NULL. */
static const Vec *lookup(fl_runtime *rt, const char *key_text)
{
    Vec *key = rt_parse_value(rt, key_text);
    const Vec *v = key ? state_get(rt_state(rt), key) : NULL;
    vec_release(key);
    return v;
}

long fl_state_get(fl_runtime *rt, const char *key_text, char *buf, size_t cap)
{
    if (!rt) return -3;
    if (!key_text) {
        rt_fail(rt, "fl_state_get: [key_text] is NULL");
        return -3;
    }
    if (!buf) cap = 0;   /* a NULL [buf] receives nothing */
    MemHandler prev = rt_enter(rt);
    const Vec *v = lookup(rt, key_text);
    long n = -1;
    if (v) {
        Buf text = BUF_INIT;
        fmt_value(&text, v, rt_symbols(rt));
        n = (long)text.len;
        copy_out(&text, buf, cap);
        buf_free(&text);
    }
    mem_leave(prev);
    return n;
}

long fl_state_get_numbers(fl_runtime *rt, const char *key_text, double *out, size_t cap)
{
    if (!rt) return -3;
    if (!key_text) {
        rt_fail(rt, "fl_state_get_numbers: [key_text] is NULL");
        return -3;
    }
    if (!out) cap = 0;   /* a NULL [out] receives nothing */
    MemHandler prev = rt_enter(rt);
    const Vec *v = lookup(rt, key_text);
    long n = -1;
    if (v && !vec_is_num(v)) {
        n = -2;
    } else if (v) {
        n = (long)vec_len(v);
        size_t k = vec_len(v) < cap ? vec_len(v) : cap;
        if (k) memcpy(out, vec_cnums(v), k * sizeof *out);
    }
    mem_leave(prev);
    return n;
}

/* Store [value] (consumed; NULL deletes) under [key_text]; [fn] names
 * the caller in the message for an empty key. */
static int store(fl_runtime *rt, const char *fn, const char *key_text, Vec *value)
{
    Vec *key = rt_parse_value(rt, key_text);
    int rc = -1;
    if (key) {
        state_set(rt_state(rt), key, value);
        rc = 0;
    } else {
        rt_fail(rt, "%s: the key text is empty (null is never stored)", fn);
    }
    vec_release(key);
    vec_release(value);
    return rc;
}

int fl_state_set(fl_runtime *rt, const char *key_text, const char *value_text)
{
    if (!rt) return -1;
    if (!key_text) return rt_fail(rt, "fl_state_set: [key_text] is NULL");
    if (!value_text) return rt_fail(rt, "fl_state_set: [value_text] is NULL (\"\" deletes)");
    MemHandler prev = rt_enter(rt);
    int rc = store(rt, "fl_state_set", key_text, rt_parse_value(rt, value_text));
    mem_leave(prev);
    return rc;
}

int fl_state_set_numbers(fl_runtime *rt, const char *key_text, const double *values, size_t n)
{
    if (!rt) return -1;
    if (!key_text) return rt_fail(rt, "fl_state_set_numbers: [key_text] is NULL");
    if (!values && n)
        return rt_fail(rt, "fl_state_set_numbers: [values] is NULL for %zu numbers", n);
    if (n > MAX_COMPOSE_LEN)
        return rt_fail(rt, "fl_state_set_numbers: %zu numbers: more than the longest vector (%llu)",
                       n, (unsigned long long)MAX_COMPOSE_LEN);
    MemHandler prev = rt_enter(rt);
    if (!mem_fits(sizeof(Vec) + n * sizeof(double))) {
        mem_leave(prev);
        return rt_fail(rt, "fl_state_set_numbers: %zu numbers: out of memory (the budget, "
                       "fl_options.max_memory)", n);
    }
    int rc = store(rt, "fl_state_set_numbers", key_text,
                   n ? vec_from_nums(values, (uint32_t)n) : NULL);
    mem_leave(prev);
    return rc;
}

size_t fl_state_count(const fl_runtime *rt)
{
    return rt ? state_count(rt_state((fl_runtime *)rt)) : 0;
}

/* One entry as text, for sorting by key text (the state dump's order). */
typedef struct TextEntry {
    char *key, *value;
} TextEntry;

static int by_key(const void *a, const void *b)
{
    return strcmp(((const TextEntry *)a)->key, ((const TextEntry *)b)->key);
}

size_t fl_state_iterate(fl_runtime *rt, fl_state_fn fn, void *ctx)
{
    if (!rt) return 0;
    if (!fn) {
        rt_fail(rt, "fl_state_iterate: [fn] is NULL");
        return 0;
    }
    MemHandler prev = rt_enter(rt);
    size_t n;
    StateEntry *e = state_entries(rt_state(rt), &n);
    TextEntry *t = mem_calloc(n, sizeof *t);
    Buf b = BUF_INIT;
    for (size_t i = 0; i < n; i++) {
        buf_reset(&b);
        fmt_value(&b, e[i].key, rt_symbols(rt));
        t[i].key = mem_strdup(buf_cstr(&b));
        buf_reset(&b);
        fmt_value(&b, e[i].value, rt_symbols(rt));
        t[i].value = mem_strdup(buf_cstr(&b));
    }
    buf_free(&b);
    free(e);
    qsort(t, n, sizeof *t, by_key);
    size_t visited = 0;
    while (visited < n) {
        const TextEntry *x = &t[visited++];
        if (fn(ctx, x->key, x->value)) break;
    }
    for (size_t i = 0; i < n; i++) {
        free(t[i].key);
        free(t[i].value);
    }
    free(t);
    mem_leave(prev);
    return visited;
}

bool fl_parse_memory(const char *text, size_t *out)
{
    return out && mem_parse_size(text, out);
}
