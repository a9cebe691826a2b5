/* PLY reader and writer (see ply.h for the supported subset).
 *
 * The reader streams the file through a fixed buffer. Before any array is allocated the
 * header's row counts are checked against the bytes left in the file (each row needs at
 * least a known number of bytes), so a lying header cannot make us allocate more than a
 * small multiple of the file size; list lengths are checked the same way row by row. */
#include "geometry/ply.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum {
    PLY_MAX_ELEMENTS = 64,
    PLY_MAX_PROPS = 64,      /* per element */
    PLY_MAX_NAME = 64,
    PLY_MAX_LINE = 1024,     /* header line length */
    PLY_MAX_HEADER_LINES = 4096,
    PLY_MAX_TOKEN = 64,      /* ASCII number length */
};

typedef enum { T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64, T_INVALID } PlyType;

static const struct {
    const char *name;
    PlyType type;
} ply_type_names[] = {
    {"char", T_I8},   {"int8", T_I8},     {"uchar", T_U8},   {"uint8", T_U8},
    {"short", T_I16}, {"int16", T_I16},   {"ushort", T_U16}, {"uint16", T_U16},
    {"int", T_I32},   {"int32", T_I32},   {"uint", T_U32},   {"uint32", T_U32},
    {"float", T_F32}, {"float32", T_F32}, {"double", T_F64}, {"float64", T_F64},
};
static const int ply_type_size[] = {1, 1, 2, 2, 4, 4, 4, 8};
static bool ply_type_is_integer(PlyType t) { return t <= T_U32; }

typedef struct {
    char name[PLY_MAX_NAME];
    bool is_list;
    PlyType count_type, value_type;
} PlyProp;

typedef struct {
    char name[PLY_MAX_NAME];
    long count;
    int line; /* header line that declared it */
    int prop_count;
    PlyProp props[PLY_MAX_PROPS];
} PlyElement;

typedef struct {
    FILE *f;
    const char *path;
    Diag *err;
    PlyFormat format;
    unsigned char buf[1 << 16];
    size_t pos, len;
    unsigned long long offset;    /* bytes consumed */
    unsigned long long file_size; /* bytes */
    int line, col;                /* position of the next byte (1-based) */
    int element_count;
    PlyElement elements[PLY_MAX_ELEMENTS];
    /* what the current value belongs to, for messages */
    const PlyElement *cur_element;
    long cur_row;
} PlyReader;

/* ---- errors ---- */

static SrcLoc file_loc(const PlyReader *r) { SrcLoc loc = {r->path, 0, 0}; return loc; }
static SrcLoc line_loc(const PlyReader *r, int line, int col)
{
    SrcLoc loc = {r->path, line, col > 0 ? col : 1};
    return loc;
}
/* Data errors carry a line only in ASCII files (binary data has no lines). */
static SrcLoc data_loc(const PlyReader *r, int line, int col)
{
    return r->format == PLY_ASCII ? line_loc(r, line, col) : file_loc(r);
}

static bool fail_eof(PlyReader *r)
{
    diag_set(r->err, WEDGE_EXIT_INPUT, data_loc(r, r->line, r->col),
             "unexpected end of file in element \"%s\" (row index %ld, %ld rows declared)",
             r->cur_element->name, r->cur_row, r->cur_element->count);
    return false;
}

/* ---- byte input ---- */

static bool refill(PlyReader *r)
{
    r->pos = 0;
    r->len = fread(r->buf, 1, sizeof r->buf, r->f);
    return r->len > 0;
}

/* Returns the next byte or -1 at end of file. */
static inline int rd_byte(PlyReader *r)
{
    if (r->pos == r->len && !refill(r)) return -1;
    r->offset++;
    int c = r->buf[r->pos++];
    if (c == '\n') {
        r->line++;
        r->col = 1;
    } else {
        r->col++;
    }
    return c;
}

static inline int peek_byte(PlyReader *r)
{
    if (r->pos == r->len && !refill(r)) return -1;
    return r->buf[r->pos];
}

static bool rd_bytes(PlyReader *r, unsigned char *dst, size_t n)
{
    while (n > 0) {
        if (r->pos == r->len && !refill(r)) return false;
        size_t take = r->len - r->pos < n ? r->len - r->pos : n;
        memcpy(dst, r->buf + r->pos, take);
        r->pos += take;
        r->offset += take;
        dst += take;
        n -= take;
    }
    return true;
}

static bool skip_bytes(PlyReader *r, unsigned long long n)
{
    while (n > 0) {
        if (r->pos == r->len && !refill(r)) return false;
        size_t avail = r->len - r->pos;
        size_t take = (unsigned long long)avail < n ? avail : (size_t)n;
        r->pos += take;
        r->offset += take;
        n -= take;
    }
    return true;
}

static unsigned long long bytes_left(const PlyReader *r)
{
    return r->file_size > r->offset ? r->file_size - r->offset : 0;
}

/* ---- header ---- */

/* Reads one header line without its "\n" (and "\r"). Returns its length, -1 at end of file,
 * -2 when longer than the buffer. */
static int rd_line(PlyReader *r, char *line, int cap)
{
    int n = 0;
    for (;;) {
        int c = rd_byte(r);
        if (c < 0) return -1;
        if (c == '\n') break;
        if (n + 1 >= cap) return -2;
        line[n++] = (char)c;
    }
    if (n > 0 && line[n - 1] == '\r') n--;
    line[n] = '\0';
    return n;
}

typedef struct {
    const char *text[8];
    int col[8];
    int count; /* may exceed 8: extra tokens are counted but not stored */
} Tokens;

static void split(char *line, Tokens *t)
{
    t->count = 0;
    char *s = line;
    for (;;) {
        while (*s == ' ' || *s == '\t') s++;
        if (!*s) break;
        if (t->count < 8) {
            t->text[t->count] = s;
            t->col[t->count] = (int)(s - line) + 1;
        }
        t->count++;
        while (*s && *s != ' ' && *s != '\t') s++;
        if (*s) *s++ = '\0';
    }
}

static PlyType parse_type(const char *name)
{
    for (size_t i = 0; i < sizeof ply_type_names / sizeof ply_type_names[0]; i++)
        if (strcmp(name, ply_type_names[i].name) == 0) return ply_type_names[i].type;
    return T_INVALID;
}

static bool copy_name(PlyReader *r, char *dst, const char *src, int line, int col)
{
    size_t n = strlen(src);
    if (n >= PLY_MAX_NAME) {
        diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line, col), "name longer than %d characters",
                 PLY_MAX_NAME - 1);
        return false;
    }
    memcpy(dst, src, n + 1);
    return true;
}

static bool read_header(PlyReader *r)
{
    char line[PLY_MAX_LINE];
    r->line = 1;
    r->col = 1;
    int n = rd_line(r, line, sizeof line);
    if (n < 0 || strcmp(line, "ply") != 0) {
        diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, 1, 1),
                 "not a PLY file (the first line must be \"ply\")");
        return false;
    }
    bool have_format = false;
    for (int lines = 1;; lines++) {
        int line_no = r->line;
        if (lines > PLY_MAX_HEADER_LINES) {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                     "header longer than %d lines", PLY_MAX_HEADER_LINES);
            return false;
        }
        n = rd_line(r, line, sizeof line);
        if (n == -1) {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                     "unexpected end of file in the header (no \"end_header\")");
            return false;
        }
        if (n == -2) {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                     "header line longer than %d characters", PLY_MAX_LINE - 2);
            return false;
        }
        Tokens t;
        split(line, &t);
        if (t.count == 0) continue;
        const char *kw = t.text[0];
        if (strcmp(kw, "comment") == 0 || strcmp(kw, "obj_info") == 0) continue;
        if (strcmp(kw, "end_header") == 0) {
            if (!have_format) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                         "missing \"format\" line before \"end_header\"");
                return false;
            }
            return true;
        }
        if (strcmp(kw, "format") == 0) {
            if (t.count != 3) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                         "malformed \"format\" line (expected: format ENCODING 1.0)");
                return false;
            }
            if (strcmp(t.text[1], "ascii") == 0) r->format = PLY_ASCII;
            else if (strcmp(t.text[1], "binary_little_endian") == 0) r->format = PLY_BINARY_LE;
            else if (strcmp(t.text[1], "binary_big_endian") == 0) r->format = PLY_BINARY_BE;
            else {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[1]),
                         "unknown PLY format \"%s\" (expected ascii, binary_little_endian or "
                         "binary_big_endian)", t.text[1]);
                return false;
            }
            if (strcmp(t.text[2], "1.0") != 0 && strcmp(t.text[2], "1") != 0) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[2]),
                         "unsupported PLY version \"%s\" (expected 1.0)", t.text[2]);
                return false;
            }
            have_format = true;
        } else if (strcmp(kw, "element") == 0) {
            if (t.count != 3) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                         "malformed \"element\" line (expected: element NAME COUNT)");
                return false;
            }
            if (r->element_count == PLY_MAX_ELEMENTS) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                         "more than %d elements", PLY_MAX_ELEMENTS);
                return false;
            }
            PlyElement *e = &r->elements[r->element_count];
            memset(e, 0, sizeof *e);
            if (!copy_name(r, e->name, t.text[1], line_no, t.col[1])) return false;
            for (int i = 0; i < r->element_count; i++)
                if (strcmp(r->elements[i].name, e->name) == 0) {
                    diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[1]),
                             "element \"%s\" declared twice", e->name);
                    return false;
                }
            const char *s = t.text[2];
            char *end = NULL;
            errno = 0;
            long long count = (*s >= '0' && *s <= '9') ? strtoll(s, &end, 10) : -1;
            if (count < 0 || errno || *end || count > INT_MAX) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[2]),
                         "bad element count \"%s\" (expected an integer from 0 to %d)", s, INT_MAX);
                return false;
            }
            e->count = (long)count;
            e->line = line_no;
            r->element_count++;
        } else if (strcmp(kw, "property") == 0) {
            if (r->element_count == 0) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                         "\"property\" before any \"element\"");
                return false;
            }
            PlyElement *e = &r->elements[r->element_count - 1];
            if (e->prop_count == PLY_MAX_PROPS) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                         "more than %d properties in element \"%s\"", PLY_MAX_PROPS, e->name);
                return false;
            }
            PlyProp *p = &e->props[e->prop_count];
            memset(p, 0, sizeof *p);
            int name_tok;
            if (t.count >= 2 && strcmp(t.text[1], "list") == 0) {
                if (t.count != 5) {
                    diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                             "malformed \"property list\" line (expected: property list "
                             "COUNT_TYPE VALUE_TYPE NAME)");
                    return false;
                }
                p->is_list = true;
                p->count_type = parse_type(t.text[2]);
                p->value_type = parse_type(t.text[3]);
                for (int k = 2; k <= 3; k++)
                    if (parse_type(t.text[k]) == T_INVALID) {
                        diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[k]),
                                 "unknown property type \"%s\"", t.text[k]);
                        return false;
                    }
                if (!ply_type_is_integer(p->count_type)) {
                    diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[2]),
                             "list count type \"%s\" is not an integer type", t.text[2]);
                    return false;
                }
                name_tok = 4;
            } else {
                if (t.count != 3) {
                    diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                             "malformed \"property\" line (expected: property TYPE NAME)");
                    return false;
                }
                p->value_type = parse_type(t.text[1]);
                if (p->value_type == T_INVALID) {
                    diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, t.col[1]),
                             "unknown property type \"%s\"", t.text[1]);
                    return false;
                }
                name_tok = 2;
            }
            if (!copy_name(r, p->name, t.text[name_tok], line_no, t.col[name_tok])) return false;
            e->prop_count++;
        } else {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, line_no, 1),
                     "unexpected header line starting with \"%s\"", kw);
            return false;
        }
    }
}

/* Smallest number of bytes one row (or one list entry) can occupy: binary sizes, or in
 * ASCII one character plus one separator per value. */
static unsigned long long min_value_bytes(const PlyReader *r, PlyType t)
{
    return r->format == PLY_ASCII ? 2 : (unsigned long long)ply_type_size[t];
}

static unsigned long long min_row_bytes(const PlyReader *r, const PlyElement *e)
{
    unsigned long long n = 0;
    for (int i = 0; i < e->prop_count; i++)
        n += min_value_bytes(r, e->props[i].is_list ? e->props[i].count_type : e->props[i].value_type);
    return n;
}

/* Rejects headers whose rows cannot fit in the file (before anything is allocated). */
static bool check_counts_fit(PlyReader *r)
{
    /* ASCII: the very last value may lack its separator. */
    unsigned long long left = bytes_left(r) + (r->format == PLY_ASCII ? 1 : 0);
    for (int i = 0; i < r->element_count; i++) {
        const PlyElement *e = &r->elements[i];
        unsigned long long row = min_row_bytes(r, e);
        if (row == 0) continue;
        if ((unsigned long long)e->count > left / row) {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, e->line, 1),
                     "element \"%s\" declares %ld rows, more than the %llu bytes of data left "
                     "in the file can hold", e->name, e->count, bytes_left(r));
            return false;
        }
        left -= (unsigned long long)e->count * row;
    }
    return true;
}

/* ---- values ---- */

/* ASCII: reads one whitespace-separated token; returns false at end of file. */
static bool rd_token(PlyReader *r, char *tok, int *line, int *col)
{
    int c;
    for (;;) {
        c = peek_byte(r);
        if (c < 0) return false;
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v')
            rd_byte(r);
        else
            break;
    }
    *line = r->line;
    *col = r->col;
    int n = 0;
    for (;;) {
        c = peek_byte(r);
        if (c < 0 || c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') break;
        rd_byte(r);
        if (n < PLY_MAX_TOKEN - 1) tok[n] = (char)c;
        n++;
    }
    if (n >= PLY_MAX_TOKEN) {
        tok[PLY_MAX_TOKEN - 1] = '\0';
        tok[PLY_MAX_TOKEN - 2] = '.'; /* marks the truncation in messages */
        tok[PLY_MAX_TOKEN - 3] = '.';
        tok[PLY_MAX_TOKEN - 4] = '.';
        return true; /* the parse below rejects it */
    }
    tok[n] = '\0';
    return true;
}

static const double type_min[] = {-128, 0, -32768, 0, -2147483648.0, 0};
static const double type_max[] = {127, 255, 32767, 65535, 2147483647.0, 4294967295.0};

/* Reads one value of type t as a double. line/col receive the value's position (ASCII). */
static bool rd_value(PlyReader *r, PlyType t, double *out, int *line, int *col)
{
    if (r->format == PLY_ASCII) {
        char tok[PLY_MAX_TOKEN];
        if (!rd_token(r, tok, line, col)) return fail_eof(r);
        char *end = NULL;
        errno = 0;
        if (ply_type_is_integer(t)) {
            long long v = strtoll(tok, &end, 10);
            if (end == tok || *end || errno || v < type_min[t] || v > type_max[t]) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, *line, *col),
                         "expected an integer of type %s but found \"%s\" (element \"%s\", row index %ld)",
                         ply_type_names[2 * t].name, tok, r->cur_element->name, r->cur_row);
                return false;
            }
            *out = (double)v;
        } else {
            double v = strtod(tok, &end);
            if (end == tok || *end || !isfinite(v)) {
                diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, *line, *col),
                         "expected a finite number but found \"%s\" (element \"%s\", row index %ld)", tok,
                         r->cur_element->name, r->cur_row);
                return false;
            }
            *out = v;
        }
        return true;
    }
    *line = *col = 0;
    unsigned char b[8];
    int size = ply_type_size[t];
    if (!rd_bytes(r, b, (size_t)size)) return fail_eof(r);
    uint64_t u = 0;
    for (int i = 0; i < size; i++) {
        int k = r->format == PLY_BINARY_LE ? size - 1 - i : i; /* most significant first */
        u = (u << 8) | b[k];
    }
    switch (t) {
    case T_I8: *out = (int8_t)(uint8_t)u; break;
    case T_U8: *out = (uint8_t)u; break;
    case T_I16: *out = (int16_t)(uint16_t)u; break;
    case T_U16: *out = (uint16_t)u; break;
    case T_I32: *out = (int32_t)(uint32_t)u; break;
    case T_U32: *out = (uint32_t)u; break;
    case T_F32: {
        uint32_t u32 = (uint32_t)u;
        float f;
        memcpy(&f, &u32, 4);
        *out = f;
        break;
    }
    case T_F64: memcpy(out, &u, 8); break;
    default: *out = 0; break;
    }
    return true;
}

/* Reads a list length and checks that that many values can still be in the file. */
static bool rd_list_count(PlyReader *r, const PlyProp *p, long *count, int *line, int *col)
{
    double v;
    if (!rd_value(r, p->count_type, &v, line, col)) return false;
    if (v < 0) {
        diag_set(r->err, WEDGE_EXIT_INPUT, data_loc(r, *line, *col),
                 "negative list length %.0f (element \"%s\", row index %ld)", v, r->cur_element->name,
                 r->cur_row);
        return false;
    }
    unsigned long long need = (unsigned long long)v * min_value_bytes(r, p->value_type);
    if (need > bytes_left(r) + (r->format == PLY_ASCII ? 1 : 0)) {
        diag_set(r->err, WEDGE_EXIT_INPUT, data_loc(r, *line, *col),
                 "list length %.0f runs past the end of the file (element \"%s\", row index %ld)", v,
                 r->cur_element->name, r->cur_row);
        return false;
    }
    *count = (long)v;
    return true;
}

/* Skips one property value (scalar or whole list), still checking it is well formed. */
static bool skip_prop(PlyReader *r, const PlyProp *p)
{
    int line, col;
    double v;
    if (!p->is_list) {
        if (r->format != PLY_ASCII) {
            if (!skip_bytes(r, (unsigned long long)ply_type_size[p->value_type])) return fail_eof(r);
            return true;
        }
        return rd_value(r, p->value_type, &v, &line, &col);
    }
    long count;
    if (!rd_list_count(r, p, &count, &line, &col)) return false;
    if (r->format != PLY_ASCII) {
        if (!skip_bytes(r, (unsigned long long)count * (unsigned long long)ply_type_size[p->value_type]))
            return fail_eof(r);
        return true;
    }
    for (long i = 0; i < count; i++)
        if (!rd_value(r, p->value_type, &v, &line, &col)) return false;
    return true;
}

/* ---- the two elements we read ---- */

enum { ROLE_NONE = -1, ROLE_X, ROLE_Y, ROLE_Z, ROLE_NX, ROLE_NY, ROLE_NZ, ROLE_U, ROLE_V, ROLE_COUNT };
static const char *const role_names[ROLE_COUNT] = {"x", "y", "z", "nx", "ny", "nz", "u", "v"};

typedef struct {
    const PlyElement *vertex, *face;
    int role_of_prop[PLY_MAX_PROPS]; /* vertex property -> ROLE_* */
    int index_prop;                  /* face property holding the vertex indices */
    bool has_normals, has_uv;
} PlyLayout;

static int find_prop(const PlyElement *e, const char *name)
{
    for (int i = 0; i < e->prop_count; i++)
        if (strcmp(e->props[i].name, name) == 0) return i;
    return -1;
}

static bool find_layout(PlyReader *r, PlyLayout *L)
{
    memset(L, 0, sizeof *L);
    for (int i = 0; i < r->element_count; i++) {
        if (strcmp(r->elements[i].name, "vertex") == 0) L->vertex = &r->elements[i];
        if (strcmp(r->elements[i].name, "face") == 0) L->face = &r->elements[i];
    }
    if (!L->vertex || L->vertex->count == 0) {
        diag_set(r->err, WEDGE_EXIT_INPUT, file_loc(r), "no vertices (a \"vertex\" element with rows is required)");
        return false;
    }
    if (!L->face || L->face->count == 0) {
        diag_set(r->err, WEDGE_EXIT_INPUT, file_loc(r), "no faces (a \"face\" element with rows is required)");
        return false;
    }
    const PlyElement *v = L->vertex;
    for (int i = 0; i < PLY_MAX_PROPS; i++) L->role_of_prop[i] = ROLE_NONE;
    int at[ROLE_COUNT];
    for (int k = 0; k < 6; k++) at[k] = find_prop(v, role_names[k]);
    for (int k = 0; k < 3; k++)
        if (at[k] < 0) {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, v->line, 1),
                     "element \"vertex\" has no property \"%s\"", role_names[k]);
            return false;
        }
    /* texture coordinates: the first complete pair of the names pbrt-v4 accepts */
    static const char *const uv_names[4][2] = {
        {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
    at[ROLE_U] = at[ROLE_V] = -1;
    for (int k = 0; k < 4 && at[ROLE_U] < 0; k++) {
        int a = find_prop(v, uv_names[k][0]), b = find_prop(v, uv_names[k][1]);
        if (a >= 0 && b >= 0) {
            at[ROLE_U] = a;
            at[ROLE_V] = b;
        }
    }
    L->has_normals = at[ROLE_NX] >= 0 && at[ROLE_NY] >= 0 && at[ROLE_NZ] >= 0;
    L->has_uv = at[ROLE_U] >= 0;
    for (int k = 0; k < ROLE_COUNT; k++) {
        if (at[k] < 0) continue;
        if ((k == ROLE_NX || k == ROLE_NY || k == ROLE_NZ) && !L->has_normals) continue;
        if (v->props[at[k]].is_list) {
            diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, v->line, 1),
                     "property \"%s\" of element \"vertex\" is a list, expected a scalar",
                     v->props[at[k]].name);
            return false;
        }
        L->role_of_prop[at[k]] = k;
    }
    const PlyElement *f = L->face;
    L->index_prop = find_prop(f, "vertex_indices");
    if (L->index_prop < 0) L->index_prop = find_prop(f, "vertex_index");
    if (L->index_prop < 0 || !f->props[L->index_prop].is_list) {
        diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, f->line, 1),
                 "element \"face\" has no list property \"vertex_indices\"");
        return false;
    }
    if (!ply_type_is_integer(f->props[L->index_prop].value_type)) {
        diag_set(r->err, WEDGE_EXIT_INPUT, line_loc(r, f->line, 1),
                 "property \"%s\" of element \"face\" must hold integers",
                 f->props[L->index_prop].name);
        return false;
    }
    return true;
}

/* ---- the data section ---- */

typedef struct {
    bool store;           /* false: count triangles only */
    TriMesh *mesh;
    size_t index_cap;     /* capacity of mesh->index in entries */
    long triangles;
    long skipped_faces;   /* faces with other than 3 or 4 vertices */
} PlyLoad;

static bool push_triangle(PlyReader *r, PlyLoad *ld, uint32_t a, uint32_t b, uint32_t c)
{
    if (ld->triangles >= MESH_MAX_TRIANGLES) {
        diag_set(r->err, WEDGE_EXIT_INPUT, file_loc(r), "more than %ld triangles", MESH_MAX_TRIANGLES);
        return false;
    }
    if (ld->store) {
        size_t need = 3 * (size_t)(ld->triangles + 1);
        if (need > ld->index_cap) {
            size_t cap = ld->index_cap ? 2 * ld->index_cap : 3 * 64;
            uint32_t *grown = realloc(ld->mesh->index, cap * sizeof *grown);
            if (!grown) {
                diag_set(r->err, WEDGE_EXIT_RUNTIME, file_loc(r), "out of memory");
                return false;
            }
            ld->mesh->index = grown;
            ld->index_cap = cap;
        }
        uint32_t *t = ld->mesh->index + 3 * ld->triangles;
        t[0] = a;
        t[1] = b;
        t[2] = c;
    }
    ld->triangles++;
    return true;
}

static bool read_vertex_row(PlyReader *r, const PlyLayout *L, PlyLoad *ld, long row)
{
    const PlyElement *e = L->vertex;
    double role_value[ROLE_COUNT] = {0};
    for (int i = 0; i < e->prop_count; i++) {
        int role = L->role_of_prop[i];
        if (role == ROLE_NONE || !ld->store) {
            if (!skip_prop(r, &e->props[i])) return false;
            continue;
        }
        int line, col;
        double v;
        if (!rd_value(r, e->props[i].value_type, &v, &line, &col)) return false;
        /* Stored as float: a value that is finite in double may still overflow. */
        if (!isfinite(v) || !isfinite((float)v)) {
            diag_set(r->err, WEDGE_EXIT_INPUT, data_loc(r, line, col),
                     "vertex %ld has a non-finite value for \"%s\"", row, e->props[i].name);
            return false;
        }
        role_value[role] = v;
    }
    if (ld->store) {
        TriMesh *m = ld->mesh;
        m->p[row] = v3((float)role_value[ROLE_X], (float)role_value[ROLE_Y], (float)role_value[ROLE_Z]);
        if (m->n) m->n[row] = v3((float)role_value[ROLE_NX], (float)role_value[ROLE_NY], (float)role_value[ROLE_NZ]);
        if (m->uv) m->uv[row] = v2((float)role_value[ROLE_U], (float)role_value[ROLE_V]);
    }
    return true;
}

static bool read_face_row(PlyReader *r, const PlyLayout *L, PlyLoad *ld, long row)
{
    const PlyElement *e = L->face;
    for (int i = 0; i < e->prop_count; i++) {
        if (i != L->index_prop) {
            if (!skip_prop(r, &e->props[i])) return false;
            continue;
        }
        const PlyProp *p = &e->props[i];
        int line, col;
        long count;
        if (!rd_list_count(r, p, &count, &line, &col)) return false;
        if (count != 3 && count != 4) {
            /* pbrt-v4 ignores such faces with a warning; so do we (one warning per file) */
            ld->skipped_faces++;
            for (long k = 0; k < count; k++) {
                double v;
                if (!rd_value(r, p->value_type, &v, &line, &col)) return false;
            }
            continue;
        }
        uint32_t idx[4];
        for (long k = 0; k < count; k++) {
            double v;
            if (!rd_value(r, p->value_type, &v, &line, &col)) return false;
            if (v < 0 || v >= (double)L->vertex->count) {
                diag_set(r->err, WEDGE_EXIT_INPUT, data_loc(r, line, col),
                         "face %ld has vertex index %.0f, out of range for %ld vertices", row, v,
                         L->vertex->count);
                return false;
            }
            idx[k] = (uint32_t)v;
        }
        if (!push_triangle(r, ld, idx[0], idx[1], idx[2])) return false;
        if (count == 4 && !push_triangle(r, ld, idx[0], idx[2], idx[3])) return false;
    }
    return true;
}

static bool read_data(PlyReader *r, const PlyLayout *L, PlyLoad *ld)
{
    for (int ei = 0; ei < r->element_count; ei++) {
        const PlyElement *e = &r->elements[ei];
        r->cur_element = e;
        bool is_vertex = e == L->vertex, is_face = e == L->face;
        /* Elements we do not read, made of scalars only, are skipped in one go in binary. */
        bool all_scalar = true;
        for (int i = 0; i < e->prop_count; i++) all_scalar &= !e->props[i].is_list;
        if (r->format != PLY_ASCII && all_scalar && !is_face && (!is_vertex || !ld->store)) {
            unsigned long long row_bytes = min_row_bytes(r, e), start = r->offset;
            if (!skip_bytes(r, (unsigned long long)e->count * row_bytes)) {
                /* only if the file shrank after the header check */
                r->cur_row = row_bytes ? (long)((r->offset - start) / row_bytes) : 0;
                return fail_eof(r);
            }
            continue;
        }
        for (long row = 0; row < e->count; row++) {
            r->cur_row = row;
            bool ok;
            if (is_vertex) ok = read_vertex_row(r, L, ld, row);
            else if (is_face) ok = read_face_row(r, L, ld, row);
            else {
                ok = true;
                for (int i = 0; ok && i < e->prop_count; i++) ok = skip_prop(r, &e->props[i]);
            }
            if (!ok) return false;
        }
    }
    return true;
}

/* ---- entry points ---- */

static PlyReader *reader_open(const char *path, Diag *err)
{
    PlyReader *r = calloc(1, sizeof *r);
    if (!r) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return NULL;
    }
    r->path = path;
    r->err = err;
    r->f = fopen(path, "rb");
    struct stat st;
    if (!r->f || fstat(fileno(r->f), &st) != 0 || !S_ISREG(st.st_mode)) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_INPUT, loc, "cannot read PLY file: %s",
                 r->f ? "not a regular file" : strerror(errno));
        if (r->f) fclose(r->f);
        free(r);
        return NULL;
    }
    r->file_size = (unsigned long long)st.st_size;
    return r;
}

static void reader_close(PlyReader *r)
{
    if (!r) return;
    if (r->f) fclose(r->f);
    free(r);
}

bool ply_read_info(const char *path, PlyInfo *info, Diag *err)
{
    memset(info, 0, sizeof *info);
    PlyReader *r = reader_open(path, err);
    if (!r) return false;
    PlyLayout L;
    bool ok = read_header(r) && check_counts_fit(r) && find_layout(r, &L);
    if (ok) {
        info->format = r->format;
        info->vertex_count = L.vertex->count;
        info->face_count = L.face->count;
        info->has_normals = L.has_normals;
        info->has_uv = L.has_uv;
    }
    reader_close(r);
    return ok;
}

long ply_count_triangles(const char *path, Diag *err)
{
    PlyReader *r = reader_open(path, err);
    if (!r) return -1;
    PlyLayout L;
    PlyLoad ld = {0};
    bool ok = read_header(r) && check_counts_fit(r) && find_layout(r, &L) && read_data(r, &L, &ld);
    reader_close(r);
    return ok ? ld.triangles : -1;
}

bool ply_read(const char *path, TriMesh *mesh, MeshWarnFn warn, void *warn_ctx, Diag *err)
{
    memset(mesh, 0, sizeof *mesh);
    PlyReader *r = reader_open(path, err);
    if (!r) return false;
    PlyLayout L;
    PlyLoad ld = {0};
    ld.store = true;
    ld.mesh = mesh;
    bool ok = read_header(r) && check_counts_fit(r) && find_layout(r, &L);
    if (ok) {
        /* counts are bounded by the file size (check_counts_fit) */
        size_t nv = (size_t)L.vertex->count;
        mesh->vertex_count = (int)nv;
        mesh->p = malloc(nv * sizeof *mesh->p);
        if (L.has_normals) mesh->n = malloc(nv * sizeof *mesh->n);
        if (L.has_uv) mesh->uv = malloc(nv * sizeof *mesh->uv);
        ld.index_cap = 3 * (size_t)L.face->count;
        mesh->index = malloc(ld.index_cap * sizeof *mesh->index);
        if (!mesh->p || (L.has_normals && !mesh->n) || (L.has_uv && !mesh->uv) || !mesh->index) {
            diag_set(err, WEDGE_EXIT_RUNTIME, file_loc(r), "out of memory");
            ok = false;
        }
    }
    ok = ok && read_data(r, &L, &ld);
    if (ok) {
        mesh->triangle_count = (int)ld.triangles;
        if (ld.skipped_faces && warn) {
            char text[256];
            snprintf(text, sizeof text,
                     "ignored %ld faces with other than 3 or 4 vertices (only triangles and quads "
                     "are supported)", ld.skipped_faces);
            warn(warn_ctx, file_loc(r), text);
        }
        if (ld.triangles == 0) {
            diag_set(err, WEDGE_EXIT_INPUT, file_loc(r), "no triangles or quads among the %ld faces",
                     L.face->count);
            ok = false;
        }
    }
    reader_close(r);
    if (!ok) mesh_free(mesh);
    return ok;
}

/* ---- writer ---- */

typedef struct {
    FILE *f;
    PlyFormat format;
} PlyOut;

static void put_value(PlyOut *o, PlyType t, double v)
{
    if (o->format == PLY_ASCII) {
        if (ply_type_is_integer(t)) fprintf(o->f, "%.0f", v);
        else if (t == T_F32) fprintf(o->f, "%.9g", v);
        else fprintf(o->f, "%.17g", v);
        return;
    }
    uint64_t u = 0;
    int size = ply_type_size[t];
    switch (t) {
    case T_I8: u = (uint8_t)(int8_t)v; break;
    case T_U8: u = (uint8_t)v; break;
    case T_I16: u = (uint16_t)(int16_t)v; break;
    case T_U16: u = (uint16_t)v; break;
    case T_I32: u = (uint32_t)(int32_t)v; break;
    case T_U32: u = (uint32_t)v; break;
    case T_F32: {
        float f = (float)v;
        uint32_t u32;
        memcpy(&u32, &f, 4);
        u = u32;
        break;
    }
    case T_F64: memcpy(&u, &v, 8); break;
    default: break;
    }
    unsigned char b[8];
    for (int i = 0; i < size; i++) {
        int shift = 8 * (o->format == PLY_BINARY_LE ? i : size - 1 - i);
        b[i] = (unsigned char)(u >> shift);
    }
    fwrite(b, 1, (size_t)size, o->f);
}

static void put_sep(PlyOut *o, bool last)
{
    if (o->format == PLY_ASCII) fputc(last ? '\n' : ' ', o->f);
}

bool ply_write(const char *path, PlyFormat format, const PlyWriteDesc *m, Diag *err)
{
    SrcLoc loc = {path, 0, 0};
    FILE *f = fopen(path, "wb");
    if (!f) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot write PLY file: %s", strerror(errno));
        return false;
    }
    PlyOut o = {f, format};
    static const char *const format_names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    fprintf(f, "ply\nformat %s 1.0\ncomment written by wedge\n", format_names[format]);
    fprintf(f, "element vertex %d\n", m->vertex_count);
    if (m->extra) fprintf(f, "property double confidence\n");
    fprintf(f, "property float x\nproperty float y\nproperty float z\n");
    if (m->n) fprintf(f, "property float nx\nproperty float ny\nproperty float nz\n");
    if (m->uv) fprintf(f, m->extra ? "property float s\nproperty float t\n" : "property float u\nproperty float v\n");
    if (m->extra) {
        fprintf(f, "property list uchar float junk\n");
        fprintf(f, "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
                   "property list uint short weights\n");
    }
    fprintf(f, "element face %d\n", m->face_count);
    if (m->extra) fprintf(f, "property int flags\nproperty list uint uint vertex_index\n"
                             "property list ushort uchar tags\n");
    else fprintf(f, "property list uchar int vertex_indices\n");
    fprintf(f, "end_header\n");

    for (int i = 0; i < m->vertex_count; i++) {
        if (m->extra) { put_value(&o, T_F64, 0.25 * i); put_sep(&o, false); }
        put_value(&o, T_F32, m->p[i].x); put_sep(&o, false);
        put_value(&o, T_F32, m->p[i].y); put_sep(&o, false);
        put_value(&o, T_F32, m->p[i].z);
        if (m->n) {
            put_sep(&o, false); put_value(&o, T_F32, m->n[i].x);
            put_sep(&o, false); put_value(&o, T_F32, m->n[i].y);
            put_sep(&o, false); put_value(&o, T_F32, m->n[i].z);
        }
        if (m->uv) {
            put_sep(&o, false); put_value(&o, T_F32, m->uv[i].x);
            put_sep(&o, false); put_value(&o, T_F32, m->uv[i].y);
        }
        if (m->extra) { /* a list of i % 3 floats */
            put_sep(&o, false); put_value(&o, T_U8, i % 3);
            for (int k = 0; k < i % 3; k++) { put_sep(&o, false); put_value(&o, T_F32, -1.5 * k); }
        }
        put_sep(&o, true);
    }
    if (m->extra)
        for (int i = 0; i < 2; i++) {
            put_value(&o, T_I32, i); put_sep(&o, false);
            put_value(&o, T_I32, i + 1); put_sep(&o, false);
            put_value(&o, T_U32, i + 1);
            for (int k = 0; k <= i; k++) { put_sep(&o, false); put_value(&o, T_I16, -7 * k); }
            put_sep(&o, true);
        }
    size_t at = 0;
    for (int i = 0; i < m->face_count; i++) {
        int n = m->face_size ? m->face_size[i] : 3;
        if (m->extra) { put_value(&o, T_I32, -i); put_sep(&o, false); }
        put_value(&o, m->extra ? T_U32 : T_U8, n);
        for (int k = 0; k < n; k++) {
            put_sep(&o, false);
            put_value(&o, m->extra ? T_U32 : T_I32, m->index[at++]);
        }
        if (m->extra) {
            put_sep(&o, false); put_value(&o, T_U16, 2);
            put_sep(&o, false); put_value(&o, T_U8, 200);
            put_sep(&o, false); put_value(&o, T_U8, 7);
        }
        put_sep(&o, true);
    }
    bool ok = !ferror(f);
    if (fclose(f) != 0) ok = false;
    if (!ok) diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot write PLY file: %s", strerror(errno));
    return ok;
}
