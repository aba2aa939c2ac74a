/* exitcodes.h: the `flitter` command's exit statuses (FORMATS.md §4). */
#ifndef FL_EXITCODES_H
#define FL_EXITCODES_H

enum {
    EXIT_OK = 0,        /* success */
    EXIT_LOAD = 1,      /* the script could not be loaded (syntax error, missing file) */
    EXIT_USAGE = 2,     /* bad command-line usage */
    EXIT_WINDOW_LOST = 3, /* the window or its X display was lost (window_lost.h), after the
                             usual --state save and dumps */
};

#endif
