/* ast.h: the abstract syntax tree that the parser builds (LANGUAGE.md §2.4)
 * and the evaluator walks.
 *
 * Every node is an `AstNode`: a kind, a source location, up to three fixed
 * children (`a`, `b`, `c`, meaning per kind), a list of variable children
 * (`kids`), a list of names (`names`) and, for literals, a value. The table
 * below is the contract between grammar/parser.y (which builds trees through
 * the ast_* builders) and lib/eval/eval.c (which reads them).
 *
 *   kind            fields
 *   AST_TOP         kids: AST_BINDING pragmas (names[0], value in `value`);
 *                   a: body (AST_SEQUENCE); c: AST_SEQUENCE of AST_LITERAL,
 *                   one per distinct symbol name seen (`value`: 1-element
 *                   string vector holding the name without ':')
 *   AST_SEQUENCE    kids: statements/expressions, composed in order
 *   AST_LITERAL     value: the vector (may be NULL for null); `op` = 1 when
 *                   the literal is a single number written in the source
 *                   (IndexLiteral rule of §3.11)
 *   AST_NAME        names[0]: the name
 *   AST_LOOKUP      a: key expression ($a)
 *   AST_BINOP       op: ArithOp; a, b: operands
 *   AST_NEG, AST_POS, AST_NOT   a: operand
 *   AST_AND, AST_OR, AST_XOR    a, b: operands
 *   AST_COMPARE     op: CmpOp; a, b
 *   AST_RANGE       a: start or NULL, b: stop, c: step or NULL
 *   AST_INDEX       a: source, b: index
 *   AST_CALL        a: callee; kids: positional args then AST_BINDING named
 *                   args; `count`: number of positional args. A template
 *                   call `@f k=v` + block has the block (AST_SEQUENCE) as its
 *                   only positional argument; `op` = 1 marks a template call
 *   AST_FUNCTION    names[0]: function name ("<anon>" when anonymous);
 *                   kids: AST_BINDING params (names[0], a: default or NULL);
 *                   a: body
 *   AST_LET         kids: AST_BINDING (names: one or more for unpacking,
 *                   a: value); a: body (the rest of the block, or the
 *                   expression qualified by `where`); `op` = 1 for
 *                   `let stable`
 *   AST_BINDING     names[0..n-1]; a: value expression (or NULL);
 *                   value: literal value (pragmas)
 *   AST_FOR         names: loop names; a: source; b: body
 *   AST_IFELSE      kids: cond0, then0, cond1, then1, ...; a: else or NULL
 *   AST_TAG         a: node expression; names[0]: tag
 *   AST_ATTRIBUTES  a: node expression; kids: AST_BINDING (names[0], a)
 *   AST_APPEND      a: parent expression; b: children expression
 *   AST_IMPORT      names: imported names; a: file expression; b: body
 *   AST_INCLUDE     a: file expression
 *   AST_EXPORT      (no fields): end of the file
 *
 * Locations are byte offsets into the source file `file` (an index into the
 * program's list of loaded sources; 0 for the main script).
 *
 * The resolver (eval.c) fills the `slot`/`slots`/`scope` fields after
 * parsing; the parser leaves them zero.
 */
#ifndef FL_AST_H
#define FL_AST_H

#include <stdint.h>

#include "value.h"

typedef struct Loc {
    uint32_t file;    /* source index (0: main script) */
    uint32_t start;   /* byte offset of the first character */
    uint32_t end;     /* byte offset just past the last character */
} Loc;

typedef enum {
    AST_TOP, AST_SEQUENCE, AST_LITERAL, AST_NAME, AST_LOOKUP,
    AST_BINOP, AST_NEG, AST_POS, AST_NOT, AST_AND, AST_OR, AST_XOR,
    AST_COMPARE, AST_RANGE, AST_INDEX, AST_CALL, AST_FUNCTION, AST_LET,
    AST_BINDING, AST_FOR, AST_IFELSE, AST_TAG, AST_ATTRIBUTES, AST_APPEND,
    AST_IMPORT, AST_INCLUDE, AST_EXPORT,
    AST__COUNT
} AstKind;

typedef enum { CMP_EQ, CMP_NE, CMP_LT, CMP_GT, CMP_LE, CMP_GE, CMP_IN } CmpOp;

typedef struct AstNode AstNode;

struct AstNode {
    uint8_t kind;         /* AstKind */
    uint8_t op;           /* ArithOp / CmpOp / flag, per kind */
    uint8_t scope;        /* resolver: where a name lives (eval.c) */
    uint8_t fast;         /* 1: aux is a compiled NumExpr (numexpr.h) */
    uint32_t count;       /* AST_CALL: number of positional args */
    Loc loc;              /* source span */
    int32_t slot;         /* resolver: slot of a name or frame size (here,
                             beside the 12-byte Loc, the node is 112 bytes:
                             one pool class, and one 128-byte malloc chunk) */
    AstNode *a, *b, *c;   /* fixed children, per kind */
    AstNode **kids;       /* variable children */
    uint32_t nkids, cap_kids;
    Str **names;          /* names bound or used */
    uint32_t nnames, cap_names;
    Vec *value;           /* AST_LITERAL / pragma value (one reference) */
    int32_t *slots;       /* resolver: one slot per entry of names[] */
    void *aux;            /* resolver: per-kind extra data (freed by ast_free
                             through aux_free) */
    void (*aux_free)(void *aux);
};

/* A new node of [kind] at [loc] with every other field zero. */
AstNode *ast_new(AstKind kind, Loc loc);
/* Free [n] and everything below it (NULL is a no-op). */
void ast_free(AstNode *n);
/* Append [kid] to n->kids (consumes [kid]; NULL kids are kept as NULL). */
void ast_push(AstNode *n, AstNode *kid);
/* Append name [s] to n->names (consumes [s]). */
void ast_push_name(AstNode *n, Str *s);

/* Convenience builders used by the parser; each returns a new node. */
AstNode *ast_literal(Vec *value_take, Loc loc);
AstNode *ast_name(Str *name_take, Loc loc);
AstNode *ast_unary(AstKind kind, AstNode *a, Loc loc);
AstNode *ast_binary(AstKind kind, int op, AstNode *a, AstNode *b, Loc loc);
AstNode *ast_range(AstNode *start, AstNode *stop, AstNode *step, Loc loc);
AstNode *ast_binding(AstNode *names_holder, AstNode *value, Loc loc);

/* Builders used by grammar/parser.y (one per tree shape of LANGUAGE.md §2.4).
 * Every builder consumes its node, Str and Vec arguments, sets the
 * result's location to [loc] and returns the result (never NULL).
 * "holder" nodes are lists the grammar grows before the real node exists. */

/* AST_LITERAL of a single number written in the source (`op` = 1). */
AstNode *ast_literal_number(Vec *value_take, Loc loc);
/* A new list node of [kind] holding [first] as its only kid (no kid when
 * [first] is NULL). */
AstNode *ast_list(AstKind kind, AstNode *first, Loc loc);
/* Append [kid] to [list]'s kids; returns [list]. */
AstNode *ast_add(AstNode *list, AstNode *kid, Loc loc);
/* Move the kids of [more] to the end of [list]'s kids and free [more]. */
AstNode *ast_concat(AstNode *list, AstNode *more, Loc loc);
/* A names holder (AST_BINDING, no value) with the single name [name]. */
AstNode *ast_names(Str *name, Loc loc);
/* Append [name] to the names of [holder]; returns [holder]. */
AstNode *ast_names_add(AstNode *holder, Str *name, Loc loc);
/* AST_BINDING with the single name [name] and value [value]: attribute
 * bindings, named arguments. */
AstNode *ast_named(Str *name, AstNode *value, Loc loc);
/* AST_LET: [bindings] (an AST_LET holder of AST_BINDING kids) scoped over
 * [body]; [stable] != 0 for `let stable`. Also `e where ...`. */
AstNode *ast_let(AstNode *bindings, AstNode *body, int stable, Loc loc);
/* Sequence let `let names =` + BLOCK + rest: AST_LET with one binding
 * [names] = [block], body [rest]. */
AstNode *ast_let_block(AstNode *names, AstNode *block, AstNode *rest, Loc loc);
/* AST_BINDING parameter [name] with default [dflt] (NULL: none). */
AstNode *ast_param(Str *name, AstNode *dflt, Loc loc);
/* AST_FUNCTION named [name] (NULL: "<anon>") from the parameter holder
 * [params] (an AST_FUNCTION whose kids are ast_param nodes) and [body]. */
AstNode *ast_function(Str *name, AstNode *params, AstNode *body, Loc loc);
/* `func name(params)` + BLOCK + rest: AST_LET binding [name] to the
 * function, body [rest]. */
AstNode *ast_func_let(Str *name, AstNode *params, AstNode *body,
                      AstNode *rest, Loc loc);
/* `import names from file` + rest: AST_IMPORT. */
AstNode *ast_import(AstNode *names, AstNode *file, AstNode *rest, Loc loc);
/* AST_FOR over the names of holder [names]; [body] may be NULL while the
 * block-for iterator list is being built. */
AstNode *ast_for(AstNode *names, AstNode *source, AstNode *body, Loc loc);
/* Block `for` with several iterators: [iterators] is an AST_SEQUENCE of
 * body-less AST_FOR nodes; they are nested first-outermost around [body]. */
AstNode *ast_for_nest(AstNode *iterators, AstNode *body, Loc loc);
/* AST_IFELSE with one (cond, then) pair and else branch [els] (or NULL). */
AstNode *ast_ifelse(AstNode *cond, AstNode *then, AstNode *els, Loc loc);
/* Add an `elif` (cond, then) pair to [ifelse]. */
AstNode *ast_elif(AstNode *ifelse, AstNode *cond, AstNode *then, Loc loc);
/* Set the else branch of [ifelse]. */
AstNode *ast_else(AstNode *ifelse, AstNode *els, Loc loc);
/* AST_CALL of [callee]; [args] is an AST_CALL holder whose kids are the
 * positional arguments followed by AST_BINDING named arguments. */
AstNode *ast_call(AstNode *callee, AstNode *args, Loc loc);
/* Template call `@callee k=v` (+ [block], or NULL): AST_CALL with `op` = 1;
 * [attrs] is an AST_CALL holder of AST_BINDING kids. */
AstNode *ast_template(AstNode *callee, AstNode *attrs, AstNode *block, Loc loc);
/* AST_TAG adding [tag] to [node]. */
AstNode *ast_tag(AstNode *node, Str *tag, Loc loc);
/* AST_ATTRIBUTES on [node] with the first binding [binding]; further
 * bindings of the same group are added with ast_add. */
AstNode *ast_attributes(AstNode *node, AstNode *binding, Loc loc);
/* Pragma `%pragma name literal`: AST_BINDING with names[0] = [name] and
 * `value` taken from the AST_LITERAL [literal] (which is freed). */
AstNode *ast_pragma(Str *name, AstNode *literal, Loc loc);
/* The flat form of a sequence (parser.y `sequence`): a `let`,
 * `func` or `import` statement is built as a "head" without the rest of
 * its sequence (the node's `scope` holds its head kind until then);
 * ast_sequence() gives each head the items after it as its body, so that
 * the tree is the one the right-recursive LANGUAGE.md §2.1 rules describe,
 * with the same locations. Consecutive heads that build plain (not
 * stable) AST_LETs are merged into one AST_LET whose bindings run in the
 * same order (the evaluator, resolver and simplifier bind a let's names
 * one after another, exactly as nested lets do), so a flat script of any
 * number of `let` lines or `func`s is one level deep, not one per line. */
AstNode *ast_head_let(AstNode *bindings, int stable, Loc loc);
AstNode *ast_head_let_block(AstNode *names, AstNode *block, Loc loc);
AstNode *ast_head_func(Str *name, AstNode *params, AstNode *body, Loc loc);
AstNode *ast_head_anon(AstNode *params, AstNode *body, Loc loc);
AstNode *ast_head_import(AstNode *names, AstNode *file, Loc loc);
/* The AST_SEQUENCE of the holder [items] (statements and heads, consumed)
 * spanning [loc], every head given its body. */
AstNode *ast_sequence(AstNode *items, Loc loc);
/* AST_TOP from the holder [pragmas] (an AST_TOP whose kids are pragma
 * bindings) and the program [body]; `c` is left for the symbol list. */
AstNode *ast_top(AstNode *pragmas, AstNode *body, Loc loc);

/* The name of [kind] ("Let", "For", ...) for AST dumps and messages. */
const char *ast_kind_name(AstKind kind);

#endif
