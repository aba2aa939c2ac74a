/* state.c: the state dictionary (LANGUAGE.md §3.17).
 *
 * An open-addressing hash table of (key vector, value vector) entries with
 * linear probing. The table size is a power of two and is doubled when more
 * than half the slots are used (live or deleted). Each slot caches the key's
 * hash, vec_hash(key, false) of LANGUAGE.md §3.16 (raw bit patterns, so 0 and
 * -0 are distinct keys, as in the reference). Deleted entries leave a
 * tombstone (key NULL, hash TOMB) so probe chains stay intact; tombstones are
 * dropped when the table is rebuilt.
 *
 * Keys are hashed once: vec_key_hash() keeps the hash in the key vector, so
 * a writer that keeps its key vectors across frames (the physics engine, the
 * beat counter, a `$` of a literal key) pays for hashing once, and a probe
 * that meets the very same key vector skips the element comparison.
 *
 * A reader that asks for one key again and again (a `$` of a literal key,
 * frame after frame) keeps where it found it (state_get_cached): the slot,
 * and the table's layout (a small counted object that stands for where
 * every key is) at that time. Adding an entry and rebuilding the table give
 * it a new layout, so a kept slot is used only while no key can have moved
 * into a slot or out of it. Deleting an entry or clearing the table leaves
 * empty slots, whose value NULL is what a kept slot then rightly reads (the
 * key is absent); a value replaced in its slot is read there.
 */
#include "state.h"

#include <stdlib.h>
#include <string.h>

#include "mem.h"

#define TOMB UINT64_C(1)     /* marks a deleted slot (with key == NULL) */

typedef struct Slot {
    Vec *key;       /* NULL: empty (hash 0) or deleted (hash TOMB) */
    Vec *value;     /* non-empty value when key != NULL */
    uint64_t hash;  /* cached vec_hash(key, false) */
} Slot;

/* A layout of the table (see above): counted, so that a reader's kept
 * layout stays a distinct object for as long as it keeps it. */
struct StateLayout {
    size_t refs;
};

struct StateDict {
    Slot *slots;      /* cap slots */
    size_t cap;       /* power of two */
    size_t live;      /* entries with a key */
    size_t used;      /* live + tombstones */
    StateCounts counts; /* reads and writes */
    struct StateLayout *layout; /* the current layout, once a reader has
                                   kept it (one reference; NULL: none yet) */
};

static void layout_release(struct StateLayout *l)
{
    if (l && --l->refs == 0) free(l);
}

/* An entry added or the slots rebuilt: slots kept by readers no longer
 * name their keys. */
static void layout_changed(StateDict *sd)
{
    layout_release(sd->layout);
    sd->layout = NULL;
}

StateDict *state_new(void)
{
    StateDict *sd = calloc(1, sizeof *sd);
    if (!sd) mem_oom();
    sd->cap = 64;
    sd->slots = calloc(sd->cap, sizeof(Slot));
    if (!sd->slots) mem_oom();
    return sd;
}

void state_clear(StateDict *sd)
{
    for (size_t i = 0; i < sd->cap; i++) {
        vec_release(sd->slots[i].key);
        vec_release(sd->slots[i].value);
        sd->slots[i] = (Slot){NULL, NULL, 0};
    }
    sd->live = sd->used = 0;
    sd->counts.compound++;
}

void state_free(StateDict *sd)
{
    if (!sd) return;
    state_clear(sd);
    layout_changed(sd);   /* (readers keep theirs) */
    free(sd->slots);
    free(sd);
}

/* The key's hash, kept clear of the two slot markers 0 and TOMB. */
static uint64_t key_hash(const Vec *key)
{
    uint64_t h = vec_key_hash(key);
    return h <= TOMB ? h + 2 : h;
}

/* The slot holding [key], or NULL. */
static Slot *find(const StateDict *sd, const Vec *key, uint64_t h)
{
    size_t mask = sd->cap - 1;
    for (size_t i = (size_t)h & mask;; i = (i + 1) & mask) {
        Slot *s = &sd->slots[i];
        if (!s->key) {
            if (s->hash != TOMB) return NULL;
            continue;
        }
        if (s->hash == h && (s->key == key || vec_key_equal(s->key, key))) return s;
    }
}

const Vec *state_get(const StateDict *sd, const Vec *key)
{
    ((StateDict *)sd)->counts.gets++;
    if (!key || !key->len) return NULL;
    Slot *s = find(sd, key, key_hash(key));
    return s ? s->value : NULL;
}

const Vec *state_get_cached(StateDict *sd, const Vec *key, StateCached *c)
{
    sd->counts.gets++;
    if (c->layout && c->layout == sd->layout) return c->slot == SIZE_MAX ? NULL : sd->slots[c->slot].value;
    if (!key || !key->len) return NULL;
    Slot *s = find(sd, key, key_hash(key));
    if (!sd->layout) {
        sd->layout = mem_alloc(sizeof *sd->layout);
        sd->layout->refs = 1;
    }
    layout_release(c->layout);
    c->layout = sd->layout;
    c->layout->refs++;
    c->slot = s ? (size_t)(s - sd->slots) : SIZE_MAX;
    return s ? s->value : NULL;
}

void state_cached_release(StateCached *c)
{
    layout_release(c->layout);
    *c = (StateCached){NULL, 0};
}

const Vec *state_get_nums(const StateDict *sd, const double *x, uint32_t n)
{
    ((StateDict *)sd)->counts.gets++;
    if (!n) return NULL;
    uint64_t h = vec_hash_nums_raw(x, n);
    if (h <= TOMB) h += 2;   /* key_hash's */
    size_t mask = sd->cap - 1;
    /* find()'s probe, with vec_key_equal of a numeric key vector: the
     * same kind and length, the same bits */
    for (size_t i = (size_t)h & mask;; i = (i + 1) & mask) {
        const Slot *s = &sd->slots[i];
        if (!s->key) {
            if (s->hash != TOMB) return NULL;
            continue;
        }
        if (s->hash != h || s->key->kind != VEC_NUM || s->key->len != n) continue;
        const double *k = vec_cnums(s->key);
        uint32_t j = 0;
        while (j < n && memcmp(&k[j], &x[j], sizeof(double)) == 0) j++;
        if (j == n) return s->value;
    }
}

static void rebuild(StateDict *sd, size_t cap)
{
    Slot *old = sd->slots;
    size_t oldcap = sd->cap;
    /* zeroed by writing: a large calloc'd table comes as pages of the
     * kernel's zero page, and each would fault twice, at the first probe
     * that reads it and again at the first insert that writes it
     * (explicit_bzero, as the compiler makes malloc and memset a calloc) */
    layout_changed(sd);
    sd->slots = malloc(cap * sizeof(Slot));
    if (!sd->slots) mem_oom();
    explicit_bzero(sd->slots, cap * sizeof(Slot));
    sd->cap = cap;
    sd->used = sd->live;
    for (size_t i = 0; i < oldcap; i++) {
        if (!old[i].key) continue;
        size_t j = (size_t)old[i].hash & (cap - 1);
        while (sd->slots[j].key) j = (j + 1) & (cap - 1);
        sd->slots[j] = old[i];
    }
    free(old);
}

/* The table size that holds [n] entries without a rebuild (more than
 * half the slots used triggers one). */
static size_t cap_for(size_t cap, size_t n)
{
    while ((n + 1) * 2 > cap) cap *= 2;
    return cap;
}

/* state_set of key [key] (hash [h]), whose slot find() gave as [s] (NULL:
 * absent), to [value]; *[stored] receives the value stored under the key
 * afterwards (NULL when none). */
static bool set_found(StateDict *sd, const Vec *key, uint64_t h, Slot *s, const Vec *value, Vec **stored)
{
    *stored = NULL;
    if (!value || !value->len) {
        if (!s) return false;
        vec_release(s->key);
        vec_release(s->value);
        *s = (Slot){NULL, NULL, TOMB};
        sd->live--;
        return true;
    }
    if (s) {
        *stored = s->value;
        if (s->value == value || vec_key_equal(s->value, value)) return false;
        Vec *old = s->value;
        s->value = *stored = vec_retain((Vec *)value);
        vec_release(old);
        return true;
    }
    if ((sd->used + 1) * 2 > sd->cap) rebuild(sd, sd->live * 4 > sd->cap ? sd->cap * 2 : sd->cap);
    size_t mask = sd->cap - 1, i = (size_t)h & mask;
    while (sd->slots[i].key) i = (i + 1) & mask;
    if (sd->slots[i].hash != TOMB) sd->used++;
    sd->slots[i] = (Slot){vec_retain((Vec *)key), *stored = vec_retain((Vec *)value), h};
    sd->live++;
    layout_changed(sd);
    return true;
}

bool state_set(StateDict *sd, const Vec *key, const Vec *value)
{
    sd->counts.sets++;
    if (!key || !key->len) return false;
    if (key->len > 1) sd->counts.compound++;
    uint64_t h = key_hash(key);
    Vec *stored;
    return set_found(sd, key, h, find(sd, key, h), value, &stored);
}

Vec *state_set_nums(StateDict *sd, const Vec *key, const double *x, uint32_t n)
{
    sd->counts.gets++;
    if (!key || !key->len || !n) return NULL;
    uint64_t h = key_hash(key);
    Slot *s = find(sd, key, h);
    Vec *cur = s ? s->value : NULL;
    if (cur && cur->refs == 1 && cur->kind == VEC_NUM && cur->len == n) {
        memcpy(vec_nums(cur), x, n * sizeof *x);
        return cur;
    }
    sd->counts.sets++;
    if (key->len > 1) sd->counts.compound++;
    Vec *v = vec_from_nums(x, n), *stored;
    set_found(sd, key, h, s, v, &stored);
    vec_release(v);
    return stored;
}

void state_reserve(StateDict *sd, size_t extra)
{
    size_t want = sd->live + extra;
    if (want < sd->live || (sd->used + extra + 1) * 2 <= sd->cap) return;
    rebuild(sd, cap_for(sd->cap, want));
}

void state_prefetch(const StateDict *sd, uint64_t hash)
{
    uint64_t h = hash <= TOMB ? hash + 2 : hash;
    __builtin_prefetch(&sd->slots[(size_t)h & (sd->cap - 1)], 1);
}

size_t state_count(const StateDict *sd) { return sd->live; }

StateCounts state_counts(const StateDict *sd) { return sd->counts; }

StateEntry *state_entries(const StateDict *sd, size_t *n)
{
    StateEntry *e = malloc((sd->live ? sd->live : 1) * sizeof *e);
    if (!e) mem_oom();
    size_t k = 0;
    for (size_t i = 0; i < sd->cap; i++)
        if (sd->slots[i].key) e[k++] = (StateEntry){sd->slots[i].key, sd->slots[i].value};
    *n = k;
    return e;
}
