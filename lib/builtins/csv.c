/* csv.c: the csv(filename, row_number) built-in (LANGUAGE.md §5.12).
 *
 * Following the reference, csv() parses with the rules of Python's csv
 * module (excel dialect: ',' separators, '"' quoting with "" for a quote,
 * records ending at "\n", "\r\n" or "\r", a blank line being an empty
 * record); each cell that Python's float() accepts becomes a number,
 * trailing empty cells are dropped, and row floor(row) is returned. A
 * runtime keeps the file's bytes while it is unchanged (filememo.c) and,
 * with them, the rows parsed so far (CsvRows), as Flitter keeps its parsed
 * rows: a loop over a table's rows parses each row once, not the file from
 * the top for every row.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "context.h"
#include "fileio.h"
#include "files.h"
#include "mem.h"
#include "utf8.h"

/* ------------------------------------------------------------------ */
/* csv                                                                 */
/* ------------------------------------------------------------------ */

typedef enum {
    CSV_START_RECORD, CSV_START_FIELD, CSV_IN_FIELD, CSV_IN_QUOTED_FIELD,
    CSV_QUOTE_IN_QUOTED_FIELD, CSV_EAT_CRNL
} CsvState;

/* Parser of one CSV record at a time (Python's csv.reader state machine). */
typedef struct {
    const char *s;      /* file contents */
    size_t n, pos;      /* length and read position */
    CsvState state;
    Buf field;          /* the field being read */
    StrList fields;     /* the record's fields so far */
} Csv;

#define CSV_EOL (-1)

static void csv_save_field(Csv *c)
{
    strlist_push(&c->fields, str_new(buf_cstr(&c->field), c->field.len));
    buf_reset(&c->field);
}

static void csv_char(Csv *c, int ch)
{
    bool eol = ch == CSV_EOL, nl = ch == '\n' || ch == '\r';
    switch (c->state) {
    case CSV_START_RECORD:
        if (eol)
            break;
        if (nl) {
            c->state = CSV_EAT_CRNL;
            break;
        }
        c->state = CSV_START_FIELD;
        /* fall through */
    case CSV_START_FIELD:
        if (nl || eol) {
            csv_save_field(c);
            c->state = eol ? CSV_START_RECORD : CSV_EAT_CRNL;
        } else if (ch == '"') {
            c->state = CSV_IN_QUOTED_FIELD;
        } else if (ch == ',') {
            csv_save_field(c);
        } else {
            buf_putc(&c->field, (char)ch);
            c->state = CSV_IN_FIELD;
        }
        break;
    case CSV_IN_FIELD:
        if (nl || eol) {
            csv_save_field(c);
            c->state = eol ? CSV_START_RECORD : CSV_EAT_CRNL;
        } else if (ch == ',') {
            csv_save_field(c);
            c->state = CSV_START_FIELD;
        } else {
            buf_putc(&c->field, (char)ch);
        }
        break;
    case CSV_IN_QUOTED_FIELD:
        if (eol)
            break;
        if (ch == '"')
            c->state = CSV_QUOTE_IN_QUOTED_FIELD;
        else
            buf_putc(&c->field, (char)ch);
        break;
    case CSV_QUOTE_IN_QUOTED_FIELD:
        if (ch == '"') {
            buf_putc(&c->field, '"');
            c->state = CSV_IN_QUOTED_FIELD;
        } else if (ch == ',') {
            csv_save_field(c);
            c->state = CSV_START_FIELD;
        } else if (nl || eol) {
            csv_save_field(c);
            c->state = eol ? CSV_START_RECORD : CSV_EAT_CRNL;
        } else {
            buf_putc(&c->field, (char)ch);
            c->state = CSV_IN_FIELD;
        }
        break;
    case CSV_EAT_CRNL:
        if (eol)
            c->state = CSV_START_RECORD;
        break;
    }
}

/* Read the next record into c->fields; false at the end of the data. */
static bool csv_next(Csv *c)
{
    strlist_free(&c->fields);
    buf_reset(&c->field);
    c->state = CSV_START_RECORD;
    do {
        if (c->pos >= c->n) {
            if (c->field.len != 0 || c->state == CSV_IN_QUOTED_FIELD) {
                csv_save_field(c);
                return true;
            }
            return false;
        }
        /* One line: up to and including "\n", "\r\n" or "\r". */
        size_t start = c->pos, end = start;
        while (end < c->n && c->s[end] != '\n' && c->s[end] != '\r')
            end++;
        if (end < c->n)
            end += (c->s[end] == '\r' && end + 1 < c->n && c->s[end + 1] == '\n') ? 2 : 1;
        /* Python decodes as it reads: undecodable text ends the file. */
        if (!utf8_all_valid(c->s + start, end - start))
            return false;
        for (size_t i = start; i < end; i++)
            csv_char(c, (unsigned char)c->s[i]);
        csv_char(c, CSV_EOL);
        c->pos = end;
    } while (c->state != CSV_START_RECORD);
    return true;
}

/* The record's cells: numbers where float() accepts them, else strings;
 * trailing empty strings dropped. */
static Vec *csv_row_value(const StrList *fields)
{
    size_t n = fields->n;
    while (n > 0 && fields->v[n - 1]->len == 0)
        n--;
    if (n == 0 || n > UINT32_MAX)
        return NULL;
    Vec *r = vec_new_obj((uint32_t)n);
    Elem *e = vec_elems(r);
    for (size_t i = 0; i < n; i++) {
        Str *s = fields->v[i];
        double x;
        if (py_parse_float(s->bytes, s->len, &x)) {
            e[i].kind = EL_NUM;
            e[i].num = x;
        } else {
            e[i].kind = EL_STR;
            e[i].str = str_retain(s);
        }
    }
    return vec_normalize_take(r);
}

struct CsvRows {
    Csv c;              /* the parser, after the last row kept */
    Vec **row;          /* the rows' values so far (NULL: an empty row) */
    size_t n, cap;
    bool done;          /* the data ended */
};

static CsvRows *csv_rows_new(const char *s, size_t n)
{
    CsvRows *r = mem_calloc(1, sizeof *r);
    r->c = (Csv){s, n, 0, CSV_START_RECORD, BUF_INIT, {NULL, 0, 0}};
    return r;
}

void csv_rows_free(CsvRows *r)
{
    if (!r)
        return;
    for (size_t i = 0; i < r->n; i++)
        vec_release(r->row[i]);
    free(r->row);
    strlist_free(&r->c.fields);
    buf_free(&r->c.field);
    free(r);
}

/* Row [row] (>= 0) of [r], a new reference (NULL: an empty row, or past
 * the end), parsing on from the last row kept; the parse stops, keeping
 * what it has, when the evaluation is interrupted (null then). */
static Vec *csv_rows_get(Eval *ev, CsvRows *r, int64_t row)
{
    while ((int64_t)r->n <= row && !r->done) {
        if ((r->n & 1023) == 1023 && eval_interrupted(ev))
            return NULL;
        if (!csv_next(&r->c)) {
            r->done = true;
            break;
        }
        if (r->n == r->cap)
            r->row = mem_realloc_array(r->row, r->cap = r->cap ? 2 * r->cap : 64, sizeof *r->row);
        r->row[r->n++] = csv_row_value(&r->c.fields);
    }
    return row < (int64_t)r->n ? vec_retain(r->row[row]) : NULL;
}

/* The row number argument as Python's `match(1, int)` takes it: *[ok]
 * false means null; a message in *[err] means an error. */
static int64_t csv_row_number(const Vec *v, const SymTab *st, bool *ok, const char **err)
{
    int64_t row = 0;
    *ok = false;
    *err = NULL;
    if (vec_is_scalar(v)) {
        double f = vec_scalar(v);
        if (st && symtab_name(st, f))
            return 0;
        if (isnan(f)) {
            *err = "cannot convert float NaN to integer";
            return 0;
        }
        if (isinf(f)) {
            *err = "cannot convert float infinity to integer";
            return 0;
        }
        f = floor(f);
        /* rows beyond 2^62 cannot exist; clamp to stay in range */
        if (f > 4611686018427387904.0)
            f = 4611686018427387904.0;
        if (f < -4611686018427387904.0)
            f = -4611686018427387904.0;
        row = (int64_t)f;
        *ok = true;
    } else if (vec_is_obj(v) && v->len == 1 && vec_celems(v)[0].kind == EL_STR) {
        const Str *s = vec_celems(v)[0].str;
        *ok = py_parse_int(s->bytes, s->len, &row);
    }
    return row;
}

Vec *bi_csv(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    bool ok;
    const char *err;
    int64_t row = csv_row_number(args[1], eval_symtab(ev), &ok, &err);
    if (err)
        return bi_error(ev, bi, "%s", err);
    if (!ok || !vec_truthy(args[0]))
        return NULL;
    Buf name = BUF_INIT, path = BUF_INIT, data = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else if (row >= 0) {
        resolve_path(ev, buf_cstr(&name), &path);
        const char *bytes;
        size_t len;
        CsvRows **rows;
        const bool got = file_memo_bytes(eval_file_memo(ev), buf_cstr(&path), &data, &bytes, &len, &rows);
        if (got && rows) {
            /* the memo's bytes: its rows */
            if (!*rows)
                *rows = csv_rows_new(bytes, len);
            r = csv_rows_get(ev, *rows, row);
        } else if (got) {
            Csv c = {bytes, len, 0, CSV_START_RECORD, BUF_INIT, {NULL, 0, 0}};
            int64_t k = 0;
            while (csv_next(&c)) {
                if (k++ == row) {
                    r = csv_row_value(&c.fields);
                    break;
                }
            }
            strlist_free(&c.fields);
            buf_free(&c.field);
        } else {
            r = read_failed(ev, bi);
        }
    }
    buf_free(&name);
    buf_free(&path);
    buf_free(&data);
    return r;
}
