/* Diagnostics: source locations, error/warning messages, exit codes.
 * Library code never exits: it fills a Diag and returns an error; only src/app exits. */
#ifndef WEDGE_CORE_DIAG_H
#define WEDGE_CORE_DIAG_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>

enum {
    WEDGE_EXIT_OK = 0,
    WEDGE_EXIT_USAGE = 1,    /* bad command line */
    WEDGE_EXIT_INPUT = 2,    /* bad scene or data file */
    WEDGE_EXIT_RUNTIME = 3,  /* failure at run time (OpenCL, I/O, memory) */
};

/* A position in a scene file. line and col are 1-based; 0 means unknown. */
typedef struct {
    const char *path;
    int line;
    int col;
} SrcLoc;

/* An error message with everything needed to print it: the formatted text holds one or
 * more complete lines ("PATH:LINE:COL: error: WHAT\n" plus "included from" lines). */
typedef struct {
    int exit_code;       /* WEDGE_EXIT_* to use if the caller gives up */
    char message[2048];
} Diag;

/* Formats "PATH:LINE:COL: error: WHAT" (location parts omitted when unknown) into d. */
void diag_set(Diag *d, int exit_code, SrcLoc loc, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Appends a line of text (e.g. "PATH:LINE:COL: note: included from here"). */
void diag_append(Diag *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prints the message to stderr as complete lines (a final newline added if missing). */
void diag_print(const Diag *d);
/* Formats a location-prefixed message into buf: "PATH:LINE:COL: KIND: WHAT". */
int diag_format(char *buf, size_t size, SrcLoc loc, const char *kind, const char *fmt, va_list ap);

#endif
