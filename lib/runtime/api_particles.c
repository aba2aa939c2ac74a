/* api_particles.c: fl_particles, the particles of one !physics system read
 * back from the state dictionary (flitter.h, "Particles").
 *
 * A !physics system with state prefix P writes, for every particle ID, its
 * position under the key P;ID and its velocity under P;ID;:velocity
 * (PHYSICS-ENGINE.md §2, step 8; Flitter 1.0.0b28 physics/engine.pyx,
 * PhysicsSystem.handle_node). A particle here is exactly such a pair of
 * numeric entries of one length D. Anchors are written the same way and
 * come too; the clock keys (P, P;:clock, ...) have no velocity key, so
 * they do not. The particles come
 * in the order of the state dump: sorted by the bytes of the key's value
 * text (FORMATS.md §2), which is also the order of `fl_state_iterate`.
 */
#include "runtime.h"

#include <stdlib.h>
#include <string.h>

#include "format.h"
#include "mem.h"

/* One candidate position entry: its key text, borrowed key and value. */
typedef struct Cand {
    char *text;        /* value text of the whole key */
    const Vec *key;    /* P;ID (borrowed from the dictionary) */
    const Vec *value;  /* the position, D numbers (borrowed) */
} Cand;

static int by_text(const void *a, const void *b)
{
    return strcmp(((const Cand *)a)->text, ((const Cand *)b)->text);
}

/* Element [i] of a non-stream vector [v] as a number (*num) or a string
 * (*str); returns false for nodes and functions. */
static bool elem_at(const Vec *v, uint32_t i, double *num, const Str **str)
{
    if (vec_is_num(v)) {
        *num = vec_cnums(v)[i];
        *str = NULL;
        return true;
    }
    const Elem *e = &vec_celems(v)[i];
    if (e->kind == EL_NUM) {
        *num = e->num;
        *str = NULL;
        return true;
    }
    if (e->kind == EL_STR) {
        *str = e->str;
        return true;
    }
    return false;
}

/* Is element [i] of [a] the same state-key element as element [j] of [b]
 * (numbers by bit pattern, strings by bytes: vec_key_equal's rule)? */
static bool same_elem(const Vec *a, uint32_t i, const Vec *b, uint32_t j)
{
    double x = 0, y = 0;
    const Str *s = NULL, *t = NULL;
    if (!elem_at(a, i, &x, &s) || !elem_at(b, j, &y, &t)) return false;
    if (s || t) return s && t && s->len == t->len && memcmp(s->bytes, t->bytes, s->len) == 0;
    return memcmp(&x, &y, sizeof x) == 0;
}

/* True when [key] is P;ID with ID non-empty: longer than [P] and starting
 * with P's elements. */
static bool under_prefix(const Vec *key, const Vec *P)
{
    if (vec_is_stream(key) || vec_len(key) <= vec_len(P)) return false;
    for (uint32_t i = 0; i < vec_len(P); i++)
        if (!same_elem(key, i, P, i)) return false;
    return true;
}

long fl_particles(fl_runtime *rt, const char *system_text, fl_particle_fn fn, void *ctx)
{
    if (!rt) return -1;
    if (!system_text) return rt_fail(rt, "fl_particles: [system_text] is NULL");
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    Vec *P = rt_parse_value(rt, system_text);
    if (!P) {
        buf_printf(rt_error_buf(rt), "empty !physics state prefix\n");
        mem_leave(prev);
        return -1;
    }
    Vec *vsym = vec_num1(symbol_value("velocity", strlen("velocity")));
    size_t n;
    StateEntry *e = state_entries(rt_state(rt), &n);
    Cand *c = mem_calloc(n ? n : 1, sizeof *c);
    size_t nc = 0;
    Buf b = BUF_INIT;
    for (size_t i = 0; i < n; i++) {
        if (!vec_is_num(e[i].value) || !under_prefix(e[i].key, P)) continue;
        buf_reset(&b);
        fmt_value(&b, e[i].key, rt_symbols(rt));
        c[nc].text = mem_strdup(buf_cstr(&b));
        c[nc].key = e[i].key;
        c[nc].value = e[i].value;
        nc++;
    }
    free(e);
    qsort(c, nc, sizeof *c, by_text);

    /* the ID's text is the key's text after P's text and its `;` */
    buf_reset(&b);
    fmt_value(&b, P, rt_symbols(rt));
    size_t plen = b.len + 1;
    long visited = 0;
    bool stop = false;
    for (size_t i = 0; i < nc && !stop; i++) {
        Vec *parts[2] = {(Vec *)c[i].key, vsym};
        Vec *vkey = vec_compose(parts, 2);
        const Vec *vel = state_get(rt_state(rt), vkey);
        vec_release(vkey);
        if (!vec_is_num(vel) || vec_len(vel) != vec_len(c[i].value)) continue;
        visited++;
        if (fn && fn(ctx, c[i].text + plen, vec_cnums(c[i].value), vec_cnums(vel),
                     vec_len(vel)))
            stop = true;
    }
    for (size_t i = 0; i < nc; i++) free(c[i].text);
    free(c);
    buf_free(&b);
    vec_release(vsym);
    vec_release(P);
    mem_leave(prev);
    return visited;
}
