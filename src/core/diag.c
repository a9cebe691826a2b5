#include "core/diag.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Control bytes (a name quoted from a binary file) as \xNN, so that a message stays one
 * line on the terminal; returns the length written (out has room for 4 * len + 1). */
static size_t escape_controls(const char *in, size_t len, char *out)
{
    size_t n = 0;
    for (size_t i = 0; i < len; ++i) {
        unsigned char c = (unsigned char)in[i];
        if (c < 0x20 || c == 0x7f) n += (size_t)sprintf(out + n, "\\x%02x", c);
        else out[n++] = (char)c;
    }
    out[n] = '\0';
    return n;
}

/* The longest quoted run ('...' or "...") of s, as [*begin, *end) inside the quotes. */
static bool longest_quoted(const char *s, size_t len, size_t *begin, size_t *end)
{
    size_t best = 0;
    bool found = false;
    for (size_t i = 0; i < len; ++i) {
        if (s[i] != '\'' && s[i] != '"') continue;
        const char *close = memchr(s + i + 1, s[i], len - i - 1);
        if (!close) break;
        size_t j = (size_t)(close - s);
        if (j - i - 1 > best) {
            best = j - i - 1;
            *begin = i + 1;
            *end = j;
            found = true;
        }
        i = j;
    }
    return found;
}

/* Fits s (length len) into buf of size bytes: the longest quoted name loses its middle
 * ("abc...xyz") rather than the message its end, which says what is wrong. */
static size_t fit(const char *s, size_t len, char *buf, size_t size)
{
    size_t b, e;
    if (len >= size && longest_quoted(s, len, &b, &e)) {
        size_t excess = len - (size - 1) + 3; /* room for "..." */
        if (excess < e - b) {
            size_t keep = (e - b) - excess, head = keep / 2, tail = keep - head;
            int n = snprintf(buf, size, "%.*s%.*s...%.*s%.*s", (int)(b + head), s, 0, "", (int)tail, s + e - tail,
                             (int)(len - e), s + e);
            return n < 0 ? 0 : (size_t)n < size ? (size_t)n : size - 1;
        }
    }
    size_t n = len < size ? len : size - 1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    return n;
}

int diag_format(char *buf, size_t size, SrcLoc loc, const char *kind, const char *fmt, va_list ap)
{
    if (size == 0) return 0;
    char head[4096];
    int h = 0;
    if (loc.path && loc.line > 0)
        h = snprintf(head, sizeof head, "%s:%d:%d: %s: ", loc.path, loc.line, loc.col, kind);
    else if (loc.path)
        h = snprintf(head, sizeof head, "%s: %s: ", loc.path, kind);
    else
        h = snprintf(head, sizeof head, "%s: ", kind);
    if (h < 0) h = 0;
    if ((size_t)h >= sizeof head) h = (int)sizeof head - 1;
    va_list copy;
    va_copy(copy, ap);
    int body = vsnprintf(NULL, 0, fmt, copy);
    va_end(copy);
    if (body < 0) body = 0;
    size_t raw_len = (size_t)h + (size_t)body;
    char *raw = malloc(raw_len + 1), *clean = raw ? malloc(4 * raw_len + 1) : NULL;
    if (!raw || !clean) { /* no memory for the long way: the plain, possibly cut, message */
        free(raw);
        int n = snprintf(buf, size, "%s", head);
        if (n >= 0 && (size_t)n < size) vsnprintf(buf + n, size - (size_t)n, fmt, ap);
        return (int)strlen(buf);
    }
    memcpy(raw, head, (size_t)h);
    vsnprintf(raw + h, (size_t)body + 1, fmt, ap);
    size_t clean_len = escape_controls(raw, raw_len, clean);
    size_t n = fit(clean, clean_len, buf, size);
    free(raw);
    free(clean);
    return (int)n;
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
