/* counter.h: the `!counter` renderer node (COUNTERS.md).
 *
 * A top-level `!counter state=KEY rate=R ...` node keeps a value in the state
 * dictionary under KEY that changes at R per unit of time; the time of its
 * last update is kept under KEY;:time. The runtime calls counter_update()
 * for each top-level !counter node after the frame's evaluation.
 */
#ifndef FL_COUNTER_H
#define FL_COUNTER_H

#include "node.h"
#include "state.h"

/* Update the counter of [node] (a !counter node, borrowed) in [state] for a
 * frame whose `time` is [frame_time] seconds.
 *   attributes: state (key, non-empty), time, rate, initial, reset, minimum
 *               (or min), maximum (or max): numeric vectors of any length,
 *               a missing or non-numeric one taking its default
 *   algorithm:  COUNTERS.md "Update, once per frame" (each vector operation
 *               rounded in turn, no fused multiply-add)
 *   errors:     a node without a non-empty `state` is ignored; never fails. */
void counter_update(const Node *node, StateDict *state, double frame_time);

#endif
