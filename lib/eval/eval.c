/* eval.c: the per-frame tree-walking evaluator (LANGUAGE.md §4).
 *
 * eval_expr() takes a resolved AST node and the current function frame
 * (ev->frame: one Vec* per slot, see program.h) and returns a new reference
 * to the node's value. There is one function per AST kind; each begins with
 * the node shape it handles and the spec section it follows. Run-time
 * problems never stop the frame: the value becomes null and a message is
 * recorded in ev->errors (§4.16).
 */
#include "program.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "config.h"
#include "context.h"
#include "eval_internal.h"
#include "format.h"
#include "kernel.h"
#include "mem.h"
#include "module.h"
#include "numexpr.h"
#include "pool.h"
#include "stable.h"

/* ====================================================================
 * Services for builtins (context.h)
 * ==================================================================== */

void eval_error(Eval *ev, const char *msg)
{
    if (ev && ev->errors) msgset_add(ev->errors, msg);
}

void eval_debug(Eval *ev, const char *msg)
{
    if (ev && ev->debug) msgset_add(ev->debug, msg);
}

const SymTab *eval_symtab(const Eval *ev) { return ev ? ev->symtab : NULL; }

const char *eval_script_dir(const Eval *ev)
{
    return ev && ev->prog && ev->prog->dir ? ev->prog->dir : ".";
}

struct NoisePerms *eval_noise_perms(Eval *ev) { return ev ? ev->noise_perms : NULL; }

struct FileMemo *eval_file_memo(Eval *ev) { return ev ? ev->file_memo : NULL; }

static void errorf(Eval *ev, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void errorf(Eval *ev, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    eval_error(ev, msg);
}

/* ====================================================================
 * The evaluation step
 * ==================================================================== */

static Vec *eval_fast(Eval *ev, const AstNode *n);

/* Evaluate [n] (may be NULL): literals and names inline, without a call or
 * the depth guard (they cannot recurse), compiled numeric subtrees by
 * eval_fast, everything else via eval_node. */
static inline Vec *eval(Eval *ev, const AstNode *n)
{
    if (!n) return NULL;
    if (n->kind == AST_LITERAL) return vec_retain(n->value);
    if (n->kind == AST_NAME) {
        switch (n->scope) {
        case SCOPE_LOCAL: return vec_retain(ev->frame[n->slot]);
        case SCOPE_GLOBAL: return ev->globals ? vec_retain(ev->globals->values[n->slot]) : NULL;
        case SCOPE_CONST: return vec_retain(n->value);
        default: return NULL;
        }
    }
    if (n->fast == 1) return eval_fast(ev, n);
    if (n->fast == 2) return eval_code(ev, n);
    return eval_node(ev, n);
}

__attribute__((noinline)) static Vec *eval_fast(Eval *ev, const AstNode *n)
{
    return run_num(ev, n, numexpr_of(n));
}

/* ====================================================================
 * Helpers
 * ==================================================================== */

bool eval_interrupted(Eval *ev)
{
    return ev && stop_requested(ev);
}

void parts_init(Parts *p)
{
    p->v = p->small;
    p->n = 0;
    p->cap = 8;
    p->chunks = 0;
    p->pushed = 0;
    p->total = 0;
    p->too_long = false;
}

void parts_collapse(Parts *p)
{
    p->v[p->chunks] = vec_compose_take(&p->v[p->chunks], p->n - p->chunks);
    p->n = ++p->chunks;
}

/* Grow [p] (full) to twice its capacity. */
void parts_grow(Parts *p)
{
    size_t cap = p->cap * 2;
    Vec **nv = pool_alloc(cap * sizeof(Vec *));
    memcpy(nv, p->v, p->n * sizeof(Vec *));
    if (p->v != p->small) pool_release(p->v, p->cap * sizeof(Vec *));
    p->v = nv;
    p->cap = cap;
}

/* Compose the parts and release them; null with an execution error when
 * they were too long. */
Vec *parts_finish(Eval *ev, Parts *p)
{
    Vec *r;
    if (p->too_long) {
        if (mem_take_refusal()) eval_error(ev, MEM_OOM_MESSAGE);
        else errorf(ev, "Vector too long (over %llu elements)", (unsigned long long)MAX_COMPOSE_LEN);
        r = NULL;
        if (p->pushed == 1) vec_release(p->v[0]);
    } else {
        r = p->pushed == 1 ? p->v[0] : vec_compose_take(p->v, p->n);
        if (!r && p->pushed > 1 && mem_take_refusal()) eval_error(ev, MEM_OOM_MESSAGE);
    }
    if (p->too_long && p->pushed != 1)
        for (size_t i = 0; i < p->n; i++) vec_release(p->v[i]);
    if (p->v != p->small) pool_release(p->v, p->cap * sizeof(Vec *));
    return r;
}

/* Bind names of [b] (AST_BINDING or AST_FOR) to [v]: one name takes the
 * whole vector, several unpack with wrap-around (§4.4). Consumes [v]. */
static void bind_unpack(Eval *ev, const AstNode *b, Vec *v)
{
    if (b->nnames == 1) {
        set_slot(ev, b->slots[0], v);
        return;
    }
    for (uint32_t i = 0; i < b->nnames; i++) set_slot(ev, b->slots[i], vec_item(v, i));
    vec_release(v);
}

/* An unshared copy of [v] (consumes [v]); object vectors only. */
Vec *vec_unshare(Vec *v)
{
    if (v->refs == 1) return v;
    Vec *c = vec_new_obj(v->len);
    Elem *d = vec_elems(c);
    const Elem *s = vec_celems(v);
    for (uint32_t i = 0; i < v->len; i++) {
        d[i] = s[i];
        switch (d[i].kind) {
        case EL_STR: str_retain(d[i].str); break;
        case EL_NODE: node_retain(d[i].node); break;
        case EL_FUNC: func_retain(d[i].func); break;
        default: break;
        }
    }
    vec_release(v);
    return c;
}

bool has_nodes(const Vec *v)
{
    if (!vec_is_obj(v)) return false;
    for (uint32_t i = 0; i < v->len; i++)
        if (vec_celems(v)[i].kind == EL_NODE) return true;
    return false;
}

/* Python-style host repr of an element, for `X is not callable`. */
static void host_repr(Buf *b, const Elem *e, const SymTab *st)
{
    (void)st;
    if (e->kind == EL_NUM) {
        size_t at = b->len;
        fmt_double(b, e->num);
        const char *s = b->data + at;
        if (!strpbrk(s, ".eni")) buf_puts(b, ".0");
    } else if (e->kind == EL_STR) {
        Vec *v = vec_str(e->str->bytes, e->str->len);
        fmt_repr(b, v, NULL);
        vec_release(v);
    } else {
        buf_puts(b, "<object>");
    }
}

/* ====================================================================
 * Calls (§4.8, §4.9)
 * ==================================================================== */

typedef struct Closure {
    const AstNode *def;   /* AST_FUNCTION */
    Program *prog;        /* keeps the AST alive */
    Vec **defaults;       /* per parameter, evaluated at definition */
    Vec **caps;           /* captured values, FnInfo order */
    uint32_t nparams, ncaps;
    uint32_t active;      /* calls in progress */
} Closure;

static void closure_destroy(Func *f)
{
    Closure *c = f->impl;
    for (uint32_t i = 0; i < c->nparams; i++) vec_release(c->defaults[i]);
    for (uint32_t i = 0; i < c->ncaps; i++) vec_release(c->caps[i]);
    pool_release(c->defaults, (c->nparams ? c->nparams : 1) * sizeof(Vec *));
    pool_release(c->caps, (c->ncaps ? c->ncaps : 1) * sizeof(Vec *));
    program_release(c->prog);
    pool_release(c, sizeof *c);
}

static Vec *call_user(Eval *ev, Func *f, const Args *a)
{
    Closure *c = f->impl;
    const AstNode *def = c->def;
    const FnInfo *fi = def->aux;
    if (c->active >= MAX_ACTIVE_CALLS) {
        errorf(ev, "Recursion depth exceeded for func '%s'", f->name->bytes);
        return NULL;
    }
    if (stop_requested(ev))
        return NULL;
    size_t frame_size = (fi->nslots ? fi->nslots : 1) * sizeof(Vec *);
    Vec **frame = pool_calloc(frame_size);
    frame[0] = vec_func_take(func_retain(f));
    for (uint32_t i = 0; i < c->nparams; i++) {
        const AstNode *p = def->kids[i];
        Vec *v = NULL;
        bool given = false;
        if (i < a->npos) {
            v = a->pos[i];
            given = true;
        } else {
            for (uint32_t k = 0; k < a->nkw && !given; k++) {
                if (str_eq(a->kwn[k]->names[0], p->names[0])) {
                    v = a->kw[k];
                    given = true;
                }
            }
        }
        if (!given) v = c->defaults[i];
        frame[p->slots[0]] = vec_retain(v);
    }
    const int32_t *dst = fi->cap_src + fi->ncaps;
    for (uint32_t k = 0; k < c->ncaps; k++) frame[dst[k]] = vec_retain(c->caps[k]);
    Vec **saved = ev->frame;
    Program *saved_prog = ev->prog;
    ev->frame = frame;
    ev->prog = c->prog;
    c->active++;
    Vec *r = eval(ev, def->a);
    c->active--;
    ev->frame = saved;
    ev->prog = saved_prog;
    for (uint32_t i = 0; i < fi->nslots; i++) vec_release(frame[i]);
    pool_release(frame, frame_size);
    return r;
}

Vec *call_builtin(Eval *ev, const Builtin *bi, const Args *a)
{
    /* every parameter given by position: pass the evaluated arguments as
     * they are (builtins read nothing past max_args) */
    if (a->nkw == 0 && bi->max_args != BI_VARIADIC && a->npos == (uint32_t)bi->max_args &&
        bi->max_args >= bi->min_args)
        return bi->fn(ev, bi, (int)a->npos, a->pos);
    Vec *args[BI_MAX_PARAMS + 8] = {0};
    Vec **argv = args;
    uint32_t n = a->npos;
    bool variadic = bi->max_args == BI_VARIADIC;
    if (!variadic && n > (uint32_t)bi->max_args)
        return bi_error(ev, bi, "%s() takes at most %d positional arguments (%u given)",
                        bi->internal, bi->max_args, n);
    if (n > sizeof args / sizeof args[0]) {
        argv = calloc(n, sizeof(Vec *));
        if (!argv) mem_oom();
    }
    for (uint32_t i = 0; i < a->npos; i++) argv[i] = a->pos[i];
    for (uint32_t k = 0; k < a->nkw; k++) {
        const Str *name = a->kwn[k]->names[0];
        int idx = -1;
        for (int p = 0; p < BI_MAX_PARAMS && bi->params[p]; p++)
            if (strcmp(bi->params[p], name->bytes) == 0) idx = p;
        if (idx < 0 || (!variadic && idx >= bi->max_args) || (uint32_t)idx >= sizeof args / sizeof args[0]) {
            if (argv != args) free(argv);
            return bi_error(ev, bi, "%s() got an unexpected keyword argument '%s'", bi->internal,
                            name->bytes);
        }
        if ((uint32_t)idx < a->npos) {
            if (argv != args) free(argv);
            return bi_error(ev, bi, "%s() got multiple values for argument '%s'", bi->internal,
                            name->bytes);
        }
        argv[idx] = a->kw[k];
        if ((uint32_t)idx + 1 > n) n = (uint32_t)idx + 1;
    }
    Vec *r;
    if (n < (uint32_t)bi->min_args)
        r = bi_error(ev, bi, "%s() takes at least %d positional arguments (%u given)", bi->internal,
                     bi->min_args, n);
    else
        r = bi->fn(ev, bi, (int)n, argv);
    if (argv != args) free(argv);
    return r;
}

/* Call every element of [callee] with [a] and compose the results. */
static Vec *call_value(Eval *ev, const Vec *callee, const Args *a)
{
    if (!vec_is_obj(callee)) return NULL;   /* null, numeric, stream: silent null */
    Parts parts;
    parts_init(&parts);
    for (uint32_t i = 0; i < callee->len; i++) {
        const Elem *e = &vec_celems(callee)[i];
        if (e->kind == EL_FUNC) {
            Func *f = e->func;
            parts_push(&parts, f->bi ? call_builtin(ev, f->bi, a) : call_user(ev, f, a));
        } else {
            Buf b = BUF_INIT;
            host_repr(&b, e, ev->symtab);
            buf_puts(&b, " is not callable");
            eval_error(ev, buf_cstr(&b));
            buf_free(&b);
        }
    }
    return parts_finish(ev, &parts);
}

Vec *eval_call_value(Eval *ev, const Vec *fn, Vec **args, uint32_t nargs)
{
    Args a = {.pos = args, .npos = nargs};
    return call_value(ev, fn, &a);
}

uint64_t eval_function_key(const Vec *fn)
{
    if (!vec_is_obj(fn)) return vec_hash(fn, false);
    uint64_t h = HASH_START;
    for (uint32_t i = 0; i < fn->len; i++) {
        const Elem *e = &vec_celems(fn)[i];
        if (e->kind != EL_FUNC || e->func->bi) {
            h = hash_update(h, e->kind == EL_FUNC ? (uint64_t)(uintptr_t)e->func->bi : (uint64_t)e->kind);
            continue;
        }
        const Closure *c = e->func->impl;
        h = hash_update(h, (uint64_t)(uintptr_t)c->def);
        h = hash_update(h, (uint64_t)(uintptr_t)c->prog);
        for (uint32_t k = 0; k < c->nparams; k++) h = hash_update(h, vec_hash(c->defaults[k], false));
        for (uint32_t k = 0; k < c->ncaps; k++) h = hash_update(h, vec_hash(c->caps[k], false));
    }
    return h;
}

/* AST_CALL: a(kids[0..count), name=value ...) — args, then named values,
 * then the callee (§4.8). */
__attribute__((noinline)) static Vec *eval_call(Eval *ev, const AstNode *n)
{
    uint32_t npos = n->count, nkw = n->nkids - n->count;
    const AstNode *fn = n->a;
    if (nkw == 0 && npos <= 8 &&
        (fn->kind == AST_LITERAL || (fn->kind == AST_NAME && fn->scope == SCOPE_CONST)) &&
        vec_is_obj(fn->value) && fn->value->len == 1 && vec_celems(fn->value)[0].kind == EL_FUNC &&
        vec_celems(fn->value)[0].func->bi) {
        /* a builtin resolved at load time (a builtin name, or a literal
         * function after the simplifier), positional arguments only: call
         * it directly (the callee is a constant, so evaluating it last, as
         * below, changes nothing) */
        Vec *args[8];
        for (uint32_t i = 0; i < npos; i++) args[i] = eval(ev, n->kids[i]);
        Args a = {args, npos, NULL, NULL, 0};
        Vec *r = call_builtin(ev, vec_celems(fn->value)[0].func->bi, &a);
        for (uint32_t i = 0; i < npos; i++) vec_release(args[i]);
        return r;
    }
    Vec *posbuf[8], *kwbuf[8];
    const AstNode *kwnbuf[8];
    Args a = {npos > 8 ? malloc(npos * sizeof(Vec *)) : posbuf, npos,
              nkw > 8 ? malloc(nkw * sizeof(AstNode *)) : kwnbuf,
              nkw > 8 ? malloc(nkw * sizeof(Vec *)) : kwbuf, nkw};
    if (!a.pos || !a.kwn || !a.kw) mem_oom();
    for (uint32_t i = 0; i < npos; i++) a.pos[i] = eval(ev, n->kids[i]);
    for (uint32_t k = 0; k < nkw; k++) {
        a.kwn[k] = n->kids[npos + k];
        a.kw[k] = eval(ev, a.kwn[k]->a);
    }
    Vec *callee = eval(ev, n->a);
    Vec *r = call_value(ev, callee, &a);
    vec_release(callee);
    for (uint32_t i = 0; i < npos; i++) vec_release(a.pos[i]);
    for (uint32_t k = 0; k < nkw; k++) vec_release(a.kw[k]);
    if (a.pos != posbuf) free(a.pos);
    if (a.kwn != kwnbuf) free(a.kwn);
    if (a.kw != kwbuf) free(a.kw);
    return r;
}

/* AST_FUNCTION: a closure with defaults evaluated and free names captured
 * now, in the defining frame (§4.8). */
__attribute__((noinline)) static Vec *eval_function(Eval *ev, const AstNode *n)
{
    const FnInfo *fi = n->aux;
    Closure *c = pool_calloc(sizeof *c);
    c->def = n;
    c->prog = ev->prog;
    c->prog->refs++;
    c->nparams = n->nkids;
    c->ncaps = fi->ncaps;
    c->defaults = pool_calloc((c->nparams ? c->nparams : 1) * sizeof(Vec *));
    c->caps = pool_calloc((c->ncaps ? c->ncaps : 1) * sizeof(Vec *));
    for (uint32_t i = 0; i < c->nparams; i++)
        c->defaults[i] = n->kids[i]->a ? eval(ev, n->kids[i]->a) : NULL;
    for (uint32_t k = 0; k < c->ncaps; k++) c->caps[k] = vec_retain(ev->frame[fi->cap_src[k]]);
    Func *f = pool_calloc(sizeof *f);
    f->refs = 1;
    f->name = str_retain(n->names[0]);
    f->impl = c;
    f->destroy = closure_destroy;
    return vec_func_take(f);
}

Vec *run_num_vec(Eval *ev, const NumExpr *x)
{
    double out[NUMEXPR_VEC_MAX];
    uint32_t n;
    if (!numexpr_run_vec(x, ev, out, &n)) return NULL;
    /* one number (a reduction: hypot of a difference) takes the pool's
     * class of one number, known at compile time */
    if (n == 1) return vec_num1(out[0]);
    Vec *v = vec_new_num(n);
    memcpy(vec_nums(v), out, n * sizeof(double));
    return v;
}

/* ====================================================================
 * Node operations (§4.10)
 * ==================================================================== */

/* AST_TAG: a #names[0] */
__attribute__((noinline)) static Vec *eval_tag(Eval *ev, const AstNode *n)
{
    Vec *v = eval(ev, n->a);
    if (!has_nodes(v)) return v;
    v = vec_unshare(v);
    Elem *e = vec_elems(v);
    for (uint32_t i = 0; i < v->len; i++) {
        if (e[i].kind != EL_NODE) continue;
        e[i].node = node_mut(e[i].node);
        node_add_tag(e[i].node, n->names[0]);
    }
    return v;
}

/* AST_ATTRIBUTES: a name=value ... — values left to right, then set. */
__attribute__((noinline)) static Vec *eval_attributes(Eval *ev, const AstNode *n)
{
    Vec *v = eval(ev, n->a);
    Vec *small[16];
    Vec **vals = n->nkids > 16 ? malloc(n->nkids * sizeof(Vec *)) : small;
    if (!vals) mem_oom();
    for (uint32_t k = 0; k < n->nkids; k++) vals[k] = eval(ev, n->kids[k]->a);
    const Node *o = v && v->kind == VEC_OBJ && v->len == 1 && vec_celems(v)[0].kind == EL_NODE
                        ? vec_celems(v)[0].node : NULL;
    if (o && (v->refs > 1 || o->refs > 1) && !o->ntags && !o->nattrs && !o->nchildren) {
        /* one shared bare node (a literal `!kind`): the copy it would get,
         * built with room for the attributes in its own block, instead of
         * a copy of the vector, of the node and then of its attribute
         * array as it grows */
        Node *nn = node_new_sized(o->kind, n->nkids);
        for (uint32_t k = 0; k < n->nkids; k++) node_set_attr(nn, n->kids[k]->names[0], vals[k]);
        if (vals != small) free(vals);
        vec_release(v);
        return vec_node_take(nn);
    }
    if (has_nodes(v)) {
        v = vec_unshare(v);
        Elem *e = vec_elems(v);
        for (uint32_t i = 0; i < v->len; i++) {
            if (e[i].kind != EL_NODE) continue;
            e[i].node = node_mut_room(e[i].node, n->nkids);
            for (uint32_t k = 0; k < n->nkids; k++)
                node_set_attr(e[i].node, n->kids[k]->names[0], vec_retain(vals[k]));
        }
    }
    for (uint32_t k = 0; k < n->nkids; k++) vec_release(vals[k]);
    if (vals != small) free(vals);
    return v;
}

/* Put the [nodes] node elements of [x] at [kids] (room for all of them),
 * in order, consuming [x]: moved with their references when [x] is held
 * only here (the same tree as appending and releasing [x], without
 * touching each node twice), else retained. */
static inline __attribute__((always_inline)) void take_nodes(Node **kids, Vec *x, uint32_t nodes)
{
    if (!nodes) {
        vec_release(x);
        return;
    }
    Elem *e = vec_elems(x);
    if (x->refs > 1) {
        for (uint32_t j = 0, k = 0; j < x->len; j++)
            if (e[j].kind == EL_NODE) kids[k++] = node_retain(e[j].node);
        vec_release(x);
        return;
    }
    if (nodes == x->len) {
        /* nodes alone: nothing is left in [x] to release */
        for (uint32_t j = 0; j < nodes; j++) kids[j] = e[j].node;
        vec_free_taken(x);
        return;
    }
    /* the rest is released with [x]; the nodes it gave up are not */
    for (uint32_t j = 0, k = 0; j < x->len; j++) {
        if (e[j].kind != EL_NODE) continue;
        kids[k++] = e[j].node;
        e[j].kind = EL_NUM;
        e[j].num = 0.0;
    }
    vec_release(x);
}

Vec *append_nodes(Vec *p, Vec *c)
{
    if (has_nodes(p) && has_nodes(c)) {
        Elem *ce = vec_elems(c);
        uint32_t count = 0, last = 0;
        for (uint32_t j = 0; j < c->len; j++) count += ce[j].kind == EL_NODE;
        if (p->len == 1 && p->refs > 1) {
            /* one shared node (a literal `(!kind ...) << ...`): its copy,
             * with room for the children, in a vector of its own, as
             * vec_unshare and node_mut below would make them */
            Node *n = node_mut_children(node_retain(vec_elems(p)[0].node), count);
            vec_release(p);
            p = vec_node_take(n);
        } else {
            p = vec_unshare(p);
        }
        Elem *e = vec_elems(p);
        for (uint32_t i = 0; i < p->len; i++)
            if (e[i].kind == EL_NODE) last = i;
        for (uint32_t i = 0; i < p->len; i++) {
            if (e[i].kind != EL_NODE) continue;
            Node *n = e[i].node = node_mut(e[i].node);
            node_reserve_children(n, n->nchildren + count);
            if (i == last) {
                /* the last parent takes [c] (take_nodes), into the room
                 * reserved above */
                take_nodes(n->children + n->nchildren, c, count);
                n->nchildren += count;
                c = NULL;
            } else {
                for (uint32_t j = 0; j < c->len; j++)
                    if (ce[j].kind == EL_NODE) node_append(n, ce[j].node);
            }
        }
    }
    vec_release(c);
    return p;
}

Vec *append_parts(Eval *ev, Vec *p, Vec **parts, uint32_t m)
{
    uint64_t total = 0;
    uint32_t count = 0, nonempty = 0, nodes[APPEND_PARTS_MAX] = {0};
    bool numeric = true;
    for (uint32_t i = 0; i < m; i++) {
        const Vec *x = parts[i];
        uint32_t len = vec_len(x);
        if (!len) continue;
        total += len;
        nonempty++;
        if (x->kind == VEC_NUM) continue;
        numeric = false;
        for (uint32_t j = 0; j < len; j++) nodes[i] += vec_celems(x)[j].kind == EL_NODE;
        count += nodes[i];
    }
    bool one = p && p->kind == VEC_OBJ && p->len == 1 && vec_celems(p)[0].kind == EL_NODE;
    /* where composing would refuse (too long, or past the memory budget:
     * the check vec_compose_take or vec_compose makes for the vector it
     * would build, of numbers or of elements), or the parent is not one
     * node: compose and append, errors and all */
    if (!one || total > MAX_COMPOSE_LEN ||
        (nonempty > 1 && !mem_room(sizeof(Vec) + (size_t)total * (numeric ? sizeof(double) : sizeof(Elem))))) {
        Parts ps;
        parts_init(&ps);
        for (uint32_t i = 0; i < m; i++) parts_push(&ps, parts[i]);
        return append_nodes(p, parts_finish(ev, &ps));
    }
    if (!count) {
        for (uint32_t i = 0; i < m; i++) vec_release(parts[i]);
        return p;
    }
    Node *n;
    if (p->refs == 1) {
        n = vec_elems(p)[0].node = node_mut_children(vec_elems(p)[0].node, count);
        node_reserve_children(n, n->nchildren + count);
    } else {
        /* a shared parent (a literal): its copy, with room for the
         * children in its own block, in a vector of its own */
        n = node_mut_children(node_retain(vec_elems(p)[0].node), count);
        vec_release(p);
        p = vec_node_take(n);
    }
    for (uint32_t i = 0; i < m; i++) {
        take_nodes(n->children + n->nchildren, parts[i], nodes[i]);
        n->nchildren += nodes[i];
    }
    return p;
}

/* AST_APPEND: a << b — node elements of b appended to each node of a. */
__attribute__((noinline)) static Vec *eval_append(Eval *ev, const AstNode *n)
{
    Vec *p = eval(ev, n->a);
    Vec *c = eval(ev, n->b);
    return append_nodes(p, c);
}

/* ====================================================================
 * Operators (§3.5-3.10)
 * ==================================================================== */

/* AST_BINOP: a OP b, with the F1 fused a + (b*c) and F2 x**2 (§4.17). */
__attribute__((noinline)) static Vec *eval_binop(Eval *ev, const AstNode *n)
{
    if (n->op == OP_POW && ast_literal_two(n->b)) {
        Vec *x = eval(ev, n->a);
        Vec *r = vec_arith(OP_MUL, x, x);
        vec_release(x);
        return r;
    }
    Vec *a = eval(ev, n->a);
    const AstNode *rb = n->b;
    if (n->op == OP_ADD && rb->kind == AST_BINOP &&
        (rb->op == OP_MUL || (rb->op == OP_POW && ast_literal_two(rb->b)))) {
        Vec *b = eval(ev, rb->a);
        Vec *c = rb->op == OP_MUL ? eval(ev, rb->b) : vec_retain(b);
        Vec *r = vec_add_mul(a, b, c);
        vec_release(a);
        vec_release(b);
        vec_release(c);
        return r;
    }
    return vec_arith_take((ArithOp)n->op, a, eval(ev, rb));
}

/* AST_COMPARE: a OP b (§3.6-3.8), 1 or 0, or null when incomparable. */
__attribute__((noinline)) static Vec *eval_compare(Eval *ev, const AstNode *n)
{
    Vec *a = eval(ev, n->a);
    Vec *b = eval(ev, n->b);
    bool same = a == b;    /* identity shortcut (§3.6 rule 1) */
    Vec *r = NULL;
    int c;
    switch (n->op) {
    case CMP_EQ: r = vec_num1(same || vec_equal(a, b)); break;
    case CMP_NE: r = vec_num1(!(same || vec_equal(a, b))); break;
    case CMP_IN: r = vec_num1(vec_contains(a, b)); break;
    default:
        c = same ? 0 : vec_cmp(a, b);
        if (c == CMP_INCOMPARABLE) break;
        switch (n->op) {
        case CMP_LT: r = vec_num1(c == -1); break;
        case CMP_GT: r = vec_num1(c == 1); break;
        case CMP_LE: r = vec_num1(c != 1); break;
        default: r = vec_num1(c != -1); break;
        }
    }
    vec_release(a);
    vec_release(b);
    return r;
}

/* AST_RANGE: a..b|c (§3.10). */
__attribute__((noinline)) static Vec *eval_range(Eval *ev, const AstNode *n)
{
    Vec *a = n->a ? eval(ev, n->a) : NULL;
    Vec *b = eval(ev, n->b);
    Vec *c = n->c ? eval(ev, n->c) : NULL;
    bool too_long = false;
    Vec *r = vec_range(a, b, c, MAX_RANGE_LEN, &too_long);
    if (too_long && mem_take_refusal()) eval_error(ev, MEM_OOM_MESSAGE);
    else if (too_long) errorf(ev, "Range too long (over %llu elements)", (unsigned long long)MAX_RANGE_LEN);
    vec_release(a);
    vec_release(b);
    vec_release(c);
    return r;
}

/* ====================================================================
 * Scopes and control (§4.3-4.7)
 * ==================================================================== */

/* AST_SEQUENCE: kids composed in order (§4.3). */
__attribute__((noinline)) static Vec *eval_sequence(Eval *ev, const AstNode *n)
{
    if (n->nkids == 1) return eval(ev, n->kids[0]);
    Parts parts;
    parts_init(&parts);
    for (uint32_t i = 0; i < n->nkids; i++) parts_push(&parts, eval(ev, n->kids[i]));
    return parts_finish(ev, &parts);
}

/* AST_LET: bindings left to right, then the body (§4.4, §4.5). */
__attribute__((noinline)) static Vec *eval_let(Eval *ev, const AstNode *n)
{
    for (uint32_t i = 0; i < n->nkids; i++) {
        const AstNode *b = n->kids[i];
        Vec *v = eval(ev, b->a);
        if (n->op == 1 && n->count && ev->stables &&
            !stable_check(ev->stables, n, i, v, ev->prog->asserted, ev->prog->nasserted))
            ev->stable_changed = true;   /* `let stable`: stable.h */
        bind_unpack(ev, b, v);
    }
    return eval(ev, n->a);
}

void bind_loop_names(Eval *ev, const AstNode *n, const Vec *src, uint32_t p)
{
    for (uint32_t j = 0; j < n->nnames; j++) bind_loop_name(ev, n, src, p, j);
}

/* The numbers of the iterations of a loop whose body is a compiled
 * expression (eval_for), gathered in order as one part of its parts:
 * [n] numbers written into [v], a numeric vector with room for every
 * number the loop's remaining iterations could give (made at the first
 * number, so that the loop allocates once: when every iteration gives its
 * numbers it becomes the result itself, which takes less memory than the
 * generic route's vector an iteration; NULL: none yet). */
typedef struct LoopNums {
    Vec *v;
    size_t n;
} LoopNums;

/* Hand the numbers gathered in [a] to [p] as one part (after the parts
 * pushed before them), and start again. Their count is in p->total
 * already. [a]'s vector itself when the numbers fill it (every iteration
 * gave them: the loop's whole result), else a copy of them. When the
 * memory budget refuses the copy, the parts are too long (parts_finish
 * reports the refusal). */
static void loop_nums_flush(Parts *p, LoopNums *a)
{
    if (!a->n) return;
    Vec *v;
    if (a->n == a->v->len) {
        v = a->v;
        a->v = NULL;
    } else {
        v = vec_from_nums(vec_cnums(a->v), (uint32_t)a->n);
    }
    a->n = 0;
    if (!v) {
        p->too_long = true;
        return;
    }
    if (p->n == p->cap) parts_grow(p);
    p->v[p->n++] = v;
    p->pushed++;
    if (p->n - p->chunks == PARTS_CHUNK) parts_collapse(p);
}

/* The [m] numbers [y] of one iteration, [left] iterations of [m] numbers
 * each being the most still to come (this one among them), counted as
 * parts_push counts a part of them (a part pushed or gathered before: the
 * limit applies): after the others, unless the parts are too long by then
 * (or the memory budget refuses room for them: a refusal, as the
 * iteration's own vector would have been). */
static void loop_nums_push(Parts *p, LoopNums *a, const double *y, uint32_t m, uint64_t left)
{
    p->total += m;
    if (p->too_long || ((p->pushed > 0 || a->n > 0) && p->total > MAX_COMPOSE_LEN)) {
        p->too_long = true;
        return;
    }
    if (!a->v) {
        uint64_t room = left * m;
        if (room > MAX_COMPOSE_LEN) room = MAX_COMPOSE_LEN;   /* (past it: too long above) */
        if (!mem_fits(sizeof(Vec) + room * sizeof(double))) {
            p->too_long = true;
            return;
        }
        a->v = vec_new_num((uint32_t)room);
    }
    double *x = vec_nums(a->v) + a->n;
    if (m == 1) x[0] = y[0];   /* (the usual count: no memcpy) */
    else memcpy(x, y, m * sizeof(double));
    a->n += m;
}

/* The numbers of a loop body compiled as [x] (AstNode.fast 1), as
 * eval_fast would make its vector (run_num's direct routes: the same
 * depth rule, the same machine), into [y] (room for NUMEXPR_DIRECT_MAX);
 * their count, or 0 where run_num would go on to the vector form or the
 * generic route. */
#define NUMEXPR_DIRECT_MAX 16
static inline uint32_t loop_body_nums(Eval *ev, const NumExpr *x, double *y)
{
    if (ev->depth + numexpr_depth(x) > MAX_EVAL_DEPTH) return 0;
    if (numexpr_small(x)) {
        const NxSmall r = numexpr_run_small(x, ev);
        y[0] = r.v;
        return r.ok;
    }
    const int32_t lead = numexpr_lead_slot(x);
    const uint32_t m = numexpr_outputs(x);
    if (m > NUMEXPR_DIRECT_MAX || (lead >= 0 && !vec_is_scalar(ev->frame[lead]))) return 0;
    return numexpr_run(x, ev, y) ? m : 0;
}

/* The start of iteration [p] of the AST_FOR [n] over [src]: false, with
 * the parts too long, once the memory budget is spent (mem.h: the nodes
 * and vectors each pass makes are charged as the pool allocates them);
 * else its names bound (one, the most usual, here: no call). */
static inline bool loop_begin(Eval *ev, const AstNode *n, const Vec *src, uint32_t p, Parts *parts)
{
    if (!mem_fits(0)) {
        parts->too_long = true;
        return false;
    }
    if (n->nnames == 1) bind_loop_name(ev, n, src, p, 0);
    else bind_loop_names(ev, n, src, p);
    return true;
}

/* eval_for's loop over [src] ([len] items, [k] a group) for a body that
 * is the compiled expression [x] (`f(i) for i in ..N`): each iteration
 * gives its numbers straight into the result, without a vector of its
 * own, while it runs on its direct routes (loop_body_nums); one that does
 * not is evaluated generically in its place. The parts compose to the
 * same vector. */
static __attribute__((noinline)) Vec *for_numbers(Eval *ev, const AstNode *n, const Vec *src, uint32_t len,
                                                 uint32_t k, const NumExpr *x)
{
    Parts parts;
    parts_init(&parts);
    LoopNums nums = {NULL, 0};
    for (uint32_t p = 0; p < len && !parts.too_long && !stop_requested(ev); p += k) {
        if (!loop_begin(ev, n, src, p, &parts)) break;
        double y[NUMEXPR_DIRECT_MAX];
        const uint32_t m = loop_body_nums(ev, x, y);
        if (m) {
            loop_nums_push(&parts, &nums, y, m, (len - p + k - 1) / k);
            continue;
        }
        loop_nums_flush(&parts, &nums);
        parts_push(&parts, eval(ev, n->b));
    }
    loop_nums_flush(&parts, &nums);
    vec_release(nums.v);
    return parts_finish(ev, &parts);
}

/* AST_FOR: names in source, body per group of len(names) items, no
 * wrap-around (§4.6); with a loop kernel (kernel.h) over numbers, its
 * route; with a body that is a compiled expression, for_numbers. */
__attribute__((noinline)) static Vec *eval_for(Eval *ev, const AstNode *n)
{
    Vec *src = eval(ev, n->a);
    if (n->fast == 3 && vec_is_num(src)) {
        bool done;
        Vec *r = kernel_eval_for(ev, n, src, &done);
        if (done) {
            vec_release(src);
            return r;
        }
    }
    uint32_t len = vec_len(src), k = n->nnames ? n->nnames : 1;
    /* the body's C_KNUM records (kernel.h) run as C_NUM here, also when
     * this loop runs inside a kernel's run of itself (recursion) */
    const unsigned char *kbase = ev->kbase;
    ev->kbase = NULL;
    Vec *r;
    if (n->b && n->b->fast == 1) {
        r = for_numbers(ev, n, src, len, k, numexpr_of(n->b));
    } else {
        Parts parts;
        parts_init(&parts);
        /* once the result is too long it is null: stop evaluating the
         * body; so too once the memory budget is spent (loop_begin) */
        for (uint32_t p = 0; p < len && !parts.too_long && !stop_requested(ev); p += k) {
            if (!loop_begin(ev, n, src, p, &parts)) break;
            parts_push(&parts, eval(ev, n->b));
        }
        r = parts_finish(ev, &parts);
    }
    ev->kbase = kbase;
    vec_release(src);
    return r;
}

/* AST_IFELSE: first true condition's branch, else `a` (§4.7). */
__attribute__((noinline)) static Vec *eval_ifelse(Eval *ev, const AstNode *n)
{
    for (uint32_t i = 0; i + 1 < n->nkids; i += 2) {
        Vec *c = eval(ev, n->kids[i]);
        bool t = vec_truthy(c);
        vec_release(c);
        if (t) return eval(ev, n->kids[i + 1]);
    }
    return n->a ? eval(ev, n->a) : NULL;
}

/* ====================================================================
 * Modules (§4.13)
 * ==================================================================== */

/* AST_IMPORT: import names from a, then the body b. */
__attribute__((noinline)) static Vec *eval_import(Eval *ev, const AstNode *n)
{
    Vec *file = eval(ev, n->a);
    Buf name = BUF_INIT, path = BUF_INIT;
    fmt_str(&name, file, ev->symtab);
    vec_release(file);
    const char *s = buf_cstr(&name);
    if (s[0] == '/') buf_puts(&path, s);
    else buf_printf(&path, "%s/%s", eval_script_dir(ev), s);
    Vec *small[8];
    Vec **vals = n->nnames > 8 ? malloc(n->nnames * sizeof(Vec *)) : small;
    if (!vals) mem_oom();
    if (ev->modules && ev->depth > MAX_IMPORT_DEPTH) {
        /* loading a module recurses too (resolve, up to AST_MAX_DEPTH):
         * keep that headroom on the C stack */
        for (uint32_t i = 0; i < n->nnames; i++) vals[i] = NULL;
        errorf(ev, "Unable to import from '%s': nested too deeply", buf_cstr(&path));
    } else if (ev->modules) {
        module_import(ev->modules, ev, buf_cstr(&path), n->names, n->nnames, vals);
    } else {
        for (uint32_t i = 0; i < n->nnames; i++) vals[i] = NULL;
        errorf(ev, "Unable to import from '%s'", buf_cstr(&path));
    }
    for (uint32_t i = 0; i < n->nnames; i++) set_slot(ev, n->slots[i], vals[i]);
    if (vals != small) free(vals);
    buf_free(&name);
    buf_free(&path);
    return eval(ev, n->b);
}

/* Append [name] = [value] (both retained) to [out]: a simplifier export. */
static void export_one(Exports *out, const Str *name, Vec *value)
{
    if (out->count == out->cap) {
        out->cap = out->cap ? out->cap * 2 : 16;
        out->names = realloc(out->names, out->cap * sizeof(Str *));
        out->values = realloc(out->values, out->cap * sizeof(Vec *));
        if (!out->names || !out->values) mem_oom();
    }
    out->names[out->count] = str_retain((Str *)name);
    out->values[out->count] = vec_retain(value);
    out->count++;
}

/* AST_EXPORT: in a module, record every top-level name's value (first the
 * names the simplifier bound to literals: kids `name=literal`). */
static void eval_export(Eval *ev, const AstNode *n)
{
    const ExportInfo *x = n->aux;
    Exports *out = ev->exports;
    if (!out || !x) return;
    for (uint32_t i = 0; i < n->nkids; i++) export_one(out, n->kids[i]->names[0], n->kids[i]->a->value);
    for (uint32_t i = 0; i < x->count; i++) {
        if (out->count == out->cap) {
            out->cap = out->cap ? out->cap * 2 : 16;
            out->names = realloc(out->names, out->cap * sizeof(Str *));
            out->values = realloc(out->values, out->cap * sizeof(Vec *));
            if (!out->names || !out->values) mem_oom();
        }
        out->names[out->count] = str_retain((Str *)x->names[i]);
        out->values[out->count] = vec_retain(ev->frame[x->slots[i]]);
        out->count++;
    }
}

/* ====================================================================
 * Dispatch
 * ==================================================================== */

Vec *eval_expr(Eval *ev, const AstNode *n) { return eval(ev, n); }

Vec *eval_node(Eval *ev, const AstNode *n)
{
    if (++ev->depth > MAX_EVAL_DEPTH) {
        ev->depth--;
        ev->overflow = true;
        eval_error(ev, "Stack overflow in program");
        return NULL;
    }
    Vec *r = NULL, *a, *b;
    switch ((AstKind)n->kind) {
    case AST_LITERAL:
    case AST_NAME:
        r = eval(ev, n);
        break;
    case AST_LOOKUP:
        a = eval(ev, n->a);
        r = ev->state ? vec_share(state_get(ev->state, a)) : NULL;
        vec_release(a);
        break;
    case AST_BINOP: r = eval_binop(ev, n); break;
    case AST_NEG:
        a = eval(ev, n->a);
        r = vec_neg(a);
        vec_release(a);
        break;
    case AST_POS:
        a = eval(ev, n->a);
        r = vec_pos(a);
        vec_release(a);
        break;
    case AST_NOT:
        a = eval(ev, n->a);
        r = vec_num1(!vec_truthy(a));
        vec_release(a);
        break;
    case AST_AND:
        a = eval(ev, n->a);
        if (!vec_truthy(a)) { r = a; break; }
        vec_release(a);
        r = eval(ev, n->b);
        break;
    case AST_OR:
        a = eval(ev, n->a);
        if (vec_truthy(a)) { r = a; break; }
        vec_release(a);
        r = eval(ev, n->b);
        break;
    case AST_XOR:
        a = eval(ev, n->a);
        b = eval(ev, n->b);
        if (!vec_truthy(a)) { r = b; vec_release(a); }
        else if (vec_truthy(b)) { r = vec_num1(0.0); vec_release(a); vec_release(b); }
        else { r = a; vec_release(b); }
        break;
    case AST_COMPARE: r = eval_compare(ev, n); break;
    case AST_RANGE: r = eval_range(ev, n); break;
    case AST_INDEX:
        a = eval(ev, n->a);
        b = eval(ev, n->b);
        r = vec_index(a, b, ast_index_is_range(n->b));
        vec_release(a);
        vec_release(b);
        break;
    case AST_CALL: r = eval_call(ev, n); break;
    case AST_FUNCTION: r = eval_function(ev, n); break;
    case AST_LET: r = eval_let(ev, n); break;
    case AST_FOR: r = eval_for(ev, n); break;
    case AST_IFELSE: r = eval_ifelse(ev, n); break;
    case AST_TAG: r = eval_tag(ev, n); break;
    case AST_ATTRIBUTES: r = eval_attributes(ev, n); break;
    case AST_APPEND: r = eval_append(ev, n); break;
    case AST_SEQUENCE: r = eval_sequence(ev, n); break;
    case AST_TOP: r = eval(ev, n->a); break;
    case AST_IMPORT: r = eval_import(ev, n); break;
    case AST_INCLUDE:
        if (n->b) r = eval(ev, n->b);
        else if (!n->op && n->a && n->a->value)
            eval_error(ev, "Dynamic include detected; is simplifier disabled?");
        break;
    case AST_EXPORT: eval_export(ev, n); break;
    case AST_BINDING:
    case AST__COUNT:
        break;
    }
    ev->depth--;
    return r;
}

Vec *eval_program_value(Eval *ev)
{
    Program *prog = ev->prog;
    size_t frame_size = (prog->nslots ? prog->nslots : 1) * sizeof(Vec *);
    Vec **frame = pool_calloc(frame_size);
    Vec **saved = ev->frame;
    ev->frame = frame;
    ev->overflow = false;
    Vec *v = eval(ev, prog->top);
    /* a refusal of the memory budget that no expression reported (a
     * builtin's or a composition's inside compiled code) is still said */
    if (mem_take_refusal()) eval_error(ev, MEM_OOM_MESSAGE);
    ev->frame = saved;
    for (uint32_t i = 0; i < prog->nslots; i++) vec_release(frame[i]);
    pool_release(frame, frame_size);
    if (ev->overflow) {
        vec_release(v);
        return NULL;
    }
    return v;
}

Node *eval_program(Eval *ev)
{
    Str *kind = str_from("root");
    Node *root = node_new(kind);
    str_release(kind);
    Vec *v = eval_program_value(ev);
    if (vec_is_obj(v)) {
        const Elem *e = vec_celems(v);
        for (uint32_t i = 0; i < v->len; i++)
            if (e[i].kind == EL_NODE) node_append(root, e[i].node);
    }
    vec_release(v);
    return root;
}
