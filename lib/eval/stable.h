/* stable.h: `let stable` bindings (LANGUAGE.md §4.4; Flitter's
 * docs/language.md "let stable"; behaviour per the reference's StableTest /
 * StableAssert instructions and engine loop).
 *
 * Each `let stable` of a simplified program has an id (AstNode.count of its
 * AST_LET, numbered by the simplifier); binding i of it is the key (id, i).
 * When a key's value is the same on two frames in a row it becomes stable:
 * after that frame the runtime simplifies the program again with the value
 * known as a literal (so the rules of §4.17 apply to it) and runs that
 * program, which asserts the value each frame. When an asserted value
 * changes, the frame is evaluated again with the program as first
 * simplified, and the key is no longer stable.
 */
#ifndef FL_STABLE_H
#define FL_STABLE_H

#include <stdbool.h>
#include <stdint.h>

#include "ast.h"
#include "value.h"

typedef struct StableCache StableCache;

/* A new, empty cache (aborts only when out of memory). */
StableCache *stable_new(void);
/* Free [sc] and its values (NULL is a no-op). */
void stable_free(StableCache *sc);
/* Forget every value and stable key (a new program was loaded). */
void stable_clear(StableCache *sc);

/* True when key ([id], [index]) is stable. */
bool stable_is_stable(const StableCache *sc, uint32_t id, uint32_t index);
/* The cached value of key ([id], [index]) (borrowed; NULL when none). */
const Vec *stable_value(const StableCache *sc, uint32_t id, uint32_t index);
/* The number of stable keys and the i-th of them. */
uint32_t stable_count(const StableCache *sc);
void stable_key(const StableCache *sc, uint32_t i, uint32_t *id, uint32_t *index);

/* The evaluator's check of binding [index] of the AST_LET [let] (a `let
 * stable` with an id) whose value is [value], for a program that asserts
 * the keys in [asserted]/[nasserted] (pairs id, index).
 *   test (key not asserted): the key becomes stable when [value] equals the
 *        cached value, else [value] is cached;
 *   assert: when [value] differs from the cached value the key stops being
 *        stable and the function returns false: the frame must be run again
 *        with the program as first simplified.
 * Once false has been returned, further checks are ignored until
 * stable_frame_done(). */
bool stable_check(StableCache *sc, const AstNode *let, uint32_t index, const Vec *value,
                  const uint32_t *asserted, uint32_t nasserted);
/* End of a frame: true when some key became stable during it (the program
 * should be simplified again); resets the per-frame flags. */
bool stable_frame_done(StableCache *sc);

#endif
