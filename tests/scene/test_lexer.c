/* Lexer: tokens with their line/column, and the number parser against strtof. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "scene/lexer.h"

static void next(Lexer *lx, Token *t)
{
    Diag d;
    bool ok = lexer_next(lx, t, &d);
    CHECK(ok);
    if (!ok) fprintf(stderr, "%s\n", d.message);
}

static void expect_tok(Lexer *lx, TokenKind kind, const char *text, int line, int col)
{
    Token t;
    next(lx, &t);
    CHECK(t.kind == kind);
    CHECK(t.len == strlen(text) && !memcmp(t.text, text, t.len));
    CHECK(t.line == line);
    CHECK(t.col == col);
    if (t.line != line || t.col != col || t.len != strlen(text))
        fprintf(stderr, "  token '%.*s' at %d:%d, expected '%s' at %d:%d\n", (int)t.len, t.text, t.line, t.col, text,
                line, col);
}

/* Distance in units in the last place between two finite floats of the same sign. */
static int64_t ulp_distance(float a, float b)
{
    int32_t ia, ib;
    memcpy(&ia, &a, 4);
    memcpy(&ib, &b, 4);
    if (ia < 0) ia = INT32_MIN - ia;
    if (ib < 0) ib = INT32_MIN - ib;
    return llabs((int64_t)ia - (int64_t)ib);
}

int main(void)
{
    const char *text = "Shape \"sphere\" [ 1 -2.5e3 ] # comment \"not a string\"\n"
                       "\t\"a\\\"b\"\n"
                       "  WorldBegin]x\n";
    Lexer lx;
    lexer_init(&lx, text, strlen(text), "t.pbrt");
    expect_tok(&lx, TOK_WORD, "Shape", 1, 1);
    expect_tok(&lx, TOK_STRING, "sphere", 1, 7);
    expect_tok(&lx, TOK_LBRACKET, "[", 1, 16);
    expect_tok(&lx, TOK_WORD, "1", 1, 18);
    expect_tok(&lx, TOK_WORD, "-2.5e3", 1, 20);
    expect_tok(&lx, TOK_RBRACKET, "]", 1, 27);
    expect_tok(&lx, TOK_STRING, "a\\\"b", 2, 2); /* raw text; escapes decoded on use */
    expect_tok(&lx, TOK_WORD, "WorldBegin", 3, 3);
    expect_tok(&lx, TOK_RBRACKET, "]", 3, 13);
    expect_tok(&lx, TOK_WORD, "x", 3, 14);
    Token t;
    next(&lx, &t);
    CHECK(t.kind == TOK_EOF);
    next(&lx, &t);
    CHECK(t.kind == TOK_EOF); /* stays at EOF */

    /* Peek does not consume. */
    lexer_init(&lx, "a b", 3, "t.pbrt");
    Diag d;
    CHECK(lexer_peek(&lx, &t, &d) && t.kind == TOK_WORD && t.text[0] == 'a');
    CHECK(lexer_next(&lx, &t, &d) && t.text[0] == 'a');
    CHECK(lexer_next(&lx, &t, &d) && t.text[0] == 'b' && t.col == 3);

    /* Comment at the end of the text without a newline; CRLF line ends. */
    lexer_init(&lx, "a\r\nb # c", 8, "t.pbrt");
    expect_tok(&lx, TOK_WORD, "a", 1, 1);
    expect_tok(&lx, TOK_WORD, "b", 2, 1);
    next(&lx, &t);
    CHECK(t.kind == TOK_EOF);

    /* Errors. */
    lexer_init(&lx, "  \"abc", 6, "t.pbrt");
    CHECK(!lexer_next(&lx, &t, &d));
    CHECK_STR(d.message, "t.pbrt:1:3: error: unterminated string");
    lexer_init(&lx, "\"ab\ncd\"", 7, "t.pbrt");
    CHECK(!lexer_next(&lx, &t, &d));
    CHECK_STR(d.message, "t.pbrt:1:1: error: unterminated string");
    lexer_init(&lx, "ab\x80", 3, "t.pbrt");
    CHECK(!lexer_next(&lx, &t, &d));
    CHECK_STR(d.message, "t.pbrt:1:3: error: unexpected byte 0x80");
    lexer_init(&lx, "\"a\\", 3, "t.pbrt"); /* backslash as the last byte */
    CHECK(!lexer_next(&lx, &t, &d));

    /* Unescape. */
    char out[16];
    CHECK(lex_unescape("a\\\"b\\n\\\\", 8, out) == 5);
    CHECK_STR(out, "a\"b\n\\");

    /* Numbers: exact small cases. */
    float f;
    int i;
    CHECK(lex_parse_float("1", 1, &f) == NUM_OK && f == 1.0f);
    CHECK(lex_parse_float("-0.5", 4, &f) == NUM_OK && f == -0.5f);
    CHECK(lex_parse_float(".25", 3, &f) == NUM_OK && f == 0.25f);
    CHECK(lex_parse_float("5.", 2, &f) == NUM_OK && f == 5.0f);
    CHECK(lex_parse_float("+1e2", 4, &f) == NUM_OK && f == 100.0f);
    CHECK(lex_parse_float("1E-2", 4, &f) == NUM_OK && f == 0.01f);
    CHECK(lex_parse_float("0.1", 3, &f) == NUM_OK && f == 0.1f);
    CHECK(lex_parse_float("-0", 2, &f) == NUM_OK && f == 0.0f && signbit(f));
    CHECK(lex_parse_float("3.4028234e38", 12, &f) == NUM_OK && f == FLT_MAX);
    CHECK(lex_parse_float("1e-50", 5, &f) == NUM_OK && f == 0.0f); /* underflow flushes to zero */
    CHECK(lex_parse_float("1e39", 4, &f) == NUM_RANGE);
    CHECK(lex_parse_float("-1e400", 6, &f) == NUM_RANGE);
    CHECK(lex_parse_float("3.5e38", 6, &f) == NUM_RANGE);
    CHECK(lex_parse_float("nan", 3, &f) == NUM_NAN_INF);
    CHECK(lex_parse_float("-INF", 4, &f) == NUM_NAN_INF);
    CHECK(lex_parse_float("Infinity", 8, &f) == NUM_NAN_INF);
    CHECK(lex_parse_float("0x10", 4, &f) == NUM_SYNTAX);
    CHECK(lex_parse_float("1e", 2, &f) == NUM_SYNTAX);
    CHECK(lex_parse_float(".", 1, &f) == NUM_SYNTAX);
    CHECK(lex_parse_float("-", 1, &f) == NUM_SYNTAX);
    CHECK(lex_parse_float("1.2.3", 5, &f) == NUM_SYNTAX);
    CHECK(lex_parse_float("1,5", 3, &f) == NUM_SYNTAX);
    CHECK(lex_parse_int("42", 2, &i) == NUM_OK && i == 42);
    CHECK(lex_parse_int("-2147483648", 11, &i) == NUM_OK && i == INT32_MIN);
    CHECK(lex_parse_int("2147483647", 10, &i) == NUM_OK && i == INT32_MAX);
    CHECK(lex_parse_int("2147483648", 10, &i) == NUM_RANGE);
    CHECK(lex_parse_int("99999999999999999999", 20, &i) == NUM_RANGE);
    CHECK(lex_parse_int("1.0", 3, &i) == NUM_SYNTAX);
    CHECK(lex_parse_int("1e3", 3, &i) == NUM_SYNTAX);

    /* Brute force against strtof on random decimals of every shape the fast path and the
     * strtod fallback handle: 1-20 significant digits, exponents -45..40. The fast path
     * rounds the exact decimal to double and then to float; that double rounding can
     * differ from strtof's direct rounding by one ulp, only when the double lands exactly
     * on a float rounding midpoint, so: never more than 1 ulp, and exact in the vast
     * majority of cases. */
    srand(12345);
    int mismatched = 0, total = 200000;
    for (int n = 0; n < total; ++n) {
        char buf[64];
        int digits = 1 + rand() % 20, point = rand() % (digits + 1), len = 0;
        if (rand() % 2) buf[len++] = '-';
        for (int k = 0; k < digits; ++k) {
            if (k == point && k > 0) buf[len++] = '.';
            buf[len++] = (char)('0' + rand() % 10);
        }
        if (rand() % 3 == 0) len += snprintf(buf + len, sizeof buf - (size_t)len, "e%d", rand() % 86 - 45);
        buf[len] = '\0';
        double ref_d = strtod(buf, NULL);
        float ours;
        NumStatus st = lex_parse_float(buf, (size_t)len, &ours);
        if (fabs(ref_d) > FLT_MAX) {
            CHECK(st == NUM_RANGE);
            continue;
        }
        CHECK(st == NUM_OK);
        float ref = strtof(buf, NULL);
        int64_t dist = ulp_distance(ours, ref);
        if (dist > 1 || (st != NUM_OK)) {
            fprintf(stderr, "  %s: ours %.9g, strtof %.9g\n", buf, (double)ours, (double)ref);
            CHECK(dist <= 1);
        }
        mismatched += dist != 0;
    }
    CHECK(mismatched * 1000 < total); /* fewer than 0.1% off by one ulp */
    printf("number parser: %d of %d differ from strtof by 1 ulp\n", mismatched, total);
    CHECK_DONE();
}
