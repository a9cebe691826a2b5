/* Finding a kernel's declaration in an OpenCL source (see kernel_decl.h). */
#include "recon/cl/kernel_decl.h"

#include <ctype.h>
#include <string.h>

static bool ident_char(char c) { return isalnum((unsigned char)c) || c == '_'; }

/* The start of the word that ends just before end (white space skipped), or NULL when the
 * text there is not the word. */
static const char *word_before(const char *start, const char *end, const char *word)
{
    while (end > start && isspace((unsigned char)end[-1])) --end;
    size_t n = strlen(word);
    if ((size_t)(end - start) < n || memcmp(end - n, word, n) != 0) return NULL;
    const char *w = end - n;
    return w > start && ident_char(w[-1]) ? NULL : w;
}

bool kernel_declared(const char *source, const char *name)
{
    size_t n = strlen(name);
    if (n == 0) return false;
    for (const char *at = strstr(source, name); at; at = strstr(at + 1, name)) {
        const char *after = at + n;
        if (ident_char(*after) || (at > source && ident_char(at[-1]))) continue; /* part of a longer name */
        while (isspace((unsigned char)*after)) ++after;
        if (*after != '(') continue;
        const char *v = word_before(source, at, "void");
        if (v && (word_before(source, v, "__kernel") || word_before(source, v, "kernel"))) return true;
    }
    return false;
}
