/* ast.h: the abstract syntax tree that the parser builds (LANGUAGE.md §2.4)
 * and the evaluator walks.
 *
 * Every node is an `AstNode`: a kind, a source location, up to three fixed
 * children (`a`, `b`, `c`, meaning per kind), a list of variable children
 * (`kids`), a list of names (`names`) and, for literals, a value. The table
 * below is the contract between grammar/parser.y (which builds trees through
 * the ast_* builders) and lib/eval.c (which reads them).
 *
 *   kind            fields
 *   AST_TOP         kids: AST_BINDING pragmas (names[0], value in `value`);
 *                   a: body (AST_SEQUENCE)
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
    uint8_t pad;
    uint32_t count;       /* AST_CALL: number of positional args */
    Loc loc;              /* source span */
    AstNode *a, *b, *c;   /* fixed children, per kind */
    AstNode **kids;       /* variable children */
    uint32_t nkids, cap_kids;
    Str **names;          /* names bound or used */
    uint32_t nnames, cap_names;
    Vec *value;           /* AST_LITERAL / pragma value (one reference) */
    int32_t slot;         /* resolver: slot of a name or frame size */
    int32_t *slots;       /* resolver: one slot per entry of names[] */
    void *aux;            /* resolver: per-kind extra data (freed by ast_free
                             through aux_free) */
    void (*aux_free)(void *aux);
};

/* A new node of [kind] at [loc] with every other field zero. */
AstNode *ast_new(AstKind kind, Loc loc);
/* Free [n] and everything below it (NULL is a no-op). */
void ast_free(AstNode *n);
/* Append [kid] to n->kids (takes ownership; NULL kids are kept as NULL). */
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

/* The name of [kind] ("Let", "For", ...) for AST dumps and messages. */
const char *ast_kind_name(AstKind kind);

#endif
