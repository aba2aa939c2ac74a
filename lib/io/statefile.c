/* statefile.c: the exact state file (format in statefile.h).
 *
 * Writing reuses format.c's shortest round-trip number text, adding the two
 * things value text drops on purpose: the sign of zero and NaN bits. Reading
 * parses into a fresh dictionary first and only then swaps it in, so a bad
 * file changes nothing.
 */
#include "statefile.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "fileio.h"
#include "format.h"
#include "mem.h"
#include "utf8.h"

#define MAGIC "flitter-state 2"
#define MAGIC_V1 "flitter-state 1"
#define QNAN_BITS UINT64_C(0x7ff8000000000000)

uint64_t statefile_hash(const char *data, size_t len)
{
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    for (size_t i = 0; i < len; i++)
        h = (h ^ (unsigned char)data[i]) * UINT64_C(0x100000001b3);
    return h;
}

/* True when symbol name [s] can stand as `:NAME` in the file: not empty,
 * and none of the bytes that end an element or a key (space, `;`, `=`,
 * quotes, backslash, control bytes). Other symbols are written as their
 * numbers, which read back to the same value. */
static bool plain_symbol(const Str *s)
{
    if (s->len == 0) return false;
    for (uint32_t i = 0; i < s->len; i++) {
        unsigned char c = (unsigned char)s->bytes[i];
        if (c <= ' ' || c == ';' || c == '=' || c == '"' || c == '\\' || c == 0x7f) return false;
    }
    return true;
}

/* [text] of [len] bytes as a quoted string with FORMATS.md's escapes. */
static void put_quoted(Buf *b, const char *text, size_t len)
{
    Str *s = str_new(text, len);
    fmt_quoted(b, s);
    str_release(s);
}

/* ====================================================================
 * Writing
 * ==================================================================== */

static void put_number(Buf *b, double x, const SymTab *st)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    const Str *sym = symtab_name(st, x);
    if (sym && plain_symbol(sym)) {
        buf_putc(b, ':');
        buf_add(b, sym->bytes, sym->len);
    } else if (isnan(x)) {
        if (bits == QNAN_BITS) buf_puts(b, "nan");
        else buf_printf(b, "nan:%016llx", (unsigned long long)bits);
    } else if (x == 0.0) {
        buf_puts(b, signbit(x) ? "-0" : "0");
    } else {
        fmt_double(b, x);
    }
}

/* False when [v] holds something that cannot be stored. */
static bool put_vector(Buf *b, const Vec *v, const SymTab *st)
{
    for (uint32_t i = 0; i < v->len; i++) {
        if (i) buf_putc(b, ';');
        if (v->kind == VEC_NUM) {
            put_number(b, vec_cnums(v)[i], st);
            continue;
        }
        const Elem *e = &vec_celems(v)[i];
        if (e->kind == EL_NUM) put_number(b, e->num, st);
        else if (e->kind == EL_STR) fmt_quoted(b, e->str);
        else return false;
    }
    return v->kind != VEC_STREAM;
}

static int line_cmp(const void *x, const void *y)
{
    return strcmp(*(char *const *)x, *(char *const *)y);
}

const char *statefile_clock_refused(const StateClock *c)
{
    if (c->frame < 0 || c->frame > MAX_FRAME) return "frame number out of range (0 to 2^53)";
    if (!(isfinite(c->time) && isfinite(c->last_time) && isfinite(c->last_beat) && isfinite(c->start)))
        return "clock time out of range (not finite)";
    if (!(isfinite(c->period) && c->period > 0 && isfinite(c->quantum) && c->quantum > 0))
        return "clock period or quantum out of range (not positive and finite)";
    return NULL;
}

int statefile_save(const StateDict *sd, const SymTab *st, const StateClock *clock,
                   const StateOrigin *origin, const char *path, size_t *skipped, Buf *err)
{
    const char *refused = statefile_clock_refused(clock);
    if (refused) {
        /* a file its own loader would refuse is never written */
        buf_printf(err, "%s: error: cannot save the state: %s\n", path, refused);
        return -1;
    }
    Buf b = BUF_INIT, line = BUF_INIT;
    buf_puts(&b, MAGIC "\n");
    if (origin && origin->script) {
        buf_puts(&b, "script ");
        put_quoted(&b, origin->script, strlen(origin->script));
        buf_printf(&b, " %016llx\n", (unsigned long long)origin->hash);
    }
    buf_printf(&b, "clock %ld", clock->frame);
    const double fields[6] = {clock->time, clock->last_time, clock->last_beat,
                              clock->period, clock->quantum, clock->start};
    for (int k = 0; k < 6; k++) {
        buf_putc(&b, ' ');
        put_number(&b, fields[k], NULL);
    }
    buf_putc(&b, '\n');
    /* the entries in the byte order of their lines, so that equal states
     * give equal files (checksum included), whatever the order of the
     * dictionary's table */
    size_t n, count = 0, skip = 0;
    StateEntry *e = state_entries(sd, &n);
    char **lines = mem_alloc((n ? n : 1) * sizeof *lines);
    for (size_t i = 0; i < n; i++) {
        buf_reset(&line);
        bool ok = put_vector(&line, e[i].key, st);
        buf_puts(&line, " = ");
        ok = ok && put_vector(&line, e[i].value, st);
        if (!ok) {
            skip++;
            continue;
        }
        lines[count++] = mem_strdup(buf_cstr(&line));
    }
    free(e);
    qsort(lines, count, sizeof *lines, line_cmp);
    for (size_t i = 0; i < count; i++) {
        buf_puts(&b, lines[i]);
        buf_putc(&b, '\n');
        free(lines[i]);
    }
    free(lines);
    buf_printf(&b, "end %zu\n", count);
    buf_printf(&b, "checksum %016llx\n", (unsigned long long)statefile_hash(b.data, b.len));
    buf_free(&line);
    if (skipped) *skipped = skip;

    Buf why = BUF_INIT;
    bool ok = file_write_atomic(path, b.data, b.len, &why);
    buf_free(&b);
    if (!ok) buf_printf(err, "%s: error: cannot save state: %s\n", path, buf_line(&why));
    buf_free(&why);
    return ok ? 0 : -1;
}

/* ====================================================================
 * Reading
 * ==================================================================== */

typedef struct Reader {
    const char *p;      /* cursor */
    const char *end;    /* end of the current line */
    SymTab *st;
} Reader;

static bool read_number(Reader *r, double *out)
{
    const char *p = r->p;
    if (strncmp(p, "nan:", 4) == 0) {
        char *e;
        unsigned long long bits = strtoull(p + 4, &e, 16);
        if (e != p + 20) return false;
        uint64_t u = bits;
        memcpy(out, &u, sizeof u);
        if (!isnan(*out)) return false;
        r->p = e;
        return true;
    }
    if (strncmp(p, "nan", 3) == 0) {
        uint64_t u = QNAN_BITS;
        memcpy(out, &u, sizeof u);
        r->p = p + 3;
        return true;
    }
    if (strncmp(p, "inf", 3) == 0 || strncmp(p, "-inf", 4) == 0) {
        *out = p[0] == '-' ? -INFINITY : INFINITY;
        r->p = p + (p[0] == '-' ? 4 : 3);
        return true;
    }
    /* only what the writer produces: -?DIGITS(.DIGITS)?(e[+-]?DIGITS)?,
     * so no hex floats, no spaces and no overflow to infinity */
    const char *q = p + (*p == '-');
    size_t digits = strspn(q, "0123456789");
    if (digits == 0) return false;
    q += digits;
    if (*q == '.') {
        digits = strspn(q + 1, "0123456789");
        if (digits == 0) return false;
        q += 1 + digits;
    }
    if (*q == 'e') {
        q += 1 + (q[1] == '+' || q[1] == '-');
        digits = strspn(q, "0123456789");
        if (digits == 0) return false;
        q += digits;
    }
    char *e;
    *out = strtod(p, &e);
    if (e != q || e > r->end || isinf(*out)) return false;
    r->p = e;
    return true;
}

static bool read_string(Reader *r, Buf *s)
{
    const char *p = r->p + 1;
    while (p < r->end && *p != '"') {
        if (*p != '\\') {
            buf_putc(s, *p++);
            continue;
        }
        p++;
        if (p >= r->end) return false;
        switch (*p) {
        case '"': buf_putc(s, '"'); break;
        case '\\': buf_putc(s, '\\'); break;
        case 'n': buf_putc(s, '\n'); break;
        case 'r': buf_putc(s, '\r'); break;
        case 't': buf_putc(s, '\t'); break;
        case 'x': {
            if (p + 2 >= r->end) return false;
            char hex[3] = {p[1], p[2], 0}, *e;
            long c = strtol(hex, &e, 16);
            if (*e) return false;
            buf_putc(s, (char)c);
            p += 2;
            break;
        }
        default: return false;
        }
        p++;
    }
    if (p >= r->end) return false;
    r->p = p + 1;
    return true;
}

/* One element at the cursor (string, symbol or number); NULL on error. */
static Vec *read_element(Reader *r)
{
    if (*r->p == '"') {
        Buf s = BUF_INIT;
        /* escapes must not make invalid UTF-8 (`\xbe`): the writer could
         * not store such a string again */
        Vec *el = read_string(r, &s) && utf8_all_valid(buf_cstr(&s), s.len)
                      ? vec_str(s.data ? s.data : "", s.len) : NULL;
        buf_free(&s);
        return el;
    }
    if (*r->p == ':') {
        const char *q = ++r->p;
        while (r->p < r->end && *r->p != ';' && *r->p != ' ') r->p++;
        return r->p == q ? NULL : vec_num1(symtab_add(r->st, q, (size_t)(r->p - q)));
    }
    double x;
    return read_number(r, &x) ? vec_num1(x) : NULL;
}

/* A value of numbers and symbols only (no string on the rest of the
 * line): parsed straight into one numeric vector, so that memory is the
 * vector itself, proportional to the file, instead of
 * one object per element; its size is asked of the memory budget first
 * (mem.h). false on a malformed element or a refusal (*[oom] set). */
static bool read_numbers(Reader *r, Vec **out, bool *oom)
{
    size_t n = 1;
    for (const char *q = r->p; (q = memchr(q, ';', (size_t)(r->end - q))); q++) n++;
    if (n > MAX_COMPOSE_LEN || !mem_fits(sizeof(Vec) + n * sizeof(double))) {
        mem_take_refusal();
        *oom = true;
        return false;
    }
    Vec *v = vec_new_num((uint32_t)n);
    double *d = vec_nums(v);
    for (size_t i = 0; i < n; i++) {
        bool ok;
        if (*r->p == ':') {
            const char *q = ++r->p;
            while (r->p < r->end && *r->p != ';' && *r->p != ' ') r->p++;
            ok = r->p != q;
            if (ok) d[i] = symtab_add(r->st, q, (size_t)(r->p - q));
        } else {
            ok = read_number(r, &d[i]);
        }
        if (!ok || (i + 1 < n ? *r->p++ != ';' : r->p != r->end)) {
            vec_release(v);
            return false;
        }
    }
    *out = v;
    return true;
}

/* One vector of `;`-separated elements: a key ([key]: up to the first
 * " = " after a whole element, so a string may hold " = ") or a value (up
 * to the end of the line); false on a malformed element or when the
 * memory budget refuses it (*[oom] set). */
static bool read_vector(Reader *r, bool key, Vec **out, bool *oom)
{
    if (!key && !memchr(r->p, '"', (size_t)(r->end - r->p))) return read_numbers(r, out, oom);
    /* one object per element, about 100 bytes each, for at most one
     * element per two bytes of the text (a key: up to its first " = "):
     * asked of the budget first */
    const char *end = key ? memmem(r->p, (size_t)(r->end - r->p), " = ", 3) : NULL;
    if (!mem_fits((size_t)((end ? end : r->end) - r->p) / 2 * 100)) {
        mem_take_refusal();
        *oom = true;
        return false;
    }
    Vec **els = NULL;
    size_t n = 0, cap = 0;
    bool ok = true;
    for (;;) {
        Vec *el = read_element(r);
        if (!el) {
            ok = false;
            break;
        }
        if (n == cap) {
            cap = cap ? cap * 2 : 8;
            els = realloc(els, cap * sizeof(Vec *));
            if (!els) mem_oom();
        }
        els[n++] = el;
        if (key ? r->end - r->p >= 3 && memcmp(r->p, " = ", 3) == 0 : r->p == r->end) break;
        if (*r->p != ';') {
            ok = false;
            break;
        }
        r->p++;
    }
    *out = ok ? vec_compose(els, n) : NULL;
    for (size_t i = 0; i < n; i++) vec_release(els[i]);
    free(els);
    return ok;
}

int statefile_load(StateDict *sd, SymTab *st, StateClock *clock, StateOrigin *origin,
                   const char *path, Buf *err)
{
    Buf text = BUF_INIT;
    if (!file_read_regular(path, &text)) {
        buf_printf(err, "%s: error: cannot read state: %s\n", path,
                   errno == EINVAL ? "not a regular file" : strerror(errno));
        buf_free(&text);
        return -1;
    }
    const char *s = buf_cstr(&text);
    if (memchr(s, '\0', text.len) || !utf8_all_valid(s, text.len)) {
        buf_printf(err, "%s: error: not a flitter state file (NUL byte or invalid UTF-8); "
                   "state file refused\n", path);
        buf_free(&text);
        return -1;
    }
    StateDict *fresh = state_new();
    StateClock c = {0};
    long lineno = 0;
    size_t entries = 0;
    int version = 0;
    bool ended = false, have_clock = false, checked = false;
    Buf script = BUF_INIT;
    uint64_t script_hash = 0;
    bool have_script = false;
    const char *why = NULL;
    const char *const start = s;
    while (*s && !why) {
        const char *nl = strchr(s, '\n');
        lineno++;
        if (!nl) {
            why = "truncated line";
            break;
        }
        Reader r = {s, nl, st};
        size_t len = (size_t)(nl - s);
        if (checked) {
            why = "text after the checksum line";
        } else if (ended) {
            /* version 2: `checksum HASH`, FNV-1a 64 of every byte before it */
            char *e;
            errno = 0;
            unsigned long long sum = len == 25 && strncmp(s, "checksum ", 9) == 0
                                         ? strtoull(s + 9, &e, 16) : 0;
            if (version != 2 || len != 25 || strncmp(s, "checksum ", 9) != 0 || e != nl ||
                errno == ERANGE || strspn(s + 9, "0123456789abcdef") != 16)
                why = version == 2 ? "malformed checksum line" : "text after the end line";
            else if (sum != statefile_hash(start, (size_t)(s - start)))
                why = "state file damaged (checksum mismatch)";
            checked = true;
        } else if (lineno == 1) {
            if (len == strlen(MAGIC) && strncmp(s, MAGIC, len) == 0) version = 2;
            else if (len == strlen(MAGIC_V1) && strncmp(s, MAGIC_V1, len) == 0) version = 1;
            else why = "not a flitter state file (version 1 or 2)";
        } else if (lineno == 2 && version == 2 && strncmp(s, "script \"", 8) == 0) {
            /* version 2: `script "PATH" HASH` (the script that saved it) */
            r.p = s + 7;
            char *e;
            if (!read_string(&r, &script) || *r.p != ' ' || nl - r.p != 17 ||
                strspn(r.p + 1, "0123456789abcdef") != 16)
                why = "malformed script line";
            else {
                script_hash = strtoull(r.p + 1, &e, 16);
                have_script = true;
            }
        } else if (strncmp(s, "clock ", 6) == 0) {
            char *e = (char *)s + 6;
            errno = 0;
            long long frame = *e >= '0' && *e <= '9' ? strtoll(s + 6, &e, 10) : -1;
            if (have_clock) why = "second clock line";
            else if (frame < 0 || frame > MAX_FRAME || errno == ERANGE)
                why = "frame number out of range (0 to 2^53)";
            c.frame = (long)frame;
            r.p = e;
            double *fields[6] = {&c.time, &c.last_time, &c.last_beat, &c.period, &c.quantum, &c.start};
            for (int k = 0; k < 6 && !why; k++) {
                if (*r.p != ' ') why = "malformed clock line";
                else {
                    r.p++;
                    if (!read_number(&r, fields[k])) why = "malformed clock line";
                }
            }
            if (!why && r.p != nl) why = "malformed clock line";
            if (!why) why = statefile_clock_refused(&c);
            have_clock = true;
        } else if (strncmp(s, "end ", 4) == 0) {
            char *e = (char *)s + 4;
            errno = 0;
            unsigned long long n = *e >= '0' && *e <= '9' ? strtoull(s + 4, &e, 10) : 0;
            if (e != nl || errno == ERANGE || n != entries)
                why = "entry count does not match (truncated file?)";
            ended = true;
        } else {
            Vec *k = NULL, *v = NULL;
            bool oom = false;
            if (!read_vector(&r, true, &k, &oom))
                why = oom ? "out of memory (past the memory budget)" : "malformed key (expected KEY = VALUE)";
            else {
                r.p += 3;
                if (!read_vector(&r, false, &v, &oom))
                    why = oom ? "out of memory (past the memory budget)" : "malformed value";
                else if (!k || !v) why = "empty key or value";
                else {
                    state_set(fresh, k, v);
                    if (state_count(fresh) != ++entries) why = "duplicate key";
                }
            }
            vec_release(k);
            vec_release(v);
        }
        s = nl + 1;
    }
    if (!why && !ended) why = "missing end line (truncated file?)";
    if (!why && version == 2 && !checked) why = "missing checksum line (truncated file?)";
    if (!why && !have_clock) why = "missing clock line";
    buf_free(&text);
    if (why) {
        buf_printf(err, "%s:%ld: error: %s; state file refused\n", path, lineno, why);
        state_free(fresh);
        buf_free(&script);
        return -1;
    }
    if (origin) {
        origin->script = have_script ? strndup(script.data ? script.data : "", script.len) : NULL;
        if (have_script && !origin->script) mem_oom();
        origin->hash = script_hash;
    }
    buf_free(&script);
    /* swap the new contents in */
    state_clear(sd);
    size_t n;
    StateEntry *e = state_entries(fresh, &n);
    for (size_t i = 0; i < n; i++) state_set(sd, e[i].key, e[i].value);
    free(e);
    state_free(fresh);
    *clock = c;
    return 0;
}
