/* runtime.c: one interpreter and its frame loop (LANGUAGE.md §6,
 * FORMATS.md §5).
 *
 * A runtime owns the program, the state dictionary, the physics world, the
 * symbol table, the engine names (Globals) and the beat clock. fl_step()
 * runs one frame in the order of LANGUAGE.md §6.3: compute the frame names,
 * (re)apply pragmas after a load, evaluate the program into a node tree,
 * hand the top-level renderer nodes (!physics, !counter) to their renderers
 * (COUNTERS.md), store the beat
 * counter under "_counter", then advance `time` by 1/fps (a running
 * floating-point sum, not frame/fps).
 */
#include "runtime.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "builtins.h"
#include "counter.h"
#include "define_value.h"
#include "fileio.h"
#include "format.h"
#include "input.h"
#include "kernel.h"
#include "lexer.h"
#include "mem.h"
#include "module.h"
#include "physics.h"
#include "pictures.h"
#include "pool.h"
#include "program.h"
#include "simplify.h"
#include "stable.h"
#include "statefile.h"
#include "syntax_dump.h"

/* The engine names of LANGUAGE.md §6.2 in a fixed order (indices into
 * Globals); defines are added after them. */
enum {
    G_FRAME, G_TIME, G_BEAT, G_DELTA, G_TEMPO, G_QUANTUM, G_FPS, G_PERFORMANCE,
    G_SLOW_FRAME, G_CLOCK, G_REALTIME, G_RUN_TIME, G_SCREEN, G_FULLSCREEN, G_VSYNC,
    G_OFFSCREEN, G_OPENGL_ES, G__COUNT
};
static const char *const engine_names[G__COUNT] = {
    "frame", "time", "beat", "delta", "tempo", "quantum", "fps", "performance",
    "slow_frame", "clock", "realtime", "run_time", "screen", "fullscreen", "vsync",
    "offscreen", "opengl_es",
};

struct fl_runtime {
    fl_options opts;        /* as given to fl_new */
    Pool *pool;             /* free lists for per-frame values */
    MemBudget budget;       /* fl_options.max_memory, charged through rt_enter (mem.h) */
    fl_stats stats;         /* counters and timers for fl_get_stats */
    uint64_t kernel_iterations; /* loop iterations run with their kernel
                                   (kernel.h), all frames */
    uint64_t kernel_reused; /* nodes refilled in place (kernel.h), all frames */
    uint64_t kernel_straight; /* iterations run as straight bodies (kernel.c), all frames */
    SymTab *symtab;         /* symbol names for value text */
    StateDict *state;       /* the state dictionary */
    PhysicsWorld *physics;  /* persistent physics systems */
    ModuleCache *modules;   /* imported modules */
    Vec *counter_key;       /* "_counter", the beat counter's state key */
    Exports scope;          /* the script's top-level names at the last frame */
    Exports repl;           /* names bound by fl_eval */
    Str **scope_names;      /* rt_scope_names() result */
    size_t nscope_names;
    Globals globals;        /* engine names and defines */
    Program *prog;          /* current program, or NULL */
    Program *run_prog;      /* prog simplified again with stable values (stable.h), or NULL */
    StableCache *stables;   /* `let stable` values */
    NoisePerms *noise_perms; /* noise()'s permutation tables of late (builtins.h) */
    FileMemo *file_memo;     /* the files the file built-ins read (builtins.h) */
    KernelScratch *kscratch; /* the loop kernels' registers (kernel.h) */
    bool pragmas_pending;   /* apply pragmas at the next step */
    Node *root;             /* last frame's tree */
    MsgSet errors[2];       /* this and the previous frame's errors */
    MsgSet debug[2];        /* this and the previous frame's debug lines */
    MsgSet sdf_errors;      /* errors of SDF functions called by the renderer, said once */
    int cur;                /* index of "this frame" in errors/debug */
    long frame;             /* frames evaluated so far */
    double frame_time;      /* `time` of the next frame, seconds */
    double last_time;       /* `time` of the last evaluated frame */
    double target_fps;      /* frame rate, after pragmas */
    bool upstream;          /* Flitter 1.0.0b28's physics, after pragmas
                               (fl_options.physics, `%pragma physics`) */
    double period;          /* beat clock: seconds per beat */
    double quantum;         /* beat clock: beats per bar */
    double start;           /* beat clock: time of beat 0 */
    double last_beat;       /* beat of the previous frame */
    double wall_start;      /* realtime: the monotonic clock when `time` was 0 */
    bool clock_started;     /* realtime: wall_start set (at the first step) */
    double performance;     /* Flitter's `performance` (realtime: 0.5..2, from 1) */
    bool slow_frame;        /* realtime: the last frame ended after the next was due */
    double paused_at;       /* fl_clock_pause: when the clock stopped, or -1 */
    bool warned_nonfinite;  /* physics: non-finite time logged already */
    bool warned_capped;     /* physics: step limit logged already */
    unsigned warned_kinds;  /* top-level kinds not supported, named already
                               (a bit per entry of renderers[]) */
    Buf error;              /* fl_error(): the last failed call's message */
    Pictures *pictures;     /* fl_draw_window's renderer */
    Input *input;           /* keys held in the shown windows */
    PathList files;         /* fl_program_files: the program's files, then
                               the modules imported while it ran */
};

fl_options fl_default_options(void)
{
    return (fl_options){.fps = 60.0, .frames = -1, .realtime = false, .max_physics_steps = 10000};
}

/* ====================================================================
 * Messages: the log callback (flitter.h fl_options.log)
 * ==================================================================== */

static void log_to_files(void *ctx, int kind, const char *line)
{
    const RtStreams *s = ctx;
    FILE *f = kind == FL_LOG_DEBUG ? s->debug : s->log;
    if (f) fprintf(f, "%s\n", line);
}

void rt_log_to_files(fl_options *o, RtStreams *s)
{
    o->log = log_to_files;
    o->ctx = s;
}

/* The default log: errors and warnings to stderr, debug lines to stdout. */
static void log_default(void *ctx, int kind, const char *line)
{
    (void)ctx;
    fprintf(kind == FL_LOG_DEBUG ? stdout : stderr, "%s\n", line);
}

/* Send one message line of [kind] (FL_LOG_*) to the runtime's log. */
__attribute__((format(printf, 3, 4)))
static void emit(const fl_runtime *rt, int kind, const char *fmt, ...)
{
    char small[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) return;
    char *line = small;
    if ((size_t)n >= sizeof small) {
        line = mem_alloc((size_t)n + 1);
        va_start(ap, fmt);
        vsnprintf(line, (size_t)n + 1, fmt, ap);
        va_end(ap);
    }
    rt->opts.log(rt->opts.ctx, kind, line);
    if (line != small) free(line);
}

int rt_fail(fl_runtime *rt, const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    Buf *b = rt_error_buf(rt);
    buf_reset(b);
    buf_printf(b, "%s\n", line);
    return -1;
}

void rt_log_target(const fl_runtime *rt, fl_log_fn *fn, void **ctx)
{
    *fn = rt->opts.log;
    *ctx = rt->opts.ctx;
}

MemHandler rt_enter(const fl_runtime *rt)
{
    /* the budget is the runtime's own state, changed by every call that allocates */
    return mem_enter_budget(rt->opts.error, rt->opts.ctx, (MemBudget *)&rt->budget);
}

Buf *rt_error_buf(fl_runtime *rt) { return &rt->error; }

/* *[out] = the value of [text] among the two option words [a] (value
 * [va]) and [b] (value [vb]); false, leaving *[out] alone, for others. */
static bool parse_choice(const char *text, const char *a, int va, const char *b, int vb, int *out)
{
    if (!text || !out) return false;
    if (strcmp(text, a) && strcmp(text, b))
        return false;
    *out = strcmp(text, a) ? vb : va;
    return true;
}

bool fl_parse_pairs(const char *text, int *out)
{
    return parse_choice(text, "naive", FL_PAIRS_NAIVE, "fast", FL_PAIRS_FAST, out);
}

bool fl_parse_particles(const char *text, int *out)
{
    return parse_choice(text, "literal", FL_PARTICLES_LITERAL, "fast", FL_PARTICLES_FAST, out);
}

bool fl_parse_physics(const char *text, int *out)
{
    return parse_choice(text, "documented", FL_PHYSICS_DOCUMENTED, "upstream", FL_PHYSICS_UPSTREAM,
                        out);
}

static double monotonic(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The render graph's `!sdf function=` callbacks (GraphEnv). */
static bool sdf_distance(void *ctx, const Vec *fn, const double *xyz, size_t n, double *out)
{
    return rt_call_distances(ctx, fn, xyz, n, out);
}

static uint64_t sdf_function_key(void *ctx, const Vec *fn)
{
    (void)ctx;
    return eval_function_key(fn);
}

fl_runtime *fl_new(const fl_options *opts)
{
    fl_options o = opts ? *opts : fl_default_options();
    MemHandler prev = mem_enter(o.error, o.ctx);
    fl_runtime *rt = mem_calloc(1, sizeof *rt);
    rt->opts = o;
    if (!rt->opts.log) rt->opts.log = log_default;
    rt->budget.limit = o.max_memory ? o.max_memory : mem_default_limit();
    mem_leave(prev);
    prev = rt_enter(rt);
    const fl_debug_options *dbg = &rt->opts.debug;
    rt->pool = pool_new(dbg->no_pool);
    if (!(rt->opts.fps > 0)) rt->opts.fps = 60.0;
    rt->symtab = symtab_new();
    rt->state = state_new();
    rt->physics = phys_new();
    if (rt->opts.threads > 0)
        phys_set_threads(rt->physics, (unsigned)rt->opts.threads);
    if (rt->opts.pairs != FL_PAIRS_DEFAULT)
        phys_set_pairs(rt->physics, rt->opts.pairs == FL_PAIRS_NAIVE);
    if (rt->opts.particles != FL_PARTICLES_DEFAULT)
        phys_set_particles(rt->physics, rt->opts.particles == FL_PARTICLES_LITERAL);
    if (dbg->simd != FL_SIMD_AUTO)
        phys_set_simd(rt->physics, dbg->simd == FL_SIMD_PORTABLE ? PHYS_SIMD_PORTABLE
                                   : dbg->simd == FL_SIMD_AVX2   ? PHYS_SIMD_AVX2
                                   : dbg->simd == FL_SIMD_AVX2_VL ? PHYS_SIMD_AVX2_VL
                                                                  : PHYS_SIMD_AVX512);
    rt->upstream = rt->opts.physics == FL_PHYSICS_UPSTREAM;
    rt->modules = module_cache_new();
    rt->stables = stable_new();
    rt->noise_perms = noise_perms_new();
    rt->file_memo = file_memo_new();
    rt->kscratch = kernel_scratch_new(!dbg->no_kernel_reuse);
    kernel_scratch_set_transient(rt->kscratch, rt->opts.transient_tree);
    pool_set_reclaim(rt->pool, kernel_scratch_reclaim, rt->kscratch, kernel_scratch_held(rt->kscratch));
    rt->counter_key = vec_str("_counter", 8);
    /* symbols the physics engine writes into state keys (PHYSICS.md) */
    static const char *const engine_symbols[] = {"clock", "last", "run", "iteration", "velocity",
                                                 "time",
                                                 /* and the windows' key states (input.h) */
                                                 "pushed", "released", "beat"};
    for (size_t i = 0; i < sizeof engine_symbols / sizeof engine_symbols[0]; i++)
        symtab_add(rt->symtab, engine_symbols[i], strlen(engine_symbols[i]));
    for (int i = 0; i < G__COUNT; i++) globals_add(&rt->globals, engine_names[i]);
    rt->globals.simplify = !rt->opts.no_simplify;
    rt->globals.interrupt = rt->opts.interrupt;
    rt->globals.routes = (LoadRoutes){
        .no_fast = dbg->no_fast, .no_templates = dbg->no_templates, .check_templates = dbg->check_templates,
        .kernel = {.off = dbg->no_kernel, .chunk = dbg->kernel_chunk, .window = dbg->kernel_window}};
    rt->globals.ndynamic = G_REALTIME;   /* frame .. clock change per frame */
    rt->target_fps = rt->opts.fps;
    rt->period = 0.5;
    rt->quantum = 4.0;
    rt->start = 0.0;
    rt->wall_start = monotonic();
    rt->performance = rt->opts.realtime ? 1.0 : 2.0;
    rt->paused_at = -1;
    /* static names (§6.2) */
    Vec *v = vec_num1(rt->opts.realtime ? 1.0 : 0.0);
    globals_set(&rt->globals, G_REALTIME, v);
    vec_release(v);
    if (rt->opts.frames >= 0) {
        v = vec_num1((double)rt->opts.frames / rt->opts.fps);
        globals_set(&rt->globals, G_RUN_TIME, v);
        vec_release(v);
    }
    v = vec_num1(0.0);
    for (int g = G_SCREEN; g <= G_OPENGL_ES; g++) globals_set(&rt->globals, g, v);
    vec_release(v);
    rt->pictures = pictures_new(&(GraphEnv){
        .symbols = rt->symtab, .log = {rt->opts.log, rt->opts.ctx, true}, .budget = &rt->budget,
        .interrupt = rt->opts.interrupt, .model_cache = rt->opts.model_cache,
        .c3d = {.no_impostors = rt->opts.debug.impostors == FL_IMPOSTORS_OFF,
                .box_impostors = rt->opts.debug.impostors == FL_IMPOSTORS_BOX,
                .occlusion = rt->opts.debug.occlusion == FL_OCCLUSION_ALWAYS  ? C3D_OCCLUSION_ALWAYS
                             : rt->opts.debug.occlusion == FL_OCCLUSION_NEVER ? C3D_OCCLUSION_NEVER
                                                                              : C3D_OCCLUSION_AUTO,
                .no_light_culling = rt->opts.debug.no_light_culling},
        .distance = sdf_distance, .function_key = sdf_function_key, .ctx = rt});
    rt->input = input_new();
    mem_leave(prev);
    return rt;
}

void fl_free(fl_runtime *rt)
{
    if (!rt) return;
    program_release(rt->prog);
    program_release(rt->run_prog);
    stable_free(rt->stables);
    noise_perms_free(rt->noise_perms);
    file_memo_free(rt->file_memo);
    kernel_scratch_free(rt->kscratch);
    node_release(rt->root);
    phys_free(rt->physics);
    module_cache_free(rt->modules);
    vec_release(rt->counter_key);
    exports_clear(&rt->scope);
    exports_clear(&rt->repl);
    free(rt->scope_names);
    state_free(rt->state);
    globals_free(&rt->globals);
    for (int i = 0; i < 2; i++) {
        msgset_clear(&rt->errors[i]);
        if (i == 0) msgset_clear(&rt->sdf_errors);
        msgset_clear(&rt->debug[i]);
    }
    pictures_free(rt->pictures);
    input_free(rt->input);
    pathlist_clear(&rt->files);
    symtab_free(rt->symtab);
    pool_free(rt->pool);
    buf_free(&rt->error);
    free(rt);
}

/* ====================================================================
 * Defines (FORMATS.md §4)
 * ==================================================================== */

static bool valid_name(const char *name)
{
    if (!name || !*name) return false;
    for (const unsigned char *p = (const unsigned char *)name; *p; p++) {
        if (*p == '_' || *p >= 0x80 || (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z')) continue;
        if (p != (const unsigned char *)name && ((*p >= '0' && *p <= '9') || *p == '\'')) continue;
        return false;
    }
    return true;
}

/* Value text [text] as a vector (NULL for ""); with [sign], a part that
 * is `-` and a number is that number negated (as the state dump prints
 * negative numbers); without it (-D, FORMATS.md §4) such a part is a
 * string. */
Vec *rt_parse_value(fl_runtime *rt, const char *text)
{
    size_t n = strlen(text), i = 0;
    Vec **parts = calloc(n + 1, sizeof(Vec *));
    if (!parts) mem_oom();
    size_t np = 0;
    while (n && i <= n) {
        size_t j = i;
        while (j < n && text[j] != ';') j++;
        const char *p = text + i;
        size_t len = j - i;
        double x;
        if (len > 1 && p[0] == ':') {
            parts[np++] = vec_num1(symtab_add(rt->symtab, p + 1, len - 1));
        } else if (lex_number_text(p, len, &x)) {
            parts[np++] = vec_num1(x);
        } else if (len > 1 && p[0] == '-' && lex_number_text(p + 1, len - 1, &x)) {
            parts[np++] = vec_num1(-x);
        } else {
            parts[np++] = vec_str(p, len);
        }
        i = j + 1;
    }
    Vec *v = vec_compose(parts, np);
    for (size_t k = 0; k < np; k++) vec_release(parts[k]);
    free(parts);
    return v;
}

int fl_define(fl_runtime *rt, const char *name, const char *text)
{
    if (!rt) return -1;
    if (!name) return rt_fail(rt, "fl_define: [name] is NULL");
    if (!text) return rt_fail(rt, "fl_define: [value_text] is NULL");
    if (!valid_name(name)) return rt_fail(rt, "fl_define: '%.200s' is not a name", name);
    MemHandler prev = rt_enter(rt);
    int g = globals_add(&rt->globals, name);
    Vec *v = define_value(rt->symtab, text, strlen(text));
    globals_set(&rt->globals, g, v);
    vec_release(v);
    mem_leave(prev);
    return 0;
}

int fl_define_numbers(fl_runtime *rt, const char *name, const double *values, size_t n)
{
    if (!rt) return -1;
    if (!name) return rt_fail(rt, "fl_define_numbers: [name] is NULL");
    if (!values && n) return rt_fail(rt, "fl_define_numbers: [values] is NULL for %zu numbers", n);
    if (n > MAX_COMPOSE_LEN)
        return rt_fail(rt, "fl_define_numbers: %zu numbers: more than the longest vector (%llu)", n,
                       (unsigned long long)MAX_COMPOSE_LEN);
    if (!valid_name(name)) return rt_fail(rt, "fl_define_numbers: '%.200s' is not a name", name);
    MemHandler prev = rt_enter(rt);
    if (!mem_fits(sizeof(Vec) + n * sizeof(double))) {
        mem_leave(prev);
        return rt_fail(rt, "fl_define_numbers: %zu numbers: out of memory (the budget, "
                       "fl_options.max_memory)", n);
    }
    int g = globals_add(&rt->globals, name);
    Vec *v = n ? vec_from_nums(values, (uint32_t)n) : NULL;
    globals_set(&rt->globals, g, v);
    vec_release(v);
    mem_leave(prev);
    return 0;
}

/* ====================================================================
 * Loading
 * ==================================================================== */

static void log_warnings(fl_runtime *rt, const Program *p)
{
    if (!p->warnings.len) return;
    const char *s = p->warnings.data;
    while (*s) {
        const char *nl = strchr(s, '\n');
        size_t len = nl ? (size_t)(nl - s) : strlen(s);
        emit(rt, FL_LOG_WARNING, "%s: warning: %.*s", p->path, (int)len, s);
        s += len + (nl ? 1 : 0);
    }
}

static int install(fl_runtime *rt, Program *p)
{
    if (!p) return -1;
    log_warnings(rt, p);
    program_release(rt->prog);
    program_release(rt->run_prog);
    rt->run_prog = NULL;
    kernel_scratch_clear(rt->kscratch);   /* nodes of the old program's loops */
    stable_clear(rt->stables);
    rt->prog = p;
    rt->pragmas_pending = true;
    pathlist_clear(&rt->files);
    pathlist_add_all(&rt->files, &p->files);
    return 0;
}

/* The bytes of blocks a load may leave cached in the runtime's pool for the
 * first frames (pool_trim): a sixteenth of the memory budget, at most
 * 8 MiB. Freed one by one, they cost a large load time, and its first
 * frames called malloc again for them. Kept, they raise a run's peak a
 * little (blocks of a frame's classes where the frame wanted other
 * sizes); past 8 MiB that cost grows faster than the time saved
 * (bench/PROFILE.md, "lib/runtime/runtime.c: the blocks a load leaves
 * cached"). */
static size_t load_keep(const fl_runtime *rt)
{
    const size_t most = (size_t)8 << 20, k = rt->budget.limit / 16;
    return rt->budget.limit && k < most ? k : most;
}

int rt_load(fl_runtime *rt, const char *path, Buf *err)
{
    /* with the runtime's pool active, the simplifier's many short-lived
     * vectors and trees reuse blocks instead of calling malloc and free */
    Pool *prev = pool_enter(rt->pool);
    int rc = install(rt, program_load(path, &rt->globals, rt->symtab, err));
    pool_leave(prev);
    pool_trim(rt->pool, load_keep(rt));
    return rc;
}

int rt_load_text(fl_runtime *rt, const char *name, const char *text, size_t len, Buf *err)
{
    Pool *prev = pool_enter(rt->pool);
    int rc = install(rt, program_load_text(name, text, len, &rt->globals, rt->symtab, err));
    pool_leave(prev);
    pool_trim(rt->pool, load_keep(rt));
    return rc;
}

int rt_dump_syntax(fl_runtime *rt, const char *path, bool ast, Buf *out, Buf *err)
{
    Buf text = BUF_INIT;
    const char *src = program_read(path, &text, err);
    bool ok = src && (ast ? dump_ast(out, err, path, src, text.len, rt->symtab, rt->opts.interrupt)
                          : dump_tokens(out, err, path, src, text.len, rt->opts.interrupt));
    buf_free(&text);
    return ok ? 0 : -1;
}

int rt_dump_program(const fl_runtime *rt, Buf *out)
{
    if (!rt->prog) return -1;
    ast_dump(out, rt->prog->top, rt->symtab);
    return 0;
}

/* ====================================================================
 * The beat clock (LANGUAGE.md §6.1)
 * ==================================================================== */

static double beat_at(const fl_runtime *rt, double t) { return (t - rt->start) / rt->period; }

/* Python float modulo: the result takes the sign of [b]. */
static double py_fmod(double a, double b)
{
    double r = fmod(a, b);
    if (r != 0.0 && ((r < 0) != (b < 0))) r += b;
    return r;
}

static void set_tempo(fl_runtime *rt, double tempo, double t)
{
    double b = beat_at(rt, t);
    rt->period = 60.0 / tempo;
    rt->start = t - b * rt->period;
}

static void set_quantum(fl_runtime *rt, double q, double t)
{
    double phase = py_fmod(beat_at(rt, t), rt->quantum);
    rt->quantum = q;
    double adj = py_fmod(phase - beat_at(rt, t), rt->quantum);
    if (adj > rt->quantum) adj -= rt->quantum;
    rt->start -= adj * rt->period;
}

/* [v] is the symbol :[word] or the string [word]. */
static bool pragma_word(const Vec *v, const char *word)
{
    if (vec_is_scalar(v))
        return vec_scalar(v) == symbol_value(word, strlen(word));
    if (!vec_is_obj(v) || v->len != 1 || vec_celems(v)[0].kind != EL_STR) return false;
    return strcmp(vec_celems(v)[0].str->bytes, word) == 0;
}

/* Apply the program's pragmas at load (LANGUAGE.md §6.4). */
static void apply_pragmas(fl_runtime *rt)
{
    bool fresh = state_get(rt->state, rt->counter_key) == NULL;
    double fps = rt->opts.fps;
    bool upstream = rt->opts.physics == FL_PHYSICS_UPSTREAM;
    for (uint32_t i = 0; i < rt->prog->npragmas; i++) {
        const Pragma *p = &rt->prog->pragmas[i];
        if (strcmp(p->name->bytes, "physics") == 0) {
            /* `%pragma physics :upstream` / `:documented` (a symbol or a
             * string): which physics (flitter.h, FL_PHYSICS_*) */
            int mode;
            if (pragma_word(p->value, "documented"))
                mode = FL_PHYSICS_DOCUMENTED;
            else if (pragma_word(p->value, "upstream"))
                mode = FL_PHYSICS_UPSTREAM;
            else {
                emit(rt, FL_LOG_WARNING, "%s: warning: %%pragma physics: expected :documented "
                     "or :upstream; ignored", rt->prog->path);
                continue;
            }
            upstream = mode == FL_PHYSICS_UPSTREAM;
            continue;
        }
        if (!vec_is_scalar(p->value)) continue;
        double x = vec_scalar(p->value);
        bool clock_pragma = strcmp(p->name->bytes, "fps") == 0
            || strcmp(p->name->bytes, "tempo") == 0 || strcmp(p->name->bytes, "quantum") == 0;
        if (clock_pragma && !(isfinite(x) && x > 0 && isfinite(60.0 / x))) {
            /* the reference divides by these and fails; we keep the
             * defaults so the clock (and a saved state) stays finite */
            emit(rt, FL_LOG_WARNING, "%s: warning: %%pragma %s %.17g ignored (out of range)",
                 rt->prog->path, p->name->bytes, x);
            continue;
        }
        if (strcmp(p->name->bytes, "fps") == 0) {
            fps = x;
        } else if (strcmp(p->name->bytes, "tempo") == 0 && fresh) {
            if (x != 60.0 / rt->period) set_tempo(rt, x, rt->frame_time);
        } else if (strcmp(p->name->bytes, "quantum") == 0 && fresh) {
            if (x != rt->quantum) set_quantum(rt, x, rt->frame_time);
        }
    }
    rt->target_fps = fps;
    rt->upstream = upstream;
}

/* ====================================================================
 * The frame
 * ==================================================================== */

static void set_num(fl_runtime *rt, int g, double x)
{
    Vec *v = vec_num1(x);
    globals_set(&rt->globals, g, v);
    vec_release(v);
}

/* Print the messages of [now] that were not in [before]. */
static void report(const fl_runtime *rt, int kind, const char *prefix, const MsgSet *now,
                   const MsgSet *before)
{
    for (uint32_t i = 0; i < now->count; i++)
        if (!msgset_has(before, now->items[i])) emit(rt, kind, "%s%s", prefix, now->items[i]);
}

/* ====================================================================
 * Renderers: the top-level nodes that act after evaluation
 * ==================================================================== */

/* A renderer receives, once per frame, the top-level nodes of its kind in
 * tree order (borrowed) and the frame's `time`. */
typedef struct Renderer {
    const char *kind;
    void (*run)(fl_runtime *rt, Node *const *nodes, size_t n, double t);
    const char *what;   /* for a kind not supported: what it would drive */
} Renderer;

static void run_physics(fl_runtime *rt, Node *const *nodes, size_t n, double t)
{
    bool nonfinite = false, capped = false;
    PhysicsFrame pf = {.time = t, .fps = rt->target_fps, .realtime = rt->opts.realtime,
                       .performance = rt->performance, .max_steps = rt->opts.max_physics_steps,
                       .interrupt = rt->opts.interrupt, .nonfinite = &nonfinite,
                       .capped = &capped, .upstream = rt->upstream};
    phys_run_frame(rt->physics, nodes, n, rt->state, &pf);
    if (mem_take_refusal())   /* world.c: a system past the memory budget (mem.h) */
        emit(rt, FL_LOG_ERROR, "Physics error: system too large for the memory budget "
             "(--max-memory); skipped");
    if (nonfinite && !rt->warned_nonfinite)
        emit(rt, FL_LOG_ERROR, "Physics error: non-finite time or resolution; frame skipped");
    if (capped && !rt->warned_capped)
        emit(rt, FL_LOG_WARNING, "Physics warning: more than %ld steps needed in one frame; "
             "simulation clock falls behind", rt->opts.max_physics_steps);
    rt->warned_nonfinite |= nonfinite;
    rt->warned_capped |= capped;
}

static void run_counters(fl_runtime *rt, Node *const *nodes, size_t n, double t)
{
    for (size_t i = 0; i < n; i++) counter_update(nodes[i], rt->state, t);
}

/* The renderers, in the order they run. Physics systems and counters keep
 * disjoint state keys, so running each kind in turn equals tree order.
 * Flitter's other top-level renderers (its pyproject's "flitter.render"
 * plugins) that flitter-c does not have: named once (NULL run). Windows
 * are drawn by the render graph (lib/runtime/pictures.c); any other kind is the
 * script's own data and is left alone, as Flitter leaves it. */
static const Renderer renderers[] = {
    {"physics", run_physics, NULL},
    {"counter", run_counters, NULL},
    {"controller", NULL, "MIDI and USB controllers"},
    {"dmx", NULL, "DMX lighting"},
    {"laser", NULL, "lasers"},
    {"osc", NULL, "OSC messages"},
};

/* Hand each renderer its top-level nodes of [root]. */
static void run_renderers(fl_runtime *rt, const Node *root, double t)
{
    Node *small[8];
    Node **nodes = root->nchildren > 8 ? malloc(root->nchildren * sizeof(Node *)) : small;
    if (!nodes) mem_oom();
    for (size_t r = 0; r < sizeof renderers / sizeof renderers[0]; r++) {
        size_t n = 0;
        for (uint32_t i = 0; i < root->nchildren; i++)
            if (node_is(root->children[i], renderers[r].kind)) nodes[n++] = root->children[i];
        if (renderers[r].run) {
            renderers[r].run(rt, nodes, n, t);
        } else if (n && !(rt->warned_kinds & (1u << r))) {
            emit(rt, FL_LOG_WARNING, "skipping unsupported !%s (%s: not in flitter-c)",
                 renderers[r].kind, renderers[r].what);
            rt->warned_kinds |= 1u << r;
        }
    }
    if (nodes != small) free(nodes);
}

static int step(fl_runtime *rt);

int fl_step(fl_runtime *rt)
{
    if (!rt) return -1;
    if (!rt->prog) return rt_fail(rt, "fl_step: no program is loaded");
    MemHandler mprev = rt_enter(rt);
    Pool *prev = pool_enter(rt->pool);
    PoolStats before = pool_stats(rt->pool);
    int rc = step(rt);
    PoolStats after = pool_stats(rt->pool);
    pool_leave(prev);
    rt->stats.frames++;
    rt->stats.last_mallocs = after.mallocs + after.stacks - before.mallocs - before.stacks;
    rt->stats.last_frees = after.frees - before.frees;
    rt->stats.mallocs = after.mallocs + after.stacks;
    rt->stats.frees = after.frees;
    mem_leave(mprev);
    return rc;
}

/* One frame (fl_step), with the runtime's pool active. */
static int step(fl_runtime *rt)
{
    double t0 = monotonic();
    if (rt->opts.realtime && !rt->clock_started) {
        /* the schedule starts now, from the clock's `time` (0, or a
         * restored state's) */
        rt->wall_start = monotonic() - rt->frame_time;
        rt->clock_started = true;
    }
    /* the program's pragmas first: their fps, tempo and quantum are the
     * names of the frame they are loaded in, frame 0 included
     * (FORMATS.md §5; Flitter 1.0.0b28 applies them after, LANGUAGE.md §6.4) */
    if (rt->pragmas_pending) {
        apply_pragmas(rt);
        rt->pragmas_pending = false;
    }
    double t = rt->frame_time;
    double beat = beat_at(rt, t);
    double delta = beat - rt->last_beat, prev_beat = rt->last_beat;
    rt->last_beat = beat;
    set_num(rt, G_FRAME, (double)rt->frame);
    set_num(rt, G_TIME, t);
    set_num(rt, G_BEAT, beat);
    set_num(rt, G_DELTA, delta);
    set_num(rt, G_TEMPO, 60.0 / rt->period);
    set_num(rt, G_QUANTUM, rt->quantum);
    set_num(rt, G_FPS, rt->target_fps);
    set_num(rt, G_PERFORMANCE, rt->performance);
    set_num(rt, G_SLOW_FRAME, rt->slow_frame ? 1.0 : 0.0);
    set_num(rt, G_CLOCK, t);
    if (rt->frame >= MAX_FRAME || !isfinite(beat) || !isfinite(t + 1.0 / rt->target_fps)) {
        /* one more frame would leave a clock that a state file cannot
         * hold (statefile_clock_refused): the clock stops here, where it
         * can still be saved */
        rt->last_beat = prev_beat;
        return rt_fail(rt, "frame %ld: the clock is at its limit (frame 2^53, or a time or beat "
                       "past the largest finite number); no further frame", rt->frame);
    }

    int prev = rt->cur;
    rt->cur ^= 1;
    msgset_clear(&rt->errors[rt->cur]);
    msgset_clear(&rt->debug[rt->cur]);
    Eval ev = {
        .prog = rt->run_prog ? rt->run_prog : rt->prog, .globals = &rt->globals,
        .state = rt->state, .symtab = rt->symtab, .errors = &rt->errors[rt->cur],
        .debug = &rt->debug[rt->cur], .modules = rt->modules, .exports = &rt->scope,
        .stables = rt->globals.simplify ? rt->stables : NULL,
        .interrupt = rt->opts.interrupt, .files = &rt->files, .noise_perms = rt->noise_perms,
        .file_memo = rt->file_memo,
        .workers = phys_workers(rt->physics), .kscratch = rt->kscratch,
    };
    exports_empty(&rt->scope);
    if (rt->opts.transient_tree) {
        /* nothing reads the last tree any more (flitter.h): its nodes are
         * the kernels' to refill. Released before the evaluation, on every
         * route: where the memory budget runs out must not depend on
         * whether, or when, a loop kernel runs. */
        node_release(rt->root);
        rt->root = NULL;
    }
    double t1 = monotonic();
    Node *root = eval_program(&ev);
    if (ev.stable_changed && !ev.interrupted) {
        /* a stable value changed: evaluate the frame again with the program
         * as first simplified (stable.h) */
        node_release(root);
        msgset_clear(&rt->errors[rt->cur]);
        msgset_clear(&rt->debug[rt->cur]);
        exports_clear(&rt->scope);
        stable_frame_done(rt->stables);
        program_release(rt->run_prog);
        rt->run_prog = NULL;
        kernel_scratch_clear(rt->kscratch);
        ev.prog = rt->prog;
        ev.stable_changed = false;
        root = eval_program(&ev);
    }
    kernel_scratch_frame_done(rt->kscratch);
    if (ev.interrupted) {
        /* discard the incomplete frame: the last tree (unless transient),
         * state and clock stay */
        node_release(root);
        rt->last_beat = prev_beat;
        rt->cur = prev;
        return 1;
    }
    node_release(rt->root);
    rt->root = root;
    rt->kernel_iterations += ev.kiters;
    rt->kernel_reused += ev.kreused;
    rt->kernel_straight += ev.kstraight;
    double t2 = monotonic();
    report(rt, FL_LOG_ERROR, "Execution error: ", &rt->errors[rt->cur], &rt->errors[prev]);
    report(rt, FL_LOG_DEBUG, "", &rt->debug[rt->cur], &rt->debug[prev]);

    double t3 = monotonic();
    run_renderers(rt, root, t);   /* physics systems, then counters */
    input_frame(rt->input, root, rt->state, rt->symtab);   /* the windows' new !key states */
    double t4 = monotonic();

    /* the beat counter (LANGUAGE.md §6.5) */
    double counter[3] = {60.0 / rt->period, rt->quantum, rt->start};
    Vec *val = vec_from_nums(counter, 3);
    state_set(rt->state, rt->counter_key, val);
    vec_release(val);

    /* values that became stable: simplify again with them known */
    if (stable_frame_done(rt->stables) && rt->globals.simplify) {
        Program *p = program_resimplify(rt->prog, &rt->globals, rt->symtab, rt->stables);
        if (p) {
            program_release(rt->run_prog);
            kernel_scratch_clear(rt->kscratch);
            rt->run_prog = p;
            pathlist_add_all(&rt->files, &p->files);
        }
    }

    rt->last_time = t;
    rt->frame++;
    rt->frame_time += 1.0 / rt->target_fps;
    if (rt->opts.realtime) {
        /* Flitter's EngineController.run: the next frame is due 1/fps
         * after this one; with a millisecond or more to spare the
         * performance rises by 0.001 (to 2), else it falls by 0.01 (to
         * 0.5); a frame that ends less than a millisecond before the next
         * is due is slow, and the schedule restarts from now */
        double now = (rt->paused_at >= 0 ? rt->paused_at : monotonic()) - rt->wall_start;
        double wait = rt->frame_time - now;
        rt->performance = wait > 0.001 ? fmin(rt->performance + 0.001, 2.0)
                                        : fmax(0.5, rt->performance - 0.01);
        rt->slow_frame = wait < 0.001;
        if (rt->slow_frame) rt->frame_time = now;
    }
    double t5 = monotonic();
    rt->stats.eval_seconds += t2 - t1;
    rt->stats.physics_seconds += t4 - t3;
    rt->stats.other_seconds += (t1 - t0) + (t3 - t2) + (t5 - t4);
    return 0;
}

uint64_t rt_kernel_iterations(const fl_runtime *rt) { return rt->kernel_iterations; }

uint64_t rt_kernel_reused(const fl_runtime *rt) { return rt->kernel_reused; }

uint64_t rt_kernel_straight(const fl_runtime *rt) { return rt->kernel_straight; }

void fl_get_stats(const fl_runtime *rt, fl_stats *out)
{
    if (!out) return;
    if (!rt) {
        *out = (fl_stats){0};
        return;
    }
    *out = rt->stats;
    StateCounts c = state_counts(rt->state);
    out->state_gets = c.gets;
    out->state_sets = c.sets;
}

/* ====================================================================
 * Evaluating text in the script's scope (the REPL)
 * ==================================================================== */

static void exports_put(Exports *x, Str *name, Vec *value)
{
    for (uint32_t i = 0; i < x->count; i++) {
        if (str_eq(x->names[i], name)) {
            Vec *old = x->values[i];
            x->values[i] = vec_retain(value);
            vec_release(old);
            return;
        }
    }
    if (x->count == x->cap) {
        x->cap = x->cap ? x->cap * 2 : 16;
        x->names = realloc(x->names, x->cap * sizeof(Str *));
        x->values = realloc(x->values, x->cap * sizeof(Vec *));
        if (!x->names || !x->values) mem_oom();
    }
    x->names[x->count] = str_retain(name);
    x->values[x->count] = vec_retain(value);
    x->count++;
}

/* Engine names and defines, then the script's names, then fl_eval's. */
static void build_scope(const fl_runtime *rt, Globals *g)
{
    g->routes = rt->globals.routes;
    for (uint32_t i = 0; i < rt->globals.count; i++)
        globals_set(g, globals_add(g, rt->globals.names[i]->bytes), rt->globals.values[i]);
    const Exports *layers[2] = {&rt->scope, &rt->repl};
    for (int l = 0; l < 2; l++)
        for (uint32_t i = 0; i < layers[l]->count; i++)
            globals_set(g, globals_add(g, layers[l]->names[i]->bytes), layers[l]->values[i]);
}

/* Parse and evaluate [text] in the REPL scope (build_scope). Returns 1
 * when the text ended early, -1 with the message in [err] on a syntax
 * error or an interrupt, else 0 with the result in [*value] (new, NULL
 * for null) and the names a `let` bound in [bound]; [*errors] is the
 * number of run-time errors logged, plus one when the text had load-time
 * warnings (an unbound name). */
static int eval_in_scope(fl_runtime *rt, const char *text, size_t len, Vec **value,
                         Exports *bound, uint32_t *errors, Buf *err)
{
    *value = NULL;
    *errors = 0;
    Globals g = {0};
    build_scope(rt, &g);
    Buf perr = BUF_INIT;
    Program *p = program_load_text("<repl>", text, len, &g, rt->symtab, &perr);
    if (!p) {
        int rc = strstr(buf_cstr(&perr), "unexpected end of input") ? 1 : -1;
        if (rc < 0) buf_add(err, perr.data, perr.len);
        buf_free(&perr);
        globals_free(&g);
        return rc;
    }
    buf_free(&perr);
    log_warnings(rt, p);
    uint32_t warned = p->warnings.len ? 1 : 0;
    MsgSet errs = {0}, debug = {0};
    Eval ev = {
        .prog = p, .globals = &g, .state = rt->state, .symtab = rt->symtab,
        .errors = &errs, .debug = &debug, .modules = rt->modules, .exports = bound,
        .interrupt = rt->opts.interrupt, .noise_perms = rt->noise_perms, .file_memo = rt->file_memo,
    };
    Vec *v = eval_program_value(&ev);
    int rc = 0;
    report(rt, FL_LOG_ERROR, "Execution error: ", &errs, &(MsgSet){0});
    report(rt, FL_LOG_DEBUG, "", &debug, &(MsgSet){0});
    *errors = errs.count + warned;
    if (ev.interrupted) {
        /* incomplete: bind and print nothing */
        buf_puts(err, "<repl>: error: interrupted\n");
        exports_clear(bound);
        vec_release(v);
        v = NULL;
        rc = -1;
    }
    *value = v;
    msgset_clear(&errs);
    msgset_clear(&debug);
    program_release(p);
    globals_free(&g);
    return rc;
}

/* The REPL's text of a result [v]: value text (FORMATS.md §1), except
 * that a node is written with its tags, attributes and children as the
 * node-tree dump writes it (FORMATS.md §3), starting on a line of its own;
 * the other elements between nodes are joined by `;` on their own lines. */
static void result_text(Buf *out, const Vec *v, const SymTab *st)
{
    bool nodes = false;
    uint32_t n = vec_len(v);
    if (v && !vec_is_num(v))
        for (uint32_t i = 0; i < n && !nodes; i++) nodes = vec_celems(v)[i].kind == EL_NODE;
    if (!nodes) {
        fmt_value(out, v, st);
        buf_putc(out, '\n');
        return;
    }
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < n;) {
        if (e[i].kind == EL_NODE) {
            fmt_tree(out, e[i].node, st);
            i++;
            continue;
        }
        for (; i < n && e[i].kind != EL_NODE; i++) {
            Vec *item = vec_item(v, i);
            fmt_value(out, item, st);
            vec_release(item);
            buf_putc(out, i + 1 < n && e[i + 1].kind != EL_NODE ? ';' : '\n');
        }
    }
}

int rt_eval(fl_runtime *rt, const char *text, size_t len, Buf *out, Buf *err)
{
    Exports bound = {0};
    Vec *v;
    uint32_t errors;
    int rc = eval_in_scope(rt, text, len, &v, &bound, &errors, err);
    if (rc != 0) return rc;
    for (uint32_t i = bound.count; i-- > 0;) {
        exports_put(&rt->repl, bound.names[i], bound.values[i]);
        buf_printf(out, "%s = ", bound.names[i]->bytes);
        result_text(out, bound.values[i], rt->symtab);
    }
    if (v || !bound.count) {
        /* an expression: its value is `_` from now on */
        Str *last = str_from("_");
        exports_put(&rt->repl, last, v);
        str_release(last);
        result_text(out, v, rt->symtab);
    }
    vec_release(v);
    exports_clear(&bound);
    return 0;
}

int rt_state_set_expr(fl_runtime *rt, const char *key_expr, const char *value_expr, Buf *out,
                      Buf *err)
{
    const char *texts[2] = {key_expr, value_expr};
    Vec *v[2] = {NULL, NULL};
    int rc = 0;
    for (int k = 0; k < 2 && rc == 0; k++) {
        Exports bound = {0};
        uint32_t errors;
        rc = eval_in_scope(rt, texts[k], strlen(texts[k]), &v[k], &bound, &errors, err);
        if (rc == 1) {
            buf_printf(err, "<repl>: error: the %s ended early (unexpected end of input)\n",
                       k ? "value" : "key");
        } else if (rc == 0 && bound.count) {
            buf_printf(err, "<repl>: error: the %s is a `let`; expected an expression\n",
                       k ? "value" : "key");
        } else if (rc == 0 && errors) {
            buf_printf(err, "<repl>: error: the %s had errors or warnings (state unchanged)\n",
                       k ? "value" : "key");
        } else if (rc == 0 && k == 0 && !v[0]) {
            buf_puts(err, "<repl>: error: the key is null\n");
        } else {
            exports_clear(&bound);
            continue;
        }
        rc = -1;
        exports_clear(&bound);
    }
    if (rc == 0) {
        fmt_value(out, v[0], rt->symtab);
        buf_puts(out, " = ");
        fmt_value(out, v[1], rt->symtab);
        buf_putc(out, '\n');
        state_set(rt->state, v[0], v[1]);
    }
    vec_release(v[0]);
    vec_release(v[1]);
    return rc;
}

void fl_eval_reset(fl_runtime *rt)
{
    if (rt) exports_clear(&rt->repl);
}

const Str *const *rt_scope_names(const fl_runtime *rt, size_t *n)
{
    fl_runtime *m = (fl_runtime *)rt;
    size_t total = rt->globals.count + rt->scope.count + rt->repl.count;
    free(m->scope_names);
    m->scope_names = malloc((total ? total : 1) * sizeof(Str *));
    if (!m->scope_names) mem_oom();
    size_t k = 0;
    for (uint32_t i = 0; i < rt->globals.count; i++) m->scope_names[k++] = rt->globals.names[i];
    for (uint32_t i = 0; i < rt->scope.count; i++) m->scope_names[k++] = rt->scope.names[i];
    for (uint32_t i = 0; i < rt->repl.count; i++) m->scope_names[k++] = rt->repl.names[i];
    m->nscope_names = k;
    *n = k;
    return (const Str *const *)m->scope_names;
}

/* ====================================================================
 * Saved state
 * ==================================================================== */

/* The loaded script as a state file names it (statefile.h): its real
 * path (as loaded when it cannot be resolved) and the hash of its bytes
 * now (0 when it cannot be read). False when no script is loaded from a
 * file. o->script is malloc'd. */
static bool script_origin(const fl_runtime *rt, StateOrigin *o)
{
    if (!rt->prog || !rt->prog->path) return false;
    o->script = realpath(rt->prog->path, NULL);
    if (!o->script) o->script = mem_strdup(rt->prog->path);
    Buf text = BUF_INIT;
    o->hash = file_read_regular(rt->prog->path, &text) ? statefile_hash(text.data ? text.data : "",
                                                                         text.len) : 0;
    buf_free(&text);
    return true;
}

int rt_save_state(const fl_runtime *rt, const char *path, Buf *err)
{
    StateClock c = {rt->frame, rt->frame_time, rt->last_time, rt->last_beat,
                    rt->period, rt->quantum, rt->start};
    StateOrigin o = {NULL, 0};
    bool named = script_origin(rt, &o);
    int rc = statefile_save(rt->state, rt->symtab, &c, named ? &o : NULL, path, NULL, err);
    free(o.script);
    return rc;
}

int rt_restore_state(fl_runtime *rt, const char *path, Buf *err)
{
    StateClock c;
    StateOrigin saved = {NULL, 0}, now = {NULL, 0};
    if (statefile_load(rt->state, rt->symtab, &c, &saved, path, err) != 0) return -1;
    /* another script's state: say so and go on (a script edited since is
     * the same script: live coding) */
    if (saved.script && script_origin(rt, &now) && strcmp(saved.script, now.script) != 0 &&
        saved.hash != now.hash)
        emit(rt, FL_LOG_WARNING, "%s: warning: state saved by %s, resumed by %s", path,
             saved.script, now.script);
    free(saved.script);
    free(now.script);
    rt->frame = c.frame;
    rt->frame_time = c.time;
    rt->last_time = c.last_time;
    rt->last_beat = c.last_beat;
    rt->period = c.period;
    rt->quantum = c.quantum;
    rt->start = c.start;
    return 0;
}

void fl_reset_state(fl_runtime *rt)
{
    if (rt) state_clear(rt->state);
}

const Node *rt_root(const fl_runtime *rt) { return rt->root; }
Pictures *rt_pictures(fl_runtime *rt) { return rt->pictures; }
const fl_options *rt_options(const fl_runtime *rt) { return &rt->opts; }
Input *rt_input(fl_runtime *rt) { return rt->input; }
double rt_beat(const fl_runtime *rt) { return rt->last_beat; }

const Vec *rt_global(const fl_runtime *rt, const char *name, size_t len)
{
    int i = globals_find(&rt->globals, name, len);
    return i >= 0 ? rt->globals.values[i] : NULL;
}

MemBudget *rt_budget(fl_runtime *rt) { return &rt->budget; }

bool rt_call_distances(fl_runtime *rt, const Vec *fn, const double *xyz, size_t n, double *out)
{
    MsgSet errs = {0}, debug = {0};
    Eval ev = {
        .prog = rt->prog, .globals = &rt->globals, .state = NULL, .symtab = rt->symtab,
        .errors = &errs, .debug = &debug, .modules = rt->modules,
        .interrupt = rt->opts.interrupt, .noise_perms = rt->noise_perms,
    };
    Pool *prev = pool_enter(rt->pool);
    bool ok = true;
    for (size_t i = 0; i < n; i++) {
        Vec *p = vec_from_nums(xyz + i * 3, 3);
        Vec *r = eval_call_value(&ev, fn, &p, 1);
        out[i] = vec_is_num(r) && vec_len(r) == 1 ? vec_cnums(r)[0] : NAN;
        vec_release(r);
        vec_release(p);
        if (ev.interrupted || (rt->opts.interrupt && *rt->opts.interrupt)) {
            ok = false;
            break;
        }
    }
    pool_leave(prev);
    report(rt, FL_LOG_ERROR, "Execution error: ", &errs, &rt->sdf_errors);
    for (uint32_t i = 0; i < errs.count; i++) msgset_add(&rt->sdf_errors, errs.items[i]);
    msgset_clear(&errs);
    msgset_clear(&debug);
    return ok;
}

const char *rt_script_path(const fl_runtime *rt) { return rt->prog ? rt->prog->path : NULL; }

bool rt_realtime(const fl_runtime *rt) { return rt->opts.realtime; }

size_t fl_program_files(fl_runtime *rt, const char **out, size_t cap)
{
    if (!rt || !rt->prog) return 0;
    if (!out) cap = 0;   /* a NULL [out] receives nothing */
    for (size_t i = 0; i < rt->files.count && i < cap; i++) out[i] = rt->files.paths[i];
    return rt->files.count;
}
StateDict *rt_state(fl_runtime *rt) { return rt->state; }
const SymTab *rt_symbols(const fl_runtime *rt) { return rt->symtab; }
long fl_frame_count(const fl_runtime *rt) { return rt ? rt->frame : -1; }
double fl_frame_time(const fl_runtime *rt) { return rt ? rt->last_time : NAN; }
double fl_target_fps(const fl_runtime *rt) { return rt ? rt->target_fps : NAN; }

double fl_next_frame_time(const fl_runtime *rt) { return rt ? rt->frame_time : NAN; }

double fl_frame_wait(const fl_runtime *rt)
{
    if (!rt) return NAN;
    if (!rt->opts.realtime || !rt->clock_started) return 0;
    double now = rt->paused_at >= 0 ? rt->paused_at : monotonic();
    return rt->frame_time - (now - rt->wall_start);
}

void fl_clock_pause(fl_runtime *rt, bool paused)
{
    if (!rt) return;
    if (paused && rt->paused_at < 0) {
        rt->paused_at = monotonic();
    } else if (!paused && rt->paused_at >= 0) {
        rt->wall_start += monotonic() - rt->paused_at;   /* `time` goes on from where it stopped */
        rt->paused_at = -1;
    }
}

static const Vec *frame_name(void *ctx, const char *name, size_t len)
{
    return rt_global(ctx, name, len);
}

/* Engine name [name] of the last frame when it is one number, else [dflt]. */
static double global_num(const fl_runtime *rt, const char *name, double dflt)
{
    const Vec *v = rt_global(rt, name, strlen(name));
    return vec_is_scalar(v) ? vec_scalar(v) : dflt;
}

void rt_graph_frame(const fl_runtime *rt, GraphFrame *f)
{
    *f = (GraphFrame){.frame = fl_frame_count(rt) - 1, .beat = global_num(rt, "beat", 0),
                      .quantum = global_num(rt, "quantum", 4), .tempo = global_num(rt, "tempo", 120),
                      .delta = global_num(rt, "delta", 0), .time = global_num(rt, "time", 0),
                      .fps = fl_target_fps(rt), .performance = global_num(rt, "performance", 1),
                      .realtime = rt->opts.realtime, .script = rt_script_path(rt)};
}

int rt_render(fl_runtime *rt, bool windows)
{
    if (rt->opts.debug.no_draw && !windows) return 0;
    /* a tree whose windows hold a function (an SDF's, called back while
     * drawn) marks the pictures as drawn here from now on: the graph may
     * keep that function, which no drawing thread may then release */
    pictures_calls_back(rt->pictures, rt->root);
    GraphFrame f;
    rt_graph_frame(rt, &f);
    f.name = frame_name;
    f.ctx = rt;
    return pictures_render(rt->pictures, rt->root, &f, windows);
}

Node *rt_hold_root(fl_runtime *rt) { return node_retain(rt->root); }

bool rt_no_draw(const fl_runtime *rt) { return rt->opts.debug.no_draw; }

uint32_t rt_hold_globals(const fl_runtime *rt, Str ***names, Vec ***values)
{
    uint32_t n = rt->globals.count;
    *names = n ? malloc(n * sizeof **names) : NULL;
    *values = n ? malloc(n * sizeof **values) : NULL;
    if (n && (!*names || !*values)) mem_oom();
    for (uint32_t i = 0; i < n; i++) {
        (*names)[i] = str_retain(rt->globals.names[i]);
        (*values)[i] = vec_retain(rt->globals.values[i]);
    }
    return n;
}

void rt_release_held(fl_runtime *rt, Node *root, uint32_t n, Str **names, Vec **values)
{
    /* inside the runtime's budget and pool, as fl_step releases a tree */
    MemHandler prev = rt_enter(rt);
    Pool *pp = pool_enter(rt->pool);
    node_release(root);
    for (uint32_t i = 0; i < n; i++) {
        str_release(names[i]);
        vec_release(values[i]);
    }
    pool_leave(pp);
    mem_leave(prev);
    free(names);
    free(values);
}
