/* Tokenizer for the pbrt-v4 scene format: quoted strings, [ ], and bare words (directives,
 * numbers, true/false); '#' starts a comment to the end of the line. Tracks line and
 * column (1-based, columns count bytes). Never reads past the end of its buffer, whatever
 * bytes it holds. */
#ifndef WEDGE_SCENE_LEXER_H
#define WEDGE_SCENE_LEXER_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"

typedef enum {
    TOK_EOF,
    TOK_STRING,   /* "..." : text is the raw contents between the quotes (escapes not applied) */
    TOK_LBRACKET,
    TOK_RBRACKET,
    TOK_WORD,     /* anything else up to whitespace, a quote, a bracket or '#' */
} TokenKind;

typedef struct {
    TokenKind kind;
    const char *text; /* not NUL-terminated */
    size_t len;
    int line, col;
} Token;

typedef struct {
    const char *src, *end, *cur;
    const char *path; /* for locations */
    int line;
    const char *line_start;
    bool has_peek;
    Token peek;
} Lexer;

void lexer_init(Lexer *lx, const char *text, size_t len, const char *path);
/* Reads the next token. Returns false with err filled on a lexical error: an unterminated
 * string (reported at its opening quote) or a byte that cannot start a token. */
bool lexer_next(Lexer *lx, Token *tok, Diag *err);
/* Looks at the next token without consuming it. */
bool lexer_peek(Lexer *lx, Token *tok, Diag *err);

static inline SrcLoc token_loc(const Lexer *lx, const Token *t)
{
    SrcLoc l = {lx->path, t->line, t->col};
    return l;
}

/* Numbers. Both accept exactly the pbrt grammar [+-]digits[.digits][(e|E)[+-]digits]
 * (also ".5", "5."), and reject NaN, infinities and values that overflow the target type.
 * On failure *why is set to a short reason for the error message. */
typedef enum { NUM_OK, NUM_SYNTAX, NUM_NAN_INF, NUM_RANGE } NumStatus;
NumStatus lex_parse_float(const char *s, size_t len, float *out);
/* Integer: digits only (no '.' or exponent) and within int32. */
NumStatus lex_parse_int(const char *s, size_t len, int *out);
/* True when a word token has the shape of a number (starts with a digit, sign or '.'). */
bool lex_looks_numeric(const char *s, size_t len);
/* True when the word is an integer literal (no '.', no exponent). */
bool lex_is_integer_literal(const char *s, size_t len);

/* Decodes a quoted string's escapes (\n \t \\ \" ...) into out (capacity len + 1).
 * Returns the decoded length. */
size_t lex_unescape(const char *s, size_t len, char *out);

#endif
