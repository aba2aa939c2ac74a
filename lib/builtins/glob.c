/* glob.c: the glob(pattern) built-in (LANGUAGE.md §5.12).
 *
 * Following the reference, glob() matches a pattern relative to the running
 * script's directory (`*`, `?`, `[...]`, `**` for any depth of directories;
 * wildcards also match names starting with '.') and returns the sorted
 * absolute, symlink-resolved paths.
 *
 * Bounded work: a directory is searched at most once for each
 * pattern component, however many paths lead to it (two symbolic links to
 * "." made the walk exponential: each wildcard level followed both). The
 * one departure: a match reached again through another link to a directory
 * already searched is not listed again (Flitter's pathlib walk lists the
 * same resolved path once per route, 3^N times for N levels there). The
 * walk looks at the interrupt flag at every directory, and stops with an
 * error beyond GLOB_MAX_MATCHES matches.
 */
#include <dirent.h>
#include <errno.h>
#include <fnmatch.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "context.h"
#include "files.h"
#include "format.h"
#include "mem.h"

/* ------------------------------------------------------------------ */
/* glob                                                                */
/* ------------------------------------------------------------------ */

enum { GLOB_MAX_MATCHES = 1000000 };

/* A directory searched for one pattern component. */
typedef struct {
    dev_t dev;
    ino_t ino;
    size_t idx;
    bool used;
} GlobSeen;

typedef struct {
    char **parts;       /* pattern components ("." and empty ones removed) */
    size_t nparts;
    bool dir_only;      /* pattern ended with '/' */
    StrList found;      /* matching paths (unresolved) */
    Eval *ev;           /* for the interrupt flag */
    bool stopped;       /* interrupted, or too many matches */
    GlobSeen *seen;     /* open-addressed set of (directory, component) */
    size_t nseen, capseen;
} Glob;

/* True the first time directory [path] is met for component [idx]; false
 * after (or when it cannot be read: nothing to search). */
static bool glob_first_visit(Glob *g, const char *path, size_t idx)
{
    struct stat st;
    if (stat(path, &st) != 0) return false;
    if (2 * (g->nseen + 1) > g->capseen) {   /* grow: keep the load under 1/2 */
        size_t cap = g->capseen ? g->capseen * 2 : 64;
        GlobSeen *t = calloc(cap, sizeof *t);
        if (!t) mem_oom();
        for (size_t i = 0; i < g->capseen; i++) {
            if (!g->seen[i].used) continue;
            size_t h = ((size_t)g->seen[i].ino * 31u + (size_t)g->seen[i].dev * 17u + g->seen[i].idx) & (cap - 1);
            while (t[h].used) h = (h + 1) & (cap - 1);
            t[h] = g->seen[i];
        }
        free(g->seen);
        g->seen = t;
        g->capseen = cap;
    }
    size_t h = ((size_t)st.st_ino * 31u + (size_t)st.st_dev * 17u + idx) & (g->capseen - 1);
    for (; g->seen[h].used; h = (h + 1) & (g->capseen - 1))
        if (g->seen[h].ino == st.st_ino && g->seen[h].dev == st.st_dev && g->seen[h].idx == idx)
            return false;
    g->seen[h] = (GlobSeen){st.st_dev, st.st_ino, idx, true};
    g->nseen++;
    return true;
}

static bool has_wildcard(const char *s)
{
    return strpbrk(s, "*?[") != NULL;
}

static bool is_dir(const char *path, bool follow)
{
    struct stat st;
    int rc = follow ? stat(path, &st) : lstat(path, &st);
    return rc == 0 && S_ISDIR(st.st_mode);
}

static void glob_select(Glob *g, const char *dir, size_t idx);

/* Match components from [idx] in [dir] and every directory below it
 * (symbolic links are not followed while descending). */
static void glob_recursive(Glob *g, const char *dir, size_t idx)
{
    if (g->stopped || !glob_first_visit(g, dir, idx + g->nparts + 1))
        return;   /* a "**" walk meets each directory once */
    glob_select(g, dir, idx);
    DIR *d = opendir(dir);
    if (!d)
        return;
    StrList subdirs = {NULL, 0, 0};
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
            continue;
        Buf child = BUF_INIT;
        buf_printf(&child, "%s/%s", dir, ent->d_name);
        if (is_dir(buf_cstr(&child), false))
            strlist_push(&subdirs, str_new(child.data, child.len));
        buf_free(&child);
    }
    closedir(d);
    for (size_t i = 0; i < subdirs.n; i++)
        glob_recursive(g, subdirs.v[i]->bytes, idx);
    strlist_free(&subdirs);
}

static void glob_select(Glob *g, const char *dir, size_t idx)
{
    if (g->stopped || eval_interrupted(g->ev)) {
        g->stopped = true;
        return;
    }
    if (idx == g->nparts) {
        if (!g->dir_only || is_dir(dir, true)) {
            if (g->found.n >= GLOB_MAX_MATCHES) {
                g->stopped = true;
                return;
            }
            strlist_push(&g->found, str_from(dir));
        }
        return;
    }
    const char *part = g->parts[idx];
    bool last = idx + 1 == g->nparts;
    if (!strcmp(part, "**")) {
        while (idx + 1 < g->nparts && !strcmp(g->parts[idx + 1], "**"))
            idx++;
        if (idx + 1 == g->nparts) {     /* trailing "**": directories only */
            bool saved = g->dir_only;
            g->dir_only = true;
            glob_recursive(g, dir, idx + 1);
            g->dir_only = saved;
        } else {
            glob_recursive(g, dir, idx + 1);
        }
        return;
    }
    if (!has_wildcard(part)) {
        Buf child = BUF_INIT;
        buf_printf(&child, "%s/%s", dir, part);
        struct stat st;
        if (last ? stat(buf_cstr(&child), &st) == 0 : is_dir(buf_cstr(&child), true))
            glob_select(g, buf_cstr(&child), idx + 1);
        buf_free(&child);
        return;
    }
    if (!glob_first_visit(g, dir, idx))
        return;   /* searched already for this component (a link to it) */
    DIR *d = opendir(dir);
    if (!d)
        return;
    StrList matches = {NULL, 0, 0};
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
            continue;
        if (fnmatch(part, ent->d_name, FNM_NOESCAPE) != 0)
            continue;
        Buf child = BUF_INIT;
        buf_printf(&child, "%s/%s", dir, ent->d_name);
        if (last || is_dir(buf_cstr(&child), true))
            strlist_push(&matches, str_new(child.data, child.len));
        buf_free(&child);
    }
    closedir(d);
    for (size_t i = 0; i < matches.n; i++)
        glob_select(g, matches.v[i]->bytes, idx + 1);
    strlist_free(&matches);
}

static int str_ptr_cmp(const void *a, const void *b)
{
    return str_cmp(*(Str *const *)a, *(Str *const *)b);
}

/* Sort [l] by bytes and drop repeated entries. */
static void strlist_sort_unique(StrList *l)
{
    if (l->n < 2)
        return;
    qsort(l->v, l->n, sizeof *l->v, str_ptr_cmp);
    size_t k = 1;
    for (size_t i = 1; i < l->n; i++) {
        if (str_eq(l->v[i], l->v[k - 1]))
            str_release(l->v[i]);
        else
            l->v[k++] = l->v[i];
    }
    l->n = k;
}

Vec *bi_glob(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    Buf pat = BUF_INIT;
    fmt_str(&pat, args[0], eval_symtab(ev));
    const char *p = buf_cstr(&pat);
    if (memchr(p, '\0', pat.len)) {
        buf_free(&pat);
        return bi_error(ev, bi, "embedded null byte");
    }
    if (p[0] == '/') {
        buf_free(&pat);
        return bi_error(ev, bi, "Non-relative patterns are unsupported");
    }
    /* Split into components, dropping empty and "." ones. */
    char *copy = strdup(p);
    if (!copy)
        mem_oom();
    Glob g = {NULL, 0, pat.len > 0 && p[pat.len - 1] == '/', {NULL, 0, 0}, ev, false, NULL, 0, 0};
    g.parts = malloc((pat.len / 2 + 1) * sizeof *g.parts);
    if (!g.parts)
        mem_oom();
    char *save = NULL;
    for (char *tok = strtok_r(copy, "/", &save); tok; tok = strtok_r(NULL, "/", &save))
        if (strcmp(tok, ".") != 0)
            g.parts[g.nparts++] = tok;
    Vec *r = NULL;
    if (g.nparts == 0) {
        r = bi_error(ev, bi, "Unacceptable pattern: '%s'", p);
    } else if (glob_select(&g, eval_script_dir(ev), 0), g.stopped) {
        r = eval_interrupted(ev) ? NULL : bi_error(ev, bi, "more than %d matches", GLOB_MAX_MATCHES);
    } else {
        strlist_sort_unique(&g.found);
        StrList resolved = {NULL, 0, 0};
        for (size_t i = 0; i < g.found.n; i++) {
            char *real = realpath(g.found.v[i]->bytes, NULL);
            if (real) {
                strlist_push(&resolved, str_from(real));
                free(real);
            } else {
                /* a dangling link: made absolute without resolving */
                Buf abs = BUF_INIT;
                char cwd[PATH_MAX];
                if (g.found.v[i]->bytes[0] != '/' && getcwd(cwd, sizeof cwd))
                    buf_printf(&abs, "%s/", cwd);
                buf_puts(&abs, g.found.v[i]->bytes);
                strlist_push(&resolved, str_new(buf_cstr(&abs), abs.len));
                buf_free(&abs);
            }
        }
        if (resolved.n > 1)
            qsort(resolved.v, resolved.n, sizeof *resolved.v, str_ptr_cmp);
        r = string_vector(resolved.v, resolved.n);
        strlist_free(&resolved);
    }
    strlist_free(&g.found);
    free(g.seen);
    free(g.parts);
    free(copy);
    buf_free(&pat);
    return r;
}
