/* state.h: the state dictionary (LANGUAGE.md §3.17, PHYSICS.md "State
 * interaction").
 *
 * A hash table from key vectors to non-empty value vectors. Keys compare with
 * vec_key_equal (raw bit patterns: 0 and -0 are different keys; `:a` and "a"
 * differ) and hash with vec_hash(key, false). Setting a key to null (or an
 * empty vector) deletes it. The ownership rule of value.h applies.
 */
#ifndef FL_STATE_H
#define FL_STATE_H

#include "value.h"

typedef struct StateDict StateDict;

/* One entry, borrowed from the dictionary (state_entries). */
typedef struct StateEntry {
    const Vec *key;     /* non-null key */
    const Vec *value;   /* non-empty value */
} StateEntry;

StateDict *state_new(void);
void state_free(StateDict *sd);
/* The value stored under [key] (borrowed; valid until the next state_set
 * or state_clear), or NULL when absent or when [key] is null. */
const Vec *state_get(const StateDict *sd, const Vec *key);
/* state_get of the numeric key vector made of the [n] numbers [x] (a
 * reader whose key is numbers it computed, without making the vector):
 * the same entry, the same count of one read; NULL when [n] is 0. */
const Vec *state_get_nums(const StateDict *sd, const double *x, uint32_t n);
/* Where a reader of one key that never changes (a `$` of a literal key in
 * compiled code) last found it, for state_get_cached. Zeroed: nothing
 * known. Owned by its reader, who frees it with state_cached_release. */
typedef struct StateCached {
    struct StateLayout *layout; /* the table's layout when it was filled (one
                                   reference; NULL: none) */
    size_t slot;                /* the key's slot in that layout, or SIZE_MAX:
                                   the key was absent */
} StateCached;
/* state_get of [key] for a reader that asks for the same [key] every time
 * with the same [c]: while no entry has been added and the table has not
 * been rebuilt since [c] was filled (by any dictionary's lookup: a
 * layout belongs to one dictionary, and [c] holds a reference to it, so its
 * address names nothing else meanwhile), the answer is the value now in
 * the slot it found (or NULL: absent), without hashing or comparing the
 * key; otherwise state_get's search, which fills [c]. The same value and
 * the same count of one read as state_get. */
const Vec *state_get_cached(StateDict *sd, const Vec *key, StateCached *c);
/* Release what [c] holds and zero it. */
void state_cached_release(StateCached *c);
/* Store [value] under [key] (both borrowed and retained). A null or empty
 * [value] deletes the entry. A null [key] is ignored. Returns true when the
 * stored value changed (a set to an equal value, or a delete of a missing
 * key, is not a change). */
bool state_set(StateDict *sd, const Vec *key, const Vec *value);
/* state[key] = the [n] numbers [x], for the dictionary's owner writing
 * numbers every frame (the physics engine): when the value stored under
 * [key] is a numeric vector of [n] numbers that nothing else holds
 * (refs == 1), they are overwritten in place (the copy-on-write rule of
 * value.h); else it is state_set with a new vector of them (an
 * equal value already stored is kept; past the memory budget, mem.h, the
 * new vector is null and the key is deleted). One lookup in all; counts
 * one read, and a write when it did not go in place. Returns the value
 * stored under [key] afterwards (borrowed, under the same rule), or NULL
 * when none ([key] or [n] 0 included). */
Vec *state_set_nums(StateDict *sd, const Vec *key, const double *x, uint32_t n);
/* Make room for [extra] more entries, so that inserting up to that many
 * rebuilds the table at most once, now (a writer about to add many). */
void state_reserve(StateDict *sd, size_t extra);
/* Fetch into the cache the slot where a lookup of a key whose
 * vec_key_hash is [hash] starts (a writer of many keys, some ahead of the
 * one it writes); changes nothing. */
void state_prefetch(const StateDict *sd, uint64_t hash);
/* How often the dictionary was read (state_get) and written (state_set);
 * [compound] counts the writes to keys of two or more elements and the
 * clears: a reader that keeps values of compound keys across calls (the
 * physics engine's particle keys, P;id) knows them unchanged while it stays
 * the same, whatever single-element keys (the beat counter) were set. */
typedef struct StateCounts {
    unsigned long long gets, sets, compound;
} StateCounts;
StateCounts state_counts(const StateDict *sd);
/* Number of entries. */
size_t state_count(const StateDict *sd);
/* Remove every entry. */
void state_clear(StateDict *sd);
/* Fill a new array (caller frees with free()) with the [*n] entries, in
 * unspecified order; the vectors are borrowed from the dictionary. */
StateEntry *state_entries(const StateDict *sd, size_t *n);

#endif
