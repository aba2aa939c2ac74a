/* cmd_sweep.c: `flitter sweep`, parameter sweeps for GNU parallel and Slurm
 * job arrays.
 *
 *   flitter sweep SCRIPT -D NAME=V1,V2,... [-D ...] --frames N --out DIR
 *                 [--runs R] [--slurm]
 *       lists the jobs: one per combination of the values (the first -D
 *       varies slowest) and run number 0..R-1, job K = combination * R +
 *       run. Each is printed as one shell command line (every word single-
 *       quoted, so any value is safe: `parallel --joblog LOG < LIST` runs
 *       them), or with --slurm written to DIR/sweep.sbatch, a job-array
 *       batch script (`sbatch DIR/sweep.sbatch`) whose task K runs job K.
 *   flitter sweep --job K --run R --out DIR --frames N [-D NAME=V ...] SCRIPT
 *       runs one job: `flitter run --frames N -D ... -D run=R
 *       --state DIR/job-K/run.state --trace-file DIR/job-K/trace.csv
 *       --dump-state SCRIPT`, stdout into DIR/job-K/final.state and stderr
 *       into DIR/job-K/log, then writes DIR/job-K/manifest (`NAME VALUE`
 *       lines: job, script, frames, param NAME TEXT and value NAME VALUE (the
 *       text as typed, the value the script receives) for each parameter,
 *       run, seed, exit,
 *       wall_seconds). A job whose manifest says exit 0 returns at once; an
 *       unfinished one starts over (its saved state is removed first). The
 *       job holds DIR/job-K/lock (flock) while it runs, and writes
 *       final.state and manifest under names of its own (NAME.PID.tmp),
 *       renamed when complete, those of killed runs removed first: a
 *       second start of the same job leaves it alone (exit 1); its
 *       `flitter run` child dies
 *       with it (a parent-death SIGKILL) and gets its SIGINT, SIGTERM and
 *       SIGHUP.
 *   flitter sweep --collect DIR
 *       prints the manifests as one CSV: job, the parameters, run, seed,
 *       exit, wall_seconds.
 *
 * The run number is bound as the name `run` (`-D run=R`): a script that
 * gives its !physics `run=run` gets the random seed vector P;run;iteration
 * (PHYSICS-ENGINE.md §2 step 5), so the manifest's seed is R; a script
 * that does not read `run` has an empty seed. Nothing here
 * goes through a shell: the job is spawned with an argument vector; the
 * printed lines are for the user's shell, quoted for it.
 */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "commands.h"
#include "exitcodes.h"
#include "flitter.h"

extern char **environ;

#define MAX_PARAMS 32
/* The most jobs one sweep lists (a line each, or a case of the batch
 * script): counts beyond are refused, never wrapped around. */
#define MAX_JOBS 1000000L

typedef struct Param {
    char *name;       /* the define's name */
    char **values;    /* its values, from V1,V2,... */
    size_t n;
} Param;

typedef struct Sweep {
    const char *script, *out, *collect;
    long frames, runs, job;   /* job: --job K, or -1 */
    long run;                 /* --run R of a job: its run number */
    int slurm;
    Param params[MAX_PARAMS];
    size_t nparams;
} Sweep;

static void usage(FILE *f)
{
    fputs("usage: flitter sweep SCRIPT -D NAME=V1,V2,... [-D ...] --frames N --out DIR\n"
          "                     [--runs R] [--slurm]\n"
          "       flitter sweep --collect DIR\n"
          "  lists one shell command line per job (each combination of the values, times\n"
          "  --runs R runs numbered 0..R-1 and bound as `run`), for `parallel --joblog`;\n"
          "  --slurm writes DIR/sweep.sbatch, a job array for sbatch, instead. Each job\n"
          "  writes DIR/job-K/: run.state, trace.csv, final.state (the --dump-state of\n"
          "  its last frame), log and manifest; a finished job run again returns at\n"
          "  once. --collect prints the manifests as CSV.\n", f);
}

static int fail(const char *fmt, const char *arg)
{
    fputs("flitter sweep: ", stderr);
    fprintf(stderr, fmt, arg);
    fputc('\n', stderr);
    return EXIT_USAGE;
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) {
        fputs("flitter sweep: out of memory\n", stderr);
        exit(70);
    }
    return p;
}

static char *xstrdup(const char *s)
{
    size_t n = strlen(s) + 1;
    return memcpy(xmalloc(n), s, n);
}

/* A name as -D takes it: a letter or '_', then letters, digits, '_'. */
static int good_name(const char *s, size_t n)
{
    if (!n || !(s[0] == '_' || ((s[0] | 32) >= 'a' && (s[0] | 32) <= 'z'))) return 0;
    for (size_t i = 1; i < n; i++)
        if (!(s[i] == '_' || (s[i] >= '0' && s[i] <= '9') || ((s[i] | 32) >= 'a' && (s[i] | 32) <= 'z')))
            return 0;
    return 1;
}

/* -D NAME=V1,V2,...: [list] splits on ',' (the sweep form), else one value. */
static int add_param(Sweep *sw, const char *def, int list)
{
    const char *eq = strchr(def, '=');
    if (!eq || !good_name(def, (size_t)(eq - def)))
        return fail("bad define '%s' (expected NAME=V1,V2,...)", def);
    for (const char *c = eq + 1; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            return fail("control character in the values of '%s'", def);
    if (sw->nparams == MAX_PARAMS) return fail("more than %s defines", "32");
    Param *p = &sw->params[sw->nparams];
    p->name = xstrdup(def);
    p->name[eq - def] = '\0';
    int clash = strcmp(p->name, "run") == 0 ? -1 : 0;
    for (size_t i = 0; i < sw->nparams && !clash; i++)
        clash = strcmp(sw->params[i].name, p->name) == 0;
    if (clash) {   /* not counted in nparams: freed here */
        int rc = clash < 0 ? fail("%s is the run number (use --runs)", "-D run")
                           : fail("'%s' defined twice", p->name);
        free(p->name);
        p->name = NULL;
        return rc;
    }
    char *vals = p->name + (eq - def) + 1;
    p->values = xmalloc((strlen(vals) + 2) * sizeof *p->values);
    p->n = 0;
    for (char *v = vals;;) {
        char *comma = list ? strchr(v, ',') : NULL;
        if (comma) *comma = '\0';
        p->values[p->n++] = v;
        if (!comma) break;
        v = comma + 1;
    }
    sw->nparams++;
    return 0;
}

static int parse_long(const char *s, long min, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < min) return 0;
    *out = v;
    return 1;
}

static int parse_args(Sweep *sw, int argc, char **argv)
{
    memset(sw, 0, sizeof *sw);
    sw->frames = -1;
    sw->runs = 1;
    sw->job = -1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            usage(stdout);
            exit(EXIT_OK);
        } else if (strcmp(a, "--slurm") == 0) {
            sw->slurm = 1;
        } else if (!next && a[0] == '-' && a[1]) {
            return fail("option %s needs a value", a);
        } else if (strcmp(a, "-D") == 0 || strcmp(a, "--define") == 0) {
            if (add_param(sw, argv[++i], 1)) return EXIT_USAGE;
        } else if (strcmp(a, "--frames") == 0) {
            if (!parse_long(argv[++i], 1, &sw->frames)) return fail("bad --frames '%s'", argv[i]);
        } else if (strcmp(a, "--runs") == 0) {
            if (!parse_long(argv[++i], 1, &sw->runs)) return fail("bad --runs '%s'", argv[i]);
        } else if (strcmp(a, "--run") == 0) {
            if (!parse_long(argv[++i], 0, &sw->run)) return fail("bad --run '%s'", argv[i]);
        } else if (strcmp(a, "--job") == 0) {
            if (!parse_long(argv[++i], 0, &sw->job)) return fail("bad --job '%s'", argv[i]);
        } else if (strcmp(a, "--out") == 0) {
            sw->out = argv[++i];
        } else if (strcmp(a, "--collect") == 0) {
            sw->collect = argv[++i];
        } else if (a[0] == '-' && a[1]) {
            return fail("unknown option '%s'", a);
        } else if (sw->script) {
            return fail("unexpected argument '%s' (one SCRIPT)", a);
        } else {
            sw->script = a;
        }
    }
    if (sw->collect) return 0;
    if (!sw->script) return fail("%s", "no SCRIPT given");
    if (sw->frames < 0) return fail("%s", "--frames N is required");
    if (!sw->out) return fail("%s", "--out DIR is required");
    if (sw->job >= 0) {
        for (size_t i = 0; i < sw->nparams; i++)
            if (sw->params[i].n != 1) return fail("--job takes one value per define (%s)", sw->params[i].name);
        return 0;
    }
    /* runs x values of each define, checked at each product */
    long njobs = sw->runs;
    for (size_t i = 0; i < sw->nparams && njobs <= MAX_JOBS; i++)
        njobs = (long)sw->params[i].n > MAX_JOBS ? MAX_JOBS + 1 : njobs * (long)sw->params[i].n;
    if (njobs > MAX_JOBS) return fail("more than %s jobs (--runs times the values of each -D)", "1000000");
    return 0;
}

/* {=====================================================================
 * Listing the jobs
 * ===================================================================== */

/* Write [s] as one word for a POSIX shell: single-quoted, each ' as '\''. */
static void put_quoted(FILE *f, const char *s)
{
    fputc('\'', f);
    for (; *s; s++) {
        if (*s == '\'') fputs("'\\''", f);
        else fputc(*s, f);
    }
    fputc('\'', f);
}

/* The command line of job [k] (values chosen by [k]'s digits). */
static void put_job(FILE *f, const Sweep *sw, const char *exe, const char *script,
                    const char *out, long k)
{
    put_quoted(f, exe);
    fprintf(f, " sweep --job %ld --run %ld --out ", k, k % sw->runs);
    put_quoted(f, out);
    fprintf(f, " --frames %ld", sw->frames);
    long rest = k / sw->runs;
    char **vals = xmalloc((sw->nparams + 1) * sizeof *vals);
    for (size_t i = sw->nparams; i-- > 0;) {
        vals[i] = sw->params[i].values[rest % (long)sw->params[i].n];
        rest /= (long)sw->params[i].n;
    }
    for (size_t i = 0; i < sw->nparams; i++) {
        fputs(" -D ", f);
        size_t n = strlen(sw->params[i].name) + strlen(vals[i]) + 2;
        char *d = xmalloc(n);
        snprintf(d, n, "%s=%s", sw->params[i].name, vals[i]);
        put_quoted(f, d);
        free(d);
    }
    free(vals);
    fputc(' ', f);
    put_quoted(f, script);
}

/* This program's absolute path (the jobs run the same flitter). */
static char *self_path(void)
{
    char buf[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return xstrdup("flitter");
    buf[n] = '\0';
    return xstrdup(buf);
}

/* The byte of [path] a `#SBATCH` directive cannot carry (a control
 * character, a blank, a quote or a backslash: sbatch reads the line's
 * words itself, with no quoting a path could rely on), or 0 when none. */
static int slurm_unsafe(const char *path)
{
    for (const unsigned char *p = (const unsigned char *)path; *p; p++)
        if (*p < 0x20 || *p == 0x7f || *p == ' ' || *p == '"' || *p == '\'' || *p == '\\') return *p;
    return 0;
}

/* [s] for a Slurm file name pattern: every `%` doubled (sbatch would read
 * `%A`, `%j` ... in a folder's name as its own). */
static void put_slurm_name(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '%') fputc('%', f);
        fputc(*s, f);
    }
}

static int list_jobs(const Sweep *sw)
{
    /* the folder's whole path goes into a #SBATCH line: checked before
     * anything is made */
    char cwd[PATH_MAX] = "";
    if (sw->slurm && sw->out[0] != '/' && !getcwd(cwd, sizeof cwd)) cwd[0] = '\0';
    int bad = sw->slurm ? (slurm_unsafe(cwd) ? slurm_unsafe(cwd) : slurm_unsafe(sw->out)) : 0;
    if (bad) {
        fprintf(stderr, "flitter sweep: --slurm: the folder's path holds a byte (0x%02x) that a #SBATCH "
                "line cannot carry (a control character, a blank, a quote or a backslash); give "
                "--out a plainer folder\n", bad);
        return EXIT_USAGE;
    }
    /* each job is one line (GNU parallel reads a line a job; a line of
     * the batch script): a line break inside a word would split it */
    const char *broken = strpbrk(sw->out, "\n\r") ? sw->out : strpbrk(sw->script, "\n\r") ? sw->script : NULL;
    for (size_t i = 0; i < sw->nparams && !broken; i++)
        for (size_t j = 0; j < sw->params[i].n && !broken; j++)
            if (strpbrk(sw->params[i].values[j], "\n\r")) broken = sw->params[i].values[j];
    if (broken) {
        fprintf(stderr, "flitter sweep: a line break in %s would split a job's command line; refused\n",
                broken == sw->out ? "--out" : broken == sw->script ? "the script's name" : "a value");
        return EXIT_USAGE;
    }
    if (mkdir(sw->out, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "flitter sweep: cannot create %s: %s\n", sw->out, strerror(errno));
        return 1;
    }
    char *out = realpath(sw->out, NULL), *script = realpath(sw->script, NULL);
    if (!out || !script) {
        fprintf(stderr, "flitter sweep: %s: %s\n", out ? sw->script : sw->out, strerror(errno));
        free(out);
        free(script);
        return 1;
    }
    char *exe = self_path();
    long njobs = sw->runs;
    for (size_t i = 0; i < sw->nparams; i++) njobs *= (long)sw->params[i].n;
    int rc = 0;
    if (!sw->slurm) {
        for (long k = 0; k < njobs; k++) {
            put_job(stdout, sw, exe, script, out, k);
            fputc('\n', stdout);
        }
        if (fflush(stdout) != 0) rc = 1;
    } else {
        size_t n = strlen(out) + 32;
        char *path = xmalloc(n), *tmp = xmalloc(n + 8);
        snprintf(path, n, "%s/sweep.sbatch", out);
        snprintf(tmp, n + 8, "%s.tmp", path);
        FILE *f = fopen(tmp, "w");
        if (!f) {
            fprintf(stderr, "flitter sweep: cannot create %s: %s\n", tmp, strerror(errno));
            rc = 1;
        } else {
            fprintf(f, "#!/bin/sh\n# flitter sweep: %ld jobs; submit with sbatch\n"
                       "#SBATCH --job-name=flitter-sweep\n#SBATCH --array=0-%ld\n"
                       "#SBATCH --ntasks=1\n#SBATCH --output=", njobs, njobs - 1);
            put_slurm_name(f, out);
            fputs("/slurm-%A_%a.out\n", f);
            fputs("case \"$SLURM_ARRAY_TASK_ID\" in\n", f);
            for (long k = 0; k < njobs; k++) {
                fprintf(f, "%ld) exec ", k);
                put_job(f, sw, exe, script, out, k);
                fputs(" ;;\n", f);
            }
            fputs("*) echo \"flitter sweep: no job $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\nesac\n", f);
            if (fclose(f) != 0 || chmod(tmp, 0755) != 0 || rename(tmp, path) != 0) {
                fprintf(stderr, "flitter sweep: cannot write %s: %s\n", path, strerror(errno));
                unlink(tmp);
                rc = 1;
            } else {
                printf("%s\n", path);
            }
        }
        free(path);
        free(tmp);
    }
    free(exe);
    free(out);
    free(script);
    return rc;
}

/* {=====================================================================
 * Running one job
 * ===================================================================== */

static char *join(const char *dir, const char *name)
{
    size_t n = strlen(dir) + strlen(name) + 2;
    char *p = xmalloc(n);
    snprintf(p, n, "%s/%s", dir, name);
    return p;
}

/* The value of line `KEY VALUE` in manifest text [m], copied into [buf]
 * ([cap] bytes, truncated), or NULL when there is no such line. */
static const char *manifest_get(const char *m, const char *key, char *buf, size_t cap)
{
    size_t k = strlen(key);
    for (const char *l = m; l && *l; l = strchr(l, '\n'), l = l ? l + 1 : NULL) {
        if (strncmp(l, key, k) == 0 && l[k] == ' ') {
            const char *v = l + k + 1, *e = strchr(v, '\n');
            size_t n = e ? (size_t)(e - v) : strlen(v);
            if (n >= cap) n = cap - 1;
            memcpy(buf, v, n);
            buf[n] = '\0';
            return buf;
        }
    }
    return NULL;
}

/* The longest manifest read (a few hundred bytes are usual). */
#define MAX_MANIFEST (1L << 20)

/* The text of the manifest [path]: a regular file (opened without
 * following a link or waiting on a FIFO) of at most MAX_MANIFEST bytes;
 * NULL with *[why] set (static text) otherwise. */
static char *read_text(const char *path, const char **why)
{
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    *why = "cannot be read";
    if (fd < 0) {
        *why = errno == ENOENT ? "missing (a job not run, or still running)"
             : errno == ELOOP  ? "a symbolic link (not followed)" : "cannot be opened";
        return NULL;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > MAX_MANIFEST) {
        *why = fstat(fd, &st) == 0 && !S_ISREG(st.st_mode) ? "not a regular file" : "too big for a manifest";
        close(fd);
        return NULL;
    }
    char *s = xmalloc((size_t)MAX_MANIFEST + 1);
    size_t n = 0;
    for (ssize_t r; n < (size_t)MAX_MANIFEST && (r = read(fd, s + n, (size_t)MAX_MANIFEST - n)) != 0;) {
        if (r < 0) {
            if (errno == EINTR) continue;
            close(fd);
            free(s);
            return NULL;
        }
        n += (size_t)r;
    }
    close(fd);
    s[n] = '\0';
    return s;
}

static void write_to_file(void *ctx, const char *text, size_t len)
{
    fwrite(text, 1, len, ctx);
}

/* `value NAME VALUE`: the value that `-D NAME=TEXT` gives the job's script
 * (fl_define's reading of the text), as value text on one line. */
static void put_received(FILE *f, const char *name, const char *text)
{
    fl_runtime *rt = fl_new(NULL);
    fprintf(f, "value %s ", name);
    if (fl_define(rt, name, text) != 0 || fl_eval(rt, name, strlen(name), write_to_file, f) != 0)
        fputc('\n', f);   /* a name flitter run refuses too: no value */
    fl_free(rt);
}

static void note_unbound_run(void *ctx, int kind, const char *line)
{
    (void)kind;
    if (strstr(line, "Unbound name 'run'")) *(bool *)ctx = true;
}

/* Whether [script] reads the name `run` (the run number the job binds):
 * loaded without it, its loader names `run` unbound. A script that does
 * not read it has no seed from the run number. */
static bool script_reads_run(const char *script, const Sweep *sw)
{
    bool reads = false;
    fl_options o = fl_default_options();
    o.log = note_unbound_run;
    o.ctx = &reads;
    fl_runtime *rt = fl_new(&o);
    for (size_t i = 0; i < sw->nparams; i++) fl_define(rt, sw->params[i].name, sw->params[i].values[0]);
    fl_load(rt, script);
    fl_free(rt);
    return reads;
}

/* The manifest's parameter lines, for comparing a re-run with the job:
 * each parameter as typed (`param`) and as the script receives it
 * (`value`). */
static void put_params(FILE *f, const Sweep *sw, const char *script, long run)
{
    fprintf(f, "job %ld\nscript %s\nframes %ld\n", sw->job, script, sw->frames);
    for (size_t i = 0; i < sw->nparams; i++) {
        fprintf(f, "param %s %s\n", sw->params[i].name, sw->params[i].values[0]);
        put_received(f, sw->params[i].name, sw->params[i].values[0]);
    }
    /* the seed is the run number only where the script reads `run`
     * (!physics run=run: PHYSICS-ENGINE.md §2 step 5) */
    if (script_reads_run(script, sw)) fprintf(f, "run %ld\nseed %ld\n", run, run);
    else fprintf(f, "run %ld\nseed \n", run);
}

/* The running job's child, for the signal handler: SIGINT, SIGTERM and
 * SIGHUP sent to the job (Slurm's scancel, a terminal) are passed on, so
 * the run ends as a signalled `flitter run` does (state saved). */
static volatile pid_t job_child;

static void pass_signal(int sig)
{
    if (job_child > 0) kill(job_child, sig);
}

/* Start `flitter run` [av] with stdout to [out], stderr to [log]: a child
 * that dies with the job (a parent-death SIGKILL: a job killed with
 * SIGKILL leaves nothing running to write over a later run's files). The
 * child's pid, or -1 with errno set. */
static pid_t start_child(const char *exe, char **av, const char *out, const char *log)
{
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid != 0) return pid;
    /* the child: async-signal-safe calls only */
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(127);
    int o = open(out, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0666);
    int l = open(log, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0666);
    if (o < 0 || l < 0 || dup2(o, 1) < 0 || dup2(l, 2) < 0) _exit(127);
    execve(exe, av, environ);
    _exit(127);
}

/* Remove the temporary files of earlier runs of the job in [dir]
 * (final.state.PID.tmp, manifest.PID.tmp), which only a run killed before
 * its renames leaves; the caller holds the folder's lock, so no live run
 * writes them (a dead run's child, still dying, keeps its own file open
 * under a name no later run uses). */
static void remove_stale_temps(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t n = strlen(e->d_name);
        bool ours = strncmp(e->d_name, "final.state.", 12) == 0 || strncmp(e->d_name, "manifest.", 9) == 0;
        if (!ours || n < 5 || strcmp(e->d_name + n - 4, ".tmp") != 0) continue;
        char *p = join(dir, e->d_name);
        unlink(p);
        free(p);
    }
    closedir(d);
}

static int run_job(const Sweep *sw)
{
    char name[32];
    snprintf(name, sizeof name, "job-%04ld", sw->job);
    if (mkdir(sw->out, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "flitter sweep: cannot create %s: %s\n", sw->out, strerror(errno));
        return 1;
    }
    char *dir = join(sw->out, name);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "flitter sweep: cannot create %s: %s\n", dir, strerror(errno));
        free(dir);
        return 1;
    }
    /* the job's folder is this process's while it runs: a second start of
     * the same job (GNU parallel retried, two array tasks) leaves it be */
    char *lockp = join(dir, "lock");
    int lock = open(lockp, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0666);
    free(lockp);
    if (lock < 0 || flock(lock, LOCK_EX | LOCK_NB) != 0) {
        fprintf(stderr, "flitter sweep: %s is %s; this start leaves it alone\n", dir,
                lock < 0 ? "not writable" : "being run by another process");
        if (lock >= 0) close(lock);
        free(dir);
        return 1;
    }
    long run = sw->run;
    /* results are written under names of this run's own and renamed by
     * this process, which holds the lock */
    remove_stale_temps(dir);
    char mname[64], fname[64];
    snprintf(mname, sizeof mname, "manifest.%ld.tmp", (long)getpid());
    snprintf(fname, sizeof fname, "final.state.%ld.tmp", (long)getpid());
    char *manifest = join(dir, "manifest"), *mtmp = join(dir, mname);
    char *state = join(dir, "run.state"), *trace = join(dir, "trace.csv");
    char *final = join(dir, "final.state"), *ftmp = join(dir, fname);
    char *logp = join(dir, "log");
    char *script = realpath(sw->script, NULL);
    if (!script) script = xstrdup(sw->script);

    /* the parameter lines, to recognise a finished job */
    char *want = NULL;
    size_t wantlen = 0;
    FILE *mf = open_memstream(&want, &wantlen);
    put_params(mf, sw, script, run);
    fclose(mf);
    int rc = 0;
    const char *ignored;
    char *old = read_text(manifest, &ignored);
    char buf[64];
    if (old && strncmp(old, want, wantlen) == 0 && manifest_get(old, "exit", buf, sizeof buf) &&
        strcmp(buf, "0") == 0) {
        fprintf(stderr, "flitter sweep: %s already finished\n", dir);
        goto done;
    }
    unlink(manifest);
    unlink(state);   /* an unfinished job starts over, not from its save */
    unlink(final);

    /* flitter run ... as an argument vector */
    char *exe = self_path(), frames[32], runarg[48];
    snprintf(frames, sizeof frames, "%ld", sw->frames);
    snprintf(runarg, sizeof runarg, "run=%ld", run);
    size_t na = 0;
    char **av = xmalloc((2 * sw->nparams + 20) * sizeof *av);
    char **defs = xmalloc((sw->nparams + 1) * sizeof *defs);
    av[na++] = exe;
    av[na++] = "run";
    av[na++] = "--frames";
    av[na++] = frames;
    for (size_t i = 0; i < sw->nparams; i++) {
        size_t n = strlen(sw->params[i].name) + strlen(sw->params[i].values[0]) + 2;
        defs[i] = xmalloc(n);
        snprintf(defs[i], n, "%s=%s", sw->params[i].name, sw->params[i].values[0]);
        av[na++] = "-D";
        av[na++] = defs[i];
    }
    av[na++] = "-D";
    av[na++] = runarg;
    av[na++] = "--state";
    av[na++] = state;
    av[na++] = "--trace-file";
    av[na++] = trace;
    av[na++] = "--dump-state";
    av[na++] = script;
    av[na] = NULL;

    struct sigaction sa, old_int, old_term, old_hup;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = pass_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    sigaction(SIGHUP, &sa, &old_hup);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int status = 0, code;
    pid_t pid = start_child(exe, av, ftmp, logp);
    if (pid < 0) {
        fprintf(stderr, "flitter sweep: cannot start %s: %s\n", exe, strerror(errno));
        code = 127;
    } else {
        job_child = pid;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
        job_child = 0;
        code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    sigaction(SIGHUP, &old_hup, NULL);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double wall = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
    if (code == 0 && rename(ftmp, final) != 0) code = 1;
    if (code != 0) unlink(ftmp);

    FILE *f = fopen(mtmp, "w");
    if (f) {
        fwrite(want, 1, wantlen, f);
        fprintf(f, "exit %d\nwall_seconds %.3f\n", code, wall);
    }
    if (!f || fclose(f) != 0 || rename(mtmp, manifest) != 0) {
        fprintf(stderr, "flitter sweep: cannot write %s: %s\n", manifest, strerror(errno));
        unlink(mtmp);
        if (code == 0) code = 1;
    }
    if (code != 0) fprintf(stderr, "flitter sweep: job %ld exited %d (see %s)\n", sw->job, code, logp);
    rc = code;
    for (size_t i = 0; i < sw->nparams; i++) free(defs[i]);
    free(defs);
    free(av);
    free(exe);
done:
    close(lock);   /* (after the manifest: the folder is left finished) */
    free(old);
    free(want);
    free(script);
    free(dir);
    free(manifest);
    free(mtmp);
    free(state);
    free(trace);
    free(final);
    free(ftmp);
    free(logp);
    return rc;
}

/* {=====================================================================
 * Collecting the manifests
 * ===================================================================== */

/* One CSV field: quoted when it holds ',', '"', CR or LF ('"' doubled). */
static void put_csv(const char *s)
{
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, stdout);
        return;
    }
    putchar('"');
    for (; *s; s++) {
        if (*s == '"') putchar('"');
        putchar(*s);
    }
    putchar('"');
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The CSV cell of parameter [name] in manifest [m]: the value the script
 * received (`value NAME VALUE`) when it has no string in it (numbers and
 * symbols: `10k` is 10000), else the text as typed (`param NAME TEXT`,
 * which is what a string receives); NULL when the job has neither. */
static const char *param_value(const char *m, const char *name, char *buf, size_t cap)
{
    size_t n = strlen(name) + 7;
    char *key = xmalloc(n);
    snprintf(key, n, "value %s", name);
    const char *v = manifest_get(m, key, buf, cap);
    if (!v || !*v || strchr(v, '"')) {
        memcpy(key, "param", 5);
        v = manifest_get(m, key, buf, cap);
    }
    free(key);
    return v;
}

/* Whether [text] is a whole decimal integer (an optional '-' when
 * [negative]) in [lo, hi]. */
static bool whole_number(const char *text, bool negative, long lo, long hi)
{
    if (!*text || (!negative && *text == '-') || isspace((unsigned char)*text)) return false;
    errno = 0;
    char *end;
    long v = strtol(text, &end, 10);
    return errno == 0 && *end == '\0' && v >= lo && v <= hi;
}

/* Why manifest text [m] of job folder [folder] is damaged, written into
 * [why] ([cap] bytes), or NULL when it is whole: every line a known key
 * (`job`, `script`, `frames`, `run`, `seed`, `exit`, `wall_seconds` once
 * each; `param` and `value` once per name), the job number that of its
 * folder, the run and frames whole numbers, the seed empty or the run,
 * the exit status 0 to 255 and the wall time a finite number of seconds
 * (what run_job writes). */
static const char *manifest_damage(const char *folder, const char *m, char *why, size_t cap)
{
    static const char *const once[] = {"job", "script", "frames", "run", "seed", "exit", "wall_seconds"};
    enum { NONCE = sizeof once / sizeof *once };
    int seen[NONCE] = {0};
    for (const char *l = m; *l; ) {
        const char *e = strchr(l, '\n'), *sp = memchr(l, ' ', e ? (size_t)(e - l) : strlen(l));
        size_t len = e ? (size_t)(e - l) : strlen(l);
        if (!sp) {
            snprintf(why, cap, "damaged (a line without a value: '%.*s')", (int)(len > 40 ? 40 : len), l);
            return why;
        }
        size_t k = (size_t)(sp - l);
        bool known = false;
        for (int i = 0; i < NONCE; i++)
            if (strlen(once[i]) == k && strncmp(l, once[i], k) == 0) {
                if (seen[i]++) {
                    snprintf(why, cap, "damaged (two '%s' lines)", once[i]);
                    return why;
                }
                known = true;
            }
        if (!known && !((k == 5 && strncmp(l, "param", 5) == 0) || (k == 5 && strncmp(l, "value", 5) == 0))) {
            snprintf(why, cap, "damaged (an unknown line '%.*s')", (int)(k > 40 ? 40 : k), l);
            return why;
        }
        if (!e) break;
        l = e + 1;
    }
    for (int i = 0; i < NONCE; i++)
        if (!seen[i]) {
            snprintf(why, cap, "damaged (no %s line)", once[i]);
            return why;
        }
    char v[4096], run[64];
    manifest_get(m, "job", v, sizeof v);
    char want[80];
    if (!whole_number(v, false, 0, LONG_MAX) ||
        (snprintf(want, sizeof want, "job-%04ld", strtol(v, NULL, 10)), strcmp(want, folder) != 0)) {
        snprintf(why, cap, "damaged (job '%.40s' is not that of its folder)", v);
        return why;
    }
    manifest_get(m, "frames", v, sizeof v);
    if (!whole_number(v, true, LONG_MIN, LONG_MAX)) {
        snprintf(why, cap, "damaged (frames '%.40s')", v);
        return why;
    }
    manifest_get(m, "run", run, sizeof run);
    if (!whole_number(run, false, 0, LONG_MAX)) {
        snprintf(why, cap, "damaged (run '%.40s')", run);
        return why;
    }
    manifest_get(m, "seed", v, sizeof v);
    if (*v && strcmp(v, run) != 0) {
        snprintf(why, cap, "damaged (seed '%.40s' is neither empty nor the run)", v);
        return why;
    }
    manifest_get(m, "exit", v, sizeof v);
    if (!whole_number(v, false, 0, 255)) {
        snprintf(why, cap, "damaged (exit status '%.40s')", v);
        return why;
    }
    manifest_get(m, "wall_seconds", v, sizeof v);
    char *end;
    errno = 0;
    double wall = strtod(v, &end);
    if (!*v || *end || errno != 0 || !(wall >= 0 && wall <= 1e12)) {
        snprintf(why, cap, "damaged (wall_seconds '%.40s')", v);
        return why;
    }
    return NULL;
}

static int collect(const char *out)
{
    DIR *d = opendir(out);
    if (!d) {
        fprintf(stderr, "flitter sweep: %s: %s\n", out, strerror(errno));
        return 1;
    }
    size_t n = 0, cap = 64, bad = 0;
    char **texts = xmalloc(cap * sizeof *texts), **names = xmalloc(cap * sizeof *names);
    for (struct dirent *e; (e = readdir(d));) {
        if (strncmp(e->d_name, "job-", 4) != 0) continue;
        char *dir = join(out, e->d_name), *mpath = join(dir, "manifest");
        const char *why;
        char *text = read_text(mpath, &why);
        free(dir);
        char damage[160];
        if (text && (why = manifest_damage(e->d_name, text, damage, sizeof damage)) != NULL) {
            free(text);
            text = NULL;
        }
        if (!text) {   /* reported and counted: the CSV lacks this job */
            fprintf(stderr, "flitter sweep: %s: %s\n", mpath, why);
            bad++;
            free(mpath);
            continue;
        }
        free(mpath);
        if (n == cap) {
            cap *= 2;
            char **t = realloc(texts, cap * sizeof *texts);
            if (!t) exit(70);
            texts = t;
        }
        size_t len = strlen(e->d_name) + 1 + strlen(text) + 1;
        texts[n] = xmalloc(len);
        snprintf(texts[n], len, "%s\n%s", e->d_name, text);   /* sorts by job name */
        free(text);
        n++;
    }
    closedir(d);
    free(names);
    qsort(texts, n, sizeof *texts, by_name);
    /* the parameter names, in the order of their first appearance */
    size_t np = 0;
    char *pn[MAX_PARAMS * 4];
    for (size_t i = 0; i < n; i++)
        for (const char *l = strchr(texts[i], '\n'); l; l = strchr(l + 1, '\n')) {
            if (strncmp(l + 1, "param ", 6) != 0) continue;
            const char *s = l + 7, *sp = strchr(s, ' ');
            if (!sp) continue;
            size_t k = (size_t)(sp - s), j = 0;
            for (; j < np; j++)
                if (strlen(pn[j]) == k && strncmp(pn[j], s, k) == 0) break;
            if (j == np && np < sizeof pn / sizeof *pn) {
                pn[np] = xmalloc(k + 1);
                memcpy(pn[np], s, k);
                pn[np++][k] = '\0';
            }
        }
    fputs("job", stdout);
    for (size_t j = 0; j < np; j++) {
        putchar(',');
        put_csv(pn[j]);
    }
    fputs(",run,seed,exit,wall_seconds\n", stdout);
    static const char *const tail[] = {"run", "seed", "exit", "wall_seconds"};
    char buf[4096];
    for (size_t i = 0; i < n; i++) {
        const char *m = strchr(texts[i], '\n') + 1;
        put_csv(manifest_get(m, "job", buf, sizeof buf) ? buf : "");
        for (size_t j = 0; j < np; j++) {
            putchar(',');
            put_csv(param_value(m, pn[j], buf, sizeof buf) ? buf : "");
        }
        for (size_t j = 0; j < 4; j++) {
            putchar(',');
            put_csv(manifest_get(m, tail[j], buf, sizeof buf) ? buf : "");
        }
        putchar('\n');
        free(texts[i]);
    }
    for (size_t j = 0; j < np; j++) free(pn[j]);
    free(texts);
    if (fflush(stdout) != 0) return 1;
    if (bad) {
        fprintf(stderr, "flitter sweep: %zu of %zu jobs have no readable manifest; their rows are missing\n",
                bad, bad + n);
        return 1;
    }
    return 0;
}

int cmd_sweep(int argc, char **argv)
{
    Sweep sw;
    int rc = parse_args(&sw, argc, argv);
    if (rc == 0) {
        if (sw.collect) rc = collect(sw.collect);
        else if (sw.job >= 0) rc = run_job(&sw);
        else rc = list_jobs(&sw);
    }
    for (size_t i = 0; i < sw.nparams; i++) {
        free(sw.params[i].name);
        free(sw.params[i].values);
    }
    return rc;
}
