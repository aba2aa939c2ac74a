/* repl.h: what the two halves of `flitter repl` share: the session
 * (cmd_repl.c: reading lines, evaluating, the `:` commands) and terminal
 * line editing (repl_edit.c: libedit set-up, history, Tab completion and
 * Ctrl-C at the prompt). */
#ifndef FL_REPL_H
#define FL_REPL_H

#include <stdbool.h>
#include <stddef.h>

#include "flitter.h"
#include "text.h"

struct ReplWindow;

typedef enum { CPL_COMMANDS, CPL_NAMES, CPL_FILES } CompletionKind;

typedef struct Repl {
    fl_runtime *rt;            /* the interpreter (owned) */
    char *script;              /* path of the current script (owned), or NULL */
    bool tty;                  /* stdin is a terminal: libedit, prompts, history */
    char *history;             /* history file path (owned), or NULL for none */
    bool history_failed;       /* a history write failed (reported once) */
    char *last_entry;          /* last entry added to the history (owned), to skip repeats */
    Text entry;                 /* the lines of the input being read, for one history entry */
    char *recovery;            /* where a quit after Ctrl-C saves the state (owned), or NULL */
    Text block;                 /* Flitter text of a multi-line input so far */
    bool in_block;             /* [block] is being continued */
    char *peeked;              /* scripted mode: the next line, read ahead (owned), or NULL */
    bool peeked_eof;           /* scripted mode: reading ahead met the end of input */
    long errors;               /* errors reported so far (the exit status of a scripted session) */
    struct ReplWindow *window; /* `:window`'s live window (repl_window.c), or NULL */
    /* completion cursor, for libedit's generator callback */
    CompletionKind cpl_kind;   /* what is being completed */
    size_t cpl_next;           /* next candidate index to try */
    char **cpl_names;          /* names in scope (owned, from fl_scope_names) */
    size_t cpl_count;          /* entries in cpl_names */
    Text cpl_path;              /* CPL_FILES: the whole path typed so far */
    size_t cpl_skip;           /* CPL_FILES: bytes of it before libedit's word */
} Repl;

/* True when [s] holds only blanks (spaces, tabs). */
static inline bool is_blank(const char *s)
{
    while (*s == ' ' || *s == '\t') s++;
    return *s == '\0';
}

/* [s] after its leading blanks. */
static inline const char *skip_space(const char *s)
{
    while (*s == ' ' || *s == '\t') s++;
    return s;
}

/* Report `error: MESSAGE` on stderr (after flushing stdout) and count it
 * in r->errors. Defined in cmd_repl.c. */
void repl_error(Repl *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The name of the [i]-th `:` command (without ':'), or NULL past the
 * last. Defined in cmd_repl.c. */
const char *repl_command_name(size_t i);

/* Terminal sessions (repl_edit.c). Catch SIGINT (a flag, see
 * repl_take_interrupt) and set libedit up for [r]: its character reader,
 * a UTF-8 character type, Tab completion, the history file
 * ($FLITTER_HISTORY, else ~/.flitter_history; a multi-line entry is kept
 * as one, its newlines encoded by libedit), and the recovery file
 * ($FLITTER_RECOVERY, else ~/.flitter_recovery.state). */
void repl_edit_begin(Repl *r);
/* The recovery file's path: $FLITTER_RECOVERY, else
 * ~/.flitter_recovery.state; NULL when neither is set (or out of
 * memory). Owned by the caller. */
char *repl_recovery_path(void);
/* Forget the in-memory history and [r] (the file stays). */
void repl_edit_end(Repl *r);
/* Add [entry] (one line, or the lines of a multi-line block joined by
 * newlines) to the history, skipping blanks and a repeat of the last
 * entry, and rewrite the history file (a failure is reported once). */
void repl_remember(Repl *r, const char *entry);
/* Read one line at [prompt] with libedit, outside the history (a
 * question's answer). Returns it (malloc'd), or NULL at the end of input
 * or after a Ctrl-C (whose flag is then left set). */
char *repl_ask(const char *prompt);
/* Whether Ctrl-C was pressed since the last call (clears the flag). */
bool repl_take_interrupt(void);
/* The flag itself, for fl_options.interrupt: the runtime polls it inside
 * evaluation and physics steps, so Ctrl-C stops a long line or frame. */
volatile int *repl_interrupt_flag(void);

#endif
