/* numexpr.c: compiling numeric subtrees to flat instruction arrays and
 * running them on doubles (numexpr.h).
 *
 * The instructions form a stack machine: operands are pushed, operators
 * pop theirs and push the result. A compiled sequence `a;b;c` leaves its
 * outputs on the stack in order. The stack depth is known at compile time
 * and bounded by NX_STACK.
 */
#include "numexpr.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "mem.h"
#include "program.h"

/* Deepest operand stack a compiled expression may need. */
#define NX_STACK 32
/* Most numbers of an NX_STREAM key. */
#define NX_STREAM_KEYS 8
/* Most numbers a compiled sequence may produce. */
#define NX_MAX_OUT 16

enum {
    NX_CONST, NX_LOCAL, NX_GLOBAL,
    NX_ADD, NX_SUB, NX_MUL, NX_DIV, NX_FLOORDIV, NX_MOD, NX_POW, NX_SQUARE,
    NX_NEG, NX_NOT, NX_CMP, NX_CALL1,
    /* an arithmetic operator whose right operand is the constant k */
    NX_ADDK, NX_SUBK, NX_MULK, NX_DIVK,
    NX_REG,     /* a register of numexpr_run_regs (numexpr_to_regs copies) */
    NX_CALL2,   /* two element functions of the top: fn2(t, &a, &b) pushes
                 * a and leaves b on top (numexpr_new_call2 only) */
    /* `v[x]` of a one-number index x, the top (vec_index_num1; sub: the
     * index is a literal range, 64-bit conversion): v is the constant
     * stream or numeric vector lit (NX_INDEX), or the vector a name
     * holds (NX_INDEXL: slot arg; NX_INDEXG: global arg), which must be a
     * stream or a numeric vector, else the run gives up */
    NX_INDEX, NX_INDEXL, NX_INDEXG,
    /* hypot(t) of the top's numbers (bi_hypot_nums): sqrt(t*t) of one
     * number, the vector form's sum of squares of several */
    NX_HYPOT,
    /* `kind(k_1;...;k_m)[x]`: the number of random stream [sub]
     * (StreamKind) seeded by the m = arg numbers below the top (vec_hash's
     * seed of them, floored, as the builtin makes its stream) at the
     * top's index x (stream_value_at) */
    NX_STREAM,
    /* map(x, y, z) and clamp(x, y, z) of the three numbers on top (z the
     * top): bi_map_num, bi_clamp_num */
    NX_MAP, NX_CLAMP,
    /* noise(seed, x_1, ..., x_k) of the seed's m = arg numbers and the
     * k = sub coordinates above them, the last on top (bi_noise_nums:
     * one point); not in a kernel's registers (its table of
     * permutations is the runtime's) */
    NX_NOISE,
    NX_END,     /* the last instruction */
};

/* NxIns.sub of an expression's first instruction: see there. */
#define NX_DIST 1

typedef struct NxIns {
    uint8_t op;         /* NX_* */
    uint8_t sub;        /* NX_CMP: CmpOp; the first instruction's NX_DIST:
                           the expression is `hypot(a-b)` of two frame
                           slots (numexpr_run_vec's direct form) */
    int32_t arg;        /* NX_LOCAL: slot; NX_GLOBAL: index; NX_REG: register */
    union {
        double k;                  /* NX_CONST */
        double (*fn)(double);      /* NX_CALL1 */
        BiKernelPair fn2;          /* NX_CALL2 */
        const Vec *lit;            /* NX_INDEX (borrowed from the AST) */
        const struct Builtin *bi;  /* NX_NOISE */
    };
} NxIns;

/* The head first (numexpr.h reads it through a pointer to the struct,
 * which points to its first member). */
struct NumExpr {
    NumExprHead h;
    NxIns ins[];
};

_Static_assert(sizeof(NxIns) == NUMEXPR_INS_SIZE && offsetof(NumExpr, ins) == NUMEXPR_HEAD_SIZE &&
                   sizeof(NumExpr) == NUMEXPR_HEAD_SIZE,
               "numexpr.h's numexpr_size");

/* ====================================================================
 * Compiling
 * ==================================================================== */

static bool small_form(const NumExpr *x);
static double compare(uint8_t op, double x, double y);

typedef struct Nx {
    NxIns *ins;
    uint32_t n, cap;
    uint32_t sp, max_sp;   /* stack depth now and at most */
    bool fail;
} Nx;

static void emit(Nx *c, NxIns i, int push)
{
    if (c->n == c->cap) {
        c->cap = c->cap ? c->cap * 2 : 16;
        c->ins = mem_realloc_array(c->ins, c->cap, sizeof *c->ins);
    }
    /* field by field into zeroed memory: no stray padding bytes, so that
     * equal instructions are equal bytes (evalcode.c compares them) */
    NxIns *d = &c->ins[c->n++];
    memset(d, 0, sizeof *d);
    d->op = i.op;
    d->sub = i.sub;
    d->arg = i.arg;
    memcpy(&d->k, &i.k, sizeof d->k);
    c->sp = (uint32_t)((int)c->sp + push);
    if (c->sp > c->max_sp) c->max_sp = c->sp;
    if (c->max_sp > NX_STACK) c->fail = true;
}

/* The builtin a callee name resolves to at load time, or NULL. */
static const Builtin *const_builtin(const AstNode *fn)
{
    /* a builtin name, or (after the simplifier) a literal function */
    if (fn->kind != AST_LITERAL && (fn->kind != AST_NAME || fn->scope != SCOPE_CONST)) return NULL;
    const Vec *v = fn->value;
    if (!vec_is_obj(v) || v->len != 1 || vec_celems(v)[0].kind != EL_FUNC) return NULL;
    return vec_celems(v)[0].func->bi;
}

/* True when [n] is a constant (a literal or a constant name) that
 * NX_INDEX can index: a stream or a numeric vector of one number or more. */
static bool indexable_const(const AstNode *n)
{
    if (n->kind != AST_LITERAL && (n->kind != AST_NAME || n->scope != SCOPE_CONST)) return false;
    return vec_is_stream(n->value) || (n->value && n->value->kind == VEC_NUM && n->value->len > 0);
}

static bool scalar_ok(const AstNode *n, int budget);
static uint32_t const_numbers(const AstNode *n);

/* The StreamKind of [call] when it is a call of uniform, normal or beta
 * (a builtin known at load time) with one positional argument and no
 * other, else -1. */
static int stream_call_kind(const AstNode *call)
{
    if (call->kind != AST_CALL || call->op != 0 || call->count != 1 || call->nkids != 1) return -1;
    const Builtin *bi = const_builtin(call->a);
    return bi ? bi_stream_kind(bi) : -1;
}

/* How many numbers the key [k] of a stream call is when the machine can
 * compute them: a one-number expression, or a sequence of such and of
 * constant numeric vectors (`:x;i`), 1 to NX_STREAM_KEYS numbers in all;
 * else 0. */
static uint32_t stream_key_numbers(const AstNode *k, int budget)
{
    if (scalar_ok(k, budget)) return 1;
    if (k->kind != AST_SEQUENCE || k->nkids < 2) return 0;
    uint32_t m = 0;
    for (uint32_t i = 0; i < k->nkids; i++) {
        const uint32_t c = const_numbers(k->kids[i]);
        if (c) m += c;
        else if (scalar_ok(k->kids[i], budget - 1)) m++;
        else return 0;
        if (m > NX_STREAM_KEYS) return 0;
    }
    return m;
}

/* True when [n] is a one-number expression the machine can run. */
static bool scalar_ok(const AstNode *n, int budget)
{
    if (!n || budget <= 0) return false;
    switch ((AstKind)n->kind) {
    case AST_LITERAL:
        return vec_is_scalar(n->value);
    case AST_NAME:
        return n->scope == SCOPE_LOCAL || n->scope == SCOPE_GLOBAL ||
               (n->scope == SCOPE_CONST && vec_is_scalar(n->value));
    case AST_BINOP:
        if (n->op > OP_POW) return false;
        return scalar_ok(n->a, budget - 1) && scalar_ok(n->b, budget - 1);
    case AST_COMPARE:
        if (n->op == CMP_IN) return false;
        return scalar_ok(n->a, budget - 1) && scalar_ok(n->b, budget - 1);
    case AST_NEG: case AST_POS: case AST_NOT:
        return scalar_ok(n->a, budget - 1);
    case AST_CALL: {
        /* a builtin known at load time, positional arguments only */
        const Builtin *bi = const_builtin(n->a);
        if (!bi || n->op != 0 || n->count != n->nkids) return false;
        if (bi_noise_route(bi, n->count)) {
            /* noise: a seed of numbers (as a stream's key), then the
             * coordinates, one number each */
            if (!stream_key_numbers(n->kids[0], budget - 1)) return false;
            for (uint32_t j = 1; j < n->count; j++)
                if (!scalar_ok(n->kids[j], budget - 1)) return false;
            return true;
        }
        if (n->count == 3 && bi_map_or_clamp(bi))
            return scalar_ok(n->kids[0], budget - 1) && scalar_ok(n->kids[1], budget - 1) &&
                   scalar_ok(n->kids[2], budget - 1);
        return n->count == 1 && (bi_kernel(bi) || bi_is_hypot(bi)) && scalar_ok(n->kids[0], budget - 1);
    }
    case AST_SEQUENCE:
        return n->nkids == 1 && scalar_ok(n->kids[0], budget - 1);
    case AST_INDEX:
        /* one number of a constant or a name's vector (a range index,
         * which is a literal of several numbers, is not one number), or
         * of a stream made from numbers (`beta(:x;i)[t]`) */
        return (indexable_const(n->a) ||
                (n->a->kind == AST_NAME && (n->a->scope == SCOPE_LOCAL || n->a->scope == SCOPE_GLOBAL)) ||
                (stream_call_kind(n->a) >= 0 && stream_key_numbers(n->a->kids[0], budget - 2))) &&
               scalar_ok(n->b, budget - 1);
    default:
        return false;
    }
}

/* True when [n] is a constant number (a literal or a constant name);
 * sets *[k]. */
static bool const_value(const AstNode *n, double *k)
{
    if ((n->kind == AST_LITERAL || (n->kind == AST_NAME && n->scope == SCOPE_CONST)) &&
        vec_is_scalar(n->value)) {
        *k = vec_scalar(n->value);
        return true;
    }
    return false;
}

static uint32_t emit_scalar(Nx *c, const AstNode *n);

/* Emit the numbers of the key [k] of a stream or the seed of noise
 * (stream_key_numbers), in order, their count in *[m]; returns the
 * generic evaluator's nesting for [k]. */
static uint32_t emit_key(Nx *c, const AstNode *k, uint32_t *m)
{
    uint32_t d = 0, e;
    *m = 0;
    if (k->kind != AST_SEQUENCE || k->nkids < 2) {
        *m = 1;
        return emit_scalar(c, k);
    }
    for (uint32_t j = 0; j < k->nkids; j++) {
        const AstNode *kj = k->kids[j];
        if (const_numbers(kj)) {
            for (uint32_t q = 0; q < kj->value->len; q++)
                emit(c, (NxIns){.op = NX_CONST, .k = vec_cnums(kj->value)[q]}, 1);
            *m += kj->value->len;
            continue;
        }
        e = emit_scalar(c, kj) + 1;
        if (e > d) d = e;
        ++*m;
    }
    return d;
}

/* Emit [n] (scalar_ok); returns the generic evaluator's nesting for it:
 * eval_node levels, literals and names taking none. */
static uint32_t emit_scalar(Nx *c, const AstNode *n)
{
    uint32_t d = 0, e;
    double k;
    switch ((AstKind)n->kind) {
    case AST_LITERAL:
        emit(c, (NxIns){.op = NX_CONST, .k = vec_scalar(n->value)}, 1);
        return 0;
    case AST_NAME:
        if (n->scope == SCOPE_LOCAL) emit(c, (NxIns){.op = NX_LOCAL, .arg = n->slot}, 1);
        else if (n->scope == SCOPE_GLOBAL) emit(c, (NxIns){.op = NX_GLOBAL, .arg = n->slot}, 1);
        else emit(c, (NxIns){.op = NX_CONST, .k = vec_scalar(n->value)}, 1);
        return 0;
    case AST_BINOP:
        if (n->op == OP_POW && ast_literal_two(n->b)) {
            /* F2 (§4.17): x**2 is x*x */
            d = emit_scalar(c, n->a);
            emit(c, (NxIns){.op = NX_SQUARE}, 0);
            return d + 1;
        }
        if (n->op <= OP_DIV && const_value(n->b, &k)) {
            /* x OP k: one instruction */
            d = emit_scalar(c, n->a);
            emit(c, (NxIns){.op = (uint8_t)(NX_ADDK + n->op), .k = k}, 0);
            return d + 1;
        }
        if ((n->op == OP_ADD || n->op == OP_MUL) && const_value(n->a, &k)) {
            /* k + x, k * x: IEEE addition and multiplication commute
             * exactly (a NaN operand gives that NaN either way) */
            d = emit_scalar(c, n->b);
            emit(c, (NxIns){.op = (uint8_t)(NX_ADDK + n->op), .k = k}, 0);
            return d + 1;
        }
        d = emit_scalar(c, n->a);
        e = emit_scalar(c, n->b);
        /* the generic route fuses a + b*c and a + b**2 (F1, §4.17); on
         * single numbers that is a + (b*c), each operation rounded, as
         * here (its nesting is one level less than counted here, which
         * only makes the depth check below a little cautious) */
        static const uint8_t ops[] = {NX_ADD, NX_SUB, NX_MUL, NX_DIV, NX_FLOORDIV, NX_MOD, NX_POW};
        emit(c, (NxIns){.op = ops[n->op]}, -1);
        return (d > e ? d : e) + 1;
    case AST_COMPARE:
        d = emit_scalar(c, n->a);
        e = emit_scalar(c, n->b);
        emit(c, (NxIns){.op = NX_CMP, .sub = n->op}, -1);
        return (d > e ? d : e) + 1;
    case AST_NEG:
        d = emit_scalar(c, n->a);
        emit(c, (NxIns){.op = NX_NEG}, 0);
        return d + 1;
    case AST_POS:
        /* +x of a number is the number itself */
        return emit_scalar(c, n->a) + 1;
    case AST_NOT:
        d = emit_scalar(c, n->a);
        emit(c, (NxIns){.op = NX_NOT}, 0);
        return d + 1;
    case AST_CALL: {
        const Builtin *bi = const_builtin(n->a);
        if (bi_noise_route(bi, n->count)) {
            /* (scalar_ok: the seed's numbers, then the coordinates) */
            uint32_t m;
            d = emit_key(c, n->kids[0], &m) + 1;
            for (uint32_t j = 1; j < n->count; j++) {
                e = emit_scalar(c, n->kids[j]);
                if (e > d) d = e;
            }
            emit(c, (NxIns){.op = NX_NOISE, .sub = (uint8_t)(n->count - 1), .arg = (int32_t)m, .bi = bi},
                 -(int)(m + n->count - 2));
            return d + 1;
        }
        if (n->count == 3) {
            /* map or clamp (scalar_ok): the arguments in order */
            for (uint32_t j = 0; j < 3; j++) {
                e = emit_scalar(c, n->kids[j]);
                if (e > d) d = e;
            }
            emit(c, (NxIns){.op = bi_map_or_clamp(bi) == BI_MAP ? NX_MAP : NX_CLAMP}, -2);
            return d + 1;
        }
        d = emit_scalar(c, n->kids[0]);
        if (bi_is_hypot(bi)) emit(c, (NxIns){.op = NX_HYPOT}, 0);
        else emit(c, (NxIns){.op = NX_CALL1, .fn = bi_kernel(bi)}, 0);
        return d + 1;
    }
    case AST_SEQUENCE:
        return emit_scalar(c, n->kids[0]) + 1;
    case AST_INDEX: {
        const int kind = indexable_const(n->a) || n->a->kind == AST_NAME ? -1 : stream_call_kind(n->a);
        if (kind >= 0) {
            /* the stream's key, number by number, then the index (the
             * call and its argument first, as eval_node's AST_INDEX
             * evaluates them; the call's level and the key sequence's
             * counted) */
            uint32_t m;
            d = emit_key(c, n->a->kids[0], &m);
            e = emit_scalar(c, n->b);
            emit(c, (NxIns){.op = NX_STREAM, .sub = (uint8_t)kind, .arg = (int32_t)m}, -(int)m);
            d += 2;
            return (d > e ? d : e) + 1;
        }
        /* the source (a constant or a name: no evaluation of its own),
         * then the index, as eval_node's AST_INDEX */
        const uint8_t range = ast_index_is_range(n->b);
        d = emit_scalar(c, n->b);
        if (indexable_const(n->a))
            emit(c, (NxIns){.op = NX_INDEX, .sub = range, .lit = n->a->value}, 0);
        else
            emit(c, (NxIns){.op = n->a->scope == SCOPE_LOCAL ? NX_INDEXL : NX_INDEXG, .sub = range,
                            .arg = n->a->slot}, 0);
        return d + 1;
    }
    default:
        c->fail = true;
        return 0;
    }
}

/* How many numbers [n] is when it is a constant numeric vector of two
 * numbers or more (a literal or a constant name: `1;0` in `h;1;0`), else
 * 0. A compiled sequence takes its numbers as constants: composing a
 * sequence copies a numeric part's numbers in order, bit for bit (§4.3),
 * so the sequence's numbers are the same. */
static uint32_t const_numbers(const AstNode *n)
{
    if (n->kind != AST_LITERAL && (n->kind != AST_NAME || n->scope != SCOPE_CONST)) return 0;
    const Vec *v = n->value;
    return v && v->kind == VEC_NUM && v->len >= 2 && v->len <= NX_MAX_OUT ? v->len : 0;
}

/* Worth compiling: an operation (not a bare literal or name, which the
 * generic route already reads without a call). */
static bool is_operation(const AstNode *n)
{
    return n->kind != AST_LITERAL && n->kind != AST_NAME;
}

bool numexpr_compile(AstNode *n)
{
    if (n->aux || n->fast) return false;
    uint32_t nout = 0;
    if (n->kind == AST_SEQUENCE && n->nkids >= 2) {
        for (uint32_t i = 0; i < n->nkids; i++) {
            uint32_t k = const_numbers(n->kids[i]);
            if (k) nout += k;
            else if (scalar_ok(n->kids[i], NX_STACK)) nout++;
            else return false;
            if (nout > NX_MAX_OUT) return false;
        }
    } else {
        if (!is_operation(n) || !scalar_ok(n, NX_STACK)) return false;
        nout = 1;
    }
    Nx c = {0};
    uint32_t depth = 0;
    if (n->kind == AST_SEQUENCE && n->nkids >= 2) {
        for (uint32_t i = 0; i < n->nkids; i++) {
            const AstNode *k = n->kids[i];
            if (const_numbers(k)) {
                /* its numbers, as the composition copies them (a literal
                 * takes no eval_node level) */
                for (uint32_t j = 0; j < k->value->len; j++)
                    emit(&c, (NxIns){.op = NX_CONST, .k = vec_cnums(k->value)[j]}, 1);
                continue;
            }
            uint32_t d = emit_scalar(&c, k);
            if (d > depth) depth = d;
        }
        depth++;   /* the sequence itself */
    } else {
        depth = emit_scalar(&c, n);
    }
    emit(&c, (NxIns){.op = NX_END}, 0);
    if (c.fail || c.sp != nout) {
        free(c.ins);
        return false;
    }
    NumExpr *x = mem_calloc(1, sizeof *x + c.n * sizeof(NxIns));   /* padding zero too */
    x->h.nins = c.n;
    x->h.nout = nout;
    x->h.depth = depth;
    x->h.lead = c.ins[0].op == NX_LOCAL ? (uint32_t)c.ins[0].arg + 1 : 0;
    memcpy(x->ins, c.ins, c.n * sizeof(NxIns));
    if (small_form(x)) x->h.lead |= NUMEXPR_SMALL;
    if (c.n == 5 && c.ins[0].op == NX_LOCAL && c.ins[1].op == NX_LOCAL && c.ins[2].op == NX_SUB &&
        c.ins[3].op == NX_HYPOT)
        x->ins[0].sub = NX_DIST;
    free(c.ins);
    n->aux = x;
    n->aux_free = free;
    n->fast = 1;
    return true;
}


/* ====================================================================
 * Running
 * ==================================================================== */

static bool is_leaf(uint8_t op) { return op == NX_CONST || op == NX_LOCAL || op == NX_GLOBAL; }

/* numexpr_small's forms: [leaf, op k | neg | square, END] and
 * [leaf, leaf, + - * / cmp, END], one output */
static bool small_form(const NumExpr *x)
{
    const NxIns *i = x->ins;
    if (x->h.nout != 1) return false;
    if (x->h.nins == 3)
        return is_leaf(i[0].op) &&
               ((i[1].op >= NX_ADDK && i[1].op <= NX_DIVK) || i[1].op == NX_NEG || i[1].op == NX_SQUARE);
    return x->h.nins == 4 && is_leaf(i[0].op) && is_leaf(i[1].op) &&
           (i[2].op == NX_ADD || i[2].op == NX_SUB || i[2].op == NX_MUL || i[2].op == NX_DIV || i[2].op == NX_CMP);
}

/* A leaf's number into *[y]; false where numexpr_exec gives up (a name
 * not one number) */
static inline bool leaf_num(const NxIns *i, const Eval *ev, double *y)
{
    const Vec *v;
    if (i->op == NX_CONST) {
        *y = i->k;
        return true;
    }
    if (i->op == NX_LOCAL) v = ev->frame[i->arg];
    else if (!ev->globals) return false;
    else v = ev->globals->values[i->arg];
    if (!vec_is_scalar(v)) return false;
    *y = vec_cnums(v)[0];
    return true;
}

NxSmall numexpr_run_small(const NumExpr *x, const Eval *ev)
{
    const NxIns *i = x->ins;
    double a, b, y;
    if (!leaf_num(&i[0], ev, &a)) return (NxSmall){0.0, false};
    if (x->h.nins == 3) {
        /* numexpr_exec's l_addk .. l_divk, l_neg, l_square */
        switch (i[1].op) {
        case NX_ADDK: y = a + i[1].k; break;
        case NX_SUBK: y = a - i[1].k; break;
        case NX_MULK: y = a * i[1].k; break;
        case NX_DIVK: y = a / i[1].k; break;
        case NX_NEG: y = -a; break;
        default: y = a * a; break;
        }
        return (NxSmall){y, true};
    }
    if (!leaf_num(&i[1], ev, &b)) return (NxSmall){0.0, false};
    switch (i[2].op) {
    case NX_ADD: y = a + b; break;
    case NX_SUB: y = a - b; break;
    case NX_MUL: y = a * b; break;
    case NX_DIV: y = a / b; break;
    default:
        /* l_cmp's */
        if (isnan(a) || isnan(b)) return (NxSmall){0.0, false};
        y = compare(i[2].sub, a, b);
        break;
    }
    return (NxSmall){y, true};
}

bool numexpr_leaves(const NumExpr *x)
{
    for (uint32_t i = 0; i + 1 < x->h.nins; i++)
        if (!is_leaf(x->ins[i].op)) return false;
    return x->h.nout == x->h.nins - 1;
}

uint32_t numexpr_run_leaves(const NumExpr *x, const Eval *ev, double *out)
{
    const uint32_t n = x->h.nout;
    for (uint32_t k = 0; k < n; k++)
        if (!leaf_num(&x->ins[k], ev, &out[k])) return 0;
    return n;
}

bool numexpr_memoizable(const NumExpr *x)
{
    uint32_t globals = 0;
    for (uint32_t i = 0; i < x->h.nins; i++) {
        /* (a name's vector is no memo key: only one-number globals are) */
        if (x->ins[i].op == NX_LOCAL || x->ins[i].op == NX_INDEXL || x->ins[i].op == NX_INDEXG) return false;
        if (x->ins[i].op == NX_GLOBAL) globals++;
    }
    return globals >= 1 && globals <= NUMEXPR_MEMO_KEYS;
}

int numexpr_globals(const NumExpr *x, int32_t *idx)
{
    int k = 0;
    for (uint32_t i = 0; i < x->h.nins && k < NUMEXPR_MEMO_KEYS; i++)
        if (x->ins[i].op == NX_GLOBAL) idx[k++] = x->ins[i].arg;
    return k;
}

/* noise of the seed's [m] numbers v[0..m) and the [k] coordinates
 * v[m..m+k), one point (bi_noise_nums: the builtin's number); false
 * where it refuses (the builtin is then called). */
__attribute__((noinline)) static bool noise_point(Eval *ev, const Builtin *bi, const double *v, uint32_t m, uint32_t k, double *y)
{
    const double *x[BI_NOISE_ARGS];
    uint32_t n[BI_NOISE_ARGS], nout;
    x[0] = v;
    n[0] = m;
    for (uint32_t j = 0; j < k; j++) {
        x[1 + j] = v + m + j;
        n[1 + j] = 1;
    }
    return bi_noise_nums(ev, bi, x, n, k + 1, y, &nout) && nout == 1;
}

/* vec_cmp of two single non-NaN numbers turned into the comparison's 1/0,
 * as eval_compare does (§3.6, §3.7). */
static double compare(uint8_t op, double x, double y)
{
    switch (op) {
    case CMP_EQ: return x == y;
    case CMP_NE: return x != y;
    case CMP_LT: return x < y;
    case CMP_GT: return x > y;
    case CMP_LE: return x <= y;
    default: return x >= y;
    }
}

/* numexpr_run and numexpr_run_regs: names read from [ev]'s frame and
 * globals, registers from [regs] (a NumExpr has one kind or the other).
 * One function, so that its table of label addresses exists once. */
bool numexpr_exec(const NumExpr *x, Eval *ev, const double *regs, double *out)
{
    /* threaded dispatch (GNU C labels as values): each instruction jumps
     * straight to the next one's code */
    static const void *const code[] = {
        [NX_CONST] = &&l_const, [NX_LOCAL] = &&l_local, [NX_GLOBAL] = &&l_global,
        [NX_ADD] = &&l_add, [NX_SUB] = &&l_sub, [NX_MUL] = &&l_mul, [NX_DIV] = &&l_div,
        [NX_FLOORDIV] = &&l_floordiv, [NX_MOD] = &&l_mod, [NX_POW] = &&l_pow,
        [NX_SQUARE] = &&l_square, [NX_NEG] = &&l_neg, [NX_NOT] = &&l_not, [NX_CMP] = &&l_cmp,
        [NX_CALL1] = &&l_call1, [NX_ADDK] = &&l_addk, [NX_SUBK] = &&l_subk,
        [NX_MULK] = &&l_mulk, [NX_DIVK] = &&l_divk, [NX_REG] = &&l_reg, [NX_CALL2] = &&l_call2,
        [NX_INDEX] = &&l_index, [NX_INDEXL] = &&l_indexl, [NX_INDEXG] = &&l_indexg, [NX_HYPOT] = &&l_hypot,
        [NX_STREAM] = &&l_stream, [NX_MAP] = &&l_map, [NX_CLAMP] = &&l_clamp, [NX_NOISE] = &&l_noise,
        [NX_END] = &&l_end,
    };
    _Static_assert(sizeof code / sizeof code[0] == NX_END + 1, "every instruction has code");
    static const void *const cmp_code[] = {
        [CMP_EQ] = &&l_eq, [CMP_NE] = &&l_ne, [CMP_LT] = &&l_lt,
        [CMP_GT] = &&l_gt, [CMP_LE] = &&l_le, [CMP_GE] = &&l_ge,
    };
    _Static_assert(sizeof cmp_code / sizeof cmp_code[0] == CMP_GE + 1, "every ordering comparison has code");
    /* the top of the stack lives in t; st[1..] holds the rest (the first
     * push saves t's meaningless initial value in st[0]) */
    double st[NX_STACK + 1];
    double *sp = st, t = 0.0, a;
    const Vec *v;
    const NxIns *i = x->ins;
    const uint32_t nout = x->h.nout;
#define NEXT goto *code[(++i)->op]
    goto *code[i->op];
l_const: *sp++ = t; t = i->k; NEXT;
l_local:
    v = ev->frame[i->arg];
    if (!vec_is_scalar(v)) return false;
    *sp++ = t;
    t = vec_cnums(v)[0];
    NEXT;
l_global:
    if (!ev->globals) return false;
    v = ev->globals->values[i->arg];
    if (!vec_is_scalar(v)) return false;
    *sp++ = t;
    t = vec_cnums(v)[0];
    NEXT;
l_reg: *sp++ = t; t = regs[i->arg]; NEXT;
l_add: a = *--sp; t = a + t; NEXT;
l_sub: a = *--sp; t = a - t; NEXT;
l_mul: a = *--sp; t = a * t; NEXT;
l_div: a = *--sp; t = a / t; NEXT;
l_floordiv: a = *--sp; t = num_floordiv(a, t); NEXT;
l_mod: a = *--sp; t = num_mod(a, t); NEXT;
l_pow: a = *--sp; t = pow(a, t); NEXT;
l_square: t = t * t; NEXT;
l_neg: t = -t; NEXT;
l_not: t = (t != 0.0 || isnan(t)) ? 0.0 : 1.0; NEXT;
l_cmp:
    a = *--sp;
    /* NaN: the generic route's answer depends on whether both operands
     * are the same vector (§3.6 rule 1) */
    if (isnan(a) || isnan(t)) return false;
    /* compare()'s cases, each reached by its own jump */
    goto *cmp_code[i->sub];
l_eq: t = a == t; NEXT;
l_ne: t = a != t; NEXT;
l_lt: t = a < t; NEXT;
l_gt: t = a > t; NEXT;
l_le: t = a <= t; NEXT;
l_ge: t = a >= t; NEXT;
l_call1: t = i->fn(t); NEXT;
l_hypot: t = sqrt(t * t); NEXT;   /* bi_hypot_nums of one number: 0 + t*t is t*t */
l_map: sp -= 2; t = bi_map_num(sp[0], sp[1], t); NEXT;
l_clamp: sp -= 2; t = bi_clamp_num(sp[0], sp[1], t); NEXT;
l_noise: {
    /* the seed's numbers and the coordinates but the last lie below the
     * top, in order; the last is t */
    const uint32_t m = (uint32_t)i->arg, k = i->sub;
    sp -= m + k - 1;
    sp[m + k - 1] = t;
    /* (into y of its own: t's address taken would keep t out of a
     * register in every instruction's code) */
    double y;
    if (!noise_point(ev, i->bi, sp, m, k, &y)) return false;
    t = y;
    NEXT;
}
l_stream:
    /* the key's numbers lie below the top, in order */
    sp -= i->arg;
    t = stream_value_at((StreamKind)i->sub, vec_hash_nums(sp, (uint32_t)i->arg, true), t);
    NEXT;
l_call2: {
    double p, q;
    i->fn2(t, &p, &q);
    *sp++ = p;
    t = q;
    NEXT;
}
l_addk: t = t + i->k; NEXT;
l_subk: t = t - i->k; NEXT;
l_mulk: t = t * i->k; NEXT;
l_divk: t = t / i->k; NEXT;
l_index: vec_index_num1(i->lit, t, i->sub, &a); t = a; NEXT;   /* (a stream or numbers: never fails) */
l_indexl:
    if (!vec_index_num1(ev->frame[i->arg], t, i->sub, &a)) return false;
    t = a;
    NEXT;
l_indexg:
    if (!ev->globals || !vec_index_num1(ev->globals->values[i->arg], t, i->sub, &a)) return false;
    t = a;
    NEXT;
l_end:
#undef NEXT
    /* the outputs: st[1..nout-1], then t */
    if (nout <= 4) {
        /* one by one: a memcpy call (what the loop compiles to) costs
         * more than the one to three numbers it would copy */
        if (nout >= 4) out[2] = st[3];
        if (nout >= 3) out[1] = st[2];
        if (nout >= 2) out[0] = st[1];
    } else {
        memcpy(out, st + 1, (nout - 1) * sizeof *out);
    }
    out[nout - 1] = t;
    return true;
}

/* One operand of numexpr_run_vec: [n] numbers (1, or the run's length) at
 * [p], which points into [v] or into a name's vector (borrowed: the names
 * keep their values while the expression runs). */
typedef struct NxVal {
    uint32_t n;
    const double *p;
    double v[NUMEXPR_VEC_MAX];
} NxVal;

/* numexpr_run_vec's name load: [v] must be 1 to NUMEXPR_VEC_MAX numbers,
 * and, when more than one, as many as every other vector of the run
 * (*[len], 0 until the first). */
static inline bool vec_operand(const Vec *v, uint32_t *len, NxVal *d)
{
    if (!vec_is_num(v) || !v->len || v->len > NUMEXPR_VEC_MAX) return false;
    if (v->len > 1) {
        if (*len && *len != v->len) return false;
        *len = v->len;
    }
    d->n = v->len;
    d->p = vec_cnums(v);
    return true;
}

_Static_assert(NX_POW - NX_ADD == OP_POW - OP_ADD && NX_SUB - NX_ADD == OP_SUB - OP_ADD,
               "the binary instructions in ArithOp's order");

/* t = f(t), number by number. */
#define NX_VEC_UNARY(EXPR)                                                   \
    do {                                                                     \
        const double *pt = t->p;                                             \
        for (uint32_t k = 0; k < t->n; k++) {                                \
            const double q = pt[k];                                          \
            t->v[k] = (EXPR);                                                \
        }                                                                    \
        t->p = t->v;                                                         \
    } while (0)

bool numexpr_run_vec(const NumExpr *x, Eval *ev, double *out, uint32_t *nout)
{
    if (x->h.nout != 1) return false;
    if (x->ins[0].sub == NX_DIST) {
        /* hypot(a-b) of two names holding vectors of one length (the
         * distance between two points): the loop's instructions on them
         * without its dispatch; other lengths go through the loop */
        const Vec *va = ev->frame[x->ins[0].arg], *vb = ev->frame[x->ins[1].arg];
        if (vec_is_num(va) && vec_is_num(vb) && va->len == vb->len && va->len - 1 < NUMEXPR_VEC_MAX) {
            const double *p = vec_cnums(va), *q = vec_cnums(vb);
            double d[NUMEXPR_VEC_MAX];
            for (uint32_t k = 0; k < va->len; k++) d[k] = p[k] - q[k];
            out[0] = bi_hypot_nums(d, va->len);
            *nout = 1;
            return true;
        }
    }
    NxVal st[NX_STACK + 1];
    NxVal *t = st, *a;   /* the top (st[0], unused, while empty), and the one below it */
    uint32_t len = 0;
    double y;
    for (const NxIns *i = x->ins;; i++) {
        switch (i->op) {
        case NX_CONST:
            t++;
            t->n = 1;
            t->v[0] = i->k;
            t->p = t->v;
            break;
        case NX_LOCAL:
            if (!vec_operand(ev->frame[i->arg], &len, ++t)) return false;
            break;
        case NX_GLOBAL:
            if (!ev->globals || !vec_operand(ev->globals->values[i->arg], &len, ++t)) return false;
            break;
        /* vec_arith: the longer length (every vector here has the same),
         * a one-number operand repeated */
        case NX_ADD: case NX_SUB: case NX_MUL: case NX_DIV: case NX_FLOORDIV: case NX_MOD: case NX_POW:
            /* (written over a's numbers: a is the longer or one number;
             * + - * of two vectors of one length here, without the call) */
            a = t - 1;
            if (a->n == t->n && i->op <= NX_MUL) {
                const double *p = a->p, *q = t->p;
                if (i->op == NX_ADD) for (uint32_t k = 0; k < a->n; k++) a->v[k] = p[k] + q[k];
                else if (i->op == NX_SUB) for (uint32_t k = 0; k < a->n; k++) a->v[k] = p[k] - q[k];
                else for (uint32_t k = 0; k < a->n; k++) a->v[k] = p[k] * q[k];
            } else {
                num_arith_into((ArithOp)(OP_ADD + (i->op - NX_ADD)), a->v, a->p, a->n, t->p, t->n);
            }
            a->n = a->n > t->n ? a->n : t->n;
            a->p = a->v;
            t = a;
            break;
        case NX_ADDK: NX_VEC_UNARY(q + i->k); break;
        case NX_SUBK: NX_VEC_UNARY(q - i->k); break;
        case NX_MULK: NX_VEC_UNARY(q * i->k); break;
        case NX_DIVK: NX_VEC_UNARY(q / i->k); break;
        case NX_SQUARE: NX_VEC_UNARY(q * q); break;
        case NX_NEG: NX_VEC_UNARY(-q); break;
        case NX_CALL1: NX_VEC_UNARY(i->fn(q)); break;
        case NX_HYPOT:
            /* the builtin's sum of squares, in order: one number of any
             * vector (the run's other vectors keep their length) */
            t->v[0] = bi_hypot_nums(t->p, t->n);
            t->n = 1;
            t->p = t->v;
            break;
        case NX_MAP: case NX_CLAMP: {
            /* the builtin's loop, each operand one number or the run's
             * length (into r first: x0's numbers may be read again after
             * t - 2, which is x0, is written) */
            const NxVal *x0 = t - 2, *x1 = t - 1;
            uint32_t m = x0->n > x1->n ? x0->n : x1->n;
            if (t->n > m) m = t->n;
            double r[NUMEXPR_VEC_MAX];
            for (uint32_t k = 0; k < m; k++) {
                const double p = x0->p[x0->n == 1 ? 0 : k], q = x1->p[x1->n == 1 ? 0 : k],
                             w = t->p[t->n == 1 ? 0 : k];
                r[k] = i->op == NX_MAP ? bi_map_num(p, q, w) : bi_clamp_num(p, q, w);
            }
            t -= 2;
            for (uint32_t k = 0; k < m; k++) t->v[k] = r[k];
            t->n = m;
            t->p = t->v;
            break;
        }
        case NX_NOISE: {
            /* one number each (a vector of coordinates is a grid) */
            const uint32_t m = (uint32_t)i->arg, k = i->sub;
            double v[NX_STREAM_KEYS + BI_NOISE_ARGS];
            for (uint32_t j = 0; j < m + k; j++) {
                const NxVal *a1 = t - (m + k - 1) + j;
                if (a1->n != 1) return false;
                v[j] = a1->p[0];
            }
            if (!noise_point(ev, i->bi, v, m, k, &y)) return false;
            t -= m + k - 1;
            t->n = 1;
            t->v[0] = y;
            t->p = t->v;
            break;
        }
        case NX_STREAM: {
            /* one number each: the key's and the index */
            double key[NX_STREAM_KEYS];
            const uint32_t m = (uint32_t)i->arg;
            for (uint32_t j = 0; j < m; j++) {
                const NxVal *kv = t - m + j;
                if (kv->n != 1) return false;
                key[j] = kv->p[0];
            }
            if (t->n != 1) return false;
            y = stream_value_at((StreamKind)i->sub, vec_hash_nums(key, m, true), t->p[0]);
            t -= m;
            t->n = 1;
            t->v[0] = y;
            t->p = t->v;
            break;
        }
        case NX_CALL2: {
            /* fn2(t) = (p, q): p left below, q pushed on top, per number */
            NxVal *r = t + 1;
            r->n = t->n;
            for (uint32_t k = 0; k < t->n; k++) {
                double y1, y2;
                i->fn2(t->p[k], &y1, &y2);
                t->v[k] = y1;
                r->v[k] = y2;
            }
            t->p = t->v;
            r->p = r->v;
            t = r;
            break;
        }
        case NX_NOT:
            /* vec_truthy of one number only (a vector's is not per number) */
            if (t->n != 1) return false;
            t->v[0] = (t->p[0] != 0.0 || isnan(t->p[0])) ? 0.0 : 1.0;
            t->p = t->v;
            break;
        case NX_CMP:
            /* vectors compare as wholes (§3.6), and NaN as numexpr_exec */
            a = t - 1;
            if (a->n != 1 || t->n != 1 || isnan(a->p[0]) || isnan(t->p[0])) return false;
            a->v[0] = compare(i->sub, a->p[0], t->p[0]);
            a->p = a->v;
            t = a;
            break;
        case NX_INDEX:
            if (t->n != 1) return false;
            vec_index_num1(i->lit, t->p[0], i->sub, &y);
            t->v[0] = y;
            t->p = t->v;
            break;
        case NX_INDEXL:
        case NX_INDEXG: {
            const Vec *src = i->op == NX_INDEXL ? ev->frame[i->arg]
                           : ev->globals ? ev->globals->values[i->arg] : NULL;
            if (t->n != 1 || !src || !vec_index_num1(src, t->p[0], i->sub, &y)) return false;
            t->v[0] = y;
            t->p = t->v;
            break;
        }
        case NX_END:
            /* (a few numbers: a call of memcpy costs more) */
            for (uint32_t k = 0; k < t->n; k++) out[k] = t->p[k];
            *nout = t->n;
            return true;
        default:   /* NX_REG: registers hold one number each */
            return false;
        }
    }
}
#undef NX_VEC_UNARY

bool numexpr_run_regs(const NumExpr *x, const double *regs, double *out)
{
    return numexpr_exec(x, NULL, regs, out);
}

NumExpr *numexpr_to_regs(const NumExpr *x, NumExprRegMap map, void *ctx)
{
    size_t size = numexpr_size(x);
    NumExpr *y = mem_alloc(size);
    memcpy(y, x, size);
    y->h.lead = 0;   /* (registers, no slots) */
    for (uint32_t i = 0; i < y->h.nins; i++) {
        NxIns *in = &y->ins[i];
        if (in->op == NX_INDEXL || in->op == NX_INDEXG ||   /* (a vector: registers hold one number) */
            in->op == NX_NOISE) {   /* (the runtime's permutations: not on other threads) */
            free(y);
            return NULL;
        }
        if (in->op != NX_LOCAL && in->op != NX_GLOBAL) continue;
        in->sub = 0;   /* (not NX_DIST: registers) */
        int32_t r = map(ctx, in->op == NX_GLOBAL, in->arg);
        if (r < 0) {
            free(y);
            return NULL;
        }
        in->op = NX_REG;
        in->arg = r;
    }
    return y;
}

/* numexpr_run_lanes for [n] lanes (below) */
static inline __attribute__((always_inline)) void run_lanes(const NumExpr *x, double *regs, size_t stride,
                                                           const uint32_t n, uint8_t *fail)
{
    /* the stack of columns: each operand is a column of [lanes] numbers;
     * the top is t, st[1..] the rest (as in exec) */
    double st[NX_STACK + 1][NUMEXPR_LANES];
    double t[NUMEXPR_LANES], *a;
    uint32_t sp = 0;
    for (const NxIns *i = x->ins;; i++) {
        switch (i->op) {
        case NX_REG:
            memcpy(st[sp++], t, n * sizeof *t);
            for (uint32_t l = 0; l < n; l++) t[l] = regs[l * stride + (uint32_t)i->arg];
            break;
        case NX_CONST:
            memcpy(st[sp++], t, n * sizeof *t);
            for (uint32_t l = 0; l < n; l++) t[l] = i->k;
            break;
        case NX_ADD: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = a[l] + t[l]; break;
        case NX_SUB: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = a[l] - t[l]; break;
        case NX_MUL: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = a[l] * t[l]; break;
        case NX_DIV: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = a[l] / t[l]; break;
        case NX_FLOORDIV: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = num_floordiv(a[l], t[l]); break;
        case NX_MOD: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = num_mod(a[l], t[l]); break;
        case NX_POW: a = st[--sp]; for (uint32_t l = 0; l < n; l++) t[l] = pow(a[l], t[l]); break;
        case NX_SQUARE: for (uint32_t l = 0; l < n; l++) t[l] = t[l] * t[l]; break;
        case NX_NEG: for (uint32_t l = 0; l < n; l++) t[l] = -t[l]; break;
        case NX_NOT: for (uint32_t l = 0; l < n; l++) t[l] = (t[l] != 0.0 || isnan(t[l])) ? 0.0 : 1.0; break;
        case NX_CMP:
            a = st[--sp];
            for (uint32_t l = 0; l < n; l++) {
                /* NaN: the lane gives up, as exec does */
                if (isnan(a[l]) || isnan(t[l])) {
                    fail[l] = 1;
                    t[l] = 0.0;
                } else {
                    t[l] = compare(i->sub, a[l], t[l]);
                }
            }
            break;
        case NX_CALL1: for (uint32_t l = 0; l < n; l++) t[l] = i->fn(t[l]); break;
        case NX_HYPOT: for (uint32_t l = 0; l < n; l++) t[l] = sqrt(t[l] * t[l]); break;
        case NX_MAP:
            for (uint32_t l = 0; l < n; l++) t[l] = bi_map_num(st[sp - 2][l], st[sp - 1][l], t[l]);
            sp -= 2;
            break;
        case NX_CLAMP:
            for (uint32_t l = 0; l < n; l++) t[l] = bi_clamp_num(st[sp - 2][l], st[sp - 1][l], t[l]);
            sp -= 2;
            break;
        case NX_STREAM: {
            const uint32_t m = (uint32_t)i->arg;
            double key[NX_STREAM_KEYS];
            for (uint32_t l = 0; l < n; l++) {
                for (uint32_t j = 0; j < m; j++) key[j] = st[sp - m + j][l];
                t[l] = stream_value_at((StreamKind)i->sub, vec_hash_nums(key, m, true), t[l]);
            }
            sp -= m;
            break;
        }
        case NX_CALL2:
            for (uint32_t l = 0; l < n; l++) i->fn2(t[l], &st[sp][l], &t[l]);
            sp++;
            break;
        case NX_ADDK: for (uint32_t l = 0; l < n; l++) t[l] = t[l] + i->k; break;
        case NX_SUBK: for (uint32_t l = 0; l < n; l++) t[l] = t[l] - i->k; break;
        case NX_MULK: for (uint32_t l = 0; l < n; l++) t[l] = t[l] * i->k; break;
        case NX_DIVK: for (uint32_t l = 0; l < n; l++) t[l] = t[l] / i->k; break;
        case NX_INDEX: for (uint32_t l = 0; l < n; l++) vec_index_num1(i->lit, t[l], i->sub, &t[l]); break;
        case NX_END: {
            /* the outputs: st[1..nout-1], then t */
            const uint32_t nout = x->h.nout, out = (uint32_t)i->arg;
            for (uint32_t o = 0; o + 1 < nout; o++)
                for (uint32_t l = 0; l < n; l++) regs[l * stride + out + o] = st[o + 1][l];
            for (uint32_t l = 0; l < n; l++) regs[l * stride + out + nout - 1] = t[l];
            return;
        }
        default:   /* NX_LOCAL, NX_GLOBAL, NX_INDEXL, NX_INDEXG: not in a register copy */
            for (uint32_t l = 0; l < n; l++) fail[l] = 1;
            return;
        }
    }
}

/* GCC at -O2 vectorizes no loop with an epilogue; the lanes' loops are
 * such loops (IEEE operations lane by lane, the same with SIMD). A full
 * set of lanes (the usual case) runs a copy whose loops have a constant
 * count, which needs no epilogue. */
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("tree-vectorize")))
#endif
void numexpr_run_lanes(const NumExpr *x, double *regs, size_t stride, uint32_t lanes, uint8_t *fail)
{
    if (lanes == NUMEXPR_LANES) run_lanes(x, regs, stride, NUMEXPR_LANES, fail);
    else run_lanes(x, regs, stride, lanes, fail);
}

void numexpr_set_out(NumExpr *x, uint32_t out)
{
    x->ins[x->h.nins - 1].arg = (int32_t)out;
}

/* The distinct arguments of [x]'s instructions of kind [op] or [op2], in
 * order of first use, into out[0 ..]; how many, or UINT32_MAX past [max]. */
static uint32_t distinct_args(const NumExpr *x, uint8_t op, uint8_t op2, int32_t *out, uint32_t max)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < x->h.nins; i++) {
        if (x->ins[i].op != op && x->ins[i].op != op2) continue;
        uint32_t j = 0;
        while (j < n && out[j] != x->ins[i].arg) j++;
        if (j < n) continue;
        if (n == max) return UINT32_MAX;
        out[n++] = x->ins[i].arg;
    }
    return n;
}

uint32_t numexpr_local_reads(const NumExpr *x, int32_t *slots, uint32_t max)
{
    return distinct_args(x, NX_LOCAL, NX_INDEXL, slots, max);
}

void numexpr_renumber_regs(NumExpr *x, int32_t (*map)(void *ctx, int32_t reg), void *ctx)
{
    for (uint32_t i = 0; i < x->h.nins; i++)
        if (x->ins[i].op == NX_REG) x->ins[i].arg = map(ctx, x->ins[i].arg);
}

uint32_t numexpr_reg_reads(const NumExpr *x, int32_t *regs, uint32_t max)
{
    return distinct_args(x, NX_REG, NX_REG, regs, max);
}

uint32_t numexpr_cost(const NumExpr *x)
{
    uint32_t c = 0;
    for (uint32_t i = 0; i < x->h.nins; i++)
        c += x->ins[i].op == NX_CALL2                                    ? 24
             : x->ins[i].op == NX_CALL1 || x->ins[i].op == NX_POW ||
                       x->ins[i].op == NX_STREAM                         ? 16   /* (a hash and a draw) */
             : x->ins[i].op == NX_INDEX                                 ? 8   /* (a random draw, or a load) */
                                                                         : 1;
    return c;
}

uint32_t numexpr_reg_calls(const NumExpr *x, NumExprCall *out, uint32_t max)
{
    uint32_t n = 0;
    /* a stack machine: a call right after a register's push takes that
     * register alone as its argument */
    for (uint32_t i = 0; i + 1 < x->h.nins; i++) {
        if (x->ins[i].op != NX_REG || x->ins[i + 1].op != NX_CALL1) continue;
        if (n < max) out[n] = (NumExprCall){x->ins[i].arg, x->ins[i + 1].fn};
        n++;
    }
    return n;
}

uint32_t numexpr_share_call(NumExpr *x, NumExprCall c, int32_t reg)
{
    uint32_t n = 0, j = 0;
    for (uint32_t i = 0; i < x->h.nins; i++) {
        x->ins[j] = x->ins[i];
        if (i + 1 < x->h.nins && x->ins[i].op == NX_REG && x->ins[i].arg == c.reg && x->ins[i + 1].op == NX_CALL1 &&
            x->ins[i + 1].fn == c.fn) {
            x->ins[j].arg = reg;
            i++;   /* the call's instruction goes */
            n++;
        }
        j++;
    }
    x->h.nins = j;
    return n;
}

NumExpr *numexpr_new_call(NumExprCall c)
{
    NumExpr *x = mem_alloc(sizeof(NumExpr) + 3 * sizeof(NxIns));
    x->h = (NumExprHead){.nins = 3, .nout = 1, .depth = 0};
    x->ins[0] = (NxIns){.op = NX_REG, .arg = c.reg};
    x->ins[1] = (NxIns){.op = NX_CALL1, .fn = c.fn};
    x->ins[2] = (NxIns){.op = NX_END};
    return x;
}

NumExpr *numexpr_new_call2(int32_t reg, BiKernelPair fn2)
{
    NumExpr *x = mem_alloc(sizeof(NumExpr) + 3 * sizeof(NxIns));
    x->h = (NumExprHead){.nins = 3, .nout = 2, .depth = 0};
    x->ins[0] = (NxIns){.op = NX_REG, .arg = reg};
    x->ins[1] = (NxIns){.op = NX_CALL2, .fn2 = fn2};
    x->ins[2] = (NxIns){.op = NX_END};
    return x;
}
