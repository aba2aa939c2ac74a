/* trace.c: trajectories as CSV or JSON Lines (see trace.h). */
#include "trace.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "buf.h"
#include "format.h"
#include "mem.h"

struct Trace {
    FILE *f;
    const SymTab *symbols;
    bool jsonl;
    int columns;      /* CSV: dimensions per vector, fixed by the first frame; 0 before */
    Buf row, tmp;
};

Trace *trace_open(const char *path, const SymTab *symbols, Buf *err)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        buf_printf(err, "%s: cannot create trace file: %s\n", path, strerror(errno));
        return NULL;
    }
    Trace *t = calloc(1, sizeof *t);
    if (!t) mem_oom();
    size_t len = strlen(path);
    t->f = f;
    t->symbols = symbols;
    t->jsonl = len >= 6 && strcasecmp(path + len - 6, ".jsonl") == 0;
    t->row = (Buf)BUF_INIT;
    t->tmp = (Buf)BUF_INIT;
    return t;
}

/* A CSV field: quoted when it holds a comma, quote or line break. */
static void csv_field(Buf *b, const char *s)
{
    if (!strpbrk(s, ",\"\r\n")) {
        buf_puts(b, s);
        return;
    }
    buf_putc(b, '"');
    for (; *s; s++) {
        if (*s == '"') buf_putc(b, '"');
        buf_putc(b, *s);
    }
    buf_putc(b, '"');
}

/* A JSON string (control bytes escaped; other bytes as they are, UTF-8). */
static void json_string(Buf *b, const char *s)
{
    buf_putc(b, '"');
    for (; *s; s++) {
        unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\') {
            buf_putc(b, '\\');
            buf_putc(b, (char)ch);
        } else if (ch < 0x20) {
            buf_printf(b, "\\u%04x", ch);
        } else {
            buf_putc(b, (char)ch);
        }
    }
    buf_putc(b, '"');
}

static void json_number(Buf *b, double x)
{
    if (isfinite(x)) fmt_double(b, x);
    else buf_puts(b, "null");
}

static void json_vector(Buf *b, const Vec *v, int dims)
{
    buf_putc(b, '[');
    for (int k = 0; k < dims; k++) {   /* absent: 0, the engine's default */
        if (k) buf_putc(b, ',');
        json_number(b, ps_coord(v, k));
    }
    buf_putc(b, ']');
}

static void csv_header(Trace *t)
{
    static const char *const xyz[] = {"x", "y", "z"};
    Buf *b = &t->row;
    buf_reset(b);
    buf_puts(b, "frame,time,system,id,kind");
    for (int v = 0; v < 2; v++)
        for (int k = 0; k < t->columns; k++) {
            if (t->columns <= 3) buf_printf(b, ",%s%s", v ? "v" : "", xyz[k]);
            else buf_printf(b, ",%s%d", v ? "v" : "x", k);
        }
    buf_putc(b, '\n');
    fputs(buf_cstr(b), t->f);
}

static void csv_vector(Buf *b, const Vec *v, int dims, int columns)
{
    for (int k = 0; k < columns; k++) {
        buf_putc(b, ',');
        /* absent: 0; a single number stands for every coordinate */
        if (k < dims && (!v || vec_len(v) == 1 || (uint32_t)k < vec_len(v))) fmt_double(b, ps_coord(v, k));
    }
}

int trace_frame(Trace *t, long frame, double time, const PsSystem *systems, size_t n)
{
    if (!t->jsonl && t->columns == 0) {
        for (size_t i = 0; i < n; i++)
            if (systems[i].dims > t->columns) t->columns = systems[i].dims;
        if (t->columns == 0) return 0;   /* nothing to trace yet */
        csv_header(t);
    }
    Buf *b = &t->row, *s = &t->tmp;
    for (size_t i = 0; i < n; i++) {
        const PsSystem *sys = &systems[i];
        Buf name = BUF_INIT;
        fmt_str(&name, sys->prefix, t->symbols);
        for (size_t j = 0; j < sys->nbodies; j++) {
            const PsBody *body = &sys->bodies[j];
            const char *kind = body->anchor ? "anchor" : "particle";
            buf_reset(b);
            buf_reset(s);
            fmt_str(s, body->id, t->symbols);
            if (t->jsonl) {
                buf_printf(b, "{\"frame\":%ld,\"time\":", frame);
                json_number(b, time);
                buf_puts(b, ",\"system\":");
                json_string(b, buf_cstr(&name));
                buf_puts(b, ",\"id\":");
                if (vec_is_scalar(body->id) && !(t->symbols && symtab_name(t->symbols, vec_scalar(body->id))))
                    json_number(b, vec_scalar(body->id));   /* a plain number, not a symbol */
                else json_string(b, buf_cstr(s));
                buf_printf(b, ",\"kind\":\"%s\",\"position\":", kind);
                json_vector(b, body->pos, sys->dims);
                buf_puts(b, ",\"velocity\":");
                json_vector(b, body->vel, sys->dims);
                buf_puts(b, "}\n");
            } else {
                buf_printf(b, "%ld,", frame);
                fmt_double(b, time);
                buf_putc(b, ',');
                csv_field(b, buf_cstr(&name));
                buf_putc(b, ',');
                csv_field(b, buf_cstr(s));
                buf_printf(b, ",%s", kind);
                csv_vector(b, body->pos, sys->dims, t->columns);
                csv_vector(b, body->vel, sys->dims, t->columns);
                buf_putc(b, '\n');
            }
            fputs(buf_cstr(b), t->f);
        }
        buf_free(&name);
    }
    return ferror(t->f) ? -1 : 0;
}

int trace_close(Trace *t)
{
    if (!t) return 0;
    int rc = ferror(t->f) ? -1 : 0;
    if (fclose(t->f) != 0) rc = -1;
    buf_free(&t->row);
    buf_free(&t->tmp);
    free(t);
    return rc;
}
