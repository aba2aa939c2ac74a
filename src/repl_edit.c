/* repl_edit.c: terminal line editing for `flitter repl` (see repl.h):
 * libedit set-up, history (a multi-line block is one entry), Tab
 * completion of `:` commands, of names in scope and built-in functions, and
 * of file names after :load, :save, :restore and :view; Ctrl-C at the
 * prompt; the recovery file's path; questions asked at the prompt.
 *
 * The globals: `interrupted`, the SIGINT flag; and, as libedit's completion
 * callbacks take no user pointer, `completing`, which points at the
 * session's Repl while libedit may call back (the completion cursor itself
 * lives in that Repl).
 */
#include <errno.h>
#include <locale.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/stat.h>
#include <unistd.h>

#include <editline/readline.h>

#include "repl.h"

#define HISTORY_LINES 1000

/* libedit's completion callbacks carry no context: see the file comment. */
static Repl *completing;

/* Set by SIGINT in a terminal session (a signal handler takes no context
 * either): polled between the frames of :step, after readline, while a
 * result is written, and by the runtime (fl_options.interrupt, a volatile
 * int: the type of sig_atomic_t here). */
static volatile int interrupted;
_Static_assert(sizeof(sig_atomic_t) == sizeof(int), "sig_atomic_t is an int");

static void on_interrupt(int sig)
{
    (void)sig;
    __atomic_store_n(&interrupted, 1, __ATOMIC_RELAXED);   /* read by worker threads too */
}

/* Forget the names collected for completion. */
static void clear_names(Repl *r)
{
    for (size_t i = 0; i < r->cpl_count; i++) free(r->cpl_names[i]);
    free(r->cpl_names);
    r->cpl_names = NULL;
    r->cpl_count = 0;
}

/* fl_scope_names callback: keep a copy of [name]. */
static int add_name(void *ctx, const char *name)
{
    Repl *r = ctx;
    char **grown = realloc(r->cpl_names, (r->cpl_count + 1) * sizeof *grown);
    char *copy = strdup(name);
    if (!grown || !copy) abort();
    r->cpl_names = grown;
    r->cpl_names[r->cpl_count++] = copy;
    return 0;
}

/* Candidate [state] of the current completion (libedit generator). */
static char *complete_next(const char *text, int state)
{
    Repl *r = completing;
    if (state == 0) r->cpl_next = 0;
    size_t tlen = strlen(text);
    if (r->cpl_kind == CPL_FILES) {
        /* libedit's word stops at '/' and '.'; complete the whole path and
         * hand back the part from its word on */
        char *m = rl_filename_completion_function(text_cstr(&r->cpl_path), state);
        if (m && strlen(m) >= r->cpl_skip) memmove(m, m + r->cpl_skip, strlen(m) - r->cpl_skip + 1);
        return m;
    }
    if (r->cpl_kind == CPL_COMMANDS) {
        for (const char *name; (name = repl_command_name(r->cpl_next)) != NULL;) {
            r->cpl_next++;
            if (tlen >= 1 && strncmp(name, text + 1, tlen - 1) == 0) {
                char *m = malloc(strlen(name) + 2);
                if (!m) abort();
                m[0] = ':';
                strcpy(m + 1, name);
                return m;
            }
        }
        return NULL;
    }
    while (r->cpl_next < r->cpl_count) {
        size_t i = r->cpl_next++;
        const char *name = r->cpl_names[i];
        if (strncmp(name, text, tlen) != 0) continue;
        bool seen = false;   /* a name may be bound in several layers */
        for (size_t j = 0; j < i && !seen; j++) seen = strcmp(r->cpl_names[j], name) == 0;
        if (seen) continue;
        char *m = strdup(name);
        if (!m) abort();
        return m;
    }
    /* then the built-in functions not shadowed by a name in scope */
    for (const char *bname; (bname = fl_builtin_name(r->cpl_next - r->cpl_count)) != NULL;) {
        r->cpl_next++;
        if (strncmp(bname, text, tlen) != 0) continue;
        bool seen = false;
        for (size_t j = 0; j < r->cpl_count && !seen; j++)
            seen = strcmp(r->cpl_names[j], bname) == 0;
        if (seen) continue;
        char *m = strdup(bname);
        if (!m) abort();
        return m;
    }
    return NULL;
}

/* libedit's attempted-completion hook: `:` commands at the start of the
 * line, file names after :load/:save/:restore, else names in scope. */
static char **complete(const char *text, int start, int end)
{
    Repl *r = completing;
    const char *line = rl_line_buffer;
    rl_attempted_completion_over = 1;
    rl_completion_append_character = '\0';
    bool at_start = true;
    for (int i = 0; i < start; i++)
        if (line[i] != ' ' && line[i] != '\t') at_start = false;
    const char *cmd = skip_space(line);
    if (at_start && text[0] == ':') {
        r->cpl_kind = CPL_COMMANDS;
        rl_completion_append_character = ' ';
    } else if (!at_start && (strncmp(cmd, ":load ", 6) == 0 || strncmp(cmd, ":save ", 6) == 0 ||
                             strncmp(cmd, ":restore ", 9) == 0 || strncmp(cmd, ":view ", 6) == 0)) {
        const char *path = skip_space(strchr(cmd, ' '));
        size_t from = (size_t)(path - line);
        if (from > (size_t)start || end < start) return NULL;
        r->cpl_kind = CPL_FILES;
        r->cpl_skip = (size_t)start - from;
        text_reset(&r->cpl_path);
        text_add(&r->cpl_path, path, (size_t)end - from);
    } else if (text[0] == ':' || (start > 0 && line[start - 1] == ':')) {
        return NULL;                        /* a symbol: nothing to offer */
    } else {
        r->cpl_kind = CPL_NAMES;
        clear_names(r);
        fl_scope_names(r->rt, add_name, r);
    }
    char **matches = rl_completion_matches(text, complete_next);
    /* one file (libedit repeats a sole match after the common prefix in
     * [0]; GNU readline does not): end a directory with '/', a file with a
     * space */
    if (r->cpl_kind == CPL_FILES && matches && (!matches[1] || !matches[2])) {
        Text full = TEXT_INIT;
        text_add(&full, text_cstr(&r->cpl_path), r->cpl_skip);
        text_puts(&full, matches[0]);
        struct stat st;
        bool dir = stat(full.data, &st) == 0 && S_ISDIR(st.st_mode);
        rl_completion_append_character = dir ? '/' : ' ';
        text_free(&full);
    }
    return matches;
}

void repl_remember(Repl *r, const char *entry)
{
    if (is_blank(entry) || (r->last_entry && strcmp(r->last_entry, entry) == 0)) return;
    add_history(entry);
    free(r->last_entry);
    r->last_entry = strdup(entry);
    if (!r->last_entry) abort();
    if (r->history && write_history(r->history) != 0 && !r->history_failed) {
        r->history_failed = true;
        repl_error(r, "cannot write history file %s", r->history);
    }
}

/* One byte of [fd], waiting with SIGINT let through only inside pselect,
 * so that a Ctrl-C at any moment, even just before the wait, ends it.
 * Returns the byte, or EOF at the end of input or after a Ctrl-C. */
static int read_byte(int fd)
{
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigprocmask(SIG_BLOCK, &block, &old);
    int rc = EOF;
    while (!interrupted) {
        fd_set in;
        FD_ZERO(&in);
        FD_SET(fd, &in);
        if (pselect(fd + 1, &in, NULL, NULL, NULL, &old) < 0) {
            if (errno == EINTR) continue;
            break;
        }
        unsigned char c;
        ssize_t n = read(fd, &c, 1);
        if (n == 1) {
            rc = c;
            break;
        }
        if (n == 0 || errno != EINTR) break;
    }
    sigprocmask(SIG_SETMASK, &old, NULL);
    return rc;
}

/* libedit's character reader (rl_getc_function): a Ctrl-C makes readline
 * return at once (the line is dropped by the session loop). libedit takes
 * the result as one character, so a UTF-8 sequence is read whole and its
 * code point returned (a malformed one byte by byte). */
static int repl_getc(FILE *f)
{
    int fd = fileno(f), c = read_byte(fd);
    if (c == EOF || c < 0xc2 || c > 0xf4) return c;
    int more = c < 0xe0 ? 1 : c < 0xf0 ? 2 : 3;
    int cp = c & (0x3f >> more);
    for (int i = 0; i < more; i++) {
        int k = read_byte(fd);
        if (k == EOF) return EOF;
        if ((k & 0xc0) != 0x80) return k;   /* malformed: drop the partial sequence */
        cp = cp << 6 | (k & 0x3f);
    }
    return cp;
}

static void setup_editing(Repl *r)
{
    completing = r;
    rl_getc_function = repl_getc;   /* before anything initialises libedit */
    /* libedit edits wide characters and hands the line back through the
     * C library's multibyte conversion: without a UTF-8 character type
     * every non-ASCII character would be lost (numbers are unaffected,
     * LC_NUMERIC stays "C") */
    const char *ctype = setlocale(LC_CTYPE, "");
    if (!ctype || (!strstr(ctype, "UTF-8") && !strstr(ctype, "utf8"))) setlocale(LC_CTYPE, "C.UTF-8");
    rl_readline_name = "flitter";
    rl_attempted_completion_function = complete;
    /* characters that cannot be part of a name (names may hold ' and digits) */
    static const char breaks[] = " \t\n\"()[]{},;+-*/%<>=!&|^~$@.#?\\`";
    rl_basic_word_break_characters = breaks;
    rl_completer_word_break_characters = (char *)breaks;
    stifle_history(HISTORY_LINES);
    const char *env = getenv("FLITTER_HISTORY"), *home = getenv("HOME");
    if (env && *env) {
        r->history = strdup(env);
    } else if (home && *home) {
        size_t n = strlen(home) + sizeof "/.flitter_history";
        r->history = malloc(n);
        if (r->history) snprintf(r->history, n, "%s/.flitter_history", home);
    }
    if (r->history) read_history(r->history);   /* a missing file is fine */
    r->recovery = repl_recovery_path();
}

char *repl_recovery_path(void)
{
    const char *env = getenv("FLITTER_RECOVERY"), *home = getenv("HOME");
    if (env && *env) return strdup(env);
    if (!home || !*home) return NULL;
    size_t n = strlen(home) + sizeof "/.flitter_recovery.state";
    char *path = malloc(n);
    if (path) snprintf(path, n, "%s/.flitter_recovery.state", home);
    return path;
}

char *repl_ask(const char *prompt)
{
    char *answer = readline(prompt);
    if (interrupted) {
        free(answer);
        return NULL;
    }
    return answer;
}

void repl_edit_begin(Repl *r)
{
    struct sigaction sa = {.sa_handler = on_interrupt};   /* no SA_RESTART: wake readline */
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    setup_editing(r);
}

void repl_edit_end(Repl *r)
{
    clear_names(r);
    clear_history();
    completing = NULL;
}

volatile int *repl_interrupt_flag(void) { return &interrupted; }

bool repl_take_interrupt(void)
{
    if (!interrupted) return false;
    interrupted = 0;
    return true;
}
