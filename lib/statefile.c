/* statefile.c: the exact state file (format in statefile.h).
 *
 * Writing reuses format.c's shortest round-trip number text, adding the two
 * things value text drops on purpose: the sign of zero and NaN bits. Reading
 * parses into a fresh dictionary first and only then swaps it in, so a bad
 * file changes nothing.
 */
#include "statefile.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "format.h"

#define MAGIC "flitter-state 1"
#define QNAN_BITS UINT64_C(0x7ff8000000000000)

/* ====================================================================
 * Writing
 * ==================================================================== */

static void put_number(Buf *b, double x, const SymTab *st)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    const Str *sym = symtab_name(st, x);
    if (sym) {
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

static bool write_all(int fd, const char *p, size_t n)
{
    while (n) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

int statefile_save(const StateDict *sd, const SymTab *st, const StateClock *clock,
                   const char *path, size_t *skipped, Buf *err)
{
    Buf b = BUF_INIT, line = BUF_INIT;
    buf_puts(&b, MAGIC "\n");
    buf_printf(&b, "clock %ld ", clock->frame);
    put_number(&b, clock->time, NULL);
    buf_putc(&b, ' ');
    put_number(&b, clock->last_time, NULL);
    buf_putc(&b, ' ');
    put_number(&b, clock->last_beat, NULL);
    buf_putc(&b, ' ');
    put_number(&b, clock->period, NULL);
    buf_putc(&b, ' ');
    put_number(&b, clock->quantum, NULL);
    buf_putc(&b, ' ');
    put_number(&b, clock->start, NULL);
    buf_putc(&b, '\n');
    size_t n, count = 0, skip = 0;
    StateEntry *e = state_entries(sd, &n);
    for (size_t i = 0; i < n; i++) {
        buf_reset(&line);
        bool ok = put_vector(&line, e[i].key, st);
        buf_puts(&line, " = ");
        ok = ok && put_vector(&line, e[i].value, st);
        if (!ok) {
            skip++;
            continue;
        }
        buf_add(&b, line.data, line.len);
        buf_putc(&b, '\n');
        count++;
    }
    free(e);
    buf_printf(&b, "end %zu\n", count);
    buf_free(&line);
    if (skipped) *skipped = skip;

    char *tmp;
    if (asprintf(&tmp, "%s.tmp%ld", path, (long)getpid()) < 0) abort();
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    bool ok = fd >= 0 && write_all(fd, b.data, b.len) && fsync(fd) == 0;
    if (fd >= 0) ok = close(fd) == 0 && ok;
    ok = ok && rename(tmp, path) == 0;
    int saved_errno = errno;
    if (!ok) unlink(tmp);
    free(tmp);
    buf_free(&b);
    if (!ok) {
        buf_printf(err, "%s: error: cannot save state: %s\n", path, strerror(saved_errno));
        return -1;
    }
    /* make the rename itself durable */
    char *dirc = strdup(path);
    if (dirc) {
        int dfd = open(dirname(dirc), O_RDONLY | O_DIRECTORY);
        if (dfd >= 0) {
            fsync(dfd);
            close(dfd);
        }
        free(dirc);
    }
    return 0;
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
    if (!(*p == '-' || (*p >= '0' && *p <= '9'))) return false;
    char *e;
    errno = 0;
    *out = strtod(p, &e);
    if (e == p || e > r->end) return false;
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

/* One vector up to [stop] (" = " or end of line); NULL on error. */
static bool read_vector(Reader *r, const char *stop, Vec **out)
{
    Vec *parts[1];
    Vec *acc = NULL;
    for (;;) {
        Vec *el = NULL;
        if (*r->p == '"') {
            Buf s = BUF_INIT;
            bool ok = read_string(r, &s);
            if (ok) el = vec_str(s.data ? s.data : "", s.len);
            buf_free(&s);
            if (!ok) goto bad;
        } else if (*r->p == ':') {
            const char *q = ++r->p;
            while (r->p < stop && *r->p != ';') r->p++;
            if (r->p == q) goto bad;
            el = vec_num1(symtab_add(r->st, q, (size_t)(r->p - q)));
        } else {
            double x;
            if (!read_number(r, &x)) goto bad;
            el = vec_num1(x);
        }
        Vec *both[2] = {acc, el};
        parts[0] = vec_compose(both, 2);
        vec_release(acc);
        vec_release(el);
        acc = parts[0];
        if (r->p == stop) break;
        if (*r->p != ';') goto bad;
        r->p++;
    }
    *out = acc;
    return true;
bad:
    vec_release(acc);
    return false;
}

int statefile_load(StateDict *sd, SymTab *st, StateClock *clock, const char *path, Buf *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        buf_printf(err, "%s: error: cannot read state: %s\n", path, strerror(errno));
        return -1;
    }
    Buf text = BUF_INIT;
    char chunk[65536];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) buf_add(&text, chunk, got);
    fclose(f);
    const char *s = buf_cstr(&text);
    StateDict *fresh = state_new();
    StateClock c = {0};
    long lineno = 0;
    size_t entries = 0;
    bool ended = false, have_clock = false;
    const char *why = NULL;
    while (*s && !why) {
        const char *nl = strchr(s, '\n');
        if (!nl) {
            why = "truncated line";
            break;
        }
        lineno++;
        Reader r = {s, nl, st};
        if (ended) {
            why = "text after the end line";
        } else if (lineno == 1) {
            if ((size_t)(nl - s) != strlen(MAGIC) || strncmp(s, MAGIC, strlen(MAGIC)) != 0)
                why = "not a flitter state file (version 1)";
        } else if (strncmp(s, "clock ", 6) == 0) {
            char *e;
            c.frame = strtol(s + 6, &e, 10);
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
            have_clock = true;
        } else if (strncmp(s, "end ", 4) == 0) {
            char *e;
            unsigned long long n = strtoull(s + 4, &e, 10);
            if (e != nl || n != entries) why = "entry count does not match (truncated file?)";
            ended = true;
        } else {
            const char *eq = strstr(s, " = ");
            Vec *k = NULL, *v = NULL;
            if (!eq || eq > nl) why = "expected KEY = VALUE";
            else if (!read_vector(&r, eq, &k)) why = "malformed key";
            else {
                r.p = eq + 3;
                if (!read_vector(&r, nl, &v)) why = "malformed value";
                else if (!k || !v) why = "empty key or value";
                else {
                    state_set(fresh, k, v);
                    entries++;
                }
            }
            vec_release(k);
            vec_release(v);
        }
        s = nl + 1;
    }
    if (!why && !ended) why = "missing end line (truncated file?)";
    if (!why && !have_clock) why = "missing clock line";
    buf_free(&text);
    if (why) {
        buf_printf(err, "%s:%ld: error: %s; state file refused\n", path, lineno, why);
        state_free(fresh);
        return -1;
    }
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
