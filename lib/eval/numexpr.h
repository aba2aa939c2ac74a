/* numexpr.h: compiled numeric expressions, the evaluator's fast route for
 * arithmetic on single numbers.
 *
 * After a program's names are resolved (program.c), the compiler
 * (evalcode_compile_tree, numexpr_compile) finds every maximal subtree
 * that is arithmetic on one-number operands: literal numbers, names, + - * / // % **, unary - + not, the comparisons
 * other than `in`, calls of the one-argument element-wise builtins
 * (sin, cos, sqrt, ...; bi_kernel in builtins.h), `hypot` of one
 * argument, `map` and `clamp` of three, `noise` of a seed of numbers and
 * one to four coordinates (one point), and `v[x]` of a one-number index
 * where v is a constant stream or numeric vector, a name (whose vector,
 * at run time, must be one of those), or a uniform, normal or beta stream
 * made from a key of up to 8 numbers (`beta(:x;i)[t]`). Such a subtree, or an
 * `a;b;...` sequence of them and of constant numeric vectors (`h;1;0`, whose
 * numbers are the sequence's in order, as composition copies them), is compiled into a flat array of small
 * instructions with the constants inline, hung on the subtree's root node
 * (AstNode.fast = 1, AstNode.aux = the NumExpr).
 *
 * numexpr_run() runs one on doubles, with no allocation and no recursion.
 * It gives up (returns false) the moment a name holds anything but a
 * one-element numeric vector (an indexed name: a stream or a numeric
 * vector), or a comparison meets a NaN (where the
 * generic evaluator's identity shortcut could matter); the caller then
 * evaluates the same subtree with the generic tree walk, which is the
 * reference. Nothing in a compiled subtree has side effects (no errors,
 * no user calls, no state; noise's table of permutations is a cache),
 * so giving up half-way and starting again changes nothing. Every operation is the one the generic route performs
 * on one-element vectors (value.c's arithmetic, vec_cmp, vec_truthy, the
 * builtin's own element function), so the results are bit-identical.
 *
 * Globals.routes.no_fast (fl_debug_options.no_fast; read by program.c when a
 * program is loaded) turns compilation off: every subtree then takes the generic
 * route, for comparing the two (tests/cli/fast_route.sh).
 */
#ifndef FL_NUMEXPR_H
#define FL_NUMEXPR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ast.h"
#include "context.h"

typedef struct NumExpr NumExpr;

/* True when [n] is the literal number 2: the exponent of the x**2 forms
 * (§4.17) that eval.c's tree walk, the compiled regions and numexpr all
 * recognise alike. */
static inline bool ast_literal_two(const AstNode *n)
{
    return n->kind == AST_LITERAL && vec_is_scalar(n->value) && vec_scalar(n->value) == 2.0;
}

/* True when the index [b] of an `a[b]` is a literal range: its numbers
 * convert to indexes in 64 bits (§5.8), as eval.c's tree walk, the
 * compiled regions' C_INDEX and numexpr's indexing all decide alike. */
static inline bool ast_index_is_range(const AstNode *b)
{
    return b->kind == AST_LITERAL && b->op == 1;
}

/* builtins.h's pair of element kernels (bi_kernel_pair) */
typedef void (*BiKernelPair)(double x, double *ya, double *yb);

/* Compile the resolved subtree [n] in place (see above) when it qualifies
 * as a whole; true when it did. Nodes that already carry resolver data
 * (aux) are left alone; a subtree too deep for the instruction stack stays
 * generic. evalcode_compile_tree (evalcode.h) calls it for every maximal
 * subtree. */
bool numexpr_compile(AstNode *n);

/* The compiled expression of [n] (n->fast must be set). */
static inline const NumExpr *numexpr_of(const AstNode *n) { return (const NumExpr *)n->aux; }

/* The first member of every NumExpr (numexpr.c has the instructions that
 * follow), here so that the getters below are inline. */
typedef struct NumExprHead {
    uint32_t nins;      /* instructions (the last is NX_END) */
    uint32_t nout;      /* numbers produced */
    uint32_t depth;     /* generic eval_node nesting of the subtree */
    uint32_t lead;      /* 1 + the frame slot the first instruction reads
                           (NX_LOCAL), or 0 (numexpr_lead_slot); and
                           NUMEXPR_SMALL (numexpr_small) */
} NumExprHead;

/* Bytes of the head (padded) and of each instruction (numexpr.c checks). */
#define NUMEXPR_HEAD_SIZE 16
#define NUMEXPR_INS_SIZE 16

/* The size in bytes of [x] (a multiple of 8); a byte copy of it (8-byte
 * aligned) is a NumExpr too (evalcode.h copies them into its blocks). */
static inline size_t numexpr_size(const NumExpr *x)
{
    return NUMEXPR_HEAD_SIZE + (size_t)((const NumExprHead *)(const void *)x)->nins * NUMEXPR_INS_SIZE;
}

/* How many numbers [x] produces (1, or the length of a compiled sequence). */
static inline uint32_t numexpr_outputs(const NumExpr *x)
{
    return ((const NumExprHead *)(const void *)x)->nout;
}

/* How deep the generic evaluator would nest (eval_node levels) to evaluate
 * [x]'s subtree: the caller checks its depth limit with it first, so a
 * stack overflow happens exactly where the generic route would have it. */
static inline uint32_t numexpr_depth(const NumExpr *x)
{
    return ((const NumExprHead *)(const void *)x)->depth;
}

/* NumExprHead.lead's flag of a small expression (numexpr_small). */
#define NUMEXPR_SMALL 0x80000000u

/* The frame slot [x]'s first instruction reads, or -1 when it reads none
 * first. numexpr_run gives up at once when that slot holds anything but
 * one number: a caller with a vector there may go to numexpr_run_vec
 * without trying (the same result, without numexpr_run's entry and exit). */
static inline int32_t numexpr_lead_slot(const NumExpr *x)
{
    return (int32_t)(((const NumExprHead *)(const void *)x)->lead & ~NUMEXPR_SMALL) - 1;
}

/* True when [x] is one operation on one or two constants or names: `i+1`,
 * `d < D`, `-x`, `a*b` (+ - * / and the comparisons; with a constant
 * operand, + - * /; negation, squaring), which numexpr_run_small runs. */
static inline bool numexpr_small(const NumExpr *x)
{
    return ((const NumExprHead *)(const void *)x)->lead & NUMEXPR_SMALL;
}

/* numexpr_run of a small [x] (numexpr_small) without its machine: the
 * same number (.ok true), or .ok false where numexpr_run gives up (a name
 * not one number, a comparison meeting a NaN). Returned by value (in
 * registers): a caller on every level of the evaluator's recursion keeps
 * no address-taken local for it. The caller checks the depth limit
 * first. */
typedef struct NxSmall {
    double v;
    bool ok;
} NxSmall;
NxSmall numexpr_run_small(const NumExpr *x, const Eval *ev);

/* True when [x] is a sequence of constants and names alone (a state key
 * such as `:dot;i`): numexpr_run_leaves can run it. */
bool numexpr_leaves(const NumExpr *x);

/* numexpr_run of such an [x] (numexpr_leaves), without its machine: each
 * constant's number, and each name's, which must be one number; their
 * count, or 0 (nothing reported) when a name holds anything else, where
 * numexpr_run would give up. The caller checks the depth limit first. */
uint32_t numexpr_run_leaves(const NumExpr *x, const Eval *ev, double *out);

/* Most engine names a memoizable expression may read. */
#define NUMEXPR_MEMO_KEYS 4

/* True when [x] reads no frame slot and between 1 and NUMEXPR_MEMO_KEYS
 * engine names: its result is a function of those names' numbers alone
 * (every instruction is pure), so it may be kept and reused while they
 * stay the same (evalcode.h C_MEMO). */
bool numexpr_memoizable(const NumExpr *x);

/* The distinct frame slots [x] reads, in order of first use, written to
 * [slots]; returns how many, or UINT32_MAX when there are more than
 * [max]. */
uint32_t numexpr_local_reads(const NumExpr *x, int32_t *slots, uint32_t max);

/* For a memoizable [x]: the indices of the engine names it reads, in
 * instruction order, written to [idx]; returns how many. */
int numexpr_globals(const NumExpr *x, int32_t *idx);

/* Run [x] in [ev]'s current frame, writing numexpr_outputs(x) numbers to
 * [out]. Returns false (with [out] undefined) when an operand is not a
 * single number or a comparison meets a NaN: evaluate the subtree
 * generically instead. */
static inline bool numexpr_run(const NumExpr *x, Eval *ev, double *out);

/* numexpr_run's machine, which numexpr_run_regs runs too: names from
 * [ev], registers from [regs] (NULL for a NumExpr with names). */
bool numexpr_exec(const NumExpr *x, Eval *ev, const double *regs, double *out);

static inline bool numexpr_run(const NumExpr *x, Eval *ev, double *out)
{
    return numexpr_exec(x, ev, NULL, out);
}

/* Most numbers numexpr_run_vec's vectors hold. */
#define NUMEXPR_VEC_MAX 16

/* The vector form of a one-output [x] (numexpr_outputs(x) == 1) for where
 * numexpr_run gave up because names hold numeric vectors: runs the same
 * instructions on vectors of 1 to NUMEXPR_VEC_MAX numbers, element by
 * element as value.c's arithmetic, element-wise builtins and negation do
 * (a one-number operand repeated), writing the result's numbers to [out]
 * and their count to *[nout]. It gives up (false) where the generic
 * route's rules for vectors are not per element or its fused forms
 * (a + b*c, F1) could repeat operands differently: two vectors of
 * different lengths (both longer than one), a comparison, `not` or an
 * index of a vector, a comparison meeting a NaN, a name holding anything
 * but 1 to NUMEXPR_VEC_MAX numbers. The numbers are then those of the
 * generic route, bit for bit. */
bool numexpr_run_vec(const NumExpr *x, Eval *ev, double *out, uint32_t *nout);

/* Registers (loop kernels, kernel.h): a copy of a compiled expression
 * whose names are read from an array of doubles instead of a frame.
 * [map](ctx, global, arg) gives the register of local slot [arg]
 * (global false) or of engine name [arg] (global true), or -1 when that
 * name cannot be a register. */
typedef int32_t (*NumExprRegMap)(void *ctx, bool global, int32_t arg);

/* A copy of [x] (free it with free()) with every name turned into a
 * register read through [map]; NULL when [map] gives -1 for a name. */
NumExpr *numexpr_to_regs(const NumExpr *x, NumExprRegMap map, void *ctx);

/* Renumber the registers of a numexpr_to_regs() copy [x] in place: each
 * read of register r becomes one of map(ctx, r). */
void numexpr_renumber_regs(NumExpr *x, int32_t (*map)(void *ctx, int32_t reg), void *ctx);

/* Run a numexpr_to_regs() copy [x] on registers [regs], writing its
 * numexpr_outputs(x) numbers to [out]; false when a comparison meets a NaN
 * (evaluate the expression's subtree generically instead). Reads nothing
 * but [x] and [regs]: any thread may run it. */
bool numexpr_run_regs(const NumExpr *x, const double *regs, double *out);

/* Most lanes numexpr_run_lanes runs at once. */
#define NUMEXPR_LANES 16

/* Run a numexpr_to_regs() copy [x] for [lanes] (at most NUMEXPR_LANES)
 * register files at once: lane l's registers are regs[l * stride ...];
 * [x]'s outputs go to each lane's registers from the one that
 * numexpr_set_out() recorded in [x]. fail[l] is set for a lane whose
 * comparison met a NaN (its outputs are then undefined); the others are
 * left alone. Every lane's numbers are those numexpr_run_regs gives, one
 * instruction at a time for all the lanes instead of one lane at a time.
 * Reads nothing but [x] and [regs]: any thread may run it. */
void numexpr_run_lanes(const NumExpr *x, double *regs, size_t stride, uint32_t lanes, uint8_t *fail);

/* Record in the register copy [x] the register its outputs go to
 * (numexpr_run_lanes). */
void numexpr_set_out(NumExpr *x, uint32_t out);

/* The distinct registers a numexpr_to_regs() copy [x] reads, in order of
 * first use, written to [regs]; returns how many, or UINT32_MAX when there
 * are more than [max]. */
uint32_t numexpr_reg_reads(const NumExpr *x, int32_t *regs, uint32_t max);

/* A rough cost of running [x]: one per instruction, 16 per call of an
 * element function or power (for sizing batches of work). */
uint32_t numexpr_cost(const NumExpr *x);

/* A call of a one-argument element function on a register alone (sin(p)
 * where p is a register), in a numexpr_to_regs() copy. */
typedef struct NumExprCall {
    int32_t reg;
    double (*fn)(double);
} NumExprCall;

/* The calls of element functions on a register alone in the register copy
 * [x], in instruction order, written to out[0 .. max); returns how many
 * there are (more than [max] when some were left out). */
uint32_t numexpr_reg_calls(const NumExpr *x, NumExprCall *out, uint32_t max);

/* In the register copy [x], read register [reg] instead of each call [c]
 * (the number [c] gives, computed once elsewhere: the same bits, as an
 * element function is a function of its argument alone). Returns how many
 * calls were replaced. */
uint32_t numexpr_share_call(NumExpr *x, NumExprCall c, int32_t reg);

/* A new register expression (free it with free()) that computes [c]'s one
 * number. */
NumExpr *numexpr_new_call(NumExprCall c);

/* A new register expression (free it with free()) that computes the two
 * numbers of [fn2] (bi_kernel_pair) of register [reg], in that order. */
NumExpr *numexpr_new_call2(int32_t reg, BiKernelPair fn2);

#endif
