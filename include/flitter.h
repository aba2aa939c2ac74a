/* flitter.h: the public interface of libflitter, the Flitter language and
 * its !physics engine as an embeddable C library.
 *
 * A `fl_runtime` is one interpreter: a loaded program, its state
 * dictionary, its physics systems, its symbol table and its clock. Nothing
 * is global, so an embedder may run several runtimes in one process (each
 * used by one thread at a time).
 *
 * Typical use (samples/embed/embed.c is a complete program):
 *     fl_runtime *rt = fl_new(NULL);
 *     if (fl_load(rt, "petri.fl") != 0) fprintf(stderr, "%s", fl_error(rt));
 *     for (int i = 0; i < 300; i++) fl_step(rt);
 *     double xy[2];
 *     fl_state_get_numbers(rt, ":dish;0", xy, 2);
 *     fl_free(rt);
 *
 * Values cross this interface as numbers, or as value text (FORMATS.md §1):
 * the text the state dump prints, e.g. `:dish;0` for the vector of the
 * symbol `dish` and the number 0, or `1;2.5` for two numbers. A text given
 * to the library (a state key, a value, a define) is split on `;`; each part
 * is `:name` (a symbol), a number with optional `_` separators and SI or
 * angle suffix (LANGUAGE.md §1.3), a time code, or else a string; the empty
 * text is null. In state keys and values (not in defines, which follow
 * `-D`), a part that is `-` followed by a number is that number negated.
 * A string part is taken as is, without quotes: `name` and the dump's
 * `"name"` are different texts.
 *
 * Ownership: every `const char *` the library returns is owned by the
 * runtime and stays valid until the next call on that runtime; text handed
 * to a callback is valid only during the call. The library never keeps a
 * pointer the caller passed in, except the option callbacks' [ctx].
 *
 * Errors: functions that can fail return a negative number and leave a
 * message, ending in a newline, for fl_error(). A NULL pointer where a
 * function's comment does not allow one, or a size past its stated limit,
 * is such an error (the value its `errors:` line gives; a void function
 * does nothing), never a crash. A NULL output array receives nothing,
 * whatever its capacity. A NULL runtime cannot hold a message: the call
 * returns its error value and fl_error(NULL) a fixed text. Out of memory
 * is the only abort: the message goes to the runtime's error callback (fl_options.error)
 * first. Script run-time errors do not fail a call: they are logged
 * (fl_options.log) and the frame goes on with null (LANGUAGE.md §4.16).
 *
 * Only standard C headers are included here; every symbol the library
 * exports starts with `fl_`.
 */
#ifndef FLITTER_H
#define FLITTER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Marks the functions of this interface: the only symbols a shared
 * libflitter exports (the library is built with -fvisibility=hidden). */
#if defined(FL_BUILDING_LIBRARY) && defined(__GNUC__)
#define FL_API __attribute__((visibility("default")))
#else
#define FL_API
#endif

/* The version of this header; fl_version() gives the library's. */
#define FL_VERSION_MAJOR 0
#define FL_VERSION_MINOR 1
#define FL_VERSION_PATCH 0
#define FL_VERSION_STRING "0.1.0"

/* The library's version as "MAJOR.MINOR.PATCH" (static storage). */
FL_API const char *fl_version(void);

typedef struct fl_runtime fl_runtime;

/* The kinds of line sent to fl_options.log. */
enum {
    FL_LOG_ERROR = 0,   /* `Execution error: ...` and `Physics error: ...` lines */
    FL_LOG_WARNING,     /* load-time and engine warnings (`PATH: warning: ...`) */
    FL_LOG_DEBUG        /* the output of the script's debug() calls */
};

/* Receives one message line of [kind] (FL_LOG_*), without its newline.
 * [line] is valid only during the call. The callback must not call back
 * into the runtime that logged. */
typedef void (*fl_log_fn)(void *ctx, int kind, const char *line);

/* Receives the message of a fatal error ("out of memory") just before the
 * library calls abort(); [message] has no newline. It may save or report
 * what it can, or leave the process itself (exit, longjmp out of the whole
 * runtime: the runtime must then not be used again); when it returns, the
 * library aborts. */
typedef void (*fl_error_fn)(void *ctx, const char *message);

/* Receives a piece of output text ([len] bytes, not NUL-terminated; dumps
 * arrive in one or more pieces). Valid only during the call. */
typedef void (*fl_write_fn)(void *ctx, const char *text, size_t len);

/* The library's routes, for tests and measurements: each switch selects
 * another way to the same results (bit for bit), slower or with less
 * memory reused, so that every fast route can be checked against a
 * literal one. All zero (fl_default_options) is what a user runs. Read
 * once, when the runtime is made (fl_new); the library reads no
 * environment variables: the flitter command maps its FLITTER_*
 * variables onto these (the name after each field; COMMAND-LINE.md). */
typedef struct fl_debug_options {
    bool no_pool;          /* FLITTER_NOPOOL: every block from malloc and back
                              to free, none kept for reuse (for valgrind) */
    bool no_fast;          /* FLITTER_NOFAST: programs run on the tree-walking
                              evaluator alone, nothing compiled */
    bool no_kernel;        /* FLITTER_NOKERNEL: loops are not compiled into
                              loop kernels (the compiled routes still run) */
    bool no_kernel_reuse;  /* FLITTER_KERNEL_REUSE=0: a loop kernel builds its
                              nodes afresh instead of refilling last frame's */
    unsigned kernel_chunk; /* FLITTER_KERNEL_CHUNK: iterations a loop kernel
                              hands a thread at a time (0: its own choice) */
    unsigned kernel_window;/* FLITTER_KERNEL_WINDOW: iterations a loop kernel
                              keeps in flight (0: its own choice) */
    bool no_templates;     /* FLITTER_NOTEMPLATES: the simplifier unrolls each
                              loop iteration alone, no shared templates */
    bool check_templates;  /* FLITTER_TEMPLATE_CHECK: each templated copy is
                              also simplified alone and must match (slow) */
    int simd;              /* FLITTER_SIMD: the physics pair tiles' vector
                              width, FL_SIMD_* */
    int impostors;         /* FLITTER_CANVAS3D_IMPOSTORS: how !canvas3d draws
                              spheres, FL_IMPOSTORS_* */
    int occlusion;         /* FLITTER_CANVAS3D_OCCLUSION: !canvas3d's occlusion
                              culling, FL_OCCLUSION_* */
    bool no_light_culling; /* FLITTER_CANVAS3D_CULLING=0: !canvas3d draws every
                              mesh with all of its group's lights, none left
                              out as unable to reach it */
    bool no_draw;          /* FLITTER_NODRAW: a frame is drawn only when a front
                              end asks for a window's picture; !record writes
                              nothing (to time evaluation and physics alone) */
} fl_debug_options;

/* fl_debug_options.simd */
enum {
    FL_SIMD_AUTO = 0,      /* AVX-512 where the processor has it, each system
                              timing the AVX-512VL tiles against it */
    FL_SIMD_PORTABLE,      /* "portable": plain C */
    FL_SIMD_AVX2,          /* "avx2" */
    FL_SIMD_AVX2_VL,       /* "avx2-avx512vl" */
    FL_SIMD_AVX512         /* "avx512" (anything else the variable says) */
};

/* fl_debug_options.impostors */
enum {
    FL_IMPOSTORS_OCTAGONS = 0, /* spheres as impostors on octagons */
    FL_IMPOSTORS_BOX,          /* "box": impostors on boxes */
    FL_IMPOSTORS_OFF           /* "0": spheres as meshes */
};

/* fl_debug_options.occlusion */
enum {
    FL_OCCLUSION_AUTO = 0, /* culled where the scene gains by it */
    FL_OCCLUSION_ALWAYS,   /* "1" */
    FL_OCCLUSION_NEVER     /* "0" */
};

typedef struct fl_options {
    double fps;          /* target frame rate (--fps), frames per second; default 60 */
    long frames;         /* planned frame count for `run_time`, or -1 (unknown) */
    bool realtime;       /* pace on the wall clock instead of lockstep */
    long max_physics_steps; /* most simulation steps one !physics system may
                               take in one frame (default 10000; 0: no limit);
                               past it the simulation clock falls behind
                               `time` (logged once per runtime) */
    volatile int *interrupt; /* polled inside loops, calls and physics steps;
                                when *interrupt becomes non-zero fl_step ends
                                the frame early and discards it (NULL: none) */
    int threads;         /* threads of the physics engine and the evaluator's loop
                            kernels (--threads); 0: every core */
    int pairs;           /* physics pair route (--pairs): FL_PAIRS_* */
    int particles;       /* physics particle-pass route (--particles): FL_PARTICLES_* */
    int physics;         /* physics behaviour (--physics): FL_PHYSICS_*; the
                            script's `%pragma physics` overrides it */
    bool no_simplify;    /* --nosimplify: run the program as parsed, without the
                            load-time simplifier (LANGUAGE.md §4.17) */
    size_t max_memory;   /* --max-memory: the memory budget in bytes (0: the
                            default, half of physical memory and at most half
                            of RLIMIT_AS). Vectors, strings, nodes, the state
                            file's numbers, !physics systems and the parser
                            are charged against it before they allocate; past
                            it an expression gives null with `Execution error:
                            ... out of memory` (LANGUAGE.md §4.16), a load or
                            fl_state_load fails with `PATH:LINE:COL: error:
                            out of memory` (the call returns its error value,
                            see fl_error), and an oversized !physics system is
                            skipped with a `Physics error:`. The budget is
                            per runtime; it is reached through a per-thread
                            pointer that every fl_ call sets on entry. Only an
                            allocation that fails inside the budget (the
                            machine really out of memory) still aborts. */
    fl_log_fn log;       /* message lines; NULL: errors and warnings to stderr,
                            debug lines to stdout, each with a newline */
    fl_error_fn error;   /* fatal errors; NULL: `flitter: MESSAGE` on stderr */
    void *ctx;           /* passed to log and error */
    int view_axes[2];    /* --view-axes: the flat projection of the physics
                            view (--view, fl_view, fl_draw_view): the
                            coordinates (0 x, 1 y, 2 z, 3 w; fl_parse_view_axes)
                            on its horizontal and vertical axes, for every
                            system that has both. {0, 0} (the default, and
                            anything but two different numbers of 0..3): a 3D
                            system is drawn in perspective, lit, through the
                            !canvas3d renderer (flat on x/y when no
                            OpenGL context can be made, said once), other
                            systems on x/y */
    bool transient_tree; /* the last frame's node tree is only read between
                            fl_step calls: fl_step releases it before it
                            evaluates the next frame, so that the nodes its
                            loops built are refilled in place in the very
                            next frame (otherwise in the one after); an
                            interrupted fl_step then leaves no tree (as
                            before the first frame) instead of the last
                            one. The next frame may then reuse the last
                            tree's memory: under max_memory a frame can fit
                            that would not with the last tree kept. Default
                            false; `flitter run` sets it when nothing reads
                            a tree after the last frame. */
    double model_cache;  /* --modelcache: seconds a 3D model (a file, CSG, an
                            SDF) no frame has used stays cached with its mesh
                            (0: Flitter's default, 300) */
    fl_debug_options debug; /* routes for tests and measurements (above);
                               all zero: the defaults */
} fl_options;

/* fl_options.pairs: the physics pair loop. Every route gives the same bits. */
enum {
    FL_PAIRS_DEFAULT = 0,  /* fast */
    FL_PAIRS_FAST,         /* neighbour grid and threads where they apply */
    FL_PAIRS_NAIVE         /* the reference all-pairs loop, one thread */
};

/* fl_options.particles: the route of the physics particle pass (the
 * per-particle appliers, barriers and the step). Every route gives the
 * same bits. */
enum {
    FL_PARTICLES_DEFAULT = 0,  /* fast */
    FL_PARTICLES_FAST,         /* compiled per dimension count, threads where they apply */
    FL_PARTICLES_LITERAL       /* PHYSICS-ENGINE.md §4 as written, one particle at a time */
};

/* fl_options.physics: which physics. Flitter 1.0.0b28 departs from its own
 * documentation (PHYSICS.md) at four places (PHYSICS-ENGINE.md [doc]):
 * the ease of force appliers and of a particle's own force, !field's
 * charge, and a barrier's max without a min. */
enum {
    FL_PHYSICS_DOCUMENTED = 0, /* PHYSICS.md: what Flitter documents (the default) */
    FL_PHYSICS_UPSTREAM        /* what Flitter 1.0.0b28 does, bit for bit */
};

/* The defaults: 60 fps, unknown frames, lockstep, 10000 physics steps per
 * frame, no interrupt flag, every core, the fast routes,
 * simplifier on, default log and error output. Start from these and change
 * fields, so that fields added later get their defaults. */
FL_API fl_options fl_default_options(void);

/* Parse a --max-memory value: "N", "NK", "NM" or "NG" (binary multiples,
 * case-insensitive, N a whole number > 0) into *[out] bytes; returns false,
 * leaving *[out] alone, for anything else (a NULL [text] or [out] too). */
FL_API bool fl_parse_memory(const char *text, size_t *out);
/* Parse a --pairs value ("naive" or "fast") into *[out] (FL_PAIRS_*);
 * returns false, leaving *[out] alone, for anything else (a NULL [text]
 * or [out] included; the same in the next two). */
FL_API bool fl_parse_pairs(const char *text, int *out);
/* Parse a --particles value ("literal" or "fast") into *[out]
 * (FL_PARTICLES_*); returns false, leaving *[out] alone, for anything else. */
FL_API bool fl_parse_particles(const char *text, int *out);
/* Parse a --physics value ("documented" or "upstream") into *[out]
 * (FL_PHYSICS_*); returns false, leaving *[out] alone, for anything else. */
FL_API bool fl_parse_physics(const char *text, int *out);

/* Parse a --view-axes value, two of x, y, z, w separated by ';' and not
 * the same (e.g. "x;z"), into out[0], out[1] (0..3: fl_options.view_axes);
 * returns false, leaving [out] alone, for anything else. */
FL_API bool fl_parse_view_axes(const char *text, int out[2]);

/* A new runtime with empty state and no program; [opts] NULL means
 * fl_default_options(). The options are copied.
 *   errors: aborts only when out of memory (after opts->error). */
FL_API fl_runtime *fl_new(const fl_options *opts);
/* Free [rt] and everything it owns (NULL is a no-op). */
FL_API void fl_free(fl_runtime *rt);

/* The message of the last failed call on [rt] (one or more lines, each
 * ending in a newline), or "" when the last failing call left none. Owned
 * by [rt]; valid until the next call that can fail. For a NULL [rt], a
 * fixed text (static storage) saying that the runtime is NULL. */
FL_API const char *fl_error(const fl_runtime *rt);

/* Bind [name] to the value of the text [value_text] for every frame (`-D
 * NAME=VALUE`), read as Flitter reads it (FORMATS.md §4 and Flitter's
 * engine/__main__.py `keyvalue`): the text split at every `;`, each part a
 * symbol if it starts with `:`, else a number as Python's float() reads it
 * (`-3`, `+2.5`, `1e3`, `inf`, `nan`, `1_000`) with an optional SI or angle
 * suffix (`10k`, `5m`, `90deg`), else a time code (`1:30` is 90), else the
 * part's text itself; so "" is the empty string and "-1;2" the vector
 * -1;2. Call it before fl_load: the loaded program sees the names that
 * were defined when it was loaded.
 *   errors: returns -1 with fl_error() text for an empty or invalid name
 *           or a NULL [name] or [value_text] (-1 for a NULL [rt]), else 0. */
FL_API int fl_define(fl_runtime *rt, const char *name, const char *value_text);
/* Bind [name] to the vector of the [n] numbers at [values] (exactly; n = 0
 * binds null), as fl_define does, without going through text.
 *   errors: as fl_define's, and -1 with fl_error() text for a NULL
 *           [values] with [n] > 0 or [n] over the longest vector. */
FL_API int fl_define_numbers(fl_runtime *rt, const char *name, const double *values, size_t n);

/* Load (or reload, keeping the state) the script at [path]. Pragmas take
 * effect at the next fl_step (LANGUAGE.md §6.4).
 *   errors: returns -1 with `PATH:LINE:COL: error: MESSAGE` (the source
 *           line and a caret under it) for fl_error(); the previous
 *           program, if any, stays loaded. Load-time warnings (unbound
 *           names) go to the log as FL_LOG_WARNING. -1 for a NULL [path]
 *           (with fl_error() text) or [rt]. */
FL_API int fl_load(fl_runtime *rt, const char *path);
/* Load program text [text] of [len] bytes from memory; [name] is used in
 * messages and to resolve relative file names. Same errors as fl_load, and
 * -1 for a NULL [name], a NULL [text] with [len] > 0 (NULL with 0 is the
 * empty program) or [len] over a script file's limit (256 MiB). */
FL_API int fl_load_text(fl_runtime *rt, const char *name, const char *text, size_t len);

/* Evaluate and simulate one frame: compute the frame names (FORMATS.md
 * §5), evaluate the program into a node tree, run every top-level !physics
 * and !counter node, write the beat counter, then advance the clock by
 * 1/fps seconds (lockstep) or to the wall clock (realtime).
 *   errors: the frame's new run-time errors are logged as
 *           `Execution error: MESSAGE`; a !physics system with a non-finite
 *           `time`/`resolution` skips the frame and one needing more than
 *           max_physics_steps steps is cut short (each logged once per
 *           runtime). Returns -1 when no program is loaded, or when
 *           the clock is at its limit (frame 2^53, or a next time or beat
 *           that would not be finite: the frame is not run, so the clock
 *           can still be saved), with fl_error() text, or [rt] is NULL; 1 when
 *           *interrupt stopped the evaluation (the frame is discarded:
 *           tree, state, clock and frame count stay as they were; an
 *           interrupt during physics steps keeps the frame, with fewer
 *           steps), else 0. */
FL_API int fl_step(fl_runtime *rt);

/* Number of frames evaluated so far (-1 for a NULL [rt]). */
FL_API long fl_frame_count(const fl_runtime *rt);
/* The `time` of the last evaluated frame, in seconds (0 before the first;
 * NaN for a NULL [rt], as in the next two). */
FL_API double fl_frame_time(const fl_runtime *rt);
/* The `time` the next frame will have, in seconds: 0 (or a restored
 * state's clock) before the first, then the last frame's plus 1/fps, or
 * the wall clock's after a slow realtime frame (Flitter's frame_time, by
 * which its --runtime counts). NaN for a NULL [rt]. */
FL_API double fl_next_frame_time(const fl_runtime *rt);
/* The frame rate the runtime steps at, in frames per second: the `fps`
 * option, or the loaded program's `%pragma fps` once a frame has applied
 * it. A realtime embedder paces fl_step with fl_frame_wait(). */
FL_API double fl_target_fps(const fl_runtime *rt);
/* Realtime (fl_options.realtime): seconds from now until the next frame
 * is due (negative when it is late); 0 in lockstep and before the first
 * frame. The clock follows Flitter's EngineController.run: a frame's
 * `time` is the last one's plus 1/fps; a frame that ends less than a
 * millisecond before the next is due sets `slow_frame` and restarts the
 * schedule from the wall clock; `performance` starts at 1 and rises by
 * 0.001 a frame (to 2) while frames end a millisecond early or more, else
 * falls by 0.01 (to 0.5). A realtime front end sleeps until this is below
 * a millisecond, then calls fl_step. */
FL_API double fl_frame_wait(const fl_runtime *rt);
/* Realtime: stop ([paused]) or restart the clock: while it is stopped
 * fl_frame_wait() stands still, and after it restarts `time` goes on from
 * where it stopped (a front end's pause key). No-op in lockstep and for a
 * NULL [rt]. */
FL_API void fl_clock_pause(fl_runtime *rt, bool paused);

/* {=====================================================================
 * The state dictionary
 * ===================================================================== */

/* Write the value text of the state value under the key [key_text] into
 * [buf] ([cap] bytes, NUL-terminated, truncated to fit; a NULL [buf]
 * receives nothing), like snprintf.
 *   returns: the length of the whole value text (without the NUL), or -1
 *            when no value is stored under that key (the empty key text
 *            is null, which is never stored), or -3 for a NULL [rt] or
 *            [key_text] (with fl_error() text for the latter). */
FL_API long fl_state_get(fl_runtime *rt, const char *key_text, char *buf, size_t cap);
/* Copy the numbers of the state value under [key_text] into [out] (at
 * most [cap] of them; a NULL [out] receives nothing).
 *   returns: the number of elements of the value (which may exceed [cap]),
 *            -1 when there is none, -2 when it is not all numbers (strings;
 *            a symbol counts as the number Flitter gives it), -3 as
 *            fl_state_get for a NULL [rt] or [key_text]. */
FL_API long fl_state_get_numbers(fl_runtime *rt, const char *key_text, double *out, size_t cap);
/* Store the value text [value_text] under [key_text] (both parsed as the
 * top of this file says); the empty value text deletes the entry.
 *   errors: returns -1 (state unchanged) with fl_error() text when the
 *           key text is empty or [key_text] or [value_text] is NULL; -1
 *           for a NULL [rt]. */
FL_API int fl_state_set(fl_runtime *rt, const char *key_text, const char *value_text);
/* Store the [n] numbers [values] under [key_text]; n = 0 deletes.
 *   errors: as fl_state_set, and -1 with fl_error() text for a NULL
 *           [values] with [n] > 0 or [n] over 2^26 (the longest vector a
 *           program may build, MAX_COMPOSE_LEN). */
FL_API int fl_state_set_numbers(fl_runtime *rt, const char *key_text, const double *values,
                                size_t n);
/* Number of entries in the state dictionary (0 for a NULL [rt]). */
FL_API size_t fl_state_count(const fl_runtime *rt);
/* Receives one state entry as key text and value text (valid during the
 * call); returns non-zero to stop the iteration. */
typedef int (*fl_state_fn)(void *ctx, const char *key_text, const char *value_text);
/* Call [fn] for every state entry, sorted by key text bytes (the order of
 * the state dump); [fn] must not change the state.
 *   returns: the number of entries visited; 0 for a NULL [rt], or for a
 *            NULL [fn] with fl_error() text. */
FL_API size_t fl_state_iterate(fl_runtime *rt, fl_state_fn fn, void *ctx);
/* Empty the state dictionary (the clock keeps running; NULL [rt]: no-op). */
FL_API void fl_reset_state(fl_runtime *rt);

/* Save the state dictionary and the clock to [path] atomically (the file
 * is replaced only when complete; FORMATS.md, `flitter run --state`).
 * Writes only what fl_restore_state reads back: a clock it would refuse
 * is not written.
 *   errors: returns -1 with a message for fl_error() (a NULL [path]
 *           included; -1 for a NULL [rt]); 0 on success. */
FL_API int fl_save_state(fl_runtime *rt, const char *path);
/* Restore the state dictionary and the clock from [path], so that the run
 * continues exactly where the saved one stopped.
 *   errors: returns -1 with a message for fl_error(), leaving everything
 *           untouched, when the file is missing, truncated or malformed
 *           or [path] is NULL (-1 for a NULL [rt]). */
FL_API int fl_restore_state(fl_runtime *rt, const char *path);

/* {=====================================================================
 * Dumps (written through [fn]; FORMATS.md)
 * ===================================================================== */

/* The state dump block of the last frame (FORMATS.md §2: `frame N time T`
 * then one `KEY = VALUE` line per entry, string keys starting with '_' left
 * out), as `flitter run --dump-state` prints it (before the first frame:
 * `frame -1 time 0`). A NULL [rt] or [fn] writes nothing (fl_error() text
 * for the latter). */
FL_API void fl_dump_state(fl_runtime *rt, fl_write_fn fn, void *ctx);
/* The node tree of the last frame (FORMATS.md §3), as `--dump-tree` prints
 * it.
 *   errors: returns -1 (writing nothing) with fl_error() text before the
 *           first frame or for a NULL [fn] (-1 for a NULL [rt]), else 0. */
FL_API int fl_dump_tree(fl_runtime *rt, fl_write_fn fn, void *ctx);
/* The loaded program as it will run (after the simplifier unless
 * no_simplify), as Flitter-like source (`--dump-simplified`).
 *   errors: returns -1 (writing nothing) with fl_error() text when no
 *           program is loaded or [fn] is NULL (-1 for a NULL [rt]). */
FL_API int fl_dump_program(fl_runtime *rt, fl_write_fn fn, void *ctx);
/* The tokens the parser reads from the script file [path] (after the
 * indentation filter: NL, INDENT, DEDENT), one a line: `LINE:COL KIND`,
 * then the token's source text when it has one (`--dump-tokens`).
 *   errors: returns -1 when the file cannot be read or at a lexical error
 *           (the tokens before it are written; `PATH:LINE:COL: error: ...`
 *           for fl_error()), else 0. As fl_dump_ast for NULL arguments. */
FL_API int fl_dump_tokens(fl_runtime *rt, const char *path, fl_write_fn fn, void *ctx);
/* The syntax tree of the script file [path] as parsed (before the
 * simplifier), one node a line, children indented two spaces: kind,
 * operator, names, literal value, `@LINE:COL`; fixed children marked `a:`,
 * `b:`, `c:` (`--dump-ast`).
 *   errors: returns -1 (writing nothing) when the file cannot be read or
 *           does not parse or [path] or [fn] is NULL, with the message
 *           for fl_error() (-1 for a NULL [rt]), else 0. */
FL_API int fl_dump_ast(fl_runtime *rt, const char *path, fl_write_fn fn, void *ctx);

/* {=====================================================================
 * Evaluating text (the REPL)
 * ===================================================================== */

/* Evaluate [text] ([len] bytes: an expression, or `let` bindings) in the
 * scope of the loaded script's top level as of the last frame (its `let`
 * and `func` names, the frame names, defines) plus the names bound by
 * earlier fl_eval calls; state lookups see the current state.
 *   output: through [fn]: the value text of an expression's result, or
 *           `NAME = VALUE` lines for the names a `let` bound, each ending
 *           in a newline; a node in a result is written with its tags,
 *           attributes and children as the node-tree dump writes it
 *           (FORMATS.md §3), on lines of its own. An expression's result
 *           is bound to the name `_` for later calls.
 *   errors: returns -1 with `<repl>:LINE:COL: error: ...` for fl_error()
 *           on a syntax error; returns 1 (writing nothing) when the text
 *           ended early, so a caller may read more lines; run-time errors
 *           go to the log; returns -1 with `<repl>: error: interrupted`
 *           (nothing bound or written) when *interrupt stopped it; -1 with
 *           fl_error() text for a NULL [text] with [len] > 0 or [len] over
 *           256 MiB (-1 for a NULL [rt]); 0 on success. A NULL [fn] drops
 *           the output. */
FL_API int fl_eval(fl_runtime *rt, const char *text, size_t len, fl_write_fn fn, void *ctx);
/* Evaluate the Flitter expressions [key_expr] and [value_expr] (NUL-
 * terminated) as fl_eval does, in the same scope, and store the value
 * under the key (the REPL's `:set :collapse 1`); a null value deletes the
 * entry. Binds no name (not `_` either).
 *   output: through [fn]: `KEY = VALUE` in value text with a newline
 *           (`KEY = null` after a deletion).
 *   errors: returns -1 with `<repl>...: error: ...` for fl_error(), the
 *           state unchanged, when either text does not parse, ends early
 *           or is a `let`, when either logged a run-time error, when the
 *           key is null, or when *interrupt stopped it; 0 on success. */
FL_API int fl_state_set_expr(fl_runtime *rt, const char *key_expr, const char *value_expr,
                             fl_write_fn fn, void *ctx);
/* Forget the names bound by fl_eval (NULL [rt]: no-op). */
FL_API void fl_eval_reset(fl_runtime *rt);
/* Call [fn] with each name visible to fl_eval (engine names and defines,
 * the script's top level, earlier fl_eval bindings), for completion, in
 * that order (a name bound in two of them comes twice); [fn] returns
 * non-zero to stop.
 *   returns: the number of names visited; 0 for a NULL [rt], or for a
 *            NULL [fn] with fl_error() text. */
FL_API size_t fl_scope_names(fl_runtime *rt, int (*fn)(void *ctx, const char *name), void *ctx);

/* The [i]-th name of the built-in functions (LANGUAGE.md §5), from 0, or
 * NULL past the last; static storage. For completion in a host's REPL. */
FL_API const char *fl_builtin_name(size_t i);

/* Write the value text of the number [x] (the shortest decimal text that
 * reads back to exactly [x], as the dumps print numbers: `0`, `-2.5`,
 * `1e+20`, `nan`, `inf`) into [buf] ([cap] bytes, NUL-terminated, truncated
 * to fit; a NULL [buf] receives nothing), like snprintf.
 *   returns: the length of the whole text (without the NUL). */
FL_API size_t fl_number_text(double x, char *buf, size_t cap);

/* {=====================================================================
 * Particles (lib/runtime/api_particles.c)
 * ===================================================================== */

/* Receives one particle: [id_text] is the value text of its id (e.g. `12`
 * or `:cell;3`; valid during the call), [position] and [velocity] its
 * [dims] coordinates (state units: positions in the system's units,
 * velocities in units per second of the system's clock). Returns non-zero
 * to stop. */
typedef int (*fl_particle_fn)(void *ctx, const char *id_text, const double *position,
                              const double *velocity, size_t dims);
/* Call [fn] (may be NULL, to count) for every particle of the !physics
 * system whose `state=` prefix is the value text [system_text] (e.g.
 * ":dish"), as the state dictionary holds it after the last frame: every
 * key P;ID with a numeric value that has a numeric P;ID;:velocity of the
 * same length (PHYSICS-ENGINE.md §2 step 8: anchors are written so too,
 * and come with the particles; the clock keys are not).
 * They come in the state dump's order (sorted by key text bytes); the
 * numbers are the stored doubles, bit for bit.
 *   returns: the number of particles visited, or -1 with fl_error() text
 *            for an empty or NULL [system_text] (-1 for a NULL [rt]). */
FL_API long fl_particles(fl_runtime *rt, const char *system_text, fl_particle_fn fn, void *ctx);

/* {=====================================================================
 * Pictures and trajectories
 * ===================================================================== */

/* What a run writes after its frames besides dumps (`flitter run`'s
 * --view, --trace and the scripts' own windows). Every field may be left
 * zero: fl_outputs_open(rt, NULL) renders the windows only. */
typedef struct fl_output_options {
    const char *view;     /* draw the !physics systems (discs by radius,
                             colour by charge, anchors, links, barriers) to
                             FILE.png or FILE.svg (the last frame), or
                             FILE.gif (an animation); NULL: none */
    long view_every;      /* .gif: a picture every K frames (0 or 1: all) */
    const char *trace;    /* write every particle's position and velocity to
                             FILE.csv or FILE.jsonl; NULL: none */
    long trace_every;     /* a trace row every K frames (0 or 1: all) */
    bool debug;           /* log each drawing node kind skipped as
                             unsupported, once (FL_LOG_WARNING) */
    const char *record;   /* record the first top-level !window/!offscreen
                             of every frame to FILE, as if it had a
                             `!record filename=FILE` child over all its
                             children (default attributes): FILE.png
                             replaced each frame, FILE.gif, or a video
                             FILE.mp4/.mov/.m4v/.mkv/.webm finished at
                             fl_outputs_close; a write error is logged
                             (FL_LOG_ERROR) once; NULL: none */
} fl_output_options;

typedef struct fl_outputs fl_outputs;

/* Open the outputs [o] asks for, for frames of [rt] (whose fps sets the
 * GIF frame delay and the video frame rate). `!window`/`!offscreen` nodes
 * with a `!record filename=...` are drawn with cairo and written (a PNG, an
 * animated GIF or a video, each under a temporary name renamed into place)
 * in every frame that fl_outputs_frame() is given.
 *   errors: NULL with fl_error() text when the --view or --trace file
 *           cannot be created or has an unknown extension (nothing is
 *           left open); NULL for a NULL [rt]; a NULL [o] asks for none. */
FL_API fl_outputs *fl_outputs_open(fl_runtime *rt, const fl_output_options *o);
/* After each fl_step() of [rt]: draw its windows, append the trace rows
 * and animation frames due (every K-th frame, counted from frame 0).
 * Windows that cannot be written are logged (FL_LOG_ERROR, once).
 *   errors: -1 with fl_error() text when the view or the trace cannot be
 *           written (that output then stops) or [out] is NULL (-1 for a
 *           NULL [rt]), else 0. */
FL_API int fl_outputs_frame(fl_outputs *out, fl_runtime *rt);
/* Whether fl_outputs_frame(out, rt) would draw pictures for [rt]'s last
 * frame: a window's !record writes a file in it, or --record's first
 * window is recorded (with no window shown by a front end, any !record
 * makes every frame drawn), or a frame of an animated --view is due (a 3D
 * system is drawn through OpenGL). Only then does fl_outputs_frame use the
 * render graph or OpenGL: a front end whose drawing thread holds
 * them (fl_picture_draw) runs such a frame's fl_outputs_frame there, with
 * the frame loop waiting, and any other on the frame loop's thread, beside
 * the drawing. False for a NULL [out] or [rt]. */
FL_API bool fl_outputs_draws(const fl_outputs *out, fl_runtime *rt);
/* Write the final --view picture (.png/.svg: of [rt]'s last frame, when
 * it ran any), finish animated GIFs and videos (they appear under their
 * names only now), close the files and free [out] (NULL is a no-op).
 *   errors: -1 when any output failed or could not be finished, a
 *           window's !record file included (the message of the last
 *           failure in fl_error()), else 0. With a NULL [rt], [out] is
 *           closed and freed without the final picture and the result is
 *           -1. */
FL_API int fl_outputs_close(fl_outputs *out, fl_runtime *rt);
/* Draw [rt]'s !physics systems as they are now to [path] (.png or .svg),
 * as fl_output_options.view does; [*nsystems] (may be NULL) gets the
 * number of systems drawn.
 *   errors: -1 with fl_error() text when [path] has another extension,
 *           cannot be written or is NULL (-1 for a NULL [rt]), else 0. */
FL_API int fl_view(fl_runtime *rt, const char *path, size_t *nsystems);
/* Whether an output file could be written at [path] now (a `--view`,
 * `--trace`, `--record` or `--state` file, checked before a run's first
 * frame): symbolic links are followed, a target that exists must be a
 * regular file, and a temporary is created next to it and removed (the
 * way every output is written: temporary, then rename).
 *   returns: 0 when it could; -1 with "PATH: REASON" (no newline) in
 *            [err] ([cap] bytes, NUL-terminated; a NULL [err] receives
 *            nothing) when not, e.g. no such directory, no permission, a
 *            directory or device, or "no file name" for a NULL [path]. */
FL_API int fl_check_output(const char *path, char *err, size_t cap);

/* {=====================================================================
 * Windows: a frame's pictures and input, for a front end that shows them
 * (the `flitter` command's SDL2 window; the library never opens a window)
 * ===================================================================== */

/* One top-level `!window` or `!offscreen` node of the last frame's tree,
 * in tree order (Flitter docs/windows.md). */
typedef struct fl_window_info {
    int width, height;   /* size=W;H in pixels (default 512;512; the same
                            bounds as !record's pictures) */
    char title[256];     /* title=, UTF-8, truncated to fit; "" when none
                            (a front end then shows the script's name) */
    bool offscreen;      /* an !offscreen node: drawn, never shown */
    int fullscreen;      /* fullscreen= : 1 true, 0 false, -1 not given */
    int vsync;           /* vsync= : 1 true, 0 false, -1 not given */
} fl_window_info;

/* The windows of [rt]'s last frame: returns how many top-level !window
 * and !offscreen nodes it has, and fills out[0 .. min(count, cap)) with
 * them (a NULL [out] receives nothing). 0 before the first frame and for a
 * NULL [rt]. */
FL_API size_t fl_windows(fl_runtime *rt, fl_window_info *out, size_t cap);

/* The picture of window [index] of [rt]'s last frame, read back into
 * [pixels]: [width] x [height] pixels (the window's own size,
 * fl_window_info), rows [stride] bytes apart, each pixel a native-endian
 * uint32_t 0xAARRGGBB: the sRGB encoding of the premultiplied light of
 * the window's picture and its alpha, as Flitter's !record stores them
 * (a !record of the window's children writes these values; copied over
 * black without blending they are what Flitter's window shows). The
 * picture is drawn by the runtime's render graph, once a frame, with
 * its !record files written then if fl_outputs_frame did not draw the
 * frame yet. A front end that has an OpenGL context of its own uses
 * fl_gl_window_texture instead: no read-back.
 *   errors: -1 with fl_error() text for an index past the last window, a
 *           size other than the window's, a NULL [pixels], or a stride
 *           below width*4 or not a multiple of 4; else 0 (node kinds that
 *           cannot be drawn are skipped, each logged once per runtime as a
 *           warning); -1 for a NULL [rt]. */
FL_API int fl_draw_window(fl_runtime *rt, size_t index, uint32_t *pixels, int width, int height,
                          size_t stride);

/* Draw [rt]'s windows with the OpenGL context that is current on the
 * calling thread (a front end's window context, OpenGL 3.3 core or later)
 * from now on, instead of a context of the library's own, and composite
 * each window's picture every frame: fl_gl_window_texture then hands the
 * picture over with no read-back. Every later call on [rt] that draws
 * (fl_outputs_frame, fl_draw_window, fl_gl_window_texture, fl_free) must
 * come with that context current on its thread; GL objects of the
 * library's own context, if any, are dropped.
 *   errors: -1 with fl_error() text when no context is current, it is
 *           below OpenGL 3.3 or libepoxy cannot be loaded (the runtime
 *           keeps drawing as before); -1 for a NULL [rt]; else 0. */
FL_API int fl_gl_attach(fl_runtime *rt);
/* The OpenGL texture (a GL_TEXTURE_2D name of the context fl_gl_attach
 * was given) holding window [index]'s picture of the last frame (drawn
 * now if it was not yet): [*width] x [*height] pixels of premultiplied
 * RGBA linear light (values above 1 kept: 16-bit float by default, as the
 * window's colorbits= says). Flitter's window shows it sRGB-encoded,
 * clamped, over black. The name stays valid until the next fl_step.
 * Returns 0 (and 0 sizes) when the window has no picture (nothing drawn,
 * no such window, no OpenGL, or a NULL [rt]). */
FL_API unsigned fl_gl_window_texture(fl_runtime *rt, size_t index, int *width, int *height);

/* A live window's dynamic resolution: from the next frame drawn on,
 * the windows' pictures (fl_gl_window_texture, fl_draw_window) are drawn
 * at [scale] (0.01 to 1) of every render pass's size in each dimension
 * (scale * scale of the pixels) and each !canvas3d with at most
 * [max_samples] samples (0: as many as it asks). The picture is the same
 * one at fewer pixels: canvases draw in the window's pixels scaled, blur
 * radii and the filters that work in pixel positions follow; a !shader's
 * `size` is its framebuffer's. fl_gl_window_texture's sizes are then the
 * scaled ones (a front end scales the texture up to show it);
 * fl_draw_window scales it up to the window's size (nearest pixels). A
 * frame in which a !record writes a file, or --record's, and every frame
 * drawn for fl_outputs_frame alone, are drawn at full size and samples.
 * A scale out of range (or NaN) means 1, a cap below 1 none. No effect
 * for a NULL [rt]. */
FL_API void fl_set_window_scale(fl_runtime *rt, double scale, int max_samples);
/* The scale the last frame's pictures were drawn at (1 when at full
 * size, or none was drawn), and in [*max_samples] (when not NULL) the cap
 * on samples they were drawn with (0: none). */
FL_API double fl_window_scale(fl_runtime *rt, int *max_samples);

/* {---------------------------------------------------------------------
 * Pictures drawn beside the frame loop: a front end draws frame N's
 * windows on a thread of its own (the drawing thread) while the frame
 * loop's thread steps frame N+1, so that neither waits for the other.
 * After fl_step the frame loop's thread takes the frame's picture
 * (fl_picture_take: its tree and engine names held, nothing copied) and
 * hands it over; the drawing thread draws it (fl_picture_texture for each
 * window; fl_picture_draw draws without asking for a texture) with the
 * OpenGL context of fl_gl_attach current there, and hands it back; the
 * frame loop's thread frees it (fl_picture_free). The textures are those
 * fl_gl_window_texture would give for that frame (fl_picture_read: the
 * pixels fl_draw_window would). A front end without an OpenGL context of
 * its own may do the same: the runtime's own context is then made current
 * on the drawing thread.
 *
 * While a picture is out (from fl_picture_take until the drawing thread
 * is done with it), the runtime's render graph is the drawing thread's:
 * the frame loop's thread may call fl_step and the calls that do not draw
 * (fl_windows, the input and clock calls, the state calls, fl_dump_state,
 * fl_view_snapshot_take, fl_get_stats, fl_outputs_frame for a frame of
 * which fl_outputs_draws says false, fl_picture_take, fl_picture_free),
 * and not fl_load, fl_free, fl_gl_attach, fl_draw_window, fl_draw_view,
 * fl_gl_window_texture, fl_set_window_scale nor fl_window_scale; the
 * drawing thread calls fl_picture_draw, fl_picture_texture and, between
 * pictures, fl_set_window_scale and fl_window_scale. A call that draws
 * (those last, fl_outputs_frame of a frame that draws, fl_load, fl_free)
 * needs the OpenGL context on its thread and no picture being drawn.
 * ---------------------------------------------------------------------} */
typedef struct fl_picture fl_picture;
/* The last frame's picture of [rt], for a drawing thread. NULL (draw that
 * frame on this thread instead, with fl_gl_window_texture) before the
 * first frame, before the windows are shown (fl_gl_attach,
 * fl_gl_window_texture or fl_draw_window first), once a frame's windows
 * hold a function (an SDF's `function=`, which the drawing calls back:
 * from then on the runtime's pictures are drawn on its own thread), for a
 * NULL [rt] or out of memory. */
FL_API fl_picture *fl_picture_take(fl_runtime *rt);
/* Draw [pic]'s windows (once: later calls do nothing) through [rt]'s
 * render graph, on the drawing thread; 0 when drawn, or the number of
 * record files that could not be written (as fl_outputs_frame counts
 * them: logged); -1 for a NULL [rt] or [pic]. Errors are logged, not left
 * in fl_error(), which is the frame loop's. */
FL_API int fl_picture_draw(fl_runtime *rt, fl_picture *pic);
/* fl_gl_window_texture for [pic]'s frame, on the drawing thread (drawn
 * first if it was not): window [index]'s texture and its size, valid
 * until the next picture is drawn; 0 when it has none. */
FL_API unsigned fl_picture_texture(fl_runtime *rt, fl_picture *pic, size_t index, int *width, int *height);
/* fl_draw_window for [pic]'s frame, on the drawing thread (drawn first if
 * it was not): window [index]'s picture read back into [pixels], the same
 * layout and pixels. -1 (and no error text: fl_error() is the frame
 * loop's) for an index past the frame's last window, a size other than
 * that window's, a NULL [pixels], a stride below width*4 or not a
 * multiple of 4, or a NULL [rt] or [pic]; else 0. */
FL_API int fl_picture_read(fl_runtime *rt, fl_picture *pic, size_t index, uint32_t *pixels, int width, int height,
                           size_t stride);
/* The number of [pic]'s frame (fl_frame_count() - 1 when it was taken);
 * -1 for NULL. */
FL_API long fl_picture_frame(const fl_picture *pic);
/* Give [pic] back (NULL is a no-op), on the frame loop's thread, once the
 * drawing thread is done with it: its tree and names are released. */
FL_API void fl_picture_free(fl_runtime *rt, fl_picture *pic);

/* Draw [rt]'s !physics systems as they are now into [pixels] (same layout
 * as fl_draw_window), as `--view` draws them (fl_view), scaled to fit
 * [width] x [height]; [*nsystems] (may be NULL) gets the number drawn.
 *   errors: -1 with fl_error() text for a size outside 1..16384, a NULL
 *           [pixels], or a stride below width*4 or not a multiple of 4
 *           (-1 for a NULL [rt]), else 0. */
FL_API int fl_draw_view(fl_runtime *rt, uint32_t *pixels, int width, int height, size_t stride,
                        size_t *nsystems);

/* The physics view drawn away from the runtime's thread: a front end that
 * steps [rt] on one thread and shows pictures on another takes a snapshot
 * on the first after each frame (cheap: the systems' numbers are copied)
 * and draws it on the second, so that drawing never holds the simulation
 * up. A snapshot drawn by a painter gives the very pixels fl_draw_view
 * gives for that frame (the same drawing code; each picture is fitted to
 * its own frame's systems, with no history).
 *
 * fl_view_snapshot_take copies what fl_draw_view would draw now into
 * [reuse] (a snapshot from an earlier call, refilled in place and
 * returned; NULL: a new one). It returns NULL, leaving [reuse] as it was,
 * when a system would be drawn in 3D (through OpenGL, which needs the
 * runtime's own renderer: draw that frame with fl_draw_view), when the
 * copy does not fit the memory budget (fl_options.max_memory; draw with
 * fl_draw_view too), and for a NULL [rt]. The snapshot holds no reference
 * into [rt]: it outlives the frame, and [rt] itself. */
typedef struct fl_view_snapshot fl_view_snapshot;
typedef struct fl_view_painter fl_view_painter;
FL_API fl_view_snapshot *fl_view_snapshot_take(fl_runtime *rt, fl_view_snapshot *reuse);
/* Free a snapshot (NULL is a no-op). */
FL_API void fl_view_snapshot_free(fl_view_snapshot *snap);
/* A painter of snapshots, to be used on one thread at a time. */
FL_API fl_view_painter *fl_view_painter_new(void);
/* Free a painter (NULL is a no-op). */
FL_API void fl_view_painter_free(fl_view_painter *painter);
/* Draw [snap] with [painter] into [pixels] (the layout and sizes of
 * fl_draw_view); [*nsystems] (may be NULL) gets the number drawn. Touches
 * no runtime: any thread may call it, one at a time per painter.
 *   errors: -1 (there is no runtime to hold a message) for a NULL
 *           [painter], [snap] or [pixels], a size outside 1..16384, a
 *           stride below width*4, not a multiple of 4 or over 2^31-1
 *           bytes, or cairo refusing the buffer; else 0. */
FL_API int fl_view_painter_draw(fl_view_painter *painter, const fl_view_snapshot *snap,
                                uint32_t *pixels, int width, int height, size_t stride,
                                size_t *nsystems);

/* A key of window [window] went down ([pressed]) or up, named as Flitter's
 * `!key name=` names keys (GLFW's names, lower case: "a".."z", "0".."9",
 * "space", "enter", "escape", "left", "right", "up", "down", "tab",
 * "backspace", "f1".."f25", "left_shift", "kp_0", ...; any case; a name
 * GLFW does not define claims nothing). Report a key's auto-repeats not
 * at all (Flitter ignores GLFW's REPEAT). When a `!key name=NAME state=S`
 * directly under that window (last frame; the last such !key of that key)
 * claims it, the state gets S = 1/0, S;:pushed = 1/0, S;:released = 0/1
 * and S;:pushed;:beat or S;:released;:beat = the beat of the last frame
 * (Flitter 1.0.0b28 render/window/__init__.py, key_callback; docs/
 * windows.md), and the result is 1; else 0 (the front end may use the key
 * itself: the arrows switch pages, Escape quits). The runtime also
 * remembers which keys are down in which window: after each frame, a
 * `!key` whose S is not in the state starts at S = 1, S;:pushed = 1,
 * S;:released = 0 when its key is held, else 0, 0, 1 (Window.handle_node;
 * off-screen and without any front end too, as Flitter's hidden windows).
 *   errors: -1 with fl_error() text for a NULL [name] (-1 for a NULL [rt]). */
FL_API int fl_key(fl_runtime *rt, size_t window, const char *name, bool pressed);

/* The pointer moved over window [window]: with [inside], the state key of
 * the window's `!pointer state=P` (directly under it, last frame; the last
 * one) gets P = x;y, fractions of the window's width and height (0..1, top
 * left 0;0); without, P = null (Flitter's pointer_movement_callback).
 * No-op when the window has no !pointer, and for a NULL [rt]. */
FL_API void fl_pointer(fl_runtime *rt, size_t window, bool inside, double x, double y);
/* Pointer button [button] (0 left, 1 right, 2 middle, as GLFW numbers
 * them) of window [window] went down or up: P;button = 1/0
 * (pointer_button_callback); no-op without a !pointer or [rt]. */
FL_API void fl_pointer_button(fl_runtime *rt, size_t window, int button, bool pressed);

/* The files the loaded program was read from: the script, then every
 * file it `%include`s and every module it `import`s, each once. Returns
 * how many there are and fills out[0 .. min(count, cap)) with their paths
 * (owned by [rt], valid until the next fl_load; a NULL [out] receives
 * nothing). 0 when nothing is loaded and for a NULL [rt].
 * Included files and literal imports are known at load; a module imported
 * only while running (--nosimplify, a computed path, or a module's own
 * imports) is listed after the first frame that imports it; a module file
 * that exists is listed even when it does not parse. A front end watches
 * them for live reload (and may ask again after each frame). */
FL_API size_t fl_program_files(fl_runtime *rt, const char **out, size_t cap);

/* {=====================================================================
 * Statistics
 * ===================================================================== */

/* Counters and timers of a runtime since fl_new (fl_get_stats). */
typedef struct fl_stats {
    long frames;              /* frames stepped */
    unsigned long long mallocs, frees;           /* malloc/free calls made for
                                                    pooled values, in total */
    unsigned long long last_mallocs, last_frees; /* the same during the last frame */
    unsigned long long state_gets, state_sets;   /* state dictionary reads and writes */
    double eval_seconds;      /* evaluating the program into a tree (and
                                 releasing the previous frame's tree) */
    double physics_seconds;   /* the physics engine, its state reads/writes included */
    double other_seconds;     /* the rest of fl_step: frame names, pragmas,
                                 messages, beat counter */
} fl_stats;

/* Fill [out] with [rt]'s statistics (wall-clock seconds, monotonic clock).
 * Allocation counts cover the values the runtime pools (vectors, strings,
 * nodes and their arrays, evaluator scratch): a steady frame makes none.
 * A NULL [out]: no-op; a NULL [rt]: all zero. */
FL_API void fl_get_stats(const fl_runtime *rt, fl_stats *out);

#endif
