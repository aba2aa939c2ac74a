/* cmd_repl.c: `flitter repl [options] [SCRIPT]`, an interactive session
 * that loads a script, steps its frames on demand and evaluates Flitter
 * text in the scope of the script's last evaluated frame (fl_eval).
 *
 * An input line that starts with `:` is a command (`:step`, `:state`, ...;
 * see the table `commands` below and `:help`); an unknown one is an error
 * (write a symbol as `(:name)`). Any other line is Flitter text: an
 * expression, whose value text is printed, or `let`/`func` bindings,
 * printed as `NAME = VALUE` lines. When the parser says the text ended
 * early (fl_eval returns 1), or while the following lines are indented,
 * more lines are read into one block; an empty line, or a non-indented
 * line that completes the block or comes after a complete block, ends it.
 * Scripted input is read one line ahead, so there a complete first line
 * followed by indented ones is one block; a terminal session evaluates a
 * complete first line at once, so there a multi-line `let` has to start
 * incomplete (`let x=`, or `func f(a)`).
 *
 * The script's names enter the scope with its first frame; the session
 * does not step by itself, so `:step 30` reports frame 29 exactly as
 * `flitter run --frames 30` would. `:state` leaves out the dump's `# frame`
 * header (`:step` prints the frame and time).
 *
 * On a terminal, lines are read with libedit: line editing, a history file
 * ($FLITTER_HISTORY, else ~/.flitter_history; rewritten after each line)
 * and Tab completion of `:` commands, of names in scope (fl_scope_names)
 * and of file names after :load/:save/:restore. Otherwise lines are read
 * with getline() with no prompt or echo, so a session can be scripted.
 * Values and command results go to stdout; errors (`<repl>:LINE:COL: error:
 * ...`, `FILE:LINE:COL: error: ...`, `error: ...`) and the runtime's log go
 * to stderr; stdout is line-buffered, and flushed before the REPL writes
 * to stderr, so the two streams interleave in order. An error never ends
 * the session; a scripted session that met one exits with status 1. In a
 * terminal session Ctrl-C stops a :step between frames or drops the line
 * being typed; a second Ctrl-C at an empty prompt asks before quitting, and
 * quitting then saves the state and clock to the recovery file
 * ($FLITTER_RECOVERY, else ~/.flitter_recovery.state) and says where. A
 * long :step on a terminal shows a progress line on stderr.
 *
 * `_` is the last expression's result and a node result prints with its
 * attributes (both fl_eval); `:set KEY VALUE` and `:unset KEY` edit the
 * state through fl_state_set_expr. On a terminal a multi-line block is one
 * history entry; recalled, its lines are taken one by one.
 *
 * Terminal line editing (libedit, history, completion, Ctrl-C at the
 * prompt) lives in repl_edit.c; the session state both share in repl.h.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <editline/readline.h>

#include "commands.h"
#include "exitcodes.h"
#include "repl.h"
#include "repl_window.h"
#include "runner.h"

#define PROMPT "flitter> "
#define PROMPT_MORE "   ...> "



/* ====================================================================
 * Output helpers
 * ==================================================================== */

void repl_error(Repl *r, const char *fmt, ...)
{
    r->errors++;
    fflush(stdout);
    va_list ap;
    va_start(ap, fmt);
    fputs("error: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* fl_write_fn: to the FILE [ctx]. */
static void write_file(void *ctx, const char *text, size_t len) { fwrite(text, 1, len, ctx); }

/* fl_write_fn: append to the Text [ctx]. */
static void write_buf(void *ctx, const char *text, size_t len) { text_add(ctx, text, len); }


/* ====================================================================
 * Evaluating Flitter text
 * ==================================================================== */

/* fl_error()'s message of the last failed call on stderr; counted. */
static void put_error(Repl *r)
{
    const char *e = fl_error(r->rt);
    size_t n = strlen(e);
    fflush(stdout);
    fputs(e, stderr);
    if (n && e[n - 1] != '\n') fputc('\n', stderr);
    r->errors++;
}

/* fl_write_fn for results: to stdout in pieces, stopping at a Ctrl-C (a
 * long vector takes minutes to print on a terminal); *[ctx] is set once
 * the output was cut. */
static void write_result(void *ctx, const char *text, size_t len)
{
    bool *cut = ctx;
    const size_t piece = 1 << 16;
    for (size_t off = 0; off < len && !*cut; off += piece) {
        if (*repl_interrupt_flag()) {
            *cut = true;
            fflush(stdout);
            fputs("\n(output interrupted)\n", stderr);
            break;
        }
        fwrite(text + off, 1, len - off < piece ? len - off : piece, stdout);
    }
}

/* Evaluate [len] bytes at [text]; print the result or the error. Returns
 * fl_eval's status (1: the text ended early, nothing printed). */
static int eval_text(Repl *r, const char *text, size_t len)
{
    bool cut = false;
    int rc = fl_eval(r->rt, text, len, write_result, &cut);   /* lines, each with its newline */
    /* a Ctrl-C during the evaluation or the output was for them, not for
     * the next prompt */
    repl_take_interrupt();
    if (rc < 0) put_error(r);
    return rc;
}

/* Evaluate the pending block, which is complete or has to be: an input
 * that still ends early is reported as an error. */
static void finish_block(Repl *r)
{
    if (eval_text(r, r->block.data, r->block.len) == 1) {
        fflush(stdout);
        fputs("<repl>: error: input ended early (unexpected end of input)\n", stderr);
        r->errors++;
    }
    text_reset(&r->block);
    r->in_block = false;
}

/* ====================================================================
 * Commands
 * ==================================================================== */

typedef enum { ARG_NONE, ARG_OPTIONAL, ARG_REQUIRED } ArgUse;

/* A command handler gets the argument text (trimmed, "" when absent) and
 * returns 1 to end the session, else 0 (errors are printed, not returned). */
typedef int CommandFn(Repl *r, const char *arg);

typedef struct Command {
    const char *name;    /* the word after ':' */
    ArgUse arg;          /* whether it takes an argument */
    const char *usage;   /* argument synopsis for :help */
    const char *help;    /* one-line description for :help */
    CommandFn *fn;
} Command;

static int cmd_help(Repl *r, const char *arg);

/* Load (or reload) [path] into the runtime, keeping the state; on success
 * it becomes the session's script. Returns 0 or -1 (error printed). */
static int load_script(Repl *r, const char *path)
{
    int rc = fl_load(r->rt, path);
    if (rc != 0) put_error(r);
    if (rc == 0 && r->script != path) {
        char *copy = strdup(path);
        if (!copy) abort();
        free(r->script);
        r->script = copy;
    }
    return rc;
}

static void print_frame(Repl *r)
{
    char t[64];
    fl_number_text(fl_frame_time(r->rt), t, sizeof t);
    printf("frame %ld time %s\n", fl_frame_count(r->rt) - 1, t);
}

/* The last path component of [path]. */
static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash && slash[1] ? slash + 1 : path;
}

/* Handle the live window's events; closed (close button, Escape): gone,
 * the session goes on. */
static void window_events(Repl *r)
{
    if (!r->window || repl_window_poll(r->window)) return;
    repl_window_close(r->window);
    r->window = NULL;
    puts("window closed");
}

static bool save_recovery(Repl *r);

/* The window's X display lost (repl_window_open; Xlib lets no X call
 * return): the session's state and clock go to the recovery file, as a
 * confirmed quit leaves them (a session not at a terminal too); the
 * process then exits with status 3. */
static void window_lost(void *ctx)
{
    Repl *r = ctx;
    if (!r->recovery) r->recovery = repl_recovery_path();   /* (a session not at a terminal) */
    save_recovery(r);
}

/* After a frame: the window's events, then its picture ([force]: now,
 * else at most 60 times a second). */
static void window_frame(Repl *r, bool force)
{
    window_events(r);
    if (r->window) repl_window_frame(r->window, r->rt, force);
}

/* `:window` opens a live window on the runtime, `:window off` closes it. */
static int cmd_window(Repl *r, const char *arg)
{
    if (strcmp(arg, "off") == 0) {
        if (!r->window) {
            puts("no window open");
            return 0;
        }
        repl_window_close(r->window);
        r->window = NULL;
        puts("window closed");
        return 0;
    }
    if (*arg) {
        repl_error(r, "usage: :window [off]");
        return 0;
    }
    if (r->window) {
        window_frame(r, true);
        puts("window already open");
        return 0;
    }
    char why[256];
    r->window = repl_window_open(r->rt, r->script ? base_name(r->script) : "flitter repl",
                                 window_lost, r, why, sizeof why);
    if (!r->window) {
        repl_error(r, "no window: %s", why);
        return 0;
    }
    puts("window open (:window off closes it)");
    return 0;
}

/* The progress line of a long :step on a terminal: shown on stderr once
 * the command has run for PROGRESS_AFTER seconds, redrawn at most every
 * PROGRESS_EVERY seconds (with a carriage return, no terminal escapes),
 * and blanked out when the command ends. */
#define PROGRESS_AFTER 0.5
#define PROGRESS_EVERY 0.2

typedef struct Progress {
    bool on;          /* on a terminal, more than one frame */
    long total;       /* frames asked for */
    double start;     /* monotonic seconds at the start */
    double shown;     /* when the line was last drawn, or 0 */
    int width;        /* columns of the last line drawn */
} Progress;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void progress_begin(Progress *p, const Repl *r, long total)
{
    *p = (Progress){.on = r->tty && total > 1 && isatty(STDERR_FILENO) == 1, .total = total};
    if (p->on) p->start = now_seconds();
}

/* Before frame [done] (0-based) of the command. */
static void progress_show(Progress *p, long done)
{
    if (!p->on || done == 0) return;
    double t = now_seconds();
    if (t - p->start < PROGRESS_AFTER || (p->shown > 0 && t - p->shown < PROGRESS_EVERY)) return;
    p->shown = t;
    double left = (t - p->start) / (double)done * (double)(p->total - done);
    fflush(stdout);
    int w = fprintf(stderr, "\rstepping: %ld of %ld frames (%d%%), about %.0f s to go; Ctrl-C stops",
                    done, p->total, (int)(100.0 * (double)done / (double)p->total), ceil(left));
    if (w > 0) {
        for (int i = w; i < p->width; i++) fputc(' ', stderr);
        if (w > p->width) p->width = w;
    }
    fflush(stderr);
}

/* Blank the progress line out, if one was drawn. */
static void progress_end(Progress *p)
{
    if (!p->on || !p->width) return;
    fputc('\r', stderr);
    for (int i = 0; i < p->width; i++) fputc(' ', stderr);
    fputc('\r', stderr);
    fflush(stderr);
    p->width = 0;
}

static int cmd_step(Repl *r, const char *arg)
{
    long n = 1;
    if (*arg) {
        char *end;
        errno = 0;
        n = strtol(arg, &end, 10);
        if (errno || end == arg || *end || n < 1) {
            repl_error(r, "bad frame count '%s' (expected a whole number >= 1)", arg);
            return 0;
        }
    }
    if (!r->script) {
        repl_error(r, "no script loaded (use :load FILE)");
        return 0;
    }
    Progress progress;
    progress_begin(&progress, r, n);
    for (long i = 0; i < n; i++) {
        progress_show(&progress, i);
        if (repl_take_interrupt()) {   /* Ctrl-C: stop between frames, keep the session */
            progress_end(&progress);
            fflush(stdout);
            fprintf(stderr, "interrupted after %ld of %ld frames\n", i, n);
            break;
        }
        int rc = fl_step(r->rt);
        if (rc == 1) {   /* Ctrl-C inside the frame: discarded, as if not begun */
            repl_take_interrupt();
            progress_end(&progress);
            fflush(stdout);
            fprintf(stderr, "interrupted after %ld of %ld frames\n", i, n);
            break;
        }
        if (rc != 0) {   /* no program, or the clock at its limit */
            progress_end(&progress);
            const char *why = fl_error(r->rt);
            if (strncmp(why, "fl_step: ", 9) == 0) why += 9;
            repl_error(r, "%.*s", (int)strcspn(why, "\n"), why);
            return 0;
        }
        if (r->window) window_frame(r, false);
    }
    progress_end(&progress);
    if (r->window) window_frame(r, true);
    print_frame(r);
    return 0;
}

/* The state dump without its `# frame` header, keeping the lines whose
 * text (KEY first) starts with [arg]. */
static int cmd_state(Repl *r, const char *arg)
{
    Text dump = TEXT_INIT;
    fl_dump_state(r->rt, write_buf, &dump);
    size_t plen = strlen(arg);
    const char *s = text_cstr(&dump);
    while (*s) {
        const char *nl = strchr(s, '\n');
        size_t len = nl ? (size_t)(nl - s) + 1 : strlen(s);
        if (s[0] != '#' && len > plen && strncmp(s, arg, plen) == 0) fwrite(s, 1, len, stdout);
        s += len;
    }
    text_free(&dump);
    return 0;
}

static int cmd_tree(Repl *r, const char *arg)
{
    (void)arg;
    if (fl_dump_tree(r->rt, write_file, stdout) != 0)   /* ends with a newline */
        repl_error(r, "no frame evaluated yet (use :step)");
    return 0;
}

static int cmd_get(Repl *r, const char *arg)
{
    Text text = TEXT_INIT;
    text_printf(&text, "$(%s)\n", arg);
    if (eval_text(r, text.data, text.len) == 1)
        repl_error(r, "incomplete key expression '%s'", arg);
    text_free(&text);
    return 0;
}

/* The length of the key at the start of a :set argument: up to the first
 * blank outside brackets and string quotes. */
static size_t key_length(const char *arg)
{
    int depth = 0;
    char quote = 0;
    size_t i = 0;
    for (; arg[i]; i++) {
        char c = arg[i];
        if (quote) {
            if (c == '\\' && arg[i + 1]) i++;
            else if (c == quote) quote = 0;
        } else if (c == '"' || c == '\'') {
            quote = c;
        } else if (c == '(' || c == '[' || c == '{') {
            depth++;
        } else if ((c == ')' || c == ']' || c == '}') && depth > 0) {
            depth--;
        } else if ((c == ' ' || c == '\t') && depth == 0) {
            break;
        }
    }
    return i;
}

/* Store [value] under [key] (Flitter expressions) and print the entry. */
static void set_state(Repl *r, const char *key, const char *value)
{
    if (fl_state_set_expr(r->rt, key, value, write_file, stdout) != 0) put_error(r);
}

/* `:set KEY VALUE`: KEY is one word or bracketed expression, VALUE the
 * rest, both Flitter expressions (`:set :collapse 1`). */
static int cmd_set(Repl *r, const char *arg)
{
    size_t klen = key_length(arg);
    const char *value = skip_space(arg + klen);
    if (!*value) {
        repl_error(r, "usage: :set KEY VALUE (e.g. :set :collapse 1)");
        return 0;
    }
    char *key = strndup(arg, klen);
    if (!key) abort();
    set_state(r, key, value);
    free(key);
    return 0;
}

/* `:unset KEY`: delete the state entry. */
static int cmd_unset(Repl *r, const char *arg)
{
    set_state(r, arg, "null");
    return 0;
}

static int cmd_reload(Repl *r, const char *arg)
{
    (void)arg;
    if (!r->script) {
        repl_error(r, "no script loaded (use :load FILE)");
        return 0;
    }
    if (load_script(r, r->script) == 0) printf("reloaded %s\n", r->script);
    return 0;
}

static int cmd_load(Repl *r, const char *arg)
{
    if (load_script(r, arg) == 0) printf("loaded %s\n", arg);
    return 0;
}

static int cmd_define(Repl *r, const char *arg)
{
    const char *eq = strchr(arg, '=');
    if (!eq) {
        repl_error(r, "expected NAME=VALUE, got '%s'", arg);
        return 0;
    }
    size_t nlen = (size_t)(eq - arg);
    while (nlen && (arg[nlen - 1] == ' ' || arg[nlen - 1] == '\t')) nlen--;
    char *name = strndup(arg, nlen);
    if (!name) abort();
    if (fl_define(r->rt, name, skip_space(eq + 1)) != 0) {
        repl_error(r, "bad name '%s' in define", name);
    } else {
        printf("defined %s\n", name);
        if (r->script) load_script(r, r->script);
    }
    free(name);
    return 0;
}

static int cmd_reset(Repl *r, const char *arg)
{
    (void)arg;
    fl_reset_state(r->rt);
    puts("state cleared");
    return 0;
}

static int cmd_save(Repl *r, const char *arg)
{
    if (fl_save_state(r->rt, arg) == 0) printf("saved %s\n", arg);
    else put_error(r);   /* `FILE: error: ...` */
    return 0;
}

static int cmd_restore(Repl *r, const char *arg)
{
    if (fl_restore_state(r->rt, arg) == 0)
        printf("restored %s (frame %ld)\n", arg, fl_frame_count(r->rt) - 1);
    else
        put_error(r);   /* `FILE: error: ...` */
    return 0;
}

/* Draw the physics systems as they are now (as `flitter run --view`). */
static int cmd_view(Repl *r, const char *arg)
{
    size_t n = 0;
    if (fl_view(r->rt, arg, &n) != 0) {
        char *msg = strdup(fl_error(r->rt));
        if (!msg) abort();
        size_t len = strlen(msg);
        if (len && msg[len - 1] == '\n') msg[len - 1] = '\0';
        repl_error(r, "%s", msg);
        free(msg);
        return 0;
    }
    printf("drew %zu system%s to %s\n", n, n == 1 ? "" : "s", arg);
    return 0;
}

static int cmd_quit(Repl *r, const char *arg)
{
    (void)r;
    (void)arg;
    return 1;
}

static const Command commands[] = {
    {"step", ARG_OPTIONAL, "[N]", "evaluate N frames (default 1); print the last frame and time", cmd_step},
    {"state", ARG_OPTIONAL, "[PREFIX]", "list state entries (KEY = VALUE) whose key text starts with PREFIX", cmd_state},
    {"tree", ARG_NONE, "", "print the node tree of the last frame", cmd_tree},
    {"get", ARG_REQUIRED, "KEY", "print the state value $(KEY); KEY is Flitter text, e.g. :dish;0", cmd_get},
    {"set", ARG_REQUIRED, "KEY VALUE", "store VALUE under KEY in the state (expressions: :set :collapse 1)", cmd_set},
    {"unset", ARG_REQUIRED, "KEY", "delete the state entry KEY", cmd_unset},
    {"reload", ARG_NONE, "", "re-read the script, keeping the state", cmd_reload},
    {"load", ARG_REQUIRED, "FILE", "load another script, keeping the state", cmd_load},
    {"define", ARG_REQUIRED, "NAME=VALUE", "bind NAME for every frame (as -D), then reload", cmd_define},
    {"reset", ARG_NONE, "", "clear the state dictionary (the clock keeps running)", cmd_reset},
    {"save", ARG_REQUIRED, "FILE", "save the state and the clock to FILE", cmd_save},
    {"restore", ARG_REQUIRED, "FILE", "restore the state and the clock from FILE", cmd_restore},
    {"view", ARG_REQUIRED, "FILE", "draw the physics systems now to FILE (.png or .svg)", cmd_view},
    {"window", ARG_OPTIONAL, "[off]", "show the last frame live in a window (off: close it)", cmd_window},
    {"help", ARG_NONE, "", "show this help", cmd_help},
    {"quit", ARG_NONE, "", "end the session (so does end of input)", cmd_quit},
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

const char *repl_command_name(size_t i) { return i < NCOMMANDS ? commands[i].name : NULL; }

static int cmd_help(Repl *r, const char *arg)
{
    (void)r;
    (void)arg;
    puts("Type a Flitter expression or `let` bindings to evaluate them in the scope of the\n"
         "script's last frame; end an indented multi-line block with an empty line (it is\n"
         "one history entry). `_` is the last expression's result. A node prints with its\n"
         "attributes and children, as :tree prints them.\n"
         "Ctrl-C stops a :step (a long one shows its progress), a line being evaluated or\n"
         "its output, or drops the line being typed; Ctrl-C twice at an empty prompt asks\n"
         "before quitting, and quitting then saves the state to a recovery file first.\n"
         "Commands:");
    for (size_t i = 0; i < NCOMMANDS; i++) {
        char head[40];
        snprintf(head, sizeof head, ":%s %s", commands[i].name, commands[i].usage);
        printf("  %-20s %s\n", head, commands[i].help);
    }
    return 0;
}

/* Run the command line [line] (starting with ':'). Returns 1 to quit. */
static int run_command(Repl *r, const char *line)
{
    const char *word = line + 1, *end = word;
    while (*end && *end != ' ' && *end != '\t') end++;
    size_t wlen = (size_t)(end - word);
    const Command *c = NULL;
    for (size_t i = 0; i < NCOMMANDS && !c; i++)
        if (strlen(commands[i].name) == wlen && strncmp(commands[i].name, word, wlen) == 0)
            c = &commands[i];
    if (!wlen) {
        repl_error(r, "missing command name after ':' (:help lists them)");
        return 0;
    }
    if (!c) {
        repl_error(r, "unknown command ':%.*s' (:help lists them; write a symbol as (:name))",
                    (int)wlen, word);
        return 0;
    }
    /* the argument, without surrounding blanks */
    const char *arg = skip_space(end);
    size_t alen = strlen(arg);
    while (alen && (arg[alen - 1] == ' ' || arg[alen - 1] == '\t')) alen--;
    if (c->arg == ARG_NONE && alen) {
        repl_error(r, ":%s takes no argument", c->name);
        return 0;
    }
    if (c->arg == ARG_REQUIRED && !alen) {
        repl_error(r, "usage: :%s %s", c->name, c->usage);
        return 0;
    }
    char *a = strndup(arg, alen);
    if (!a) abort();
    int rc = c->fn(r, a);
    free(a);
    return rc;
}

/* ====================================================================
 * Reading lines
 * ==================================================================== */


/* The next input line without its newline (malloc'd), or NULL at the end
 * of input. */
static char *read_line(Repl *r)
{
    if (r->tty) return readline(r->in_block ? PROMPT_MORE : PROMPT);
    if (r->peeked || r->peeked_eof) {
        char *line = r->peeked;
        r->peeked = NULL;
        r->peeked_eof = false;
        return line;
    }
    char *line = NULL;
    size_t cap = 0;
    ssize_t n = getline(&line, &cap, stdin);
    if (n < 0) {
        free(line);
        return NULL;
    }
    while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r')) line[--n] = '\0';
    return line;
}

static bool is_indented(const char *line)
{
    return (line[0] == ' ' || line[0] == '\t') && !is_blank(line);
}

/* Scripted mode: move the indented lines that follow into the block, so
 * that `let x=1` followed by indented bindings is one input. (A terminal
 * session cannot wait for the next line: there a complete first line is
 * evaluated at once.) */
static void take_indented(Repl *r)
{
    if (r->tty) return;
    for (;;) {
        if (!r->peeked && !r->peeked_eof) {
            r->peeked = read_line(r);
            r->peeked_eof = !r->peeked;
        }
        if (!r->peeked || !is_indented(r->peeked)) return;
        text_puts(&r->block, r->peeked);
        text_putc(&r->block, '\n');
        free(r->peeked);
        r->peeked = NULL;
    }
}


/* ====================================================================
 * The session
 * ==================================================================== */

/* Terminal sessions: add [line] to the input being read, which becomes
 * one history entry when it is complete (end_entry). */
static void note_line(Repl *r, const char *line)
{
    if (!r->tty) return;
    if (r->entry.len) text_putc(&r->entry, '\n');
    text_puts(&r->entry, line);
}

/* The input read so far (a line, or a whole multi-line block) is
 * complete: one history entry. */
static void end_entry(Repl *r)
{
    if (!r->tty) return;
    if (r->entry.len) repl_remember(r, text_cstr(&r->entry));
    text_reset(&r->entry);
}

/* The pending block is over when it evaluates (it was complete): then it
 * is done with. */
static void end_block_if_complete(Repl *r)
{
    if (eval_text(r, r->block.data, r->block.len) != 1) {
        text_reset(&r->block);
        r->in_block = false;
        end_entry(r);
    }
}

/* Handle one input line. Returns 1 to end the session. */
static int handle_line(Repl *r, const char *line)
{
    if (r->in_block) {
        if (is_blank(line)) {
            finish_block(r);
            end_entry(r);
            return 0;
        }
        bool indented = line[0] == ' ' || line[0] == '\t';
        /* a non-indented line starts a new input, unless the block still
         * needs more text */
        if (!indented && eval_text(r, r->block.data, r->block.len) != 1) {
            text_reset(&r->block);
            r->in_block = false;
            end_entry(r);
            return handle_line(r, line);
        }
        note_line(r, line);
        text_puts(&r->block, line);
        text_putc(&r->block, '\n');
        take_indented(r);
        /* ... and a non-indented line that completes it ends it */
        if (!indented) end_block_if_complete(r);
        return 0;
    }
    line = skip_space(line);
    if (!*line) return 0;
    note_line(r, line);
    if (line[0] == ':') {
        end_entry(r);
        return run_command(r, line);
    }
    text_puts(&r->block, line);
    text_putc(&r->block, '\n');
    take_indented(r);
    if (eval_text(r, r->block.data, r->block.len) == 1) {
        r->in_block = true;
    } else {
        text_reset(&r->block);
        end_entry(r);
    }
    return 0;
}

/* Handle what one read gave: a line, or on a terminal a multi-line
 * history entry recalled whole, whose lines are taken one by one and whose
 * block ends with it when it is complete. Returns 1 to end the session. */
static int handle_input(Repl *r, char *input)
{
    char *nl = strchr(input, '\n');
    if (!nl) return handle_line(r, input);
    for (char *line = input; line;) {
        nl = strchr(line, '\n');
        if (nl) *nl = '\0';
        if (handle_line(r, line)) return 1;
        line = nl ? nl + 1 : NULL;
    }
    if (r->in_block) end_block_if_complete(r);
    return 0;
}

/* Save the state and the clock to the recovery file, saying where.
 * Returns false (reported) when it cannot be written. */
static bool save_recovery(Repl *r)
{
    if (fl_state_count(r->rt) == 0 && fl_frame_count(r->rt) == 0) return true;   /* nothing */
    if (!r->recovery) {
        repl_error(r, "no recovery file (set FLITTER_RECOVERY or HOME)");
        return false;
    }
    if (fl_save_state(r->rt, r->recovery) != 0) {
        put_error(r);
        return false;
    }
    printf("state saved to %s (frame %ld; `flitter repl SCRIPT` then `:restore %s` resumes)\n",
           r->recovery, fl_frame_count(r->rt) - 1, r->recovery);
    return true;
}

/* A second Ctrl-C at an empty prompt: ask before ending the session.
 * Yes (or Ctrl-D) quits, the state and clock saved first to the recovery
 * file; anything else, or Ctrl-C, goes on. Returns true to quit. */
static bool confirm_quit(Repl *r)
{
    char *answer = repl_ask("\nQuit? The state is saved to the recovery file first. [y/N] ");
    bool cancelled = repl_take_interrupt();
    const char *a = answer ? skip_space(answer) : NULL;
    bool yes = !cancelled && (!answer || *a == 'y' || *a == 'Y');
    if (cancelled || !answer) putchar('\n');
    free(answer);
    if (!yes) {
        puts("(going on)");
        return false;
    }
    if (!save_recovery(r)) {
        fflush(stdout);
        fputs("not quitting: the state would be lost (:save FILE, then :quit)\n", stderr);
        return false;
    }
    return true;
}

static void repl_usage(FILE *f)
{
    fputs("usage: flitter repl [options] [SCRIPT]\n"
          "  --fps F             frame rate of :step (default 60; %pragma fps overrides it)\n"
          "  -D, --define NAME=VALUE  bind NAME before evaluation\n"
          "  --threads N         threads for physics and loop kernels (default:\n"
          "                      FLITTER_THREADS, else all cores)\n"
          "  --max-memory SIZE   memory budget (K, M, G; default half of physical memory)\n"
          "  --pairs naive|fast  physics pair loop (default fast; same results)\n"
          "  --particles literal|fast  physics particle pass (default fast; same results)\n"
          "  --physics documented|upstream  PHYSICS.md (default) or Flitter 1.0.0b28's\n"
          "                      published behaviour (%pragma physics overrides it)\n"
          "  --nosimplify        run scripts as parsed, without the load-time simplifier\n"
          "Type :help in the session for its commands.\n",
          f);
}

/* Parse the options into [opts] and the runtime's defines; returns 0, -1
 * after --help, or EXIT_USAGE. Sets [*script] to SCRIPT or NULL. */
static int parse_args(int argc, char **argv, fl_options *opts, fl_runtime **rt,
                      const char **script)
{
    static const struct option longopts[] = {
        {"fps", required_argument, NULL, 'f'},
        {"define", required_argument, NULL, 'D'},
        {"threads", required_argument, NULL, 't'},
        {"max-memory", required_argument, NULL, 'm'},
        {"pairs", required_argument, NULL, 'p'},
        {"particles", required_argument, NULL, 'P'},
        {"physics", required_argument, NULL, 'y'},
        {"nosimplify", no_argument, NULL, 'n'},
        {"no-simplify", no_argument, NULL, 'n'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    char **defines = calloc((size_t)argc + 1, sizeof(char *));
    if (!defines) abort();
    int ndefines = 0, c, rc = 0;
    optind = 0;
    opterr = 0;
    while (rc == 0 && (c = getopt_long(argc, argv, "+D:h", longopts, NULL)) != -1) {
        char *end;
        switch (c) {
        case 'f':
            opts->fps = strtod(optarg, &end);
            if (end == optarg || *end || !(opts->fps > 0) || isinf(opts->fps)) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '--fps'\n", optarg);
                rc = EXIT_USAGE;
            }
            break;
        case 't': {
            long n = strtol(optarg, &end, 10);
            if (end == optarg || *end || n < 1 || n > 1024) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '--threads'\n", optarg);
                rc = EXIT_USAGE;
            }
            opts->threads = (int)n;
            break;
        }
        case 'm':
            if (!fl_parse_memory(optarg, &opts->max_memory)) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '--max-memory'\n", optarg);
                rc = EXIT_USAGE;
            }
            break;
        case 'p':
            if (!fl_parse_pairs(optarg, &opts->pairs)) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '--pairs'\n", optarg);
                rc = EXIT_USAGE;
            }
            break;
        case 'P':
            if (!fl_parse_particles(optarg, &opts->particles)) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '--particles'\n", optarg);
                rc = EXIT_USAGE;
            }
            break;
        case 'y':
            if (!fl_parse_physics(optarg, &opts->physics)) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '--physics'\n", optarg);
                rc = EXIT_USAGE;
            }
            break;
        case 'D':
            if (!strchr(optarg, '=')) {
                fprintf(stderr, "flitter repl: bad value '%s' for option '-D'\n", optarg);
                rc = EXIT_USAGE;
            }
            defines[ndefines++] = optarg;
            break;
        case 'n': opts->no_simplify = true; break;
        case 'h':
            repl_usage(stdout);
            rc = -1;
            break;
        default:
            fprintf(stderr, "flitter repl: unknown option or missing value: '%s'\n",
                    argv[optind - 1]);
            repl_usage(stderr);
            rc = EXIT_USAGE;
        }
    }
    if (rc == 0 && argc - optind > 1) {
        fputs("flitter repl: at most one SCRIPT expected\n", stderr);
        repl_usage(stderr);
        rc = EXIT_USAGE;
    }
    *script = rc == 0 && optind < argc ? argv[optind] : NULL;
    if (rc == 0) {
        runspec_options_from_env(opts);
        *rt = fl_new(opts);
        for (int i = 0; i < ndefines && rc == 0; i++) {
            char *eq = strchr(defines[i], '=');
            *eq = '\0';
            if (fl_define(*rt, defines[i], eq + 1) != 0) {
                fprintf(stderr, "flitter repl: bad name in define '%s'\n", defines[i]);
                rc = EXIT_USAGE;
            }
            *eq = '=';
        }
        if (rc != 0) {
            fl_free(*rt);
            *rt = NULL;
        }
    }
    free(defines);
    return rc;
}

int cmd_repl(int argc, char **argv)
{
    fl_options opts = fl_default_options();
    const char *script;
    Repl r = {.tty = isatty(STDIN_FILENO) == 1, .block = TEXT_INIT, .entry = TEXT_INIT};
    if (r.tty)   /* Ctrl-C (caught in terminal sessions) stops a long line or frame */
        opts.interrupt = repl_interrupt_flag();
    setvbuf(stdout, NULL, _IOLBF, 0);   /* keep stdout and stderr lines in order */
    int rc = parse_args(argc, argv, &opts, &r.rt, &script);
    if (rc != 0) return rc < 0 ? EXIT_OK : rc;
    if (script && load_script(&r, script) != 0) {
        /* stay in the session: the file can be fixed and :reload-ed */
        r.script = strdup(script);
        if (!r.script) abort();
    }
    if (r.tty) {
        repl_edit_begin(&r);
        puts("flitter repl: :help lists the commands, :quit or Ctrl-D ends the session");
    }
    bool after_interrupt = false;   /* the last prompt ended with Ctrl-C */
    for (;;) {
        window_events(&r);
        char *line = read_line(&r);
        if (r.tty && repl_take_interrupt()) {
            /* Ctrl-C at the prompt drops the line (and a pending block);
             * a second one at an empty prompt ends the session */
            bool empty = !r.in_block && (!line || is_blank(line));
            free(line);
            text_reset(&r.block);
            r.in_block = false;
            end_entry(&r);   /* the lines of a dropped block stay in the history */
            if (empty && after_interrupt) {
                after_interrupt = false;
                if (confirm_quit(&r)) break;
                continue;
            }
            after_interrupt = empty;
            fputs(empty ? "\n(Ctrl-C again to quit, or Ctrl-D)\n" : "\n", stdout);
            continue;
        }
        after_interrupt = false;
        if (!line) {
            if (r.in_block) finish_block(&r);
            end_entry(&r);
            if (r.tty) putchar('\n');
            break;
        }
        int quit = handle_input(&r, line);
        free(line);
        fflush(stdout);
        if (quit) break;
        if (ferror(stdout)) {
            /* standard output closed (a pipe's reader gone): with a
             * window open SIGPIPE is blocked, so the write fails instead
             * of ending the process, and the session ends here */
            fputs("flitter repl: cannot write to standard output (closed?): the session ends\n", stderr);
            break;
        }
    }
    repl_window_close(r.window);
    fflush(stdout);
    if (r.tty) repl_edit_end(&r);
    text_free(&r.block);
    text_free(&r.entry);
    text_free(&r.cpl_path);
    free(r.recovery);
    free(r.peeked);
    free(r.last_entry);
    free(r.history);
    free(r.script);
    fl_free(r.rt);
    /* a scripted session that met an error says so in its exit status */
    return !r.tty && r.errors ? EXIT_LOAD : EXIT_OK;
}
