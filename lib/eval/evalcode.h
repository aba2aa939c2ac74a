/* evalcode.h: the compact, pre-resolved form of the program's hot structure
 * built once after name resolution and run by eval.c.
 *
 * A tree walk over AstNodes (120 bytes each, allocated one by one) touches
 * scattered memory: on a simplified program of 10,000 unrolled loop bodies
 * that is tens of MB per frame, and the frame time goes to cache misses,
 * not arithmetic. evalcode_compile_tree() therefore copies every maximal
 * region of the kinds that dominate such programs - sequences, plain
 * `let`s, attribute settings, `<<` appends, positional calls of builtins,
 * state lookups, indexing, `if`/`else` and the operators on vectors -
 * into one contiguous block of small records laid out in evaluation order,
 * with compiled numeric subtrees (numexpr.h) copied inline and names turned
 * into slot reads. The region's root AstNode gets n->fast = 2 and
 * n->aux = the block (a CBlock; record 0 is the root).
 *
 * Anything else inside a region is a C_AST record pointing back at its
 * AstNode, which the generic evaluator runs (and whose own subtrees may be
 * compiled regions again). The records mirror eval.c's functions for those
 * kinds step for step - the same evaluation order, the same depth
 * accounting (§4.16 stack overflow), the same helpers - so results,
 * messages and errors are identical; Globals.routes.no_fast turns compilation off
 * (numexpr.h) for comparing the two routes.
 */
#ifndef FL_EVALCODE_H
#define FL_EVALCODE_H

#include <stdint.h>

#include "ast.h"
#include "kernel.h"
#include "numexpr.h"

enum {
    C_AST,      /* p.node: evaluate the AstNode generically */
    C_LIT,      /* p.lit: a constant (borrowed from the AST; may be NULL) */
    C_LOCAL,    /* n: frame slot */
    C_GLOBAL,   /* n: global index */
    C_NUM,      /* p.node: fallback; followed by a NumExpr (numexpr.h) */
    C_SEQ,      /* n kids: uint32 offsets follow (§4.3) */
    C_LET,      /* n bindings: CLetTail follows (§4.4) */
    C_ATTRS,    /* n bindings: CAttrsTail follows (§4.10); pad 1: on a
                   literal of one node, names pairwise different and none
                   of them the node's own (each added without a search) */
    C_CALLBI,   /* p.bi, n positional args: uint32 offsets follow (§4.8);
                   pad 1: one argument, to a builtin with a numeric route
                   (builtins.h bi_call_nums); pad 2: several arguments, to
                   a builtin with a numeric route for them all
                   (bi_call_nums_args: map, clamp, noise) */
    C_APPEND,   /* uint32 offsets of parent and children follow (§4.10) */
    C_MEMO,     /* a C_NUM reading engine names and constants only
                   (numexpr_memoizable): n is its memo cell, shared by every
                   record of the block with the same instructions; the
                   result is kept there and handed out again while those
                   names hold the same numbers, bit for bit (not when it is
                   NaN, where the identity of vectors matters, §3.6). The
                   NumExpr is kept once per cell, after the code (CMemo.expr),
                   not in each record: a CMemoHint follows the header, and
                   aux is the NumExpr's depth (numexpr_depth) */
    C_NEWNODE,  /* C_ATTRS on a literal bare node (no tags, attributes or
                   children; p.kind is its kind, borrowed from the AST): a
                   new node of that kind with the attributes set, the
                   literal left untouched */
    C_KNUM,     /* a C_NUM of a loop body whose loop kernel computes it
                   (kernel.h): n is the register of its first output;
                   while that kernel runs (Eval.kbase is this block's code)
                   and holds the number, the record returns it, else it
                   runs as C_NUM */
    C_KCALL,    /* a C_CALLBI of one argument, a C_KNUM, whose loop kernel
                   computes it through the builtin's numeric kernel
                   (builtins.h BiVecKernel): n is the register of its first
                   output, aux how many, pad the argument's numexpr_depth;
                   one uint32 offset (the argument) follows, as for
                   C_CALLBI, which it runs as when the kernel does not hold
                   its numbers */
    C_KLET,     /* a C_LET of a loop body some of whose bindings only the
                   kernel's records read (kernel.h): CLetTail.pad has a bit
                   for each such binding (the first 32); while the kernel
                   runs a clean iteration (Eval.kclean) and the depth is at
                   most MAX_EVAL_DEPTH - aux, those bindings are not made
                   (their records take the kernel's numbers and read no
                   slot); otherwise it runs as C_LET */
    C_KNODE,    /* a C_NEWNODE of a loop body whose attributes are all
                   C_KNUM, C_KCALL or C_MEMO records (kernel.h): while the
                   kernel runs a clean iteration and the depth is at most
                   MAX_EVAL_DEPTH - aux, the node is built from the
                   kernel's numbers directly; otherwise it runs as
                   C_NEWNODE */
    C_LOOKUP,   /* p.node: `$key` (§3.17), the key's record at the uint32
                   offset that follows: a C_NUM key is run into numbers and
                   looked up as they are (state_get_nums), without making
                   the key vector; a C_LIT key is looked up through its
                   lookup cell, a StateCached at byte offset n from the
                   block's memo cells (CBlock.memos; CLOOK_NONE: none), so
                   that frame after frame it is found where it was
                   (state_get_cached) */
    C_INDEX,    /* p.node: `a[b]` (§5.8), pad: the index is a literal
                   range (64-bit index conversion); uint32 offsets of a and
                   b follow: a C_NUM index is run into numbers and used as
                   they are (vec_index_nums); when a is a random stream
                   (uniform, normal, beta) of a C_NUM key, its seed is
                   hashed from the key's numbers and no key or stream
                   vector is made (evalrun.c run_stream_index) */
    C_IF,       /* `if`/`elif`/`else` (§4.7): n conditions; 2n + 1 uint32
                   offsets follow, each condition's then its value's, and
                   the `else` value's (CREC_NONE: none); a C_NUM condition
                   is run into numbers, without making its vector */
    C_BINOP,    /* a OP b (§3.5) that numexpr does not take (vectors), in
                   eval_binop's forms (§4.17): pad BINOP_PLAIN, n the
                   ArithOp, offsets of a and b; BINOP_SQUARE (x**2), the
                   offset of x; BINOP_ADD_MUL (a + b*c), of a, b and c;
                   BINOP_ADD_SQUARE (a + b**2), of a and b */
};

enum { BINOP_PLAIN, BINOP_SQUARE, BINOP_ADD_MUL, BINOP_ADD_SQUARE };

/* An offset that names no record (C_IF without `else`). */
#define CREC_NONE UINT32_MAX
/* A C_LOOKUP record without a lookup cell. */
#define CLOOK_NONE UINT32_MAX

struct Builtin;

/* Every record starts with this header; offsets are bytes from the start
 * of the block. Records are 8-byte aligned. */
typedef struct CRec {
    uint8_t op;         /* C_* */
    uint8_t pad;
    uint16_t aux;       /* C_MEMO: numexpr_depth of its NumExpr */
    uint32_t n;         /* per op */
    union {
        const AstNode *node;
        Vec *lit;
        Str *kind;
        const struct Builtin *bi;
    } p;
} CRec;

typedef struct CBind {
    int32_t slot;       /* C_LET: slot bound */
    uint32_t off;       /* value record */
} CBind;

typedef struct CLetTail {
    uint32_t body;      /* body record */
    uint32_t pad;
    CBind binds[];      /* n of them, in order */
} CLetTail;

typedef struct CAttr {
    Str *name;          /* attribute name (borrowed from the AST) */
    uint32_t off;       /* value record */
    uint32_t pad;
} CAttr;

typedef struct CAttrsTail {
    uint32_t node;      /* node expression record */
    uint32_t pad;
    CAttr attrs[];      /* n of them, in order */
} CAttrsTail;

/* A memo cell of C_MEMO records: 64 bytes, what a hit reads first (the
 * cells are allocated on 64-byte boundaries, so a cell is one cache
 * line). */
typedef struct CMemo {
    Vec *value;                          /* last result (one reference), or NULL */
    uint64_t keys[NUMEXPR_MEMO_KEYS];    /* its names' numbers' bits when [value] was made */
    int32_t nkeys;                       /* engine names read */
    int32_t names[NUMEXPR_MEMO_KEYS];    /* their indices (Globals) */
    uint32_t expr;                       /* offset of the NumExpr in the block's code */
} CMemo;
_Static_assert(sizeof(CMemo) == 64, "a memo cell is one cache line");

/* After the header of a C_MEMO record: which cells the C_MEMO records
 * MEMO_AHEAD and 2*MEMO_AHEAD places further in the block's code use
 * (CMEMO_NONE: none). A region has no branches, so its records run in code
 * order: running this record, the runner asks for the farther cell and for
 * the value kept in the nearer one (asked for MEMO_AHEAD records ago), so
 * that neither is a cache miss by the time it is used. Only a hint: a
 * wrong or stale one costs a wasted fetch, nothing else. */
typedef struct CMemoHint {
    uint32_t cell_far;      /* cell of the record 2*MEMO_AHEAD places on */
    uint32_t cell_near;     /* cell of the record MEMO_AHEAD places on */
} CMemoHint;

#define MEMO_AHEAD 8
#define CMEMO_NONE UINT32_MAX

/* A compiled region: AstNode.aux of its root (n->fast == 2). */
typedef struct CBlock {
    CMemo *memos;       /* memo cells, then nlooks lookup cells (StateCached,
                           C_LOOKUP) in the same allocation (NULL: none) */
    uint32_t nmemos;
    uint32_t nlooks;
    uint32_t len;       /* bytes of code */
    _Alignas(16) unsigned char code[];   /* records; the root is at offset 0 */
} CBlock;

/* Compile the regions and the numeric subtrees (numexpr.h) of the
 * resolved tree [top] in place (see above), and the loops' kernels as
 * [ko] says (kernel.h). Never fails. */
void evalcode_compile_tree(AstNode *top, const KernelOptions *ko);

/* How many operand offsets follow C_BINOP record [r]. */
static inline uint32_t binop_operands(const CRec *r)
{
    return r->pad == BINOP_SQUARE ? 1 : r->pad == BINOP_ADD_MUL ? 3 : 2;
}

/* The record at byte offset [off] of block [base]. */
static inline const CRec *crec(const unsigned char *base, uint32_t off)
{
    return (const CRec *)(const void *)(base + off);
}

#endif
