/* Hand-written pbrt-v4 tokenizer and number parser. Numbers take a strtod-free fast path
 * when the decimal mantissa has at most 15 significant digits and the power of ten is at
 * most 22: both are then exact doubles and one multiplication or division rounds correctly
 * (Clinger 1990, "How to read floating point numbers accurately", the fast path). Anything
 * else goes to strtod. */
#include "scene/lexer.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void lexer_init(Lexer *lx, const char *text, size_t len, const char *path)
{
    memset(lx, 0, sizeof *lx);
    lx->src = lx->cur = text;
    lx->end = text + len;
    lx->path = path;
    lx->line = 1;
    lx->line_start = text;
}

static inline bool is_space(unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
static inline bool is_delim(unsigned char c) { return is_space(c) || c == '"' || c == '[' || c == ']' || c == '#'; }

static int column(const Lexer *lx, const char *p) { return (int)(p - lx->line_start) + 1; }

bool lexer_next(Lexer *lx, Token *tok, Diag *err)
{
    if (lx->has_peek) {
        *tok = lx->peek;
        lx->has_peek = false;
        return true;
    }
    const char *p = lx->cur, *end = lx->end;
    for (;;) {
        while (p < end && is_space((unsigned char)*p)) {
            if (*p == '\n') {
                lx->line++;
                lx->line_start = p + 1;
            }
            ++p;
        }
        if (p < end && *p == '#') {
            const char *nl = memchr(p, '\n', (size_t)(end - p));
            p = nl ? nl : end;
            continue;
        }
        break;
    }
    tok->line = lx->line;
    tok->col = column(lx, p);
    tok->text = p;
    if (p >= end) {
        tok->kind = TOK_EOF;
        tok->len = 0;
        lx->cur = p;
        return true;
    }
    unsigned char c = (unsigned char)*p;
    if (c == '[' || c == ']') {
        tok->kind = c == '[' ? TOK_LBRACKET : TOK_RBRACKET;
        tok->len = 1;
        lx->cur = p + 1;
        return true;
    }
    if (c == '"') {
        const char *q = p + 1;
        while (q < end && *q != '"' && *q != '\n') {
            if (*q == '\\' && q + 1 < end && q[1] != '\n') { /* an escaped character */
                /* the escapes pbrt-v4 knows; another one is a typo, not a character to drop */
                if (q[1] == '\0' || !strchr("bfnrt\\'\"", q[1])) {
                    SrcLoc loc = {lx->path, tok->line, tok->col + (int)(q - p)};
                    unsigned char e = (unsigned char)q[1];
                    if (e >= 0x20 && e < 0x7f)
                        diag_set(err, WEDGE_EXIT_INPUT, loc, "unknown escape '\\%c' in a string (known: \\b \\f \\n \\r \\t \\\\ \\' \\\")", e);
                    else
                        diag_set(err, WEDGE_EXIT_INPUT, loc, "unknown escape '\\' followed by byte 0x%02x in a string", e);
                    return false;
                }
                ++q;
            }
            ++q;
        }
        if (q >= end || *q != '"') {
            SrcLoc loc = {lx->path, tok->line, tok->col};
            diag_set(err, WEDGE_EXIT_INPUT, loc, "unterminated string");
            return false;
        }
        tok->kind = TOK_STRING;
        tok->text = p + 1;
        tok->len = (size_t)(q - p - 1);
        lx->cur = q + 1;
        return true;
    }
    /* Bare words: printable ASCII only, so binary garbage stops here with a clear message. */
    if (c < 0x21 || c > 0x7e) {
        SrcLoc loc = {lx->path, tok->line, tok->col};
        diag_set(err, WEDGE_EXIT_INPUT, loc, "unexpected byte 0x%02x", c);
        return false;
    }
    const char *q = p;
    while (q < end && !is_delim((unsigned char)*q)) {
        unsigned char d = (unsigned char)*q;
        if (d < 0x21 || d > 0x7e) {
            int col = column(lx, q);
            SrcLoc loc = {lx->path, lx->line, col};
            diag_set(err, WEDGE_EXIT_INPUT, loc, "unexpected byte 0x%02x", d);
            return false;
        }
        ++q;
    }
    tok->kind = TOK_WORD;
    tok->len = (size_t)(q - p);
    lx->cur = q;
    return true;
}

bool lexer_peek(Lexer *lx, Token *tok, Diag *err)
{
    if (!lx->has_peek) {
        if (!lexer_next(lx, &lx->peek, err)) return false;
        lx->has_peek = true;
    }
    *tok = lx->peek;
    return true;
}

bool lex_looks_numeric(const char *s, size_t len)
{
    if (len == 0) return false;
    unsigned char c = (unsigned char)s[0];
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

bool lex_is_integer_literal(const char *s, size_t len)
{
    for (size_t i = 0; i < len; ++i)
        if (s[i] == '.' || s[i] == 'e' || s[i] == 'E') return false;
    return true;
}

static bool is_nan_inf_word(const char *s, size_t len)
{
    if (len && (s[0] == '-' || s[0] == '+')) {
        ++s;
        --len;
    }
    char low[9];
    if (len < 3 || len > 8) return false;
    if ((s[0] | 0x20) != 'n' && (s[0] | 0x20) != 'i') return false; /* the common case: a digit */
    for (size_t i = 0; i < len; ++i) low[i] = (char)(s[i] | 0x20);
    low[len] = '\0';
    return !strcmp(low, "nan") || !strcmp(low, "inf") || !strcmp(low, "infinity");
}

/* Exact powers of ten representable in a double. */
static const double pow10_exact[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                       1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                       1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* Validates the grammar and tries the fast path. Returns NUM_OK with *out set, NUM_SYNTAX,
 * or NUM_RANGE meaning "valid syntax, use strtod". */
static NumStatus parse_decimal(const char *s, size_t len, double *out)
{
    const char *p = s, *end = s + len;
    bool neg = false;
    if (p < end && (*p == '-' || *p == '+')) neg = (*p++ == '-');
    uint64_t mant = 0;
    int sig_digits = 0, exp10 = 0, digits = 0;
    bool mant_exact = true;
    while (p < end && *p >= '0' && *p <= '9') {
        if (mant != 0 || *p != '0') {
            if (sig_digits < 19) mant = mant * 10 + (uint64_t)(*p - '0');
            else {
                ++exp10;
                if (*p != '0') mant_exact = false;
            }
            ++sig_digits;
        }
        ++digits;
        ++p;
    }
    if (p < end && *p == '.') {
        ++p;
        while (p < end && *p >= '0' && *p <= '9') {
            if (mant != 0 || *p != '0') {
                if (sig_digits < 19) {
                    mant = mant * 10 + (uint64_t)(*p - '0');
                    --exp10;
                } else if (*p != '0') mant_exact = false;
                ++sig_digits;
            } else {
                --exp10;
            }
            ++digits;
            ++p;
        }
    }
    if (digits == 0) return NUM_SYNTAX;
    if (p < end && (*p == 'e' || *p == 'E')) {
        ++p;
        bool eneg = false;
        if (p < end && (*p == '-' || *p == '+')) eneg = (*p++ == '-');
        if (p >= end) return NUM_SYNTAX;
        int e = 0;
        while (p < end && *p >= '0' && *p <= '9') {
            if (e < 100000) e = e * 10 + (*p - '0');
            ++p;
        }
        exp10 += eneg ? -e : e;
    }
    if (p != end) return NUM_SYNTAX;
    if (mant == 0) {
        *out = neg ? -0.0 : 0.0;
        return NUM_OK;
    }
    if (mant_exact && sig_digits <= 15 && exp10 >= -22 && exp10 <= 22) {
        double v = (double)mant;
        v = exp10 >= 0 ? v * pow10_exact[exp10] : v / pow10_exact[-exp10];
        *out = neg ? -v : v;
        return NUM_OK;
    }
    return NUM_RANGE;
}

static double slow_strtod(const char *s, size_t len)
{
    char buf[64];
    char *tmp = len < sizeof buf ? buf : malloc(len + 1);
    if (!tmp) return NAN;
    memcpy(tmp, s, len);
    tmp[len] = '\0';
    errno = 0;
    double v = strtod(tmp, NULL);
    if (tmp != buf) free(tmp);
    return v;
}

NumStatus lex_parse_float(const char *s, size_t len, float *out)
{
    if (is_nan_inf_word(s, len)) return NUM_NAN_INF;
    double v;
    NumStatus st = parse_decimal(s, len, &v);
    if (st == NUM_SYNTAX) return st;
    if (st == NUM_RANGE) v = slow_strtod(s, len);
    if (isnan(v)) return NUM_SYNTAX;
    /* Values that round to infinity in float overflow; tiny values flush toward zero as in
     * any float parser. */
    if (!(fabs(v) <= (double)FLT_MAX)) return NUM_RANGE;
    *out = (float)v;
    return NUM_OK;
}

NumStatus lex_parse_int(const char *s, size_t len, int *out)
{
    if (is_nan_inf_word(s, len)) return NUM_NAN_INF;
    const char *p = s, *end = s + len;
    bool neg = false;
    if (p < end && (*p == '-' || *p == '+')) neg = (*p++ == '-');
    if (p >= end) return NUM_SYNTAX;
    int64_t v = 0;
    for (; p < end; ++p) {
        if (*p < '0' || *p > '9') return NUM_SYNTAX;
        v = v * 10 + (*p - '0');
        if (v > (int64_t)INT_MAX + 1) return NUM_RANGE;
    }
    if (neg) v = -v;
    if (v > INT_MAX || v < INT_MIN) return NUM_RANGE;
    *out = (int)v;
    return NUM_OK;
}

size_t lex_unescape(const char *s, size_t len, char *out)
{
    size_t n = 0;
    for (size_t i = 0; i < len; ++i) {
        char c = s[i];
        if (c == '\\' && i + 1 < len) {
            char e = s[++i];
            switch (e) {
            case 'b': c = '\b'; break;
            case 'f': c = '\f'; break;
            case 'n': c = '\n'; break;
            case 'r': c = '\r'; break;
            case 't': c = '\t'; break;
            default: c = e; break; /* \\ \" \' and anything else: the character itself */
            }
        }
        out[n++] = c;
    }
    out[n] = '\0';
    return n;
}
