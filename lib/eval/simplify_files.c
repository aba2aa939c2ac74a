/* simplify_files.c: the simplifier and other files (LANGUAGE.md §4.13,
 * §4.14, §4.17; tree.pyx `Include`, `Import` and `Export._simplify`).
 *
 * `%include` with a literal path splices the file's simplified statements
 * in place. `import` with a literal path simplifies the module on its own
 * (no engine names, as when it runs) and takes the names it ends with bound
 * to literals or inlineable functions as static bindings of the importing
 * program; only the remaining names are imported when the program runs.
 */
#include "simplify_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"
#include "mem.h"
#include "parse.h"

/* ====================================================================
 * Files: %include, import, the end of a file
 * ==================================================================== */

/* Register the symbol literals of a parsed file (AST_TOP.c). */
static void register_symbols(const AstNode *top, SymTab *st)
{
    const AstNode *list = top ? top->c : NULL;
    for (uint32_t i = 0; list && i < list->nkids; i++) {
        const AstNode *k = list->kids[i];
        if (!k || !vec_is_obj(k->value)) continue;
        const Elem *e = &vec_celems(k->value)[0];
        if (e->kind == EL_STR) symtab_add(st, e->str->bytes, e->str->len);
    }
}

static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return strdup(".");
    if (slash == path) return strdup("/");
    return strndup(path, (size_t)(slash - path));
}

AstNode *simp_include(Simp *s, const AstNode *n)
{
    if (s->tg || s->talone) {   /* files read once per copy: not shared by a template pass */
        s->tabort = true;
        return mk_lit(NULL, n->loc);
    }
    AstNode *file = simp(s, n->a);
    if (!is_lit(file)) return ast_unary(AST_INCLUDE, file, n->loc);
    const Vec *v = file->value;
    if (!vec_len(v)) {
        ast_free(file);
        return mk_lit(NULL, n->loc);
    }
    if (!vec_is_obj(v) || v->len != 1 || vec_celems(v)[0].kind != EL_STR)
        return ast_unary(AST_INCLUDE, file, n->loc);
    const Str *name = vec_celems(v)[0].str;
    char *path;
    if (name->bytes[0] == '/') path = strdup(name->bytes);
    else if (asprintf(&path, "%s/%s", s->dir, name->bytes) < 0) path = NULL;
    if (!path) mem_oom();
    for (uint32_t i = 0; i < s->ndeps; i++) {
        if (strcmp(s->deps[i], path) == 0) {
            char msg[600];
            snprintf(msg, sizeof msg, "Cannot include path '%s' multiple times", name->bytes);
            simp_warn(s, msg);
            free(path);
            ast_free(file);
            return mk_lit(NULL, n->loc);
        }
    }
    Buf text = BUF_INIT, err = BUF_INIT;
    AstNode *top = NULL;
    if (file_read_regular(path, &text))
        top = parse_program(path, text.data ? text.data : "", text.len, s->next_file, &err);
    buf_free(&text);
    buf_free(&err);
    if (top && s->files) pathlist_add(s->files, path);
    if (!top) {   /* left for the resolver, which reports it */
        free(path);
        return ast_unary(AST_INCLUDE, file, n->loc);
    }
    s->next_file++;
    register_symbols(top, s->symtab);
    simplify_number_stables(top, s->stable_ids);
    s->deps = realloc(s->deps, (s->ndeps + 1) * sizeof *s->deps);
    if (!s->deps) mem_oom();
    s->deps[s->ndeps++] = path;
    char *saved_dir = s->dir;
    bool saved_inc = s->in_include;
    s->dir = dir_of(path);
    if (!s->dir) mem_oom();
    s->in_include = true;
    AstNode *r = simp(s, top->a);
    free(s->dir);
    s->dir = saved_dir;
    s->in_include = saved_inc;
    ast_free(top);
    ast_free(file);
    return r;
}

/* Simplify the module at [path] on its own and return its static exports
 * through a finished sub-simplifier; false when it cannot be read or
 * parsed (the import is then left to the evaluator, which reports it). */
static bool module_exports(Simp *s, const char *path, Simp *sub)
{
    Buf text = BUF_INIT, err = BUF_INIT;
    AstNode *top = NULL;
    bool read = file_read_regular(path, &text);
    if (read)
        top = parse_program(path, text.data ? text.data : "", text.len, s->next_file, &err);
    buf_free(&text);
    buf_free(&err);
    if (read && s->files) pathlist_add(s->files, path);   /* watched even when it does not parse */
    if (!top) return false;
    s->next_file++;
    register_symbols(top, s->symtab);
    char *dir = dir_of(path);
    if (!dir) mem_oom();
    simp_init(sub, s->symtab, s->warnings, dir, path, s->next_file);
    free(dir);
    sub->ev.interrupt = s->ev.interrupt;
    sub->no_templates = s->no_templates;
    sub->check_templates = s->check_templates;
    if (sub->warnings == s->warnings) simp_share_warnings(sub, s);
    sub->parent = s;
    sub->collect_exports = true;
    sub->is_module = true;
    sub->stable_ids = s->stable_ids;
    sub->stables = s->stables;
    sub->files = s->files;   /* its includes and imports are the program's files too */
    sub->depth = s->depth;   /* the same C stack */
    simplify_number_stables(top, s->stable_ids);
    AstNode *r = simp(sub, top);
    ast_free(r);
    ast_free(top);
    if (sub->too_deep) {   /* no static exports: imported when the program runs */
        simp_fini(sub);
        return false;
    }
    return true;
}

/* import NAMES from FILE, then the rest [n->b]: names the module binds to
 * literals or inlineable functions become bindings of a `let` around the
 * rest; the others stay imported when the program runs. */
AstNode *simp_import(Simp *s, const AstNode *n)
{
    if (s->tg || s->talone) {   /* files read once per copy: not shared by a template pass */
        s->tabort = true;
        return mk_lit(NULL, n->loc);
    }
    AstNode *file = simp(s, n->a);
    Simp sub;
    bool have = false, circular = false;
    const char *name = NULL;
    if (is_lit(file) && vec_is_obj(file->value) && file->value->len == 1 &&
        vec_celems(file->value)[0].kind == EL_STR) {
        name = vec_celems(file->value)[0].str->bytes;
        char *path;
        if (name[0] == '/') path = strdup(name);
        else if (asprintf(&path, "%s/%s", s->dir, name) < 0) path = NULL;
        if (!path) mem_oom();
        for (const Simp *p = s; p && !circular; p = p->parent)
            circular = p->path && strcmp(p->path, path) == 0;
        if (circular) {
            char msg[600];
            snprintf(msg, sizeof msg, "Circular import of '%s'", name);
            simp_warn(s, msg);
        } else {
            have = module_exports(s, path, &sub);
        }
        free(path);
    }
    uint32_t mark = s->nnames;
    AstNode *let = ast_new(AST_LET, n->loc);
    AstNode *imp = ast_new(AST_IMPORT, n->loc);
    for (uint32_t j = 0; j < n->nnames; j++) {
        const Str *nm = n->names[j];
        AstNode *value = NULL;
        if (circular) value = mk_lit(NULL, n->loc);
        for (uint32_t k = have ? sub.nexports : 0; k-- > 0 && !value;) {
            if (!str_eq(sub.exports[k].name, nm)) continue;
            value = sub.exports[k].fn ? ast_copy(sub.exports[k].fn)
                                      : mk_lit(vec_retain(sub.exports[k].value), n->loc);
        }
        if (value) {
            ast_push(let, mk_binding1((Str *)nm, value, n->loc));
        } else {
            ast_push_name(imp, str_retain((Str *)nm));
            scope_push(s, (Str *)nm, NB_DYNAMIC, NULL, NULL, NULL);
        }
    }
    if (have) simp_fini(&sub);
    AstNode *body;
    if (let->nkids) {
        let->a = ast_copy(n->b);
        body = resimp(s, let);
    } else {
        ast_free(let);
        body = simp(s, n->b);
    }
    scope_restore(s, mark);
    if (!imp->nnames) {
        ast_free(imp);
        ast_free(file);
        return body;
    }
    imp->a = file;
    imp->b = body;
    return imp;
}

/* The end of a file: in an included file nothing; otherwise the export
 * point, which also records the names bound to literals (their bindings
 * are gone from the tree) as AST_BINDING kids with literal values. In a
 * module it uses every name (no top-level binding is dropped as unused);
 * in the main program (Flitter drops its export) it keeps nothing alive,
 * and exports only what is left, for the REPL's scope. */
AstNode *simp_export(Simp *s, const AstNode *n)
{
    if (s->tg || s->talone) {   /* files read once per copy: not shared by a template pass */
        s->tabort = true;
        return mk_lit(NULL, n->loc);
    }
    if (s->in_include) return mk_lit(NULL, n->loc);
    AstNode *x = ast_new(AST_EXPORT, n->loc);
    if (!s->is_module) x->op = EXPORT_MAIN;
    for (uint32_t i = 0; i < s->nnames; i++) {
        NameBind *b = &s->names[i];
        if (scope_find(s, b->name) != b) continue;
        if (b->kind == NB_LITERAL)
            ast_push(x, mk_binding1(b->name, mk_lit(vec_retain(b->value), n->loc), n->loc));
        if (!s->collect_exports || (b->kind != NB_LITERAL && b->kind != NB_FUNCTION)) continue;
        if (s->nexports == s->capexports) {
            s->capexports = s->capexports ? s->capexports * 2 : 8;
            s->exports = realloc(s->exports, s->capexports * sizeof *s->exports);
            if (!s->exports) mem_oom();
        }
        s->exports[s->nexports++] = (SimpExport){str_retain(b->name), vec_retain(b->value),
                                                 b->kind == NB_FUNCTION ? ast_copy(b->fn) : NULL};
    }
    return x;
}
