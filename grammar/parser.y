/* parser.y: the Flitter grammar (LANGUAGE.md §2.1-§2.3) and its trees
 * (§2.4, shapes in lib/syntax/ast.h).
 *
 * A pure LALR(1) parser fed by parse_lex() (lib/syntax/parse.c: the re2c lexer
 * followed by the indentation filter). Every action is one call to a
 * builder of lib/syntax/ast.c; there is no mid-rule action and no evaluation here.
 * The expression grammar is written as one nonterminal per precedence level
 * (§2.2) rather than with %left/%right, so associativity and the syntax
 * errors it implies (`2**-1`, `a < b < c`) fall out of the productions.
 *
 * Contextual keywords (§1.7, option (b)): the lexer always returns keyword
 * tokens, and the `name*` nonterminals at the end accept keywords as names
 * where the reference's contextual lexer would see a NAME:
 *   name       any keyword: after `let` continuation lines, `where`,
 *              `import`, `for`, in parameter lists, after ';' in name lists
 *   name_let   first name after `let`: all but `stable`
 *   name_next  a name right after an operand (attribute names, further
 *              bindings on a `let`/`where` line): all but the keywords that
 *              can continue an expression (in where or xor and for if else);
 *              right after a `#tag` those name attributes too (kw_operator)
 *   name_arg   named arguments: all but `func` and `not`, which can start
 *              an argument expression
 *   name_atom  names read as values: `stable from in where or xor and
 *              elif else` (`elif`/`else` stay keywords right after an `if`
 *              block). The reference would also read `let import for if
 *              func not` as names in operand positions (`x + let`);
 *              accepting them here would make LALR(1) conflicts with the
 *              statements they start, so such variables can be bound but
 *              not read back (rare).
 */

%require "3.6"
%define api.pure full
/* flp_parse, FLP_STYPE, flp_lex...: no yy* names in the library, where they
 * would clash with an embedding program's own parser */
%define api.prefix {flp_}
%define api.token.prefix {TK_}
%define api.location.type {Loc}
%define parse.error custom
%define parse.lac full
%expect 0
%locations
%param {ParseCtx *pc}
%parse-param {AstNode **out}

%code requires {
#include "ast.h"

/* The parser driver's state (lib/syntax/parse.c). */
typedef struct ParseCtx ParseCtx;
}

%code provides {
/* Hooks between the generated parser and its driver (lib/syntax/parse.c). */

/* The next token for the parser: its kind, semantic value and span.
 *   errors: a lexical or indentation error is reported into [pc] and
 *           TK_FLP_error returned (the parser then stops). */
int parse_lex(FLP_STYPE *value, Loc *loc, ParseCtx *pc);
/* Report a syntax error at [loc]: the unexpected token's name and up to
 * [nexpected] names of tokens that would have been accepted (0: too many
 * to list). */
void parse_syntax_error(ParseCtx *pc, Loc loc, const char *unexpected,
                        const char *const *expected, int nexpected);
/* Report a parser failure that is not a syntax error ("memory exhausted"). */
void parse_failure(ParseCtx *pc, Loc loc, const char *msg);
/* The location before the first token (empty, offset 0, [pc]'s file). */
Loc parse_start(ParseCtx *pc);
}

%code {
#define flp_lex parse_lex
#define flp_error(loc, pc, out, msg) ((void)(out), parse_failure((pc), *(loc), (msg)))

/* A span from the first to the last symbol; empty rules sit at the end of
 * the previous symbol. */
#define YYLLOC_DEFAULT(Cur, Rhs, N)                                  \
    do {                                                             \
        if (N) {                                                     \
            (Cur).file = YYRHSLOC(Rhs, 1).file;                      \
            (Cur).start = YYRHSLOC(Rhs, 1).start;                    \
            (Cur).end = YYRHSLOC(Rhs, N).end;                        \
        } else {                                                     \
            (Cur).file = YYRHSLOC(Rhs, 0).file;                      \
            (Cur).start = (Cur).end = YYRHSLOC(Rhs, 0).end;          \
        }                                                            \
    } while (0)
}

%initial-action { @$ = parse_start(pc); }

%union {
    AstNode *node;   /* a subtree or a holder list */
    Str *str;        /* a name */
    Vec *vec;        /* a literal's value */
}

%destructor { ast_free($$); } <node>
%destructor { str_release($$); } <str>
%destructor { vec_release($$); } <vec>

%token <str> NAME "name"
%token <str> TAG "tag"
%token <vec> NUMBER "number"
%token <vec> TIMECODE "time code"
%token <vec> STRING "string"
%token <vec> SYMBOL "symbol"
%token <vec> NODE "node literal"
%token HASHBANG "'#!' line"
%token NL "newline"
%token INDENT "indent"
%token DEDENT "dedent"
%token END "end of input"
%token LPAREN "'('" RPAREN "')'" LBRACKET "'['" RBRACKET "']'"
%token SEMI "';'" COMMA "','" ASSIGN "'='" PIPE "'|'" DOLLAR "'$'" AT "'@'"
%token DOTDOT "'..'" APPEND "'<<'"
%token PLUS "'+'" MINUS "'-'" STAR "'*'" SLASH "'/'" DSLASH "'//'"
%token PERCENT "'%'" POW "'**'"
%token EQ "'=='" NE "'!='" LT "'<'" GT "'>'" LE "'<='" GE "'>='"
%token LET "'let'" STABLE "'stable'" FUNC "'func'" IMPORT "'import'"
%token FROM "'from'" FOR "'for'" IN "'in'" IF "'if'" ELIF "'elif'"
%token ELSE "'else'" WHERE "'where'" OR "'or'" XOR "'xor'" AND "'and'"
%token NOT "'not'" PRAGMA "'%pragma'" INCLUDE "'%include'"

/* Three deliberate ambiguities, all resolved as the reference's LALR parser
 * (which shifts) resolves them. After an attribute binding or a `where`
 * binding, a following `name=` could start another binding of the same
 * group or close the group; shifting keeps it in the group: `!a x=1 y=2`
 * is one Attributes node, and in `!a x=p where p=1 y=2` the `y=2` is a
 * second `where` binding. After an `if` block, `elif`/`else` continue the
 * `if` rather than start a statement reading a variable named so. GROUP_END
 * is the precedence of closing the group; the tokens that can continue it
 * bind tighter. (Without the two %precedence lines bison reports 18
 * shift/reduce conflicts, all of these three kinds; check with
 * `bison --report=all` that only rules `statement: if_chain`,
 * `node: attr_node` and `comprehension: comprehension WHERE ...` are
 * resolved by precedence after any grammar change.) */
%precedence GROUP_END
%precedence NAME STABLE FROM LET IMPORT ELIF FUNC NOT ELSE

%type <node> pragmas pragma sequence items let_head statement
%type <node> let_bindings stable_bindings let_line binding_line binding_lines
%type <node> binding_let binding_any binding_next names names_let names_next
%type <node> if_chain iterators iterator tattrs tag_attr_binding
%type <node> inline_append node attr_node attr_binding composition comp_list
%type <node> anonymous comprehension where_bindings where_first where_next
%type <node> conditional or_expr and_expr not_expr comparison range sum
%type <node> product unary power call args pos_args named_args named_arg
%type <node> atom literal params param_list param
%type <str> name name_let name_next name_arg name_atom
%type <str> kw_stable kw_from kw_infix kw_loop kw_stmt kw_prefix kw_operator

%start top

%%

/* {=====================================================================
 * Programs, sequences and block statements (§2.1 top .. statement)
 * ===================================================================== */

/* top -> HASHBANG? NL? pragma* NL? sequence
 * (the second NL? cannot occur here: a pragma's NL token already holds all
 * the blank and comment lines after it) */
top
    : opt_hashbang opt_nl pragmas sequence  { *out = ast_top($pragmas, $sequence, @$); }
    ;

opt_hashbang
    : %empty
    | HASHBANG
    ;

opt_nl
    : %empty
    | NL
    ;

/* pragma* */
pragmas
    : %empty          { $$ = ast_list(AST_TOP, NULL, @$); }
    | pragmas pragma  { $$ = ast_add($1, $2, @$); }
    ;

/* pragma -> "%pragma" NAME literal NL */
pragma
    : PRAGMA name literal NL  { $$ = ast_pragma($name, $literal, @$); }
    ;

/* sequence -> statement* let_tail?
 * let_tail -> "let" bindings_ml sequence
 *           | "let" "stable" bindings_ml sequence
 *           | "let" name_list "=" NL INDENT sequence DEDENT sequence
 *           | "func" "(" params ")" NL INDENT sequence DEDENT sequence
 *           | "func" NAME "(" params ")" NL INDENT sequence DEDENT sequence
 *           | "import" name_list "from" composition NL sequence
 * Each let_tail ends with the rest of its sequence, so the sequence is read
 * flat here, as (statement | let_head)*, where a let_head is a let_tail
 * without its trailing sequence; ast_sequence() then gives every head the
 * items after it as its body. Written right-recursively, every `let` line
 * kept parser stack entries until the end of the block, so a flat script of
 * 3,332 `let` lines or 1,000 `func`s overflowed the stack (issue 28). */
sequence
    : items  { $$ = ast_sequence($1, @$); }
    ;

items
    : %empty           { $$ = ast_list(AST_SEQUENCE, NULL, @$); }
    | items statement  { $$ = ast_add($1, $2, @$); }
    | items let_head   { $$ = ast_add($1, $2, @$); }
    ;

let_head
    : LET let_bindings
        { $$ = ast_head_let($let_bindings, 0, @$); }
    | LET STABLE stable_bindings
        { $$ = ast_head_let($stable_bindings, 1, @$); }
    | LET names_let ASSIGN NL INDENT sequence[block] DEDENT
        { $$ = ast_head_let_block($names_let, $block, @$); }
    | FUNC LPAREN params RPAREN NL INDENT sequence[body] DEDENT
        { $$ = ast_head_anon($params, $body, @$); }
    | FUNC name LPAREN params RPAREN NL INDENT sequence[body] DEDENT
        { $$ = ast_head_func($name, $params, $body, @$); }
    | IMPORT names FROM composition NL
        { $$ = ast_head_import($names, $composition, @$); }
    ;

/* bindings_ml -> binding+ NL ( INDENT ( binding+ NL )+ DEDENT )?
 * The first binding after `let` uses name_let, after `let stable` any name;
 * continuation lines start with any name. */
let_bindings
    : let_line NL                              { $$ = $1; }
    | let_line NL INDENT binding_lines DEDENT  { $$ = ast_concat($1, $4, @$); }
    ;

stable_bindings
    : binding_line NL                              { $$ = $1; }
    | binding_line NL INDENT binding_lines DEDENT  { $$ = ast_concat($1, $4, @$); }
    ;

let_line
    : binding_let                { $$ = ast_list(AST_LET, $1, @$); }
    | let_line binding_next      { $$ = ast_add($1, $2, @$); }
    ;

binding_line
    : binding_any                { $$ = ast_list(AST_LET, $1, @$); }
    | binding_line binding_next  { $$ = ast_add($1, $2, @$); }
    ;

binding_lines
    : binding_line NL                { $$ = $1; }
    | binding_lines binding_line NL  { $$ = ast_concat($1, $2, @$); }
    ;

/* binding -> name_list "=" composition */
binding_let
    : names_let ASSIGN composition   { $$ = ast_binding($1, $3, @$); }
    ;

binding_any
    : names ASSIGN composition       { $$ = ast_binding($1, $3, @$); }
    ;

binding_next
    : names_next ASSIGN composition  { $$ = ast_binding($1, $3, @$); }
    ;

/* name_list -> NAME ( ";" NAME )* */
names
    : name             { $$ = ast_names($1, @$); }
    | names SEMI name  { $$ = ast_names_add($1, $3, @$); }
    ;

names_let
    : name_let             { $$ = ast_names($1, @$); }
    | names_let SEMI name  { $$ = ast_names_add($1, $3, @$); }
    ;

names_next
    : name_next             { $$ = ast_names($1, @$); }
    | names_next SEMI name  { $$ = ast_names_add($1, $3, @$); }
    ;

/* statement -> node NL
 *            | node "<<" NL? statement
 *            | node NL INDENT sequence DEDENT
 *            | "@" atom attr_binding* NL ( INDENT sequence DEDENT )?
 *            | "for" iterator ( "," iterator )* NL INDENT sequence DEDENT
 *            | "if" cond_block ( "elif" cond_block )* ( "else" NL INDENT sequence DEDENT )?
 *            | "%include" composition NL
 *            | EOF */
statement
    : node NL                                 { $$ = $1; }
    | node APPEND opt_nl statement            { $$ = ast_binary(AST_APPEND, 0, $1, $4, @$); }
    | node NL INDENT sequence DEDENT          { $$ = ast_binary(AST_APPEND, 0, $1, $4, @$); }
    | AT atom tattrs NL                       { $$ = ast_template($atom, $tattrs, NULL, @$); }
    | AT atom tattrs NL INDENT sequence DEDENT
        { $$ = ast_template($atom, $tattrs, $sequence, @$); }
    | FOR iterators NL INDENT sequence DEDENT { $$ = ast_for_nest($iterators, $sequence, @$); }
    | if_chain %prec GROUP_END                { $$ = $1; }
    | if_chain ELSE NL INDENT sequence DEDENT { $$ = ast_else($if_chain, $sequence, @$); }
    | INCLUDE composition NL                  { $$ = ast_unary(AST_INCLUDE, $2, @$); }
    | END                                     { $$ = ast_new(AST_EXPORT, @1); }
    ;

/* cond_block -> composition NL INDENT sequence DEDENT */
if_chain
    : IF composition NL INDENT sequence DEDENT
        { $$ = ast_ifelse($composition, $sequence, NULL, @$); }
    | if_chain ELIF composition NL INDENT sequence DEDENT
        { $$ = ast_elif($1, $composition, $sequence, @$); }
    ;

/* iterator -> name_list "in" composition */
iterators
    : iterator                  { $$ = ast_list(AST_SEQUENCE, $1, @$); }
    | iterators COMMA iterator  { $$ = ast_add($1, $3, @$); }
    ;

iterator
    : names IN composition  { $$ = ast_for($names, $composition, NULL, @$); }
    ;

/* attr_binding* of a template call */
tattrs
    : %empty               { $$ = ast_list(AST_CALL, NULL, @$); }
    | tattrs attr_binding  { $$ = ast_add($1, $2, @$); }
    ;

/* }===================================================================== */

/* {=====================================================================
 * Node expressions and compositions (§2.2 levels 1-5)
 * ===================================================================== */

/* inline_append -> node | node "<<" inline_append */
inline_append
    : node
    | node APPEND inline_append  { $$ = ast_binary(AST_APPEND, 0, $1, $3, @$); }
    ;

/* node -> composition | node TAG | node attr_binding+
 * Consecutive attribute bindings form one group (one Attributes node); a
 * tag or parentheses in between start a new, nesting group. Nothing can
 * follow a tag as an operator, so right after one even `in`, `for`, `if`,
 * `else`, `where`, `and`, `or`, `xor` name an attribute (as in the
 * reference). */
node
    : composition
    | node TAG                   { $$ = ast_tag($1, $2, @$); }
    | attr_node %prec GROUP_END
    ;

attr_node
    : node attr_binding           { $$ = ast_attributes($1, $2, @$); }
    | node TAG tag_attr_binding   { $$ = ast_attributes(ast_tag($1, $2, @$), $3, @$); }
    | attr_node attr_binding      { $$ = ast_add($1, $2, @$); }
    ;

/* attr_binding -> NAME "=" composition */
attr_binding
    : name_next ASSIGN composition  { $$ = ast_named($1, $3, @$); }
    ;

tag_attr_binding
    : kw_operator ASSIGN composition  { $$ = ast_named($1, $3, @$); }
    ;

/* composition -> anonymous ( ";" anonymous )* */
composition
    : anonymous
    | comp_list
    ;

comp_list
    : anonymous SEMI anonymous  { $$ = ast_add(ast_list(AST_SEQUENCE, $1, @1), $3, @$); }
    | comp_list SEMI anonymous  { $$ = ast_add($1, $3, @$); }
    ;

/* anonymous -> comprehension | "func" "(" params ")" anonymous */
anonymous
    : comprehension
    | FUNC LPAREN params RPAREN anonymous  { $$ = ast_function(NULL, $params, $5, @$); }
    ;

/* comprehension -> conditional
 *                | comprehension "for" name_list "in" conditional
 *                | comprehension "where" ( name_list "=" conditional )+ */
comprehension
    : conditional
    | comprehension FOR names IN conditional  { $$ = ast_for($names, $5, $1, @$); }
    | comprehension WHERE where_bindings %prec GROUP_END
        { $$ = ast_let($where_bindings, $1, 0, @$); }
    ;

where_bindings
    : where_first                 { $$ = ast_list(AST_LET, $1, @$); }
    | where_bindings where_next   { $$ = ast_add($1, $2, @$); }
    ;

where_first
    : names ASSIGN conditional       { $$ = ast_binding($1, $3, @$); }
    ;

where_next
    : names_next ASSIGN conditional  { $$ = ast_binding($1, $3, @$); }
    ;

/* }===================================================================== */

/* {=====================================================================
 * Operators (§2.2 levels 6-17)
 * ===================================================================== */

/* conditional -> or_expr | or_expr "if" or_expr ( "else" conditional )? */
conditional
    : or_expr
    | or_expr[then] IF or_expr[cond]
        { $$ = ast_ifelse($cond, $then, NULL, @$); }
    | or_expr[then] IF or_expr[cond] ELSE conditional[else]
        { $$ = ast_ifelse($cond, $then, $else, @$); }
    ;

/* or_expr -> and_expr | or_expr "or" and_expr | or_expr "xor" and_expr */
or_expr
    : and_expr
    | or_expr OR and_expr   { $$ = ast_binary(AST_OR, 0, $1, $3, @$); }
    | or_expr XOR and_expr  { $$ = ast_binary(AST_XOR, 0, $1, $3, @$); }
    ;

/* and_expr -> not_expr | and_expr "and" not_expr */
and_expr
    : not_expr
    | and_expr AND not_expr  { $$ = ast_binary(AST_AND, 0, $1, $3, @$); }
    ;

/* not_expr -> comparison | "not" not_expr */
not_expr
    : comparison
    | NOT not_expr  { $$ = ast_unary(AST_NOT, $2, @$); }
    ;

/* comparison -> range | range CMP range   (non-associative) */
comparison
    : range
    | range EQ range  { $$ = ast_binary(AST_COMPARE, CMP_EQ, $1, $3, @$); }
    | range NE range  { $$ = ast_binary(AST_COMPARE, CMP_NE, $1, $3, @$); }
    | range LT range  { $$ = ast_binary(AST_COMPARE, CMP_LT, $1, $3, @$); }
    | range GT range  { $$ = ast_binary(AST_COMPARE, CMP_GT, $1, $3, @$); }
    | range LE range  { $$ = ast_binary(AST_COMPARE, CMP_LE, $1, $3, @$); }
    | range GE range  { $$ = ast_binary(AST_COMPARE, CMP_GE, $1, $3, @$); }
    | range IN range  { $$ = ast_binary(AST_COMPARE, CMP_IN, $1, $3, @$); }
    ;

/* range -> sum | sum? ".." sum ( "|" sum )? */
range
    : sum
    | DOTDOT sum[stop]                         { $$ = ast_range(NULL, $stop, NULL, @$); }
    | sum[start] DOTDOT sum[stop]              { $$ = ast_range($start, $stop, NULL, @$); }
    | DOTDOT sum[stop] PIPE sum[step]          { $$ = ast_range(NULL, $stop, $step, @$); }
    | sum[start] DOTDOT sum[stop] PIPE sum[step]
        { $$ = ast_range($start, $stop, $step, @$); }
    ;

/* sum -> product | sum ("+"|"-") product */
sum
    : product
    | sum PLUS product   { $$ = ast_binary(AST_BINOP, OP_ADD, $1, $3, @$); }
    | sum MINUS product  { $$ = ast_binary(AST_BINOP, OP_SUB, $1, $3, @$); }
    ;

/* product -> unary | product ("*"|"/"|"//"|"%") unary */
product
    : unary
    | product STAR unary     { $$ = ast_binary(AST_BINOP, OP_MUL, $1, $3, @$); }
    | product SLASH unary    { $$ = ast_binary(AST_BINOP, OP_DIV, $1, $3, @$); }
    | product DSLASH unary   { $$ = ast_binary(AST_BINOP, OP_FLOORDIV, $1, $3, @$); }
    | product PERCENT unary  { $$ = ast_binary(AST_BINOP, OP_MOD, $1, $3, @$); }
    ;

/* unary -> power | "-" unary | "+" unary */
unary
    : power
    | MINUS unary  { $$ = ast_unary(AST_NEG, $2, @$); }
    | PLUS unary   { $$ = ast_unary(AST_POS, $2, @$); }
    ;

/* power -> call | power "**" call   (left-associative; no unary operand) */
power
    : call
    | power POW call  { $$ = ast_binary(AST_BINOP, OP_POW, $1, $3, @$); }
    ;

/* call -> atom | call "(" args ")" | call "[" inline_append "]" */
call
    : atom
    | call LPAREN args RPAREN              { $$ = ast_call($1, $args, @$); }
    | call LBRACKET inline_append RBRACKET { $$ = ast_binary(AST_INDEX, 0, $1, $3, @$); }
    ;

/* args -> inline_append ( "," inline_append )* ( "," named_arg )*
 *       | ( named_arg ( "," named_arg )* )? */
args
    : %empty                        { $$ = ast_list(AST_CALL, NULL, @$); }
    | pos_args
    | pos_args COMMA named_args     { $$ = ast_concat($1, $3, @$); }
    | named_args
    ;

pos_args
    : inline_append                 { $$ = ast_list(AST_CALL, $1, @$); }
    | pos_args COMMA inline_append  { $$ = ast_add($1, $3, @$); }
    ;

named_args
    : named_arg                     { $$ = ast_list(AST_CALL, $1, @$); }
    | named_args COMMA named_arg    { $$ = ast_add($1, $3, @$); }
    ;

/* named_arg -> NAME "=" inline_append */
named_arg
    : name_arg ASSIGN inline_append  { $$ = ast_named($1, $3, @$); }
    ;

/* atom -> literal | NAME | "$" atom | "(" inline_append ")" */
atom
    : literal
    | name_atom                    { $$ = ast_name($1, @1); }
    | DOLLAR atom                  { $$ = ast_unary(AST_LOOKUP, $2, @$); }
    | LPAREN inline_append RPAREN  { $$ = $2; }
    ;

/* literal -> NUMBER | TIMECODE | STRING | SYMBOL | NODE */
literal
    : NUMBER    { $$ = ast_literal_number($1, @1); }
    | TIMECODE  { $$ = ast_literal_number($1, @1); }
    | SYMBOL    { $$ = ast_literal_number($1, @1); }
    | STRING    { $$ = ast_literal($1, @1); }
    | NODE      { $$ = ast_literal($1, @1); }
    ;

/* params -> ( param ( "," param )* )? */
params
    : %empty
        { $$ = ast_list(AST_FUNCTION, NULL, @$); }
    | param_list
    ;

param_list
    : param                   { $$ = ast_list(AST_FUNCTION, $1, @$); }
    | param_list COMMA param  { $$ = ast_add($1, $3, @$); }
    ;

/* param -> NAME ( "=" node )? */
param
    : name              { $$ = ast_param($1, NULL, @$); }
    | name ASSIGN node  { $$ = ast_param($1, $3, @$); }
    ;

/* }===================================================================== */

/* {=====================================================================
 * Names: keywords accepted as names (§1.7, see the header comment)
 * ===================================================================== */

name
    : NAME | kw_stable | kw_from | kw_infix | kw_loop | kw_stmt | kw_prefix
    ;

name_let
    : NAME | kw_from | kw_infix | kw_loop | kw_stmt | kw_prefix
    ;

name_next
    : NAME | kw_stable | kw_from | kw_stmt | kw_prefix
    ;

name_arg
    : NAME | kw_stable | kw_from | kw_infix | kw_loop | kw_stmt
    ;

name_atom
    : NAME | kw_stable | kw_from | kw_infix | ELIF { $$ = str_from("elif"); }
    | ELSE { $$ = str_from("else"); }
    ;

kw_stable
    : STABLE  { $$ = str_from("stable"); }
    ;

kw_from
    : FROM    { $$ = str_from("from"); }
    ;

kw_infix
    : IN      { $$ = str_from("in"); }
    | WHERE   { $$ = str_from("where"); }
    | OR      { $$ = str_from("or"); }
    | XOR     { $$ = str_from("xor"); }
    | AND     { $$ = str_from("and"); }
    ;

kw_loop
    : FOR     { $$ = str_from("for"); }
    | IF      { $$ = str_from("if"); }
    | ELSE    { $$ = str_from("else"); }
    ;

kw_stmt
    : LET     { $$ = str_from("let"); }
    | IMPORT  { $$ = str_from("import"); }
    | ELIF    { $$ = str_from("elif"); }
    ;

kw_prefix
    : FUNC    { $$ = str_from("func"); }
    | NOT     { $$ = str_from("not"); }
    ;

/* the keywords that can follow an operand */
kw_operator
    : kw_infix | kw_loop
    ;

/* }===================================================================== */

%%

/* Bison's hook for `parse.error custom`: hand the unexpected token and the
 * expected ones to the driver, which formats the message. */
static int yyreport_syntax_error(const yypcontext_t *ctx, ParseCtx *pc, AstNode **out)
{
    enum { MAX_EXPECTED = 5 };
    yysymbol_kind_t kinds[MAX_EXPECTED];
    const char *names[MAX_EXPECTED];
    int n = yypcontext_expected_tokens(ctx, kinds, MAX_EXPECTED);
    for (int i = 0; i < n; i++)
        names[i] = yysymbol_name(kinds[i]);
    (void)out;
    parse_syntax_error(pc, *yypcontext_location(ctx),
                       yysymbol_name(yypcontext_token(ctx)), names, n < 0 ? 0 : n);
    return 0;
}

const char *parse_token_name(int kind)
{
    return yysymbol_name(YYTRANSLATE(kind));
}
