/* stable.c: the `let stable` value cache (stable.h). */
#include "stable.h"

#include <stdlib.h>

#include "mem.h"

typedef struct Entry {
    uint32_t id, index;
    Vec *value;      /* cached value (one reference) */
    bool stable;
} Entry;

struct StableCache {
    Entry *v;
    uint32_t n, cap;
    bool changed;    /* a key became stable this frame */
    bool aborted;    /* an asserted value changed this frame */
};

StableCache *stable_new(void)
{
    StableCache *sc = calloc(1, sizeof *sc);
    if (!sc) mem_oom();
    return sc;
}

void stable_clear(StableCache *sc)
{
    for (uint32_t i = 0; i < sc->n; i++) vec_release(sc->v[i].value);
    sc->n = 0;
    sc->changed = sc->aborted = false;
}

void stable_free(StableCache *sc)
{
    if (!sc) return;
    stable_clear(sc);
    free(sc->v);
    free(sc);
}

static Entry *find(const StableCache *sc, uint32_t id, uint32_t index)
{
    for (uint32_t i = 0; i < sc->n; i++)
        if (sc->v[i].id == id && sc->v[i].index == index) return &sc->v[i];
    return NULL;
}

bool stable_is_stable(const StableCache *sc, uint32_t id, uint32_t index)
{
    const Entry *e = sc ? find(sc, id, index) : NULL;
    return e && e->stable;
}

const Vec *stable_value(const StableCache *sc, uint32_t id, uint32_t index)
{
    const Entry *e = sc ? find(sc, id, index) : NULL;
    return e ? e->value : NULL;
}

uint32_t stable_count(const StableCache *sc)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < sc->n; i++) k += sc->v[i].stable;
    return k;
}

void stable_key(const StableCache *sc, uint32_t i, uint32_t *id, uint32_t *index)
{
    for (uint32_t j = 0; j < sc->n; j++) {
        if (!sc->v[j].stable) continue;
        if (i-- == 0) {
            *id = sc->v[j].id;
            *index = sc->v[j].index;
            return;
        }
    }
}

bool stable_check(StableCache *sc, const AstNode *let, uint32_t index, const Vec *value,
                  const uint32_t *asserted, uint32_t nasserted)
{
    if (sc->aborted) return true;
    uint32_t id = let->count;
    bool is_asserted = false;
    for (uint32_t i = 0; i < nasserted && !is_asserted; i++)
        is_asserted = asserted[2 * i] == id && asserted[2 * i + 1] == index;
    Entry *e = find(sc, id, index);
    /* equality as the reference's Vector.eq (identity, then values) */
    bool same = e && (e->value == value || vec_equal(e->value, value));
    if (is_asserted) {
        if (same) return true;
        if (e) {
            vec_release(e->value);
            *e = sc->v[--sc->n];
        }
        sc->aborted = true;
        return false;
    }
    if (same) {
        e->stable = true;
        sc->changed = true;
        return true;
    }
    if (!e) {
        if (sc->n == sc->cap) {
            sc->cap = sc->cap ? sc->cap * 2 : 8;
            sc->v = realloc(sc->v, sc->cap * sizeof *sc->v);
            if (!sc->v) mem_oom();
        }
        e = &sc->v[sc->n++];
        *e = (Entry){id, index, NULL, false};
    }
    vec_release(e->value);
    e->value = vec_retain((Vec *)value);
    return true;
}

bool stable_frame_done(StableCache *sc)
{
    bool changed = sc->changed;
    sc->changed = sc->aborted = false;
    return changed;
}
