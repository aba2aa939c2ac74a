/* lexer.re: the Flitter tokenizer (LANGUAGE.md §1), compiled by
 * `re2c --utf8 -I /usr/share/re2c/stdlib`.
 *
 * One scanning function, lex_next(), holds the whole re2c block: named
 * definitions first (letters, numbers, time codes, the four string forms,
 * newline runs), then the rules. The input is the lexer's own copy of the
 * source with the '\n' of §1.1 appended when missing and a NUL sentinel
 * after it, so re2c runs with YYFILL off; a NUL before the end is an
 * unexpected character. Every rule leaves through finish() (or fail() for
 * a lexical error), which stores the kind and byte span in one place; no
 * rule counts lines (positions are offsets, parse.h maps them).
 *
 * State lives in the `Lexer` struct (lexer.h): cursor, marker, the previous
 * token kind (only used to tell `%include`/`%pragma` from '%' at the start
 * of a statement) and the end of the last real token (where TK_END goes).
 * Keywords are returned as keyword tokens; grammar/parser.y accepts them as
 * names where the reference's contextual lexer would (§1.7, option (b)).
 * Numbers, time codes and strings are converted here (§1.3-§1.5), so a bad
 * underscore or escape is a lexical error at the token.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lexer.h"
#include "utf8.h"

/*!include:re2c "unicode_categories.re" */

/* {=====================================================================
 * Setup and token exits
 * ===================================================================== */

void lex_init(Lexer *lx, const char *text, size_t len)
{
    memset(lx, 0, sizeof *lx);
    bool add_nl = len == 0 || text[len - 1] != '\n';
    lx->len = len + (add_nl ? 1 : 0);
    lx->text = malloc(lx->len + 1);
    if (!lx->text) {
        fputs("flitter: out of memory\n", stderr);
        abort();
    }
    if (len)
        memcpy(lx->text, text, len);
    if (add_nl)
        lx->text[len] = '\n';
    lx->text[lx->len] = '\0';
    lx->cur = (const unsigned char *)lx->text;
    lx->mark = lx->cur;
    lx->prev = TK_FLP_EMPTY;
}

void lex_free(Lexer *lx)
{
    free(lx->text);
    buf_free(&lx->msg);
    memset(lx, 0, sizeof *lx);
}

const char *lex_message(Lexer *lx)
{
    return buf_cstr(&lx->msg);
}

static uint32_t offset(const Lexer *lx, const unsigned char *p)
{
    return (uint32_t)(p - (const unsigned char *)lx->text);
}

/* The single exit for a token of [kind] spanning [tok, cursor). */
static int finish(Lexer *lx, Token *t, int kind, const unsigned char *tok)
{
    t->kind = kind;
    t->start = offset(lx, tok);
    t->end = offset(lx, lx->cur);
    lx->prev = kind;
    if (kind != TK_NL)
        lx->last_end = t->end;
    return kind;
}

/* The exit for a lexical error spanning [tok, cursor): message [what],
 * followed by the quoted token text when [quote] is set. */
static int fail(Lexer *lx, Token *t, const unsigned char *tok,
                const char *what, bool quote)
{
    buf_reset(&lx->msg);
    buf_puts(&lx->msg, what);
    if (quote) {
        buf_puts(&lx->msg, " '");
        buf_add(&lx->msg, (const char *)tok, (size_t)(lx->cur - tok));
        buf_putc(&lx->msg, '\'');
    }
    token_clear(t);
    return finish(lx, t, TK_FLP_error, tok);
}

/* Length of the UTF-8 sequence starting at [p] (1 for a bad byte). */
static size_t utf8_len(const unsigned char *p)
{
    size_t n = *p < 0x80 ? 1 : *p >= 0xf0 ? 4 : *p >= 0xe0 ? 3 : *p >= 0xc0 ? 2 : 1;
    for (size_t i = 1; i < n; i++)
        if ((p[i] & 0xc0) != 0x80)
            return 1;
    return n;
}

/* Error for the character at [tok] that starts no token. */
static int bad_char(Lexer *lx, Token *t, const unsigned char *tok)
{
    char hex[8];
    lx->cur = tok + utf8_len(tok);
    if (lx->cur - tok > 1 || (*tok >= 0x20 && *tok < 0x7f))
        return fail(lx, t, tok, "unexpected character", true);
    snprintf(hex, sizeof hex, "\\x%02x", *tok);
    int kind = fail(lx, t, tok, "unexpected character '", false);
    buf_puts(&lx->msg, hex);
    buf_putc(&lx->msg, '\'');
    return kind;
}

/* }===================================================================== */

/* {=====================================================================
 * Conversions: numbers (§1.3), time codes (§1.4), strings (§1.5)
 * ===================================================================== */

/* Value of NUMBER text [s, s+n): suffix multiplier, underscore check and
 * removal, strtod, one multiplication. False when an underscore is not
 * between two digits. */
static bool convert_number(const char *s, size_t n, double *out)
{
    static const struct { const char *suffix; double mul; } suffixes[] = {
        {"\xc2\xb0", 1.0 / 360}, {"deg", 1.0 / 360}, {"p", 1e-12},
        {"n", 1e-9}, {"u", 1e-6}, {"\xc2\xb5", 1e-6}, {"m", 1e-3},
        {"k", 1e3}, {"M", 1e6}, {"G", 1e9}, {"T", 1e12},
    };
    double mul = 1.0;
    bool scaled = false;
    for (size_t i = 0; i < sizeof suffixes / sizeof suffixes[0]; i++) {
        size_t k = strlen(suffixes[i].suffix);
        if (n > k && memcmp(s + n - k, suffixes[i].suffix, k) == 0) {
            mul = suffixes[i].mul;
            scaled = true;
            n -= k;
            break;
        }
    }
    char *digits = malloc(n + 1);
    if (!digits) {
        fputs("flitter: out of memory\n", stderr);
        abort();
    }
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (s[i] == '_') {
            bool ok = i > 0 && i + 1 < n && s[i - 1] >= '0' && s[i - 1] <= '9'
                      && s[i + 1] >= '0' && s[i + 1] <= '9';
            if (!ok) {
                free(digits);
                return false;
            }
            continue;
        }
        digits[m++] = s[i];
    }
    digits[m] = '\0';
    double x = strtod(digits, NULL);
    free(digits);
    *out = scaled ? x * mul : x;
    return true;
}

/* Value of TIMECODE text [s, s+n) (§1.4): seconds, then + 60*minutes, then
 * + 3600*hours, where 3600*hours is the exact integer rounded once to a
 * double (as Python adds an int to a float). */
static double convert_timecode(const char *s, size_t n)
{
    const char *c1 = memchr(s, ':', n);
    const char *c2 = memchr(c1 + 1, ':', n - (size_t)(c1 + 1 - s));
    const char *sec = c2 ? c2 + 1 : c1 + 1;
    const char *min = c2 ? c1 + 1 : s;
    size_t sl = (size_t)(s + n - sec);
    char *text = malloc(sl + 1);
    if (!text) {
        fputs("flitter: out of memory\n", stderr);
        abort();
    }
    memcpy(text, sec, sl);             /* a copy: strtod must not read on */
    text[sl] = '\0';                   /* into a following "e5" */
    double seconds = strtod(text, NULL);
    free(text);
    int minutes = 0;
    for (const char *p = min; *p != ':'; p++)
        minutes = minutes * 10 + (*p - '0');
    seconds = seconds + (double)(60 * minutes);
    if (c2) {
        /* hours * 3600 as decimal text: hours * 36, then two zeros */
        size_t hl = (size_t)(c1 - s);
        char *prod = malloc(hl + 5);
        if (!prod) {
            fputs("flitter: out of memory\n", stderr);
            abort();
        }
        unsigned carry = 0;
        size_t len = hl + 2;
        for (size_t i = hl; i-- > 0;) {
            unsigned d = (unsigned)(s[i] - '0') * 36 + carry;
            prod[i + 2] = (char)('0' + d % 10);
            carry = d / 10;
        }
        prod[1] = (char)('0' + carry % 10);
        prod[0] = (char)('0' + carry / 10);
        prod[len] = '0';
        prod[len + 1] = '0';
        prod[len + 2] = '\0';
        seconds = seconds + strtod(prod, NULL);
        free(prod);
    }
    return seconds;
}

static int hex_value(unsigned char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/* Decode the body [s, s+n) of a string token with Python's literal rules
 * (§1.5). Line ends are first normalised as Python reads source (CR LF and
 * a lone CR become LF), which makes a raw CR in a one-line string an error
 * and backslash + line end a continuation. Returns NULL and sets *[out], or
 * returns the error message. */
static const char *decode_string(const unsigned char *s, size_t n, bool triple,
                                 Str **out)
{
    Buf b = BUF_INIT;
    size_t i = 0;
    while (i < n) {
        unsigned char c = s[i++];
        if (c == '\r') {
            if (!triple) {
                buf_free(&b);
                return "unterminated string";
            }
            if (i < n && s[i] == '\n')
                i++;
            buf_putc(&b, '\n');
            continue;
        }
        if (c != '\\') {
            buf_putc(&b, (char)c);
            continue;
        }
        c = s[i];                      /* the lexer guarantees i < n */
        int digits = 0, value;
        uint32_t cp = 0;
        switch (c) {
        case '\r':                     /* backslash + line end: continuation */
            i++;
            if (i < n && s[i] == '\n')
                i++;
            continue;
        case '\n': i++; continue;
        case '\\': case '\'': case '"': buf_putc(&b, (char)c); i++; continue;
        case 'a': buf_putc(&b, '\a'); i++; continue;
        case 'b': buf_putc(&b, '\b'); i++; continue;
        case 'f': buf_putc(&b, '\f'); i++; continue;
        case 'n': buf_putc(&b, '\n'); i++; continue;
        case 'r': buf_putc(&b, '\r'); i++; continue;
        case 't': buf_putc(&b, '\t'); i++; continue;
        case 'v': buf_putc(&b, '\v'); i++; continue;
        case 'x': digits = 2; break;
        case 'u': digits = 4; break;
        case 'U': digits = 8; break;
        case 'N':
            buf_free(&b);
            return "unsupported \\N{...} escape in string";
        default:
            if (c >= '0' && c <= '7') {
                for (int k = 0; k < 3 && i < n && s[i] >= '0' && s[i] <= '7'; k++)
                    cp = cp * 8 + (uint32_t)(s[i++] - '0');
                utf8_put(&b, cp);
            } else {
                buf_putc(&b, '\\');    /* unknown escape: kept as written */
            }
            continue;
        }
        i++;
        for (int k = 0; k < digits; k++) {
            if (i >= n || (value = hex_value(s[i])) < 0) {
                buf_free(&b);
                return c == 'x' ? "truncated \\xXX escape in string"
                     : c == 'u' ? "truncated \\uXXXX escape in string"
                                : "truncated \\UXXXXXXXX escape in string";
            }
            cp = cp * 16 + (uint32_t)value;
            i++;
        }
        if (cp > 0x10ffff) {
            buf_free(&b);
            return "illegal Unicode character in \\U escape";
        }
        utf8_put(&b, cp);
    }
    *out = str_new(b.data ? b.data : "", b.len);
    buf_free(&b);
    return NULL;
}

/* }===================================================================== */

/* {=====================================================================
 * Keywords and the scanner
 * ===================================================================== */

bool lex_number_text(const char *s, size_t len, double *out)
{
    Lexer lx;
    Token t = {0}, next = {0};
    lex_init(&lx, s, len);
    int kind = lex_next(&lx, &t);
    bool ok = (kind == TK_NUMBER || kind == TK_TIMECODE) && t.start == 0 && t.end == len;
    if (ok) {
        int after = lex_next(&lx, &next);
        ok = after == TK_NL || after == TK_END;
        token_clear(&next);
    }
    if (ok) *out = t.num;
    token_clear(&t);
    lex_free(&lx);
    return ok;
}

int lex_keyword(const char *s, size_t len)
{
    static const struct { const char *word; int kind; } words[] = {
        {"let", TK_LET}, {"stable", TK_STABLE}, {"func", TK_FUNC},
        {"import", TK_IMPORT}, {"from", TK_FROM}, {"for", TK_FOR},
        {"in", TK_IN}, {"if", TK_IF}, {"elif", TK_ELIF}, {"else", TK_ELSE},
        {"where", TK_WHERE}, {"or", TK_OR}, {"xor", TK_XOR},
        {"and", TK_AND}, {"not", TK_NOT},
    };
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++)
        if (strlen(words[i].word) == len && memcmp(words[i].word, s, len) == 0)
            return words[i].kind;
    return -1;
}

/* True when a statement may start here, so `%include`/`%pragma` are
 * directives rather than '%' followed by a name. */
static bool at_statement_start(const Lexer *lx)
{
    return lx->prev == TK_FLP_EMPTY || lx->prev == TK_NL
        || lx->prev == TK_HASHBANG || lx->prev == TK_APPEND;
}

/* A run of line ends: the indentation is the whitespace after its last
 * '\n' (spaces count 1, tabs 8). */
static int newline(Lexer *lx, Token *t, const unsigned char *tok)
{
    const unsigned char *p = lx->cur;
    uint32_t col = 0;
    while (p[-1] != '\n')
        p--;
    for (; p < lx->cur; p++)
        col += *p == '\t' ? 8 : 1;
    t->indent = col;
    return finish(lx, t, TK_NL, tok);
}

/* A name, keyword, node literal (!), tag (#) or symbol (:). One rule for
 * the four keeps the Unicode letter tables in the DFA once. */
static int word(Lexer *lx, Token *t, const unsigned char *tok)
{
    switch (*tok) {
    case '!': return finish(lx, t, TK_NODE, tok);
    case '#': return finish(lx, t, TK_TAG, tok);
    case ':': return finish(lx, t, TK_SYMBOL, tok);
    default: break;
    }
    int kw = lex_keyword((const char *)tok, (size_t)(lx->cur - tok));
    return finish(lx, t, kw >= 0 ? kw : TK_NAME, tok);
}

/* A string token [tok, cursor) whose quotes are [q] bytes long. */
static int string(Lexer *lx, Token *t, const unsigned char *tok, size_t q)
{
    const char *err = decode_string(tok + q, (size_t)(lx->cur - tok) - 2 * q,
                                    q == 3, &t->str);
    if (err)
        return fail(lx, t, tok, err, false);
    return finish(lx, t, TK_STRING, tok);
}

int lex_next(Lexer *lx, Token *t)
{
    memset(t, 0, sizeof *t);
    if (lx->len >= UINT32_MAX - 1) {
        lx->done = true;
        buf_reset(&lx->msg);
        buf_puts(&lx->msg, "source file too large");
        t->kind = TK_FLP_error;
        return t->kind;
    }
    if (lx->done) {
        t->kind = TK_YYEOF;
        t->start = t->end = lx->last_end;
        return t->kind;
    }
    for (;;) {
        const unsigned char *tok = lx->cur;
        /*!re2c
        re2c:define:YYCTYPE = "unsigned char";
        re2c:define:YYCURSOR = "lx->cur";
        re2c:define:YYMARKER = "lx->mark";
        re2c:yyfill:enable = 0;

        letter   = L | Nl;
        alnum    = letter | Nd;
        word     = (letter | "_") (alnum | "_")* "'"*;

        dig      = [0-9];
        mantissa = dig (dig | "_")* ("." dig (dig | "_")*)? | "." dig (dig | "_")*;
        exponent = [eE] [+-]? dig (dig | "_")*;
        suffix   = [pnumkMGT] | "\u00b5" | "\u00b0" | "deg";   /* µ ° */
        number   = mantissa exponent? suffix?;
        timecode = (dig+ ":")? [0-5]? dig ":" [0-5]? dig ("." dig+)?;

        sq_str   = "'" ([^'\\\n\x00] | "\\" [^\n\x00])* "'";
        dq_str   = "\"" ([^"\\\n\x00] | "\\" [^\n\x00])* "\"";
        tsq_str  = "'''" ("'"{0,2} ([^'\\\x00] | "\\" [^\n\x00]))* "'''";
        tdq_str  = "\"\"\"" ("\""{0,2} ([^"\\\x00] | "\\" [^\n\x00]))* "\"\"\"";

        newlines = (("--" [^\r\n\x00]*)? "\r"? "\n" [\t ]*)+;
        hashbang = "#!" [^\n\x00]* "\n";

        "\x00" {
            if (offset(lx, tok) < lx->len)
                return bad_char(lx, t, tok);
            lx->cur = tok;
            lx->done = true;
            t->kind = TK_END;
            t->start = t->end = lx->last_end;
            return t->kind;
        }
        [ \t]+     { continue; }
        "\\\n"     { continue; }
        newlines   { return newline(lx, t, tok); }
        hashbang   { return finish(lx, t, TK_HASHBANG, tok); }

        "%include" {
            if (at_statement_start(lx))
                return finish(lx, t, TK_INCLUDE, tok);
            lx->cur = tok + 1;
            return finish(lx, t, TK_PERCENT, tok);
        }
        "%pragma" {
            if (at_statement_start(lx))
                return finish(lx, t, TK_PRAGMA, tok);
            lx->cur = tok + 1;
            return finish(lx, t, TK_PERCENT, tok);
        }

        [!#:]? word { return word(lx, t, tok); }

        timecode {
            t->num = convert_timecode((const char *)tok, (size_t)(lx->cur - tok));
            return finish(lx, t, TK_TIMECODE, tok);
        }
        number {
            if (!convert_number((const char *)tok, (size_t)(lx->cur - tok), &t->num))
                return fail(lx, t, tok, "invalid number", true);
            return finish(lx, t, TK_NUMBER, tok);
        }

        tsq_str | tdq_str { return string(lx, t, tok, 3); }
        sq_str | dq_str   { return string(lx, t, tok, 1); }
        ['"]              { return fail(lx, t, tok, "unterminated string", false); }

        "("  { return finish(lx, t, TK_LPAREN, tok); }
        ")"  { return finish(lx, t, TK_RPAREN, tok); }
        "["  { return finish(lx, t, TK_LBRACKET, tok); }
        "]"  { return finish(lx, t, TK_RBRACKET, tok); }
        ";"  { return finish(lx, t, TK_SEMI, tok); }
        ","  { return finish(lx, t, TK_COMMA, tok); }
        "="  { return finish(lx, t, TK_ASSIGN, tok); }
        "|"  { return finish(lx, t, TK_PIPE, tok); }
        "$"  { return finish(lx, t, TK_DOLLAR, tok); }
        "@"  { return finish(lx, t, TK_AT, tok); }
        ".." { return finish(lx, t, TK_DOTDOT, tok); }
        "+"  { return finish(lx, t, TK_PLUS, tok); }
        "-"  { return finish(lx, t, TK_MINUS, tok); }
        "*"  { return finish(lx, t, TK_STAR, tok); }
        "/"  { return finish(lx, t, TK_SLASH, tok); }
        "//" { return finish(lx, t, TK_DSLASH, tok); }
        "%"  { return finish(lx, t, TK_PERCENT, tok); }
        "**" { return finish(lx, t, TK_POW, tok); }
        "==" { return finish(lx, t, TK_EQ, tok); }
        "!=" { return finish(lx, t, TK_NE, tok); }
        "<"  { return finish(lx, t, TK_LT, tok); }
        ">"  { return finish(lx, t, TK_GT, tok); }
        "<=" { return finish(lx, t, TK_LE, tok); }
        ">=" { return finish(lx, t, TK_GE, tok); }
        "<<" { return finish(lx, t, TK_APPEND, tok); }

        *    { return bad_char(lx, t, tok); }
        */
    }
}

/* }===================================================================== */
