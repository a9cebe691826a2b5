#include "core/diag.h"

#include <stdio.h>
#include <string.h>

int diag_format(char *buf, size_t size, SrcLoc loc, const char *kind, const char *fmt, va_list ap)
{
    int n = 0;
    if (loc.path && loc.line > 0)
        n = snprintf(buf, size, "%s:%d:%d: %s: ", loc.path, loc.line, loc.col, kind);
    else if (loc.path)
        n = snprintf(buf, size, "%s: %s: ", loc.path, kind);
    else
        n = snprintf(buf, size, "%s: ", kind);
    if (n < 0) n = 0;
    if ((size_t)n < size) n += vsnprintf(buf + n, size - (size_t)n, fmt, ap);
    return n;
}

void diag_set(Diag *d, int exit_code, SrcLoc loc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    d->exit_code = exit_code;
    diag_format(d->message, sizeof d->message, loc, "error", fmt, ap);
    va_end(ap);
}

void diag_append(Diag *d, const char *fmt, ...)
{
    size_t used = strnlen(d->message, sizeof d->message);
    if (used + 1 >= sizeof d->message) return;
    d->message[used++] = '\n';
    d->message[used] = '\0';
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message + used, sizeof d->message - used, fmt, ap);
    va_end(ap);
}

void diag_print(const Diag *d)
{
    size_t n = strnlen(d->message, sizeof d->message);
    fwrite(d->message, 1, n, stderr);
    if (n && d->message[n - 1] != '\n') fputc('\n', stderr);
}
