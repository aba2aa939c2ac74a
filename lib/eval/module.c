/* module.c: the module cache behind `import` (LANGUAGE.md §4.13).
 *
 * The cache is a small list of entries keyed by path. An entry records the
 * file's modification time, the exported (name, value) pairs of its last
 * run, and whether it is being run right now: meeting an entry that is still
 * running means an import cycle, which gives `Circular import of 'FILE'`
 * rather than endless recursion.
 */
#include "module.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "mem.h"

typedef struct Module {
    char *path;              /* module file */
    struct timespec mtime;   /* modification time when loaded */
    bool running;            /* being evaluated now (cycle detection) */
    bool failed;             /* missing or unparseable */
    Exports exports;         /* names bound at the end of its top level */
    PathList files;          /* the files its last run read: its own, its
                                %includes and, transitively, its imports */
} Module;

struct ModuleCache {
    Module *mods;
    uint32_t count, cap;
};

ModuleCache *module_cache_new(void)
{
    ModuleCache *mc = calloc(1, sizeof *mc);
    if (!mc) mem_oom();
    return mc;
}

void exports_empty(Exports *x)
{
    for (uint32_t i = 0; i < x->count; i++) {
        str_release(x->names[i]);
        vec_release(x->values[i]);
    }
    x->count = 0;
}

void exports_clear(Exports *x)
{
    for (uint32_t i = 0; i < x->count; i++) {
        str_release(x->names[i]);
        vec_release(x->values[i]);
    }
    free(x->names);
    free(x->values);
    *x = (Exports){0};
}

void module_cache_free(ModuleCache *mc)
{
    if (!mc) return;
    for (uint32_t i = 0; i < mc->count; i++) {
        free(mc->mods[i].path);
        exports_clear(&mc->mods[i].exports);
        pathlist_clear(&mc->mods[i].files);
    }
    free(mc->mods);
    free(mc);
}

static Module *find_or_add(ModuleCache *mc, const char *path)
{
    for (uint32_t i = 0; i < mc->count; i++)
        if (strcmp(mc->mods[i].path, path) == 0) return &mc->mods[i];
    if (mc->count == mc->cap) {
        mc->cap = mc->cap ? mc->cap * 2 : 8;
        mc->mods = realloc(mc->mods, mc->cap * sizeof(Module));
        if (!mc->mods) mem_oom();
    }
    Module *m = &mc->mods[mc->count++];
    *m = (Module){0};
    m->path = strdup(path);
    m->failed = true;
    m->mtime.tv_sec = -1;
    if (!m->path) mem_oom();
    return m;
}

/* Run the module file of [m] afresh (index [mi] in [mc], whose array may
 * move during nested imports). */
static void run_module(ModuleCache *mc, uint32_t mi, Eval *ev)
{
    Module *m = &mc->mods[mi];
    exports_clear(&m->exports);
    pathlist_clear(&m->files);
    m->failed = true;
    Buf err = BUF_INIT;
    /* simplified (as a module, with no engine names) when the importer is */
    const Globals *ig = ev->globals;
    Globals mg = {.simplify = ig && ig->simplify, .module = true};
    if (ig) mg.routes = ig->routes;   /* the importer's routes */
    Program *p = program_load(m->path, &mg, (SymTab *)ev->symtab, &err);
    buf_free(&err);
    if (!p) return;
    /* load-time warnings (unbound names) are reported like run-time errors */
    for (const char *w = p->warnings.data; w && *w;) {
        const char *nl = strchr(w, '\n');
        size_t len = nl ? (size_t)(nl - w) : strlen(w);
        char *line = strndup(w, len);
        if (!line) mem_oom();
        eval_error(ev, line);
        free(line);
        w += len + (nl ? 1 : 0);
    }
    m->running = true;
    Exports ex = {0};
    /* collected apart: nested imports may move mc->mods */
    PathList files = {0};
    pathlist_add_all(&files, &p->files);
    /* the importer's nesting depth and interrupt flag carry on into the
     * module, so a chain of imports shares one bound on the C stack and an
     * interrupt stops it too */
    Eval mev = {
        .prog = p, .globals = NULL, .state = NULL, .symtab = ev->symtab,
        .errors = ev->errors, .debug = ev->debug, .modules = mc, .exports = &ex,
        .depth = ev->depth, .interrupt = ev->interrupt, .files = &files,
    };
    Node *root = eval_program(&mev);
    node_release(root);
    m = &mc->mods[mi];
    m->running = false;
    m->files = files;
    if (mev.interrupted) {
        /* incomplete exports are not cached: the module runs again */
        ev->interrupted = true;
        exports_clear(&ex);
    } else {
        m->failed = false;
        m->exports = ex;
    }
    program_release(p);
}

void module_import(ModuleCache *mc, Eval *ev, const char *path, Str *const *names,
                   uint32_t n, Vec **values)
{
    char msg[1200];
    for (uint32_t i = 0; i < n; i++) values[i] = NULL;
    Module *m = find_or_add(mc, path);
    uint32_t mi = (uint32_t)(m - mc->mods);
    if (m->running) {
        snprintf(msg, sizeof msg, "Circular import of '%s'", path);
        eval_error(ev, msg);
        return;
    }
    struct stat sb;
    bool exists = stat(path, &sb) == 0;
    if (!exists || m->failed || sb.st_mtim.tv_sec != m->mtime.tv_sec ||
        sb.st_mtim.tv_nsec != m->mtime.tv_nsec) {
        if (exists) m->mtime = sb.st_mtim;
        run_module(mc, mi, ev);
        m = &mc->mods[mi];
    }
    if (ev->files && exists) {   /* watched even when it does not load */
        pathlist_add(ev->files, path);
        pathlist_add_all(ev->files, &m->files);
    }
    if (m->failed) {
        snprintf(msg, sizeof msg, "Unable to import from '%s'", path);
        eval_error(ev, msg);
        return;
    }
    for (uint32_t i = 0; i < n; i++) {
        bool found = false;
        for (uint32_t k = m->exports.count; k-- > 0 && !found;) {
            if (str_eq(m->exports.names[k], names[i])) {
                values[i] = vec_retain(m->exports.values[k]);
                found = true;
            }
        }
        if (!found) {
            snprintf(msg, sizeof msg, "Unable to import '%s' from '%s'", names[i]->bytes, path);
            eval_error(ev, msg);
        }
    }
}
