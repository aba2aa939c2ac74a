/* indent.c: the indentation filter between the lexer and the grammar
 * (LANGUAGE.md §1.10), the same algorithm as Lark's `Indenter` with a tab
 * length of 8.
 *
 * State: `parens`, the number of '(' not yet closed (newlines inside round
 * parentheses vanish; '[' does not count), and `stack`, the indentation
 * columns of the open blocks, strictly increasing from stack[0] = 0. A
 * newline token at paren depth 0 is passed on and then compared with the
 * top of the stack: deeper pushes one INDENT, shallower pops one DEDENT per
 * block closed and must land exactly on an enclosing column. The column of
 * a line is computed by the lexer (Token.indent: spaces + 8 * tabs, not
 * tab-stop aligned). At TK_END every open block is closed before TK_END is
 * passed on. The output is a FIFO queue, so the filter can be fed a token
 * array in a unit test or pulled one token at a time by the parser driver.
 */
#include "lexer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

void token_clear(Token *t)
{
    str_release(t->str);
    t->str = NULL;
}

void indent_init(Indenter *in)
{
    memset(in, 0, sizeof *in);
    in->cap = 8;
    in->stack = mem_realloc(NULL, in->cap * sizeof *in->stack);
    in->stack[0] = 0;
    in->depth = 1;
}

void indent_free(Indenter *in)
{
    for (size_t i = in->qhead; i < in->qlen; i++)
        token_clear(&in->queue[i]);
    free(in->queue);
    free(in->stack);
    memset(in, 0, sizeof *in);
}

/* Append [t] to the output queue (compacting the consumed prefix first). */
static void enqueue(Indenter *in, const Token *t)
{
    if (in->qhead == in->qlen)
        in->qhead = in->qlen = 0;
    if (in->qlen == in->qcap) {
        if (in->qhead > 0) {
            memmove(in->queue, in->queue + in->qhead,
                    (in->qlen - in->qhead) * sizeof *in->queue);
            in->qlen -= in->qhead;
            in->qhead = 0;
        } else {
            in->qcap = in->qcap ? 2 * in->qcap : 8;
            in->queue = mem_realloc(in->queue, in->qcap * sizeof *in->queue);
        }
    }
    in->queue[in->qlen++] = *t;
}

/* A zero-width layout token of [kind] at byte offset [at]. */
static void enqueue_layout(Indenter *in, int kind, uint32_t at)
{
    Token t = {.kind = kind, .start = at, .end = at};
    enqueue(in, &t);
}

static void push_column(Indenter *in, uint32_t col)
{
    if (in->depth == in->cap) {
        in->cap *= 2;
        in->stack = mem_realloc(in->stack, in->cap * sizeof *in->stack);
    }
    in->stack[in->depth++] = col;
}

bool indent_feed(Indenter *in, Token *t)
{
    switch (t->kind) {
    case TK_NL: {
        if (in->parens > 0)
            return true;                      /* newline inside ( ) */
        uint32_t col = t->indent;
        uint32_t top = in->stack[in->depth - 1];
        if (col > top) {
            enqueue(in, t);
            push_column(in, col);
            enqueue_layout(in, TK_INDENT, t->end);
            return true;
        }
        size_t depth = in->depth;
        while (col < in->stack[depth - 1])
            depth--;
        if (col != in->stack[depth - 1])
            return false;                     /* matches no open block */
        enqueue(in, t);
        for (; in->depth > depth; in->depth--)
            enqueue_layout(in, TK_DEDENT, t->end);
        return true;
    }
    case TK_END:
        for (; in->depth > 1; in->depth--)
            enqueue_layout(in, TK_DEDENT, t->start);
        enqueue(in, t);
        return true;
    case TK_LPAREN:
        in->parens++;
        break;
    case TK_RPAREN:
        if (in->parens > 0)                   /* a stray ')' is the */
            in->parens--;                     /* grammar's error    */
        break;
    default:
        break;
    }
    enqueue(in, t);
    t->str = NULL;
    return true;
}

bool indent_pop(Indenter *in, Token *out)
{
    if (in->qhead == in->qlen)
        return false;
    *out = in->queue[in->qhead++];
    return true;
}
