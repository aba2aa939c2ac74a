/* builtins.h: the registry of built-in functions (LANGUAGE.md §5).
 *
 * Each family of built-ins lives in its own file (maths.c, vector.c,
 * random.c, noise.c, colour.c, text.c, ...) and exports a table of
 * `Builtin` descriptors ending with an entry whose name is NULL. bi_lookup()
 * searches all tables. A builtin receives its arguments already mapped to
 * positions (named arguments matched against `params`); it returns a new
 * vector (or NULL for null) and reports problems through bi_error().
 */
#ifndef FL_BUILTINS_H
#define FL_BUILTINS_H

#include <stdint.h>

#include "value.h"

typedef struct Eval Eval;   /* the evaluator's per-call context (context.h) */
typedef struct Builtin Builtin;

/* A runtime's memo of noise() permutation tables (noise.c): the tables of
 * the last few seeds, so that `noise(:seed, i/5, t) for i in ..500` builds
 * its table (255 uniform draws) once a frame, not 500 times. A table is a
 * function of its seed's hash alone, so a kept one is the one that would
 * be made. One per runtime (the evaluator finds it through
 * eval_noise_perms, context.h); not shared between threads. */
typedef struct NoisePerms NoisePerms;
/* A new, empty memo; NULL when out of memory (noise then builds every
 * table, as without one). */
NoisePerms *noise_perms_new(void);
/* Free [p] (NULL is a no-op). */
void noise_perms_free(NoisePerms *p);
/* A runtime's memo of the files read by read(), read_bytes(), csv() and
 * srt() (filememo.c): each file's contents (and read()'s string of them),
 * kept while the file at that path keeps its device, inode, size,
 * modification and change times, so that a file read every frame, or
 * once per row, is read once, as Flitter's cache reads it. One per
 * runtime (eval_file_memo, context.h); not shared between threads. */
typedef struct FileMemo FileMemo;
/* A new, empty memo; NULL when out of memory (every file is then read
 * afresh at each use). */
FileMemo *file_memo_new(void);
/* Free [m] and what it keeps (NULL is a no-op). */
void file_memo_free(FileMemo *m);
/* Set [m]'s racy window (filememo.c) to [ns] nanoseconds, for tests: a
 * file changed less than that before it was read is read again at each
 * use (2 s unless set). */
void file_memo_set_window(FileMemo *m, int64_t ns);
/* Most arguments of a noise() call with a numeric route: the seed and up
 * to four coordinates. */
#define BI_NOISE_ARGS 5
/* True when a call of [bi] with [nargs] positional arguments has
 * bi_noise_nums' route: noise() with a seed and one to four coordinates
 * (bi_args_route asks). */
bool bi_noise_route(const Builtin *bi, uint32_t nargs);
/* The result of noise([seed], [coordinates]...) for callers that hold the
 * arguments' numbers on the C stack (bi_call_nums_args):
 * x[i][0..n[i]) are the numbers of numeric argument i (1 <= n[i]; x[0]
 * the seed, hashed as its vector is). Writes the result's numbers to
 * [out] (at most BI_NUMS_MAX) and their count to *[nout] and returns true
 * when the builtin's result is that numeric vector, the same bits
 * (Flitter docs/builtins.md, noise: one value for each combination of the
 * coordinates, the last varying fastest). False, with nothing done that
 * shows, when it would be anything else: more than BI_NUMS_MAX values, no
 * room in the memory budget, a stop asked for (the caller then calls the
 * builtin, which says why). */
bool bi_noise_nums(Eval *ev, const Builtin *bi, const double *const *x, const uint32_t *n, uint32_t nargs,
                   double *out, uint32_t *nout);

/* [nargs] arguments in [args] (each may be NULL = null; a named argument
 * that skipped an earlier parameter leaves that one NULL). nargs is between
 * the descriptor's min_args and max_args (checked by the caller). */
typedef Vec *(*BuiltinFn)(Eval *ev, const Builtin *bi, int nargs, Vec *const *args);

/* The parameter list of a BuiltinFn definition, for built-ins that do not
 * use every argument: `static Vec *bi_sin(BI_PARAMS) { ... }`. */
#define BI_PARAMS Eval *ev __attribute__((unused)), const Builtin *bi __attribute__((unused)), \
                  int nargs __attribute__((unused)), Vec *const *args

#define BI_MAX_PARAMS 8
#define BI_VARIADIC (-1)

/* Flags. BI_DYNAMIC: depends on more than its arguments (debug, read, ...). */
enum { BI_DYNAMIC = 1 };

struct Builtin {
    const char *name;                      /* name in scripts, e.g. "sin" */
    const char *internal;                  /* the reference's internal name,
                                              e.g. "sinv", used in messages */
    int8_t min_args;                       /* fewest positional arguments */
    int8_t max_args;                       /* most, or BI_VARIADIC */
    const char *params[BI_MAX_PARAMS];     /* keyword names by position */
    BuiltinFn fn;                          /* implementation */
    uint8_t flags;                         /* BI_* */
};

/* The builtin called [name] (UTF-8, [len] bytes), or NULL. */
const Builtin *bi_lookup(const char *name, size_t len);
/* The StreamKind of the stream [bi] returns when called with one
 * argument, keyed by that argument's seed hash (vec_hash(value, true)):
 * uniform, normal and beta (LANGUAGE.md §5.8); -1 for every other
 * builtin. The simplifier makes a template pass's stream columns so. */
int bi_stream_kind(const Builtin *bi);

/* Record `Error calling INTERNAL: DETAIL` for [bi] in [ev] and return NULL
 * (so a builtin can `return bi_error(...)`). */
Vec *bi_error(Eval *ev, const Builtin *bi, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* The element kernel f of a one-argument element-wise builtin (sin, cos,
 * sqrt, abs, the waveforms and easings, ...: those that apply f to each
 * element of a numeric argument and give null for any other), or NULL for
 * every other builtin. The builtin's result on a one-element numeric vector
 * [x] is exactly the one-element vector f(x), so a caller holding one number
 * may call f instead (numexpr.c). */
typedef double (*BiKernel)(double);
BiKernel bi_kernel(const Builtin *bi);

/* hypot of one numeric argument of [n] numbers (n >= 1): the square root
 * of the sum of their squares, added in order from 0 (Flitter's
 * `hypot(v)`). What the builtin's result holds, bit for bit; the
 * evaluator's compiled expressions call it (numexpr.c, NX_HYPOT). */
double bi_hypot_nums(const double *x, uint32_t n);
/* True when [bi] is hypot (whose one numeric argument gives
 * bi_hypot_nums of its numbers). */
bool bi_is_hypot(const Builtin *bi);

/* Two element kernels of one argument computed at once: for the kernel
 * [a] of bi_kernel(), a function f with f(x, &ya, &yb) writing a(x) and
 * b(x), bit for bit, for less than the two calls cost, and that kernel b
 * into [b]; NULL (b untouched) when [a] has no such partner. sin's partner
 * is cos (sincos_t of turns.h). */
typedef void (*BiKernelPair)(double x, double *ya, double *yb);
BiKernelPair bi_kernel_pair(BiKernel a, BiKernel *b);

/* The numeric kernel of a builtin of one argument whose result, for a
 * numeric argument, is a numeric vector of a length set by the argument's
 * (hsv, hsl: three numbers), for callers holding the argument as [n]
 * doubles (the evaluator's loop kernels, kernel.h): run(x, n, out) writes
 * the result's nout(n) numbers to [out], the same numbers the builtin's
 * result holds, and returns true; false when the builtin's result is
 * anything else (null: the caller calls the builtin). Pure: any thread may
 * run it. */
typedef struct BiVecKernel {
    BuiltinFn fn;                                          /* the builtin */
    uint32_t (*nout)(uint32_t n);                          /* at most 16 */
    bool (*run)(const double *x, uint32_t n, double *out);
} BiVecKernel;
/* [bi]'s numeric kernel, or NULL when it has none. */
const BiVecKernel *bi_vec_kernel(const Builtin *bi);
/* The index of [bi]'s numeric kernel among them, or -1 when it has none. */
int bi_vec_kernel_index(const Builtin *bi);
/* The numeric kernel of index [i] (bi_vec_kernel_index), or NULL. */
const BiVecKernel *bi_vec_kernel_at(int i);

/* Most numbers bi_call_nums takes and gives. */
#define BI_NUMS_MAX 16

/* True when [bi] has a numeric route for one argument (bi_call_nums):
 * hypot, the element-wise builtins of bi_kernel, and those of
 * bi_vec_kernel. The evaluator asks once, when it compiles a call. */
bool bi_nums_route(const Builtin *bi);

/* The result of calling [bi] with one argument, the numeric vector of the
 * [n] numbers [x] (1 <= n <= BI_NUMS_MAX), for callers that hold those
 * numbers on the C stack (the evaluator's compiled calls, evalrun.c):
 * writes the result's numbers (at most BI_NUMS_MAX) to [out] and their
 * count to *[nout] and returns true, when the builtin's result is a
 * numeric vector of exactly those numbers, bit for bit (hypot: the square
 * root of the sum of the squares, in order; an element-wise builtin: its
 * kernel on each number; hsv, hsl: BiVecKernel). False otherwise (no such
 * route, or the builtin's result is not numbers): the caller then calls
 * the builtin. Pure, no errors. */
bool bi_call_nums(const Builtin *bi, const double *x, uint32_t n, double *out, uint32_t *nout);
/* [bi]'s route for bi_call_nums as a small number for a caller to keep
 * (a compiled call keeps it: evalcode.c), so that each call goes straight
 * to its kernel instead of looking for it among the builtins' kernels; 0
 * when it has none (bi_nums_route false). */
uint16_t bi_nums_route_id(const Builtin *bi);
/* bi_call_nums of the builtin whose route is [id] (bi_nums_route_id,
 * nonzero): the same numbers, and false in the same cases. */
bool bi_call_nums_id(uint16_t id, const double *x, uint32_t n, double *out, uint32_t *nout);

/* Most arguments bi_call_nums_args takes. */
#define BI_ARGS_MAX BI_NOISE_ARGS
/* True when a call of [bi] with [nargs] positional arguments has a
 * numeric route for all of them (bi_call_nums_args): map and clamp of
 * three, noise of a seed and one to four coordinates. The evaluator asks
 * once, when it compiles a call. */
bool bi_args_route(const Builtin *bi, uint32_t nargs);
/* map(x, y, z) of one number each: (1 - x)*y + x*z, each operation
 * rounded (the builtin's, number by number). */
static inline double bi_map_num(double x, double y, double z) { return (1 - x) * y + x * z; }
/* clamp(d, lo, hi) of one number each: C max(lo, d) = (d > lo ? d : lo),
 * then C min(d, hi) = (hi < d ? hi : d) (the builtin's, NaN included). */
static inline double bi_clamp_num(double d, double lo, double hi)
{
    d = d > lo ? d : lo;
    return hi < d ? hi : d;
}
/* BI_MAP when [bi] is map, BI_CLAMP when it is clamp, else 0 (the
 * evaluator's compiled expressions take their three numbers: numexpr.c). */
enum { BI_MAP = 1, BI_CLAMP = 2 };
int bi_map_or_clamp(const Builtin *bi);
/* The result of calling [bi] with [nargs] positional arguments, the
 * numeric vectors x[i][0..n[i]) (1 <= n[i] <= BI_NUMS_MAX), for callers
 * that hold those numbers on the C stack (the evaluator's compiled calls,
 * evalrun.c): writes the result's numbers (at most BI_NUMS_MAX) to [out]
 * and their count to *[nout] and returns true, when the builtin's result
 * is a numeric vector of exactly those numbers, bit for bit (map, clamp:
 * the builtin's loop, each argument repeated to the longest; noise:
 * bi_noise_nums). False, with nothing done that shows, otherwise: the
 * caller then calls the builtin. */
bool bi_call_nums_args(Eval *ev, const Builtin *bi, const double *const *x, const uint32_t *n, uint32_t nargs,
                       double *out, uint32_t *nout);

/* The family tables (each ends with a {NULL} entry). */
extern const Builtin bi_vector_table[];
extern const Builtin bi_maths_table[];
extern const Builtin bi_random_table[];
extern const Builtin bi_noise_table[];
extern const Builtin bi_colour_table[];
extern const Builtin bi_text_table[];
extern const Builtin bi_file_table[];

#endif
