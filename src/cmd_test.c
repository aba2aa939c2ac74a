/* cmd_test.c: `flitter test`, the golden-output runner.
 *
 * A test is a script NAME.fl with expected output beside it: NAME.state (a
 * state-dump stream, FORMATS.md §2) and/or NAME.tree (a node-tree dump,
 * FORMATS.md §3), both from runs without the simplifier (`--nosimplify` is
 * implied), and/or NAME.simplified.state / NAME.simplified.tree from runs in
 * Flitter's default mode (simplifier on unless the options say
 * `--nosimplify`), and/or NAME.upstream.state from runs in Flitter's
 * default mode with `--physics=upstream` (Flitter 1.0.0b28's own physics).
 * The `flitter run` options of a test come from a line
 * `NAME.fl OPTIONS...` in a MANIFEST file in the same directory, or else
 * from a header line `# options: OPTIONS...` at the top of the expected
 * file (default: --frames 1). Each test runs in-process; its output is
 * compared byte for byte. On a mismatch the runner prints a short unified
 * diff (from diff(1)) and, for state dumps, says whether the frames line
 * up (when they do not, no ULP figure pretends they were compared), which
 * keys are only on one side, and the largest numeric difference in units
 * in the last place between the numbers that line up. `--update` rewrites the expected files
 * (atomically: temporary file, fsync, rename). The last line is
 * `N passed, M failed`.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <spawn.h>
#include <unistd.h>

extern char **environ;

#include "commands.h"
#include "exitcodes.h"
#include "flitter.h"
#include "runner.h"

typedef struct Totals {
    int passed, failed;
} Totals;

/* The whole file at [path], NUL-terminated (malloc'd), or NULL when it
 * cannot be read. */
static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *data = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&data, &len);
    if (!m) abort();
    char chunk[65536];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) fwrite(chunk, 1, n, m);
    bool ok = !ferror(f);
    fclose(f);
    fclose(m);
    if (!ok) {
        free(data);
        return NULL;
    }
    return data;
}

/* Replace [path] with [len] bytes at [data]: written to a temporary file
 * beside it, then renamed over it. Returns false with errno set. */
static bool write_text(const char *path, const char *data, size_t len)
{
    char *tmp;
    if (asprintf(&tmp, "%s.tmp%ld", path, (long)getpid()) < 0) abort();
    FILE *f = fopen(tmp, "wb");
    bool ok = f && fwrite(data, 1, len, f) == len;
    if (f && fclose(f) != 0) ok = false;
    if (ok && rename(tmp, path) != 0) ok = false;
    if (!ok) {
        int e = errno;
        unlink(tmp);
        errno = e;
    }
    free(tmp);
    return ok;
}

/* The options line for [script] from [dir]/MANIFEST, or NULL. */
static char *manifest_options(const char *dir, const char *script)
{
    char *path;
    if (asprintf(&path, "%s/MANIFEST", dir) < 0) return NULL;
    char *text = read_text(path);
    char *found = NULL;
    if (text) {
        size_t sl = strlen(script);
        for (char *line = text; line && *line && !found;) {
            char *nl = strchr(line, '\n');
            if (nl) *nl = '\0';
            while (*line == ' ' || *line == '\t') line++;
            if (*line != '#' && strncmp(line, script, sl) == 0 &&
                (line[sl] == ' ' || line[sl] == '\t' || line[sl] == '\0' || line[sl] == '\r'))
                found = strdup(line + sl);
            line = nl ? nl + 1 : NULL;
        }
    }
    free(text);
    free(path);
    return found;
}

/* Split [s] on white space into a NULL-terminated argv (argv[0] = "run"). */
static char **split_args(char *s, int *argc)
{
    size_t cap = 8, n = 1;
    char **v = malloc(cap * sizeof(char *));
    if (!v) abort();
    v[0] = "run";
    for (char *tok = strtok(s, " \t\r\n"); tok; tok = strtok(NULL, " \t\r\n")) {
        if (n + 2 > cap) {
            cap *= 2;
            v = realloc(v, cap * sizeof(char *));
            if (!v) abort();
        }
        v[n++] = tok;
    }
    v[n] = NULL;
    *argc = (int)n;
    return v;
}

/* The expected text without its `# options:` header lines. */
static const char *skip_header(const char *s)
{
    while (strncmp(s, "# options:", 10) == 0) {
        const char *nl = strchr(s, '\n');
        s = nl ? nl + 1 : s + strlen(s);
    }
    return s;
}

/* ---- numeric comparison of state dumps --------------------------------- */

static uint64_t ordered(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return (u >> 63) ? ~u : u | UINT64_C(0x8000000000000000);
}

/* One line of a state dump: [text] up to [len] bytes (no newline). */
typedef struct Line {
    const char *text;
    size_t len;
} Line;

/* The next line at *[s] (advancing it), false at the end. */
static bool next_line(const char **s, Line *l)
{
    if (!**s) return false;
    const char *nl = strchr(*s, '\n');
    l->text = *s;
    l->len = nl ? (size_t)(nl - *s) : strlen(*s);
    *s = nl ? nl + 1 : *s + l->len;
    return true;
}

static bool is_header(const Line *l) { return l->len >= 8 && strncmp(l->text, "# frame ", 8) == 0; }

/* The key of a `KEY = VALUE` line (its length in [*klen]), or NULL. */
static const char *line_key(const Line *l, size_t *klen)
{
    for (size_t i = 0; i + 3 <= l->len; i++)
        if (memcmp(l->text + i, " = ", 3) == 0) {
            *klen = i;
            return l->text;
        }
    return NULL;
}

/* The frame numbers of the dump's blocks, as text ("2, 5, 8"), at most
 * [cap] bytes, and their count. */
static int frame_list(const char *dump, char *out, size_t cap)
{
    int n = 0;
    size_t used = 0;
    out[0] = '\0';
    Line l;
    for (const char *s = dump; next_line(&s, &l);) {
        if (!is_header(&l)) continue;
        const char *num = l.text + 8, *sp = memchr(num, ' ', l.len - 8);
        int w = (int)(sp ? (size_t)(sp - num) : l.len - 8);
        if (used + (size_t)w + 8 < cap) used += (size_t)snprintf(out + used, cap - used, "%s%.*s", n ? ", " : "", w, num);
        else if (used + 5 < cap && !strstr(out, "...")) used += (size_t)snprintf(out + used, cap - used, ", ...");
        n++;
    }
    return n;
}

/* The block of [dump] whose header is [header] (its lines after the
 * header, up to the next header), or NULL. */
static const char *find_block(const char *dump, const Line *header)
{
    Line l;
    for (const char *s = dump; next_line(&s, &l);)
        if (is_header(&l) && l.len == header->len && memcmp(l.text, header->text, l.len) == 0) return s;
    return NULL;
}

/* Bytewise order of two keys (the dump's order: a prefix first). */
static int key_cmp(const char *a, size_t al, const char *b, size_t bl)
{
    int c = memcmp(a, b, al < bl ? al : bl);
    return c ? c : (al > bl) - (al < bl);
}

/* Compare two state-dump streams as numbers and say how they differ:
 * whether their frames line up (blocks are matched by their `# frame N
 * time T` header), keys only in one of them, values of another length,
 * and the largest distance in units in the last place between numbers of
 * equal keys in matching frames. */
static void explain_state_diff(const char *expected, const char *actual)
{
    char ef[512], af[512];
    int en = frame_list(expected, ef, sizeof ef), an = frame_list(actual, af, sizeof af);
    bool frames_match = en == an && strcmp(ef, af) == 0;
    if (!frames_match)
        printf("frames do not line up: expected %d dump%s (frame %s), got %d (frame %s); "
               "numbers are compared only in frames both have\n",
               en, en == 1 ? "" : "s", en ? ef : "none", an, an ? af : "none");
    double worst = 0;
    char where[300] = "";
    long only_e = 0, only_a = 0, length = 0, compared = 0, matched_blocks = 0;
    char first_e[200] = "", first_a[200] = "", first_len[200] = "";
    Line h;
    for (const char *s = expected; next_line(&s, &h);) {
        if (!is_header(&h)) continue;
        const char *e = s, *a = find_block(actual, &h);
        if (!a) continue;
        matched_blocks++;
        Line el, al;
        bool he = next_line(&e, &el) && !is_header(&el), ha = next_line(&a, &al) && !is_header(&al);
        while (he || ha) {
            size_t ek = 0, ak = 0;
            const char *ekey = he ? line_key(&el, &ek) : NULL, *akey = ha ? line_key(&al, &ak) : NULL;
            int c = !ha ? -1 : !he ? 1 : (!ekey || !akey) ? 0 : key_cmp(ekey, ek, akey, ak);
            if (c < 0) {
                if (!only_e++) snprintf(first_e, sizeof first_e, "%.*s", (int)(ekey ? ek : el.len), el.text);
            } else if (c > 0) {
                if (!only_a++) snprintf(first_a, sizeof first_a, "%.*s", (int)(akey ? ak : al.len), al.text);
            } else if (ekey && akey) {
                const char *x = el.text + ek + 3, *y = al.text + ak + 3;
                const char *xend = el.text + el.len, *yend = al.text + al.len;
                long nx = 1, ny = 1;
                for (const char *p = x; p < xend; p++) nx += *p == ';';
                for (const char *p = y; p < yend; p++) ny += *p == ';';
                if (nx != ny && !length++) snprintf(first_len, sizeof first_len, "%.*s", (int)ek, ekey);
                while (nx == ny && x < xend && y < yend) {
                    char *xe, *ye;
                    double dx = strtod(x, &xe), dy = strtod(y, &ye);
                    if (xe == x || ye == y) break;
                    if (!isnan(dx) && !isnan(dy)) {
                        compared++;
                        uint64_t ox = ordered(dx), oy = ordered(dy);
                        double d = (double)(ox > oy ? ox - oy : oy - ox);
                        if (d > worst) {
                            worst = d;
                            snprintf(where, sizeof where, "%.*s (%.*s)", (int)ek, ekey,
                                     (int)(h.len - 2), h.text + 2);
                        }
                    }
                    x = memchr(xe, ';', (size_t)(xend - xe));
                    y = memchr(ye, ';', (size_t)(yend - ye));
                    if (!x || !y) break;
                    x++;
                    y++;
                }
            }
            if (c <= 0) he = next_line(&e, &el) && !is_header(&el);
            if (c >= 0) ha = next_line(&a, &al) && !is_header(&al);
        }
    }
    if (only_e || only_a)
        printf("keys that do not line up: %ld only in expected%s%s%s, %ld only in actual%s%s%s\n",
               only_e, only_e ? " (first: " : "", first_e, only_e ? ")" : "",
               only_a, only_a ? " (first: " : "", first_a, only_a ? ")" : "");
    if (length) printf("values of another length: %ld (first: %s)\n", length, first_len);
    if (worst > 0)
        printf("largest numeric difference: %.0f ULP at %s\n", worst, where);
    else if (!matched_blocks)
        puts("no numbers compared: no frame is in both");
    else if (compared)
        printf("no numeric difference in the %ld numbers that line up\n", compared);
    else
        puts("no numbers compared");
}

/* Print a unified diff of the two texts (first 40 lines) using diff(1),
 * spawned with an argument vector: the label (from a file name that may
 * come from anyone) never reaches a shell. */
static void show_diff(const char *label, const char *expected, const char *actual)
{
    char ef[] = "/tmp/flitter-expected-XXXXXX", af[] = "/tmp/flitter-actual-XXXXXX";
    int efd = mkstemp(ef), afd = mkstemp(af);
    if (efd < 0 || afd < 0) {
        if (efd >= 0) { close(efd); unlink(ef); }
        if (afd >= 0) { close(afd); unlink(af); }
        return;
    }
    FILE *f = fdopen(efd, "w");
    fputs(expected, f);
    fclose(f);
    f = fdopen(afd, "w");
    fputs(actual, f);
    fclose(f);
    char *l1 = NULL, *l2 = NULL;
    int fds[2] = {-1, -1};
    if (asprintf(&l1, "%s (expected)", label) >= 0 && asprintf(&l2, "%s (actual)", label) >= 0 &&
        pipe2(fds, O_CLOEXEC) == 0) {
        char *argv[] = {"diff", "-u", "--label", l1, "--label", l2, ef, af, NULL};
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
        pid_t pid;
        fflush(stdout);
        int rc = posix_spawnp(&pid, "diff", &fa, NULL, argv, environ);
        posix_spawn_file_actions_destroy(&fa);
        close(fds[1]);
        FILE *in = rc == 0 ? fdopen(fds[0], "r") : NULL;
        if (in) {
            /* the first 40 lines, then read on to the end so diff can finish */
            char *line = NULL;
            size_t cap = 0;
            for (int n = 0; getline(&line, &cap, in) >= 0; n++)
                if (n < 40) fputs(line, stdout);
            free(line);
            fclose(in);
        } else {
            close(fds[0]);
        }
        if (rc == 0) {
            int status;
            while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
        } else {
            printf("(no diff: cannot run diff: %s)\n", strerror(rc));
        }
    }
    free(l1);
    free(l2);
    unlink(ef);
    unlink(af);
}

/* ---- one test ---------------------------------------------------------- */

/* True for the state-dump kinds ("state", "simplified.state", "upstream.state"). */
static bool is_state_kind(const char *kind)
{
    size_t n = strlen(kind);
    return n >= 5 && strcmp(kind + n - 5, "state") == 0;
}

static bool has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}


static void run_one(const char *dir, const char *script, const char *kind, bool update, Totals *t)
{
    char *base = strndup(script, strlen(script) - 3);   /* without ".fl" */
    char *expected_path, *script_path;
    if (!base || asprintf(&expected_path, "%s/%s.%s", dir, base, kind) < 0 ||
        asprintf(&script_path, "%s/%s", dir, script) < 0)
        abort();
    char *expected = read_text(expected_path);
    if (!expected) goto done_quiet;

    const char *exp = expected;
    char *opts = manifest_options(dir, script);
    if (!opts && strncmp(exp, "# options:", 10) == 0) {
        const char *nl = strchr(exp, '\n');
        opts = strndup(exp + 10, nl ? (size_t)(nl - exp - 10) : strlen(exp + 10));
    }
    if (!opts) opts = strdup("--frames 1");
    int argc;
    char **argv = split_args(opts, &argc);
    RunSpec spec;
    char *label;
    if (asprintf(&label, "%s/%s.%s", dir, base, kind) < 0) abort();
    if (runspec_parse(&spec, argc, argv, RUNSPEC_NO_SCRIPT, stdout) != 0) {
        printf("FAIL %s: bad options\n", label);
        t->failed++;
    } else {
        spec.script = script_path;
        if (is_state_kind(kind)) spec.dump_state = true;
        else spec.dump_tree = true;
        bool upstream = strncmp(kind, "upstream.", 9) == 0;
        if (strncmp(kind, "simplified.", 11) != 0 && !upstream) spec.no_simplify = true;
        if (upstream) spec.physics = FL_PHYSICS_UPSTREAM;
        spec.dump_simplified = false;
        char *out = NULL, *log = NULL;
        size_t outlen = 0, loglen = 0;
        FILE *fo = open_memstream(&out, &outlen), *fl = open_memstream(&log, &loglen);
        int rc = runspec_execute(&spec, fo, fl, NULL);
        fclose(fo);
        fclose(fl);
        const char *want = skip_header(exp);
        if (rc != 0) {
            printf("FAIL %s: flitter run exited with %d\n%s", label, rc, log);
            t->failed++;
        } else if (strcmp(want, out) == 0) {
            printf("PASS %s\n", label);
            t->passed++;
        } else if (update) {
            size_t head = (size_t)(want - exp);   /* keep the header */
            char *nb = malloc(head + outlen + 1);
            if (!nb) abort();
            memcpy(nb, exp, head);
            memcpy(nb + head, out, outlen);
            if (write_text(expected_path, nb, head + outlen)) {
                printf("UPDATED %s\n", label);
                t->passed++;
            } else {
                printf("FAIL %s: cannot write: %s\n", label, strerror(errno));
                t->failed++;
            }
            free(nb);
        } else {
            printf("FAIL %s\n", label);
            show_diff(label, want, out);
            if (is_state_kind(kind)) explain_state_diff(want, out);
            t->failed++;
        }
        free(out);
        free(log);
    }
    runspec_free(&spec);
    free(label);
    free(argv);
    free(opts);
done_quiet:
    free(expected);
    free(expected_path);
    free(script_path);
    free(base);
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The expected-output suffixes a script may have beside it. */
static const char *const test_kinds[] = {"state", "tree", "simplified.state", "simplified.tree",
                                         "upstream.state"};

/* Run every test in directory [dir] in name order. */
static int run_dir(const char *dir, bool update, Totals *t)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "flitter test: cannot open '%s': %s\n", dir, strerror(errno));
        return -1;
    }
    char **names = NULL;
    size_t n = 0, cap = 0;
    struct dirent *de;
    while ((de = readdir(d))) {
        if (!has_suffix(de->d_name, ".fl")) continue;
        if (n == cap) {
            cap = cap ? cap * 2 : 32;
            names = realloc(names, cap * sizeof(char *));
            if (!names) abort();
        }
        names[n++] = strdup(de->d_name);
    }
    closedir(d);
    if (n) qsort(names, n, sizeof(char *), by_name);
    int before = t->passed + t->failed;
    for (size_t i = 0; i < n; i++) {
        for (size_t k = 0; k < sizeof test_kinds / sizeof test_kinds[0]; k++)
            run_one(dir, names[i], test_kinds[k], update, t);
        free(names[i]);
    }
    free(names);
    if (t->passed + t->failed == before) {   /* say so rather than pass nothing */
        struct stat sb;
        char *manifest = NULL;
        bool has_manifest = asprintf(&manifest, "%s/MANIFEST", dir) >= 0 && stat(manifest, &sb) == 0;
        free(manifest);
        fprintf(stderr, "flitter test: no tests in '%s' (%s; a test is NAME.fl with NAME.state, "
                "NAME.tree, NAME.simplified.state, NAME.simplified.tree or NAME.upstream.state "
                "beside it)\n", dir, has_manifest ? "its MANIFEST names none with expected output"
                                                               : "no MANIFEST there");
        return -1;
    }
    return 0;
}

int cmd_test(int argc, char **argv)
{
    bool update = false;
    Totals t = {0};
    int first = 1, status = 0;
    for (; first < argc && argv[first][0] == '-'; first++) {
        if (strcmp(argv[first], "--update") == 0) {
            update = true;
        } else if (strcmp(argv[first], "-h") == 0 || strcmp(argv[first], "--help") == 0) {
            puts("usage: flitter test [--update] [PATH...]\n"
                 "  Runs every NAME.fl in each directory PATH (default .) that has a NAME.state\n"
                 "  or NAME.tree beside it (run with --nosimplify), or NAME.simplified.state or\n"
                 "  NAME.simplified.tree (Flitter's default mode), or NAME.upstream.state\n"
                 "  (default mode with --physics=upstream), or the given .fl files, and\n"
                 "  compares the output.\n"
                 "  --update   rewrite expected files that differ");
            return EXIT_OK;
        } else {
            fprintf(stderr, "flitter test: unknown option '%s'\n", argv[first]);
            return EXIT_USAGE;
        }
    }
    if (first == argc) {
        if (run_dir(".", update, &t) != 0) status = EXIT_USAGE;
    }
    for (int i = first; i < argc; i++) {
        struct stat sb;
        if (stat(argv[i], &sb) != 0) {
            fprintf(stderr, "flitter test: cannot open '%s': %s\n", argv[i], strerror(errno));
            status = EXIT_USAGE;
        } else if (S_ISDIR(sb.st_mode)) {
            if (run_dir(argv[i], update, &t) != 0) status = EXIT_USAGE;
        } else {
            char *copy = strdup(argv[i]);
            char *slash = strrchr(copy, '/');
            const char *dir = ".", *file = copy;
            if (slash) {
                *slash = '\0';
                dir = slash == copy ? "/" : copy;
                file = slash + 1;
            }
            for (size_t k = 0; k < sizeof test_kinds / sizeof test_kinds[0]; k++)
                run_one(dir, file, test_kinds[k], update, &t);
            free(copy);
        }
    }
    printf("%d passed, %d failed\n", t.passed, t.failed);
    if (t.failed) return 1;
    return status;
}
