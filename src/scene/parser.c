/* pbrt-v4 scene parser: statements -> SceneDesc.
 *
 * Semantics follow pbrt-v4's BasicSceneBuilder: a current transformation matrix (CTM) per
 * shutter time (start, end), changed by post-multiplication and only for the times that
 * ActiveTransform selects; AttributeBegin/End save and restore the whole graphics state;
 * WorldBegin resets both CTMs to the identity and names the result "world"; Camera
 * records camera_from_world = CTM and names its inverse "camera".
 *
 * Robustness: the attribute stack is on the heap (no recursion per nesting level), the
 * only recursion is Include/Import, bounded by INCLUDE_DEPTH_MAX, and the total amount of
 * included text is capped, so no input can recurse or allocate without bound. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "scene/lexer.h"
#include "scene/name_map.h"
#include "scene/scene_desc.h"
#include "scene/scene_internal.h"
#include "scene/spectrum.h"

enum {
    INCLUDE_DEPTH_MAX = 32,
    INCLUDE_FILES_MAX = 10000,   /* every Include counts, also repeated ones */
    PARAMS_PER_LIST_MAX = 1024,
    ATTRIBUTE_PARAMS_MAX = 256,  /* distinct "Attribute" parameter names per target */
    ATTRIBUTE_DEPTH_MAX = 100000,
    FILM_RES_MAX = 65536,
};
/* Scene text read in total (main file plus all includes, counting repeats). */
static const size_t INCLUDED_BYTES_MAX = (size_t)4 << 30;

/* ---- growable arrays (malloc'd while parsing, copied into the arena at the end) ---- */

static bool grow(void **p, int *cap, int need, size_t elem)
{
    if (need <= *cap) return true;
    int ncap = *cap ? *cap : 16;
    while (ncap < need) {
        if (ncap > INT_MAX / 2) return false;
        ncap *= 2;
    }
    void *q = realloc(*p, (size_t)ncap * elem);
    if (!q) return false;
    *p = q;
    *cap = ncap;
    return true;
}

#define VEC(T) struct { T *v; int n, cap; }
#define VEC_PUSH(P, vec, item)                                                          \
    (grow((void **)&(vec).v, &(vec).cap, (vec).n + 1, sizeof *(vec).v)                  \
         ? ((vec).v[(vec).n++] = (item), true)                                          \
         : oom(P))

/* ---- graphics state ---- */

enum { ACTIVE_START = 1, ACTIVE_END = 2, ACTIVE_ALL = 3 };

typedef struct {
    Mat4 ctm[2];
    int active;               /* ACTIVE_* bits */
    bool reverse_orientation;
    int material;             /* anonymous material index, or -1 */
    const char *material_name;/* NamedMaterial in effect (wins over material when set) */
    SrcLoc material_loc;
    int area_light;           /* index into area lights, or -1 */
    ParamSet shape_attrs, light_attrs, material_attrs, medium_attrs, texture_attrs;
    const char *color_space;
} GState;

typedef struct {
    GState gs;
    char kind;                /* 'A' AttributeBegin, 'T' TransformBegin, 'O' ObjectBegin, 'I' Import */
    SrcLoc loc;
} Pushed;

typedef struct {
    const char *name;
    Mat4 m[2];
} NamedCoordSys;

typedef struct {
    dev_t dev;
    ino_t ino;
} FileId;

typedef struct {
    SceneDesc *scene;
    Diag *err;
    Arena *arena;

    VEC(MaterialDesc) materials;
    VEC(TextureDesc) textures;
    VEC(AreaLightDesc) area_lights;
    VEC(LightDesc) lights;
    VEC(ShapeDesc) shapes;
    VEC(ObjectDesc) objects;
    VEC(InstanceDesc) instances;
    VEC(const char *) instance_names;
    VEC(const char *) shape_material_names; /* per shape: NamedMaterial to resolve, or NULL */
    VEC(SrcLoc) shape_material_locs;
    VEC(NamedCoordSys) coord_systems;
    VEC(Pushed) stack;
    VEC(FileId) include_stack;
    VEC(const char *) source_files;
    VEC(FileId) source_ids;
    NameMap warned_kinds;         /* kinds of warning already given (value unused) */
    NameMap named_materials;      /* name -> index into materials */
    NameMap float_textures, spectrum_textures; /* name -> index into textures */
    NameMap object_names;         /* name -> index into objects */
    NameMap coord_sys_names;      /* name -> index into coord_systems */

    /* scratch for parameter values */
    VEC(float) fscratch;
    VEC(int32_t) iscratch;
    VEC(const char *) sscratch;
    VEC(bool) bscratch;
    VEC(Param) pscratch;

    GState gs;
    bool in_world;
    int current_object;       /* index into objects while inside ObjectBegin, else -1 */
    bool camera_seen;
    const char *base_dir;     /* directory of the file being read: Include and data files */
    size_t bytes_read;
    int files_included;
    int stack_floor;          /* pushes below this belong to an importing file (Import) */
    SrcLoc eof_loc;           /* where the last file read ended (the main file's end at finish) */
} Parser;

static bool oom(Parser *P)
{
    diag_set(P->err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory while parsing the scene");
    return false;
}

static void warn_once(Parser *P, const char *kind, SrcLoc loc, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void warn_once(Parser *P, const char *kind, SrcLoc loc, const char *fmt, ...)
{
    if (name_map_get(&P->warned_kinds, kind) >= 0) return;
    const char *k = arena_strdup(P->arena, kind);
    if (!k || !name_map_put(&P->warned_kinds, k, 1)) return;
    char text[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    scene_warn(P->scene, loc, "%s", text);
}

/* ---- tokens ---- */

static bool tok_is(const Token *t, const char *word)
{
    size_t n = strlen(word);
    return t->kind == TOK_WORD && t->len == n && !memcmp(t->text, word, n);
}

/* A string token's value, escapes decoded, in the arena. */
static const char *tok_string(Parser *P, const Token *t)
{
    if (!memchr(t->text, '\\', t->len)) return arena_strndup(P->arena, t->text, t->len);
    char *s = arena_alloc(P->arena, t->len + 1);
    if (s) lex_unescape(t->text, t->len, s);
    return s;
}

/* For messages: a token shown in quotes, shortened. */
static void tok_show(const Token *t, char *buf, size_t size)
{
    if (t->kind == TOK_EOF) {
        snprintf(buf, size, "end of file");
        return;
    }
    size_t n = t->len < 40 ? t->len : 40;
    char tmp[48];
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)t->text[i];
        tmp[i] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    tmp[n] = '\0';
    snprintf(buf, size, "\"%s%s\"", tmp, t->len > n ? "..." : "");
}

static const char *const directive_names[] = {
    "Accelerator", "ActiveTransform", "AreaLightSource", "Attribute", "AttributeBegin", "AttributeEnd",
    "Camera", "ColorSpace", "ConcatTransform", "CoordinateSystem", "CoordSysTransform", "Film", "Identity",
    "Import", "Include", "Integrator", "LightSource", "LookAt", "MakeNamedMaterial", "MakeNamedMedium",
    "Material", "MediumInterface", "NamedMaterial", "ObjectBegin", "ObjectEnd", "ObjectInstance", "Option",
    "PixelFilter", "ReverseOrientation", "Rotate", "Sampler", "Scale", "Shape", "Texture", "Transform",
    "TransformBegin", "TransformEnd", "TransformTimes", "Translate", "WorldBegin", "WorldEnd",
};

static bool is_directive(const Token *t)
{
    /* Every directive starts with a capital letter, no number does: keeps this off the
     * per-value path of big meshes. */
    if (t->kind != TOK_WORD || t->len == 0 || t->text[0] < 'A' || t->text[0] > 'Z') return false;
    for (size_t i = 0; i < sizeof directive_names / sizeof directive_names[0]; ++i)
        if (tok_is(t, directive_names[i])) return true;
    return false;
}

/* ---- parameter lists ---- */

static bool parse_param_type(const char *s, size_t n, ParamType *t)
{
#define IS(w) (n == sizeof(w) - 1 && !memcmp(s, w, n))
    if (IS("integer")) *t = PARAM_INTEGER;
    else if (IS("float")) *t = PARAM_FLOAT;
    else if (IS("point2")) *t = PARAM_POINT2;
    else if (IS("vector2")) *t = PARAM_VECTOR2;
    else if (IS("point3") || IS("point")) *t = PARAM_POINT3;
    else if (IS("vector3") || IS("vector")) *t = PARAM_VECTOR3;
    else if (IS("normal3") || IS("normal")) *t = PARAM_NORMAL3;
    else if (IS("rgb") || IS("color")) *t = PARAM_RGB;
    else if (IS("spectrum")) *t = PARAM_SPECTRUM;
    else if (IS("blackbody")) *t = PARAM_BLACKBODY;
    else if (IS("bool")) *t = PARAM_BOOL;
    else if (IS("string")) *t = PARAM_STRING;
    else if (IS("texture")) *t = PARAM_TEXTURE;
    else return false;
    return true;
#undef IS
}

typedef struct {
    ParamType type;
    char decl[160];  /* "float fov" for messages */
    SrcLoc loc;
    int kind;        /* for spectrum: 0 undecided, 1 numbers, 2 strings */
} ValueCtx;

static bool number_error(Parser *P, SrcLoc loc, const Token *t, NumStatus st, const ValueCtx *vc)
{
    char shown[64];
    tok_show(t, shown, sizeof shown);
    if (st == NUM_NAN_INF)
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "invalid number %s: NaN and infinity are not allowed", shown);
    else if (st == NUM_RANGE)
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "number %s is out of range", shown);
    else if (vc && vc->type == PARAM_INTEGER && lex_looks_numeric(t->text, t->len)) {
        float f;
        if (lex_parse_float(t->text, t->len, &f) == NUM_OK)
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" expects integers, got %s", vc->decl, shown);
        else
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "invalid number %s", shown);
    } else
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "invalid number %s", shown);
    return false;
}

/* Appends one value token to the scratch arrays according to the parameter's type. */
static bool param_value(Parser *P, Lexer *lx, const Token *t, ValueCtx *vc)
{
    SrcLoc loc = token_loc(lx, t);
    char shown[64];
    ParamType type = vc->type;
    if (type == PARAM_SPECTRUM) {
        int k = t->kind == TOK_STRING ? 2 : 1;
        if (vc->kind && vc->kind != k) {
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" mixes numbers and strings", vc->decl);
            return false;
        }
        vc->kind = k;
        if (k == 2) {
            const char *s = tok_string(P, t);
            return s ? VEC_PUSH(P, P->sscratch, s) : oom(P);
        }
        type = PARAM_FLOAT;
    }
    if (type == PARAM_BOOL) {
        const char *s = t->text;
        size_t n = t->len;
        if ((t->kind == TOK_STRING || t->kind == TOK_WORD) && n == 4 && !memcmp(s, "true", 4))
            return VEC_PUSH(P, P->bscratch, true);
        if ((t->kind == TOK_STRING || t->kind == TOK_WORD) && n == 5 && !memcmp(s, "false", 5))
            return VEC_PUSH(P, P->bscratch, false);
        tok_show(t, shown, sizeof shown);
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" expects true or false, got %s", vc->decl, shown);
        return false;
    }
    if (type == PARAM_STRING || type == PARAM_TEXTURE) {
        if (t->kind != TOK_STRING) {
            tok_show(t, shown, sizeof shown);
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" expects quoted strings, got %s", vc->decl,
                     shown);
            return false;
        }
        const char *s = tok_string(P, t);
        return s ? VEC_PUSH(P, P->sscratch, s) : oom(P);
    }
    /* numeric */
    if (t->kind != TOK_WORD) {
        tok_show(t, shown, sizeof shown);
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" expects numbers, got %s", vc->decl, shown);
        return false;
    }
    if (type == PARAM_INTEGER) {
        int v;
        NumStatus st = lex_parse_int(t->text, t->len, &v);
        if (st != NUM_OK) return number_error(P, loc, t, st, vc);
        return VEC_PUSH(P, P->iscratch, v);
    }
    float f;
    NumStatus st = lex_parse_float(t->text, t->len, &f);
    if (st != NUM_OK) {
        if (st == NUM_SYNTAX && !lex_looks_numeric(t->text, t->len)) {
            tok_show(t, shown, sizeof shown);
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" expects numbers, got %s", vc->decl, shown);
            return false;
        }
        return number_error(P, loc, t, st, vc);
    }
    return VEC_PUSH(P, P->fscratch, f);
}

static int value_count(const Parser *P, const ValueCtx *vc)
{
    switch (vc->type) {
    case PARAM_INTEGER: return P->iscratch.n;
    case PARAM_BOOL: return P->bscratch.n;
    case PARAM_STRING: case PARAM_TEXTURE: return P->sscratch.n;
    case PARAM_SPECTRUM: return vc->kind == 2 ? P->sscratch.n : P->fscratch.n;
    default: return P->fscratch.n;
    }
}

/* Checks the number of values against the type and stores them into p (arena copies). */
static bool finish_param(Parser *P, const ValueCtx *vc, Param *p)
{
    int n = value_count(P, vc);
    if (n == 0) {
        diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc, "parameter \"%s\" has no values", vc->decl);
        return false;
    }
    int tuple = 1;
    switch (vc->type) {
    case PARAM_POINT2: case PARAM_VECTOR2: tuple = 2; break;
    case PARAM_POINT3: case PARAM_VECTOR3: case PARAM_NORMAL3: case PARAM_RGB: tuple = 3; break;
    default: break;
    }
    if (n % tuple != 0) {
        diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc, "parameter \"%s\" needs a multiple of %d values, got %d",
                 vc->decl, tuple, n);
        return false;
    }
    if (vc->type == PARAM_BLACKBODY && n != 1) {
        diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc,
                 "parameter \"%s\" needs exactly 1 value (a temperature in Kelvin), got %d", vc->decl, n);
        return false;
    }
    if (vc->type == PARAM_TEXTURE && n != 1) {
        diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc, "parameter \"%s\" needs exactly 1 texture name, got %d",
                 vc->decl, n);
        return false;
    }
    if (vc->type == PARAM_SPECTRUM) {
        if (vc->kind == 2 && n != 1) {
            diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc, "parameter \"%s\" needs exactly 1 spectrum name, got %d",
                     vc->decl, n);
            return false;
        }
        if (vc->kind == 1 && n != 1) {
            if (n % 2 != 0) {
                diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc,
                         "parameter \"%s\" needs (wavelength, value) pairs, got %d values", vc->decl, n);
                return false;
            }
            for (int i = 2; i < n; i += 2)
                if (!(P->fscratch.v[i] > P->fscratch.v[i - 2])) {
                    diag_set(P->err, WEDGE_EXIT_INPUT, vc->loc,
                             "parameter \"%s\": wavelengths must increase (%g after %g)", vc->decl,
                             (double)P->fscratch.v[i], (double)P->fscratch.v[i - 2]);
                    return false;
                }
        }
    }
    p->type = vc->type;
    p->count = n;
    if (vc->type == PARAM_INTEGER) {
        int32_t *d = arena_alloc(P->arena, (size_t)n * sizeof *d);
        if (!d) return oom(P);
        memcpy(d, P->iscratch.v, (size_t)n * sizeof *d);
        p->ints = d;
    } else if (vc->type == PARAM_BOOL) {
        bool *d = arena_alloc(P->arena, (size_t)n * sizeof *d);
        if (!d) return oom(P);
        memcpy(d, P->bscratch.v, (size_t)n * sizeof *d);
        p->bools = d;
    } else if (vc->type == PARAM_STRING || vc->type == PARAM_TEXTURE ||
               (vc->type == PARAM_SPECTRUM && vc->kind == 2)) {
        const char **d = arena_alloc(P->arena, (size_t)n * sizeof *d);
        if (!d) return oom(P);
        memcpy(d, P->sscratch.v, (size_t)n * sizeof *d);
        p->strings = d;
    } else {
        float *d = arena_alloc(P->arena, (size_t)n * sizeof *d);
        if (!d) return oom(P);
        memcpy(d, P->fscratch.v, (size_t)n * sizeof *d);
        p->floats = d;
    }
    return true;
}

/* Named spectra: known names are kept; unknown ones get a warning (the getter substitutes,
 * see spectrum_unknown_substitute). Spectrum files are not read: warning + substitution. */
static char *read_file(const char *path, size_t *len, int *err_no, FileId *id);
static const char *join_path(Parser *P, const char *base_dir, const char *name);

enum { SPECTRUM_FILE_MAX = 1 << 20 };

/* pbrt-v4 reads a spectrum file when the string is not a named spectrum: whitespace
 * separated (lambda_nm, value) pairs with '#' comments. On success the parameter becomes
 * numeric, as if the pairs had been written in the scene. */
static bool read_spectrum_file(Parser *P, Param *p)
{
    const char *path = join_path(P, P->base_dir, p->strings[0]);
    struct stat st;
    if (!path || stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > SPECTRUM_FILE_MAX) return false;
    size_t len = 0;
    int err_no = 0;
    FileId id;
    char *text = read_file(path, &len, &err_no, &id);
    if (!text) return false;
    Lexer lx;
    lexer_init(&lx, text, len, path);
    P->fscratch.n = 0;
    bool ok = true;
    for (;;) {
        Token t;
        Diag d;
        float v;
        if (!lexer_next(&lx, &t, &d) || (t.kind != TOK_WORD && t.kind != TOK_EOF)) {
            ok = false;
            break;
        }
        if (t.kind == TOK_EOF) break;
        if (lex_parse_float(t.text, t.len, &v) != NUM_OK || !VEC_PUSH(P, P->fscratch, v)) {
            ok = false;
            break;
        }
    }
    free(text);
    int n = P->fscratch.n;
    if (!ok || n < 2 || n % 2) return false;
    for (int i = 2; i < n; i += 2)
        if (!(P->fscratch.v[i] > P->fscratch.v[i - 2])) return false;
    float *vals = arena_alloc(P->arena, (size_t)n * sizeof *vals);
    if (!vals) return false;
    memcpy(vals, P->fscratch.v, (size_t)n * sizeof *vals);
    p->floats = vals;
    p->strings = NULL;
    p->count = n;
    return true;
}

/* Named spectra: known names are kept (the getters convert them); spectrum files are read;
 * anything else gets a warning and the getter's substitute (spectrum_unknown_substitute). */
static void check_named_spectrum(Parser *P, Param *p)
{
    if (p->type != PARAM_SPECTRUM || !p->strings) return;
    float rgb[3];
    if (spectrum_named_rgb(p->strings[0], rgb)) return;
    const char *name = p->strings[0];
    if (read_spectrum_file(P, p)) return;
    spectrum_unknown_substitute(name, rgb);
    scene_warn(P->scene, p->loc, "unknown named spectrum \"%s\" (or unreadable spectrum file): using constant %g instead",
               name, (double)rgb[0]);
}

/* Reads "type name" value pairs until the next token is not a string. */
static bool parse_params(Parser *P, Lexer *lx, ParamSet *out)
{
    P->pscratch.n = 0;
    for (;;) {
        Token t;
        if (!lexer_peek(lx, &t, P->err)) return false;
        if (t.kind != TOK_STRING) break;
        lexer_next(lx, &t, P->err);
        SrcLoc loc = token_loc(lx, &t);
        /* "type name": exactly two words separated by blanks. */
        const char *s = t.text, *e = t.text + t.len;
        while (s < e && (*s == ' ' || *s == '\t')) ++s;
        const char *tb = s;
        while (s < e && *s != ' ' && *s != '\t') ++s;
        const char *te = s;
        while (s < e && (*s == ' ' || *s == '\t')) ++s;
        const char *nb = s;
        while (s < e && *s != ' ' && *s != '\t') ++s;
        const char *ne = s;
        while (s < e && (*s == ' ' || *s == '\t')) ++s;
        char shown[64];
        tok_show(&t, shown, sizeof shown);
        if (te == tb || ne == nb || s != e) {
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "invalid parameter declaration %s (expected \"TYPE NAME\")",
                     shown);
            return false;
        }
        ValueCtx vc = {0};
        vc.loc = loc;
        if (!parse_param_type(tb, (size_t)(te - tb), &vc.type)) {
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "unknown parameter type \"%.*s\" in %s", (int)(te - tb), tb,
                     shown);
            return false;
        }
        snprintf(vc.decl, sizeof vc.decl, "%.*s %.*s", (int)(te - tb), tb, (int)(ne - nb), nb);
        Param p;
        memset(&p, 0, sizeof p);
        p.loc = loc;
        p.name = arena_strndup(P->arena, nb, (size_t)(ne - nb));
        if (!p.name) return oom(P);
        for (int i = 0; i < P->pscratch.n; ++i)
            if (!strcmp(P->pscratch.v[i].name, p.name)) {
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "parameter \"%s\" given twice", p.name);
                return false;
            }
        if (P->pscratch.n >= PARAMS_PER_LIST_MAX) {
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "too many parameters in one statement (limit %d)",
                     PARAMS_PER_LIST_MAX);
            return false;
        }
        P->fscratch.n = P->iscratch.n = P->sscratch.n = P->bscratch.n = 0;
        Token v;
        if (!lexer_next(lx, &v, P->err)) return false;
        if (v.kind == TOK_LBRACKET) {
            SrcLoc open = token_loc(lx, &v);
            for (;;) {
                if (!lexer_next(lx, &v, P->err)) return false;
                if (v.kind == TOK_RBRACKET) break;
                if (v.kind == TOK_EOF || v.kind == TOK_LBRACKET || is_directive(&v)) {
                    diag_set(P->err, WEDGE_EXIT_INPUT, open, "unbalanced '[': no matching ']'");
                    return false;
                }
                if (!param_value(P, lx, &v, &vc)) return false;
            }
        } else if (v.kind == TOK_STRING || (v.kind == TOK_WORD && !is_directive(&v))) {
            if (!param_value(P, lx, &v, &vc)) return false;
        } else {
            char got[64];
            tok_show(&v, got, sizeof got);
            if (v.kind == TOK_RBRACKET) snprintf(got, sizeof got, "']'");
            diag_set(P->err, WEDGE_EXIT_INPUT, token_loc(lx, &v), "parameter \"%s\" has no value (got %s)", vc.decl,
                     got);
            return false;
        }
        if (!finish_param(P, &vc, &p)) return false;
        check_named_spectrum(P, &p);
        if (!VEC_PUSH(P, P->pscratch, p)) return false;
    }
    out->count = P->pscratch.n;
    out->items = NULL;
    if (out->count) {
        out->items = arena_alloc(P->arena, (size_t)out->count * sizeof *out->items);
        if (!out->items) return oom(P);
        memcpy(out->items, P->pscratch.v, (size_t)out->count * sizeof *out->items);
    }
    return true;
}

/* Attribute defaults ("Attribute "shape" ...") fill in what a statement does not give. */
static bool merge_attrs(Parser *P, ParamSet *ps, const ParamSet *attrs)
{
    if (!attrs->count) return true;
    int extra = 0;
    for (int i = 0; i < attrs->count; ++i) {
        bool have = false;
        for (int j = 0; j < ps->count && !have; ++j) have = !strcmp(ps->items[j].name, attrs->items[i].name);
        extra += !have;
    }
    if (!extra) return true;
    Param *items = arena_alloc(P->arena, (size_t)(ps->count + extra) * sizeof *items);
    if (!items) return oom(P);
    if (ps->count) memcpy(items, ps->items, (size_t)ps->count * sizeof *items);
    int n = ps->count;
    for (int i = 0; i < attrs->count; ++i) {
        bool have = false;
        for (int j = 0; j < ps->count && !have; ++j) have = !strcmp(ps->items[j].name, attrs->items[i].name);
        if (!have) items[n++] = attrs->items[i];
    }
    ps->items = items;
    ps->count = n;
    return true;
}

/* ---- directive arguments ---- */

/* Reads exactly n numbers (optionally inside [ ]) after a directive. */
static bool read_numbers(Parser *P, Lexer *lx, const Token *dir, int n, double *out)
{
    Token t;
    SrcLoc dloc = token_loc(lx, dir);
    char name[32];
    snprintf(name, sizeof name, "%.*s", (int)(dir->len < 31 ? dir->len : 31), dir->text);
    if (!lexer_peek(lx, &t, P->err)) return false;
    bool bracket = t.kind == TOK_LBRACKET;
    SrcLoc open = token_loc(lx, &t);
    if (bracket) lexer_next(lx, &t, P->err);
    int got = 0;
    for (;;) {
        if (!lexer_peek(lx, &t, P->err)) return false;
        /* Any bare word that is not a directive must be one of the numbers. */
        if (t.kind != TOK_WORD || is_directive(&t)) break;
        lexer_next(lx, &t, P->err);
        float f;
        NumStatus st = lex_parse_float(t.text, t.len, &f);
        if (st != NUM_OK) return number_error(P, token_loc(lx, &t), &t, st, NULL);
        if (got < n) out[got] = f;
        ++got;
    }
    if (bracket) {
        if (t.kind != TOK_RBRACKET) {
            diag_set(P->err, WEDGE_EXIT_INPUT, open, "unbalanced '[': no matching ']'");
            return false;
        }
        lexer_next(lx, &t, P->err);
    }
    if (got != n) {
        diag_set(P->err, WEDGE_EXIT_INPUT, dloc, "%s expects %d numbers, got %d", name, n, got);
        return false;
    }
    return true;
}

/* Reads the quoted string argument of a directive. */
static bool read_string(Parser *P, Lexer *lx, const Token *dir, const char *what, const char **out, SrcLoc *loc)
{
    Token t;
    if (!lexer_next(lx, &t, P->err)) return false;
    if (t.kind != TOK_STRING) {
        char shown[64];
        tok_show(&t, shown, sizeof shown);
        diag_set(P->err, WEDGE_EXIT_INPUT, token_loc(lx, &t), "%.*s expects a quoted %s, got %s", (int)dir->len,
                 dir->text, what, shown);
        return false;
    }
    *out = tok_string(P, &t);
    if (loc) *loc = token_loc(lx, &t);
    return *out ? true : oom(P);
}

/* ---- transforms ---- */

static bool finite_matrix(const Mat4 *m);

/* Applies m to the CTMs that ActiveTransform selects. Long chains of large scales can
 * overflow even a double: that is an error here, so no infinity reaches the renderer. */
static bool apply_ctm(Parser *P, const Mat4 *m, bool replace, SrcLoc loc)
{
    for (int i = 0; i < 2; ++i)
        if (P->gs.active & (1 << i)) {
            Mat4 r = replace ? *m : mat4_mul(&P->gs.ctm[i], m);
            if (!finite_matrix(&r)) {
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "the transformation overflows (matrix is not finite)");
                return false;
            }
            P->gs.ctm[i] = r;
        }
    return true;
}

static XformPair ctm_pair(const Parser *P)
{
    XformPair x;
    x.m[0] = P->gs.ctm[0];
    x.m[1] = P->gs.ctm[1];
    return x;
}

static bool finite_matrix(const Mat4 *m)
{
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!isfinite(m->m[i][j])) return false;
    return true;
}

static bool set_coord_sys_to(Parser *P, const char *name, const Mat4 m[2])
{
    int i = name_map_get(&P->coord_sys_names, name);
    if (i >= 0) {
        P->coord_systems.v[i].m[0] = m[0];
        P->coord_systems.v[i].m[1] = m[1];
        return true;
    }
    NamedCoordSys c = {name, {m[0], m[1]}};
    return VEC_PUSH(P, P->coord_systems, c) &&
           (name_map_put(&P->coord_sys_names, name, P->coord_systems.n - 1) || oom(P));
}

static bool set_coord_sys(Parser *P, const char *name) { return set_coord_sys_to(P, name, P->gs.ctm); }

/* ---- statement helpers ---- */

static bool require_world(Parser *P, Lexer *lx, const Token *dir, bool world)
{
    if (P->in_world == world) return true;
    if (world)
        diag_set(P->err, WEDGE_EXIT_INPUT, token_loc(lx, dir), "%.*s is only allowed after WorldBegin",
                 (int)dir->len, dir->text);
    else
        diag_set(P->err, WEDGE_EXIT_INPUT, token_loc(lx, dir), "%.*s is not allowed after WorldBegin",
                 (int)dir->len, dir->text);
    return false;
}

static const char *find_base_dir(Parser *P, const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return arena_strdup(P->arena, ".");
    if (slash == path) return arena_strdup(P->arena, "/");
    return arena_strndup(P->arena, path, (size_t)(slash - path));
}

static const char *join_path(Parser *P, const char *base_dir, const char *name)
{
    if (name[0] == '/' || !base_dir || !strcmp(base_dir, ".")) return arena_strdup(P->arena, name);
    size_t a = strlen(base_dir), b = strlen(name);
    char *s = arena_alloc(P->arena, a + b + 2);
    if (!s) return NULL;
    memcpy(s, base_dir, a);
    s[a] = '/';
    memcpy(s + a + 1, name, b + 1);
    return s;
}

static bool parse_text(Parser *P, const char *text, size_t len, const char *path, const char *base_dir);

/* Reads a whole regular file (not a device or FIFO: those could block forever). */
static char *read_file(const char *path, size_t *len, int *err_no, FileId *id)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        *err_no = errno;
        return NULL;
    }
    if (!S_ISREG(st.st_mode)) {
        *err_no = S_ISDIR(st.st_mode) ? EISDIR : EINVAL;
        return NULL;
    }
    id->dev = st.st_dev;
    id->ino = st.st_ino;
    FILE *f = fopen(path, "rb");
    if (!f) {
        *err_no = errno;
        return NULL;
    }
    size_t cap = (size_t)st.st_size + 1, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        size_t r = fread(buf + n, 1, cap - n, f);
        n += r;
        if (n < cap) break;
        if (cap > INCLUDED_BYTES_MAX) break;
        char *nb = realloc(buf, cap * 2);
        if (!nb) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = nb;
        cap *= 2;
    }
    if (ferror(f)) {
        *err_no = errno ? errno : EIO;
        free(buf);
        fclose(f);
        return NULL;
    }
    fclose(f);
    if (!buf) {
        *err_no = ENOMEM;
        return NULL;
    }
    *len = n;
    return buf;
}

static bool note_source_file(Parser *P, const char *path, FileId id)
{
    for (int i = 0; i < P->source_ids.n; ++i)
        if (P->source_ids.v[i].dev == id.dev && P->source_ids.v[i].ino == id.ino) return true;
    return VEC_PUSH(P, P->source_ids, id) && VEC_PUSH(P, P->source_files, path);
}

/* Include/Import: parse another file in place. Errors inside it get an "included from
 * here" note at this statement. */
static const char *kind_begin(char k);

static bool include_file(Parser *P, Lexer *lx, const Token *dir, bool import)
{
    const char *name;
    SrcLoc nloc;
    if (!read_string(P, lx, dir, "file name", &name, &nloc)) return false;
    const char *path = join_path(P, P->base_dir, name);
    if (!path) return oom(P);
    if (P->include_stack.n >= INCLUDE_DEPTH_MAX) {
        diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "includes nested too deeply (limit %d)", INCLUDE_DEPTH_MAX);
        return false;
    }
    if (++P->files_included > INCLUDE_FILES_MAX) {
        diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "too many included files (limit %d)", INCLUDE_FILES_MAX);
        return false;
    }
    size_t len = 0;
    int err_no = 0;
    FileId id = {0, 0};
    char *text = read_file(path, &len, &err_no, &id);
    if (!text) {
        diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "cannot open included file \"%s\": %s", path,
                 err_no == EINVAL ? "not a regular file" : strerror(err_no));
        return false;
    }
    for (int i = 0; i < P->include_stack.n; ++i)
        if (P->include_stack.v[i].dev == id.dev && P->include_stack.v[i].ino == id.ino) {
            free(text);
            diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "include cycle: \"%s\" is already being read", path);
            return false;
        }
    P->bytes_read += len;
    if (P->bytes_read > INCLUDED_BYTES_MAX) {
        free(text);
        diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "too much included scene text (limit %zu bytes)",
                 INCLUDED_BYTES_MAX);
        return false;
    }
    if (!note_source_file(P, path, id) || !VEC_PUSH(P, P->include_stack, id)) {
        free(text);
        return false;
    }
    /* Import (pbrt-v4): the imported file starts from the current graphics state but its
     * changes to it do not leak back. */
    GState saved = P->gs;
    int saved_depth = P->stack.n, saved_floor = P->stack_floor;
    if (import) P->stack_floor = P->stack.n;
    const char *inc_base = find_base_dir(P, path);
    const char *saved_base = P->base_dir;
    bool ok = inc_base && parse_text(P, text, len, path, inc_base);
    P->base_dir = saved_base;
    free(text);
    P->include_stack.n--;
    if (!ok) {
        diag_append(P->err, "%s:%d:%d: note: included from here", lx->path, nloc.line, nloc.col);
        return false;
    }
    if (import) {
        /* An imported file must balance its own AttributeBegin/End (pbrt-v4 parses it
         * with a separate builder). */
        if (P->stack.n > saved_depth) {
            Pushed *top = &P->stack.v[P->stack.n - 1];
            diag_set(P->err, WEDGE_EXIT_INPUT, top->loc, "%s without matching %s", kind_begin(top->kind),
                     top->kind == 'A' ? "AttributeEnd" : top->kind == 'T' ? "TransformEnd" : "ObjectEnd");
            diag_append(P->err, "%s:%d:%d: note: included from here", lx->path, nloc.line, nloc.col);
            return false;
        }
        P->gs = saved;
        P->stack_floor = saved_floor;
    }
    return true;
}

static bool push_state(Parser *P, char kind, SrcLoc loc)
{
    if (P->stack.n >= ATTRIBUTE_DEPTH_MAX) {
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "attributes nested too deeply (limit %d)", ATTRIBUTE_DEPTH_MAX);
        return false;
    }
    Pushed p = {P->gs, kind, loc};
    return VEC_PUSH(P, P->stack, p);
}

static const char *kind_begin(char k)
{
    return k == 'A' ? "AttributeBegin" : k == 'T' ? "TransformBegin" : "ObjectBegin";
}

static bool pop_state(Parser *P, Lexer *lx, const Token *dir, char kind)
{
    SrcLoc loc = token_loc(lx, dir);
    const char *end = kind == 'A' ? "AttributeEnd" : kind == 'T' ? "TransformEnd" : "ObjectEnd";
    if (P->stack.n <= P->stack_floor) {
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "%s without matching %s", end, kind_begin(kind));
        return false;
    }
    Pushed *top = &P->stack.v[P->stack.n - 1];
    if (top->kind != kind) {
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "%s does not match %s at line %d:%d", end, kind_begin(top->kind),
                 top->loc.line, top->loc.col);
        return false;
    }
    if (kind == 'T') {
        /* TransformEnd restores only the transform. */
        P->gs.ctm[0] = top->gs.ctm[0];
        P->gs.ctm[1] = top->gs.ctm[1];
        P->gs.active = top->gs.active;
    } else {
        P->gs = top->gs;
    }
    P->stack.n--;
    return true;
}

/* ---- entities ---- */

static const char *const shapes_kept[] = {"trianglemesh", "bilinearmesh", "sphere", "disk", "plymesh", "loopsubdiv"};
static const char *const lights_kept[] = {"point", "spot", "distant", "infinite"};
static const char *const materials_known[] = {"diffuse", "coateddiffuse", "coatedconductor", "conductor",
                                              "dielectric", "thindielectric", "diffusetransmission", "mix",
                                              "interface", "measured", "hair", "subsurface", "", "none"};
static const char *const textures_supported[] = {"constant", "checkerboard", "imagemap", "scale", "mix"};
static const char *const textures_known[] = {"constant", "checkerboard", "imagemap", "scale", "mix",
                                             "directionmix", "bilerp", "dots", "fbm", "wrinkled",
                                             "marble", "windy", "ptex"};

static bool in_list(const char *s, const char *const *list, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!strcmp(s, list[i])) return true;
    return false;
}
#define IN_LIST(s, list) in_list((s), (list), sizeof(list) / sizeof((list)[0]))

static bool stmt_shape(Parser *P, Lexer *lx, const Token *dir)
{
    SrcLoc loc = token_loc(lx, dir);
    const char *type;
    if (!read_string(P, lx, dir, "shape type", &type, NULL)) return false;
    ShapeDesc s;
    memset(&s, 0, sizeof s);
    s.type = type;
    s.loc = loc;
    if (!parse_params(P, lx, &s.params)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (!IN_LIST(type, shapes_kept)) {
        warn_once(P, type, loc, "unsupported shape \"%s\" ignored", type);
        return true;
    }
    /* Attribute defaults are merged after the check: pbrt-v4 never reports them unused. */
    if (!params_check_known(P->scene, "shape", type, &s.params, P->err)) return false;
    if (!merge_attrs(P, &s.params, &P->gs.shape_attrs)) return false;
    s.world_from_object = ctm_pair(P);
    if (!finite_matrix(&s.world_from_object.m[0]) || !finite_matrix(&s.world_from_object.m[1])) {
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "shape transform is not finite");
        return false;
    }
    s.reverse_orientation = P->gs.reverse_orientation;
    s.material = P->gs.material_name ? -1 : P->gs.material;
    s.area_light = P->gs.area_light;
    s.object = P->current_object;
    s.base_dir = P->base_dir;
    if (P->current_object >= 0 && s.area_light >= 0) {
        warn_once(P, "arealight-in-object", loc,
                  "area lights are not supported inside ObjectBegin (as in pbrt-v4); the shape is not emissive");
        s.area_light = -1;
    }
    if (!shape_validate(P->scene, &s, P->err)) return false;
    const char *mname = P->gs.material_name;
    SrcLoc mloc = P->gs.material_loc;
    if (!VEC_PUSH(P, P->shapes, s) || !VEC_PUSH(P, P->shape_material_names, mname) ||
        !VEC_PUSH(P, P->shape_material_locs, mloc))
        return false;
    if (P->current_object >= 0) P->objects.v[P->current_object].shape_count++;
    return true;
}

static bool stmt_material(Parser *P, Lexer *lx, const Token *dir, bool named)
{
    SrcLoc loc = token_loc(lx, dir);
    MaterialDesc m;
    memset(&m, 0, sizeof m);
    m.loc = loc;
    SrcLoc nloc = loc;
    if (named) {
        if (!read_string(P, lx, dir, "material name", &m.name, &nloc)) return false;
    } else {
        if (!read_string(P, lx, dir, "material type", &m.type, NULL)) return false;
    }
    if (!parse_params(P, lx, &m.params)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (named) {
        m.type = params_string(&m.params, "type", NULL);
        if (!m.type) {
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "MakeNamedMaterial \"%s\": missing \"string type\" parameter",
                     m.name);
            return false;
        }
        if (name_map_get(&P->named_materials, m.name) >= 0) {
            diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "named material \"%s\" redefined", m.name);
            return false;
        }
    }
    if (!IN_LIST(m.type, materials_known))
        warn_once(P, m.type, loc, "unknown material type \"%s\": kept, rendered as diffuse", m.type);
    if (!params_check_known(P->scene, "material", m.type, &m.params, P->err)) return false;
    if (!merge_attrs(P, &m.params, &P->gs.material_attrs)) return false;
    if (!VEC_PUSH(P, P->materials, m)) return false;
    if (named && !name_map_put(&P->named_materials, m.name, P->materials.n - 1)) return oom(P);
    if (!named) {
        P->gs.material = P->materials.n - 1;
        P->gs.material_name = NULL;
    }
    return true;
}

static bool stmt_texture(Parser *P, Lexer *lx, const Token *dir)
{
    SrcLoc loc = token_loc(lx, dir);
    TextureDesc t;
    memset(&t, 0, sizeof t);
    t.loc = loc;
    SrcLoc nloc, vloc;
    if (!read_string(P, lx, dir, "texture name", &t.name, &nloc)) return false;
    if (!read_string(P, lx, dir, "texture type", &t.value_type, &vloc)) return false;
    if (!read_string(P, lx, dir, "texture class", &t.tex_class, NULL)) return false;
    if (!parse_params(P, lx, &t.params)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (!strcmp(t.value_type, "color")) t.value_type = "spectrum"; /* pbrt-v3 spelling */
    if (strcmp(t.value_type, "float") && strcmp(t.value_type, "spectrum")) {
        diag_set(P->err, WEDGE_EXIT_INPUT, vloc, "texture type \"%s\" unknown (expected \"float\" or \"spectrum\")",
                 t.value_type);
        return false;
    }
    NameMap *names = !strcmp(t.value_type, "float") ? &P->float_textures : &P->spectrum_textures;
    if (name_map_get(names, t.name) >= 0) {
        diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "%s texture \"%s\" redefined", t.value_type, t.name);
        return false;
    }
    if (!IN_LIST(t.tex_class, textures_supported))
        warn_once(P, t.tex_class, loc, "%s texture class \"%s\" is not supported: kept, rendered as constant",
                  IN_LIST(t.tex_class, textures_known) ? "pbrt-v4" : "unknown", t.tex_class);
    if (!params_check_known(P->scene, "texture", t.tex_class, &t.params, P->err)) return false;
    if (!merge_attrs(P, &t.params, &P->gs.texture_attrs)) return false;
    t.world_from_texture = P->gs.ctm[0];
    t.base_dir = P->base_dir;
    return VEC_PUSH(P, P->textures, t) && (name_map_put(names, t.name, P->textures.n - 1) || oom(P));
}

static bool stmt_light(Parser *P, Lexer *lx, const Token *dir)
{
    SrcLoc loc = token_loc(lx, dir);
    LightDesc l;
    memset(&l, 0, sizeof l);
    l.loc = loc;
    if (!read_string(P, lx, dir, "light type", &l.type, NULL)) return false;
    if (!parse_params(P, lx, &l.params)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (!IN_LIST(l.type, lights_kept)) {
        warn_once(P, l.type, loc, "unsupported light \"%s\" ignored", l.type);
        return true;
    }
    if (P->current_object >= 0) {
        warn_once(P, "light-in-object", loc, "LightSource inside ObjectBegin is not supported; ignored");
        return true;
    }
    if (!params_check_known(P->scene, "light", l.type, &l.params, P->err)) return false;
    if (!merge_attrs(P, &l.params, &P->gs.light_attrs)) return false;
    l.world_from_light = ctm_pair(P);
    l.base_dir = P->base_dir;
    return VEC_PUSH(P, P->lights, l);
}

static bool stmt_area_light(Parser *P, Lexer *lx, const Token *dir)
{
    SrcLoc loc = token_loc(lx, dir);
    AreaLightDesc a;
    memset(&a, 0, sizeof a);
    a.loc = loc;
    SrcLoc tloc;
    if (!read_string(P, lx, dir, "area light type", &a.type, &tloc)) return false;
    if (!parse_params(P, lx, &a.params)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (strcmp(a.type, "diffuse")) {
        diag_set(P->err, WEDGE_EXIT_INPUT, tloc, "area light type \"%s\" unknown (pbrt-v4 has only \"diffuse\")",
                 a.type);
        return false;
    }
    if (!params_check_known(P->scene, "arealight", a.type, &a.params, P->err)) return false;
    if (!VEC_PUSH(P, P->area_lights, a)) return false;
    P->gs.area_light = P->area_lights.n - 1;
    return true;
}

static bool positive_int_param(Parser *P, const ParamSet *ps, const char *name, int def, int lo, int hi, int *out)
{
    const Param *p = params_find(ps, name);
    *out = def;
    if (!p || p->type != PARAM_INTEGER) return true;
    int v = p->ints[0];
    if (v < lo || v > hi) {
        if (v < lo)
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"integer %s\" must be at least %d, got %d", name, lo, v);
        else
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"integer %s\" must be at most %d, got %d", name, hi, v);
        return false;
    }
    *out = v;
    return true;
}

static bool stmt_camera(Parser *P, Lexer *lx, const Token *dir)
{
    CameraDesc *c = &P->scene->camera;
    SrcLoc loc = token_loc(lx, dir);
    const char *type;
    SrcLoc tloc;
    if (!read_string(P, lx, dir, "camera type", &type, &tloc)) return false;
    ParamSet ps;
    if (!parse_params(P, lx, &ps)) return false;
    if (!require_world(P, lx, dir, false)) return false;
    if (strcmp(type, "perspective")) {
        diag_set(P->err, WEDGE_EXIT_INPUT, tloc, "camera \"%s\" is not supported (only \"perspective\")", type);
        return false;
    }
    if (!params_check_known(P->scene, "camera", type, &ps, P->err)) return false;
    c->type = type;
    c->params = ps;
    c->loc = loc;
    c->camera_from_world = ctm_pair(P);
    Mat4 inv[2];
    for (int i = 0; i < 2; ++i)
        if (!finite_matrix(&P->gs.ctm[i]) || !mat4_inverse(&P->gs.ctm[i], &inv[i])) {
            diag_set(P->err, WEDGE_EXIT_INPUT, loc, "camera transform is singular");
            return false;
        }
    /* pbrt-v4: namedCoordinateSystems["camera"] = Inverse(cameraFromWorld). */
    if (!set_coord_sys_to(P, "camera", inv)) return false;
    c->fov_deg = params_float(&ps, "fov", 90.0f);
    c->lens_radius = params_float(&ps, "lensradius", 0.0f);
    c->focal_distance = params_float(&ps, "focaldistance", 1e6f);
    c->shutter_open = params_float(&ps, "shutteropen", 0.0f);
    c->shutter_close = params_float(&ps, "shutterclose", 1.0f);
    c->frame_aspect = params_float(&ps, "frameaspectratio", 0.0f);
    const Param *p;
    if ((p = params_find(&ps, "fov")) && !(c->fov_deg > 0.0f && c->fov_deg < 180.0f)) {
        diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"float fov\" must be in (0, 180) degrees, got %g",
                 (double)c->fov_deg);
        return false;
    }
    if ((p = params_find(&ps, "lensradius")) && c->lens_radius < 0.0f) {
        diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"float lensradius\" must not be negative, got %g",
                 (double)c->lens_radius);
        return false;
    }
    if ((p = params_find(&ps, "focaldistance")) && !(c->focal_distance > 0.0f)) {
        diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"float focaldistance\" must be positive, got %g",
                 (double)c->focal_distance);
        return false;
    }
    if ((p = params_find(&ps, "frameaspectratio")) && !(c->frame_aspect > 0.0f)) {
        diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"float frameaspectratio\" must be positive, got %g",
                 (double)c->frame_aspect);
        return false;
    }
    if ((p = params_find(&ps, "screenwindow"))) {
        if (p->count != 4) {
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "\"float screenwindow\" needs 4 values, got %d", p->count);
            return false;
        }
        const float *w = p->floats;
        if (!(isfinite(w[0]) && isfinite(w[1]) && isfinite(w[2]) && isfinite(w[3]) && w[0] < w[1] && w[2] < w[3])) {
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc,
                     "\"float screenwindow\" needs xmin xmax ymin ymax with xmin < xmax and ymin < ymax, got [%g %g %g %g]",
                     (double)w[0], (double)w[1], (double)w[2], (double)w[3]);
            return false;
        }
        c->has_screen_window = true;
        memcpy(c->screen_window, p->floats, sizeof c->screen_window);
    }
    if (c->shutter_close < c->shutter_open) {
        /* pbrt-v4 swaps them with a warning. */
        scene_warn(P->scene, loc, "shutter close time %g < shutter open time %g: swapped", (double)c->shutter_close,
                   (double)c->shutter_open);
        float t = c->shutter_open;
        c->shutter_open = c->shutter_close;
        c->shutter_close = t;
    }
    P->camera_seen = true;
    return true;
}

static bool stmt_film(Parser *P, Lexer *lx, const Token *dir)
{
    FilmDesc *f = &P->scene->film;
    SrcLoc loc = token_loc(lx, dir);
    const char *type;
    SrcLoc tloc;
    if (!read_string(P, lx, dir, "film type", &type, &tloc)) return false;
    ParamSet ps;
    if (!parse_params(P, lx, &ps)) return false;
    if (!require_world(P, lx, dir, false)) return false;
    if (strcmp(type, "rgb") && strcmp(type, "gbuffer") && strcmp(type, "spectral")) {
        diag_set(P->err, WEDGE_EXIT_INPUT, tloc, "film \"%s\" unknown (expected \"rgb\", \"gbuffer\" or \"spectral\")",
                 type);
        return false;
    }
    if (!strcmp(type, "spectral"))
        scene_warn(P->scene, tloc, "film \"spectral\" is not supported: rendering an \"rgb\" film instead");
    if (!params_check_known(P->scene, "film", type, &ps, P->err)) return false;
    f->type = type;
    f->params = ps;
    f->loc = loc;
    if (!positive_int_param(P, &ps, "xresolution", 1280, 1, FILM_RES_MAX, &f->xres)) return false;
    if (!positive_int_param(P, &ps, "yresolution", 720, 1, FILM_RES_MAX, &f->yres)) return false;
    f->filename = params_string(&ps, "filename", "pbrt.exr");
    const Param *p = params_find(&ps, "cropwindow");
    if (p) {
        const float *c = p->floats;
        if (p->count != 4 || !(c[0] >= 0 && c[1] <= 1 && c[0] < c[1] && c[2] >= 0 && c[3] <= 1 && c[2] < c[3])) {
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc,
                     "\"float cropwindow\" needs 4 values xmin xmax ymin ymax with 0 <= min < max <= 1");
            return false;
        }
        memcpy(f->crop, c, sizeof f->crop);
    }
    if ((p = params_find(&ps, "pixelbounds"))) {
        const int32_t *b = p->ints;
        if (p->count != 4 || !(b[0] >= 0 && b[0] < b[1] && b[1] <= f->xres && b[2] >= 0 && b[2] < b[3] && b[3] <= f->yres)) {
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc,
                     "\"integer pixelbounds\" needs 4 values x0 x1 y0 y1 inside the %dx%d film with x0 < x1 and y0 < y1",
                     f->xres, f->yres);
            return false;
        }
    }
    return true;
}

static bool stmt_named_options(Parser *P, Lexer *lx, const Token *dir, const char *kind, const char **type_out,
                               ParamSet *ps_out, SrcLoc *loc_out)
{
    SrcLoc loc = token_loc(lx, dir);
    const char *type;
    if (!read_string(P, lx, dir, "type name", &type, NULL)) return false;
    ParamSet ps;
    if (!parse_params(P, lx, &ps)) return false;
    if (!require_world(P, lx, dir, false)) return false;
    if (!params_check_known(P->scene, kind, type, &ps, P->err)) return false;
    *type_out = type;
    *ps_out = ps;
    *loc_out = loc;
    return true;
}

static bool stmt_object_begin(Parser *P, Lexer *lx, const Token *dir)
{
    SrcLoc loc = token_loc(lx, dir);
    const char *name;
    SrcLoc nloc;
    if (!read_string(P, lx, dir, "object name", &name, &nloc)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (P->current_object >= 0) {
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "ObjectBegin inside the definition of object \"%s\"",
                 P->objects.v[P->current_object].name);
        return false;
    }
    if (name_map_get(&P->object_names, name) >= 0) {
        diag_set(P->err, WEDGE_EXIT_INPUT, nloc, "object \"%s\" redefined", name);
        return false;
    }
    if (!push_state(P, 'O', loc)) return false;
    ObjectDesc o = {name, P->shapes.n, 0, loc};
    if (!VEC_PUSH(P, P->objects, o)) return false;
    if (!name_map_put(&P->object_names, name, P->objects.n - 1)) return oom(P);
    P->current_object = P->objects.n - 1;
    return true;
}

static bool stmt_object_instance(Parser *P, Lexer *lx, const Token *dir)
{
    SrcLoc loc = token_loc(lx, dir);
    const char *name;
    if (!read_string(P, lx, dir, "object name", &name, NULL)) return false;
    if (!require_world(P, lx, dir, true)) return false;
    if (P->current_object >= 0) {
        diag_set(P->err, WEDGE_EXIT_INPUT, loc, "ObjectInstance inside the definition of object \"%s\"",
                 P->objects.v[P->current_object].name);
        return false;
    }
    InstanceDesc in;
    memset(&in, 0, sizeof in);
    in.object = -1;
    in.world_from_instance = ctm_pair(P);
    in.loc = loc;
    return VEC_PUSH(P, P->instances, in) && VEC_PUSH(P, P->instance_names, name);
}

static bool stmt_active_transform(Parser *P, Lexer *lx, const Token *dir)
{
    Token t;
    if (!lexer_next(lx, &t, P->err)) return false;
    if (tok_is(&t, "StartTime")) P->gs.active = ACTIVE_START;
    else if (tok_is(&t, "EndTime")) P->gs.active = ACTIVE_END;
    else if (tok_is(&t, "All")) P->gs.active = ACTIVE_ALL;
    else {
        char shown[64];
        tok_show(&t, shown, sizeof shown);
        diag_set(P->err, WEDGE_EXIT_INPUT, token_loc(lx, &t),
                 "ActiveTransform expects StartTime, EndTime or All, got %s", shown);
        (void)dir;
        return false;
    }
    return true;
}

static bool stmt_attribute(Parser *P, Lexer *lx, const Token *dir)
{
    const char *target;
    SrcLoc tloc;
    if (!read_string(P, lx, dir, "attribute target", &target, &tloc)) return false;
    ParamSet ps;
    if (!parse_params(P, lx, &ps)) return false;
    ParamSet *dst;
    if (!strcmp(target, "shape")) dst = &P->gs.shape_attrs;
    else if (!strcmp(target, "light")) dst = &P->gs.light_attrs;
    else if (!strcmp(target, "material")) dst = &P->gs.material_attrs;
    else if (!strcmp(target, "medium")) dst = &P->gs.medium_attrs;
    else if (!strcmp(target, "texture")) dst = &P->gs.texture_attrs;
    else {
        diag_set(P->err, WEDGE_EXIT_INPUT, tloc,
                 "attribute target \"%s\" unknown (expected shape, light, material, medium or texture)", target);
        return false;
    }
    /* pbrt-v4 appends each Attribute statement's parameters to the list and lookups take
     * the first match, so an earlier value of the same name wins. */
    ParamSet merged = *dst;
    if (!merge_attrs(P, &merged, &ps)) return false;
    /* Each new name copies the list: a cap keeps that linear in the input. */
    if (merged.count > ATTRIBUTE_PARAMS_MAX) {
        diag_set(P->err, WEDGE_EXIT_INPUT, tloc, "too many Attribute parameters for \"%s\" (limit %d)", target,
                 ATTRIBUTE_PARAMS_MAX);
        return false;
    }
    *dst = merged;
    return true;
}

static bool stmt_ignored_with_params(Parser *P, Lexer *lx, const Token *dir, int strings, const char *kind,
                                     const char *what)
{
    SrcLoc loc = token_loc(lx, dir);
    for (int i = 0; i < strings; ++i) {
        const char *s;
        if (!read_string(P, lx, dir, "name", &s, NULL)) return false;
    }
    ParamSet ps;
    if (!parse_params(P, lx, &ps)) return false;
    warn_once(P, kind, loc, "%s", what);
    return true;
}

/* ---- the statement loop ---- */

static bool statement(Parser *P, Lexer *lx, const Token *t)
{
    SrcLoc loc = token_loc(lx, t);
    double v[16];
    const char *s;
    switch (t->text[0]) {
    case 'A':
        if (tok_is(t, "AttributeBegin")) return require_world(P, lx, t, true) && push_state(P, 'A', loc);
        if (tok_is(t, "AttributeEnd")) return require_world(P, lx, t, true) && pop_state(P, lx, t, 'A');
        if (tok_is(t, "Attribute")) return stmt_attribute(P, lx, t);
        if (tok_is(t, "ActiveTransform")) return stmt_active_transform(P, lx, t);
        if (tok_is(t, "AreaLightSource")) return stmt_area_light(P, lx, t);
        if (tok_is(t, "Accelerator"))
            return stmt_ignored_with_params(P, lx, t, 1, "Accelerator",
                                            "Accelerator ignored: wedge always builds an Embree BVH");
        break;
    case 'C':
        if (tok_is(t, "Camera")) return stmt_camera(P, lx, t);
        if (tok_is(t, "ConcatTransform")) {
            if (!read_numbers(P, lx, t, 16, v)) return false;
            Mat4 m;
            for (int i = 0; i < 16; ++i) m.m[i % 4][i / 4] = v[i]; /* column-major in the file */
            return apply_ctm(P, &m, false, loc);
        }
        if (tok_is(t, "CoordinateSystem")) {
            if (!read_string(P, lx, t, "coordinate system name", &s, NULL)) return false;
            return set_coord_sys(P, s);
        }
        if (tok_is(t, "CoordSysTransform")) {
            SrcLoc nloc;
            if (!read_string(P, lx, t, "coordinate system name", &s, &nloc)) return false;
            int cs = name_map_get(&P->coord_sys_names, s);
            if (cs >= 0) {
                P->gs.ctm[0] = P->coord_systems.v[cs].m[0];
                P->gs.ctm[1] = P->coord_systems.v[cs].m[1];
                return true;
            }
            /* pbrt-v4 warns and leaves the CTM unchanged. */
            scene_warn(P->scene, nloc, "coordinate system \"%s\" not defined; CoordSysTransform ignored", s);
            return true;
        }
        if (tok_is(t, "ColorSpace")) {
            SrcLoc nloc;
            if (!read_string(P, lx, t, "colour space name", &s, &nloc)) return false;
            if (strcmp(s, "srgb"))
                warn_once(P, "colorspace", nloc, "colour space \"%s\" not supported: rgb values are read as sRGB", s);
            P->gs.color_space = s;
            P->scene->color_space = s;
            return true;
        }
        break;
    case 'F':
        if (tok_is(t, "Film")) return stmt_film(P, lx, t);
        break;
    case 'I':
        if (tok_is(t, "Identity")) {
            Mat4 id = mat4_identity();
            return apply_ctm(P, &id, true, loc);
        }
        if (tok_is(t, "Include")) return include_file(P, lx, t, false);
        if (tok_is(t, "Import")) return include_file(P, lx, t, true);
        if (tok_is(t, "Integrator")) {
            IntegratorDesc *d = &P->scene->integrator;
            if (!stmt_named_options(P, lx, t, "integrator", &d->type, &d->params, &d->loc)) return false;
            return positive_int_param(P, &d->params, "maxdepth", 5, 0, INT_MAX, &d->max_depth);
        }
        break;
    case 'L':
        if (tok_is(t, "LookAt")) {
            if (!read_numbers(P, lx, t, 9, v)) return false;
            Mat4 m;
            if (!mat4_lookat(v, v + 3, v + 6, &m)) {
                diag_set(P->err, WEDGE_EXIT_INPUT, loc,
                         "LookAt: the up vector is parallel to the view direction (or eye equals look)");
                return false;
            }
            return apply_ctm(P, &m, false, loc);
        }
        if (tok_is(t, "LightSource")) return stmt_light(P, lx, t);
        break;
    case 'M':
        if (tok_is(t, "MakeNamedMaterial")) return stmt_material(P, lx, t, true);
        if (tok_is(t, "Material")) return stmt_material(P, lx, t, false);
        if (tok_is(t, "MakeNamedMedium"))
            return stmt_ignored_with_params(P, lx, t, 1, "media",
                                            "participating media are not supported: MakeNamedMedium and "
                                            "MediumInterface ignored");
        if (tok_is(t, "MediumInterface")) {
            /* One or two names, not a parameter list. */
            if (!read_string(P, lx, t, "medium name", &s, NULL)) return false;
            Token n;
            if (!lexer_peek(lx, &n, P->err)) return false;
            if (n.kind == TOK_STRING) lexer_next(lx, &n, P->err);
            warn_once(P, "media", loc,
                      "participating media are not supported: MakeNamedMedium and MediumInterface ignored");
            return true;
        }
        break;
    case 'N':
        if (tok_is(t, "NamedMaterial")) {
            SrcLoc nloc;
            if (!read_string(P, lx, t, "material name", &s, &nloc)) return false;
            if (!require_world(P, lx, t, true)) return false;
            P->gs.material_name = s;
            P->gs.material_loc = nloc;
            return true;
        }
        break;
    case 'O':
        if (tok_is(t, "ObjectBegin")) return stmt_object_begin(P, lx, t);
        if (tok_is(t, "ObjectEnd")) {
            if (P->current_object < 0) {
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "ObjectEnd without matching ObjectBegin");
                return false;
            }
            if (!pop_state(P, lx, t, 'O')) return false;
            P->current_object = -1;
            return true;
        }
        if (tok_is(t, "ObjectInstance")) return stmt_object_instance(P, lx, t);
        if (tok_is(t, "Option")) {
            ParamSet ps;
            if (!parse_params(P, lx, &ps)) return false;
            if (!require_world(P, lx, t, false)) return false;
            if (!params_check_known(P->scene, "option", NULL, &ps, P->err)) return false;
            ParamSet *o = &P->scene->options;
            Param *items = arena_alloc(P->arena, (size_t)(o->count + ps.count + 1) * sizeof *items);
            if (!items) return oom(P);
            if (o->count) memcpy(items, o->items, (size_t)o->count * sizeof *items);
            if (ps.count) memcpy(items + o->count, ps.items, (size_t)ps.count * sizeof *items);
            o->items = items;
            o->count += ps.count;
            return true;
        }
        break;
    case 'P':
        if (tok_is(t, "PixelFilter")) {
            FilterDesc *f = &P->scene->filter;
            return stmt_named_options(P, lx, t, "filter", &f->type, &f->params, &f->loc);
        }
        break;
    case 'R':
        if (tok_is(t, "Rotate")) {
            if (!read_numbers(P, lx, t, 4, v)) return false;
            /* pbrt-v4 normalises the axis and gets NaN for a zero one; we rotate by nothing,
             * and say so */
            if (!(v[1] * v[1] + v[2] * v[2] + v[3] * v[3] > 0.0) && v[0] != 0.0)
                scene_warn(P->scene, loc, "Rotate %g about the zero axis (0, 0, 0) has no direction: ignored", v[0]);
            Mat4 m = mat4_rotate(v[0], v[1], v[2], v[3]);
            return apply_ctm(P, &m, false, loc);
        }
        if (tok_is(t, "ReverseOrientation")) {
            P->gs.reverse_orientation = !P->gs.reverse_orientation;
            return true;
        }
        break;
    case 'S':
        if (tok_is(t, "Shape")) return stmt_shape(P, lx, t);
        if (tok_is(t, "Scale")) {
            if (!read_numbers(P, lx, t, 3, v)) return false;
            Mat4 m = mat4_scale(v[0], v[1], v[2]);
            return apply_ctm(P, &m, false, loc);
        }
        if (tok_is(t, "Sampler")) {
            SamplerDesc *d = &P->scene->sampler;
            if (!stmt_named_options(P, lx, t, "sampler", &d->type, &d->params, &d->loc)) return false;
            if (!strcmp(d->type, "stratified")) {
                /* pbrt-v4: spp = xsamples * ysamples (default 4 x 4). */
                int xs, ys;
                if (!positive_int_param(P, &d->params, "xsamples", 4, 1, 1 << 12, &xs)) return false;
                if (!positive_int_param(P, &d->params, "ysamples", 4, 1, 1 << 12, &ys)) return false;
                d->spp = xs * ys; /* at most 2^24, SCENE_SPP_MAX */
                return true;
            }
            /* the same bound as wedge render --spp: a scene cannot ask for unbounded work */
            return positive_int_param(P, &d->params, "pixelsamples", 16, 1, SCENE_SPP_MAX, &d->spp);
        }
        break;
    case 'T':
        if (tok_is(t, "Translate")) {
            if (!read_numbers(P, lx, t, 3, v)) return false;
            Mat4 m = mat4_translate(v[0], v[1], v[2]);
            return apply_ctm(P, &m, false, loc);
        }
        if (tok_is(t, "Transform")) {
            if (!read_numbers(P, lx, t, 16, v)) return false;
            Mat4 m;
            for (int i = 0; i < 16; ++i) m.m[i % 4][i / 4] = v[i];
            return apply_ctm(P, &m, true, loc);
        }
        if (tok_is(t, "Texture")) return stmt_texture(P, lx, t);
        if (tok_is(t, "TransformTimes")) {
            if (!read_numbers(P, lx, t, 2, v)) return false;
            if (!(v[1] >= v[0])) {
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "TransformTimes end time %g is before start time %g", v[1],
                         v[0]);
                return false;
            }
            P->scene->transform_start_time = (float)v[0];
            P->scene->transform_end_time = (float)v[1];
            return true;
        }
        if (tok_is(t, "TransformBegin")) {
            warn_once(P, "TransformBegin", loc,
                      "TransformBegin/TransformEnd are deprecated in pbrt-v4; use AttributeBegin/AttributeEnd");
            return push_state(P, 'T', loc);
        }
        if (tok_is(t, "TransformEnd")) return pop_state(P, lx, t, 'T');
        break;
    case 'W':
        if (tok_is(t, "WorldBegin")) {
            if (P->in_world) {
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "WorldBegin given twice");
                return false;
            }
            P->in_world = true;
            Mat4 id = mat4_identity();
            P->gs.ctm[0] = P->gs.ctm[1] = id;
            P->gs.active = ACTIVE_ALL;
            return set_coord_sys(P, "world");
        }
        if (tok_is(t, "WorldEnd")) {
            warn_once(P, "WorldEnd", loc, "WorldEnd is a pbrt-v3 statement; ignored");
            return true;
        }
        break;
    default:
        break;
    }
    char shown[64];
    tok_show(t, shown, sizeof shown);
    diag_set(P->err, WEDGE_EXIT_INPUT, loc, "unknown directive %s", shown);
    return false;
}

static bool parse_text(Parser *P, const char *text, size_t len, const char *path, const char *base_dir)
{
    P->base_dir = base_dir;
    Lexer lx;
    lexer_init(&lx, text, len, path);
    for (;;) {
        Token t;
        if (!lexer_next(&lx, &t, P->err)) return false;
        if (t.kind == TOK_EOF) {
            P->eof_loc = token_loc(&lx, &t);
            return true;
        }
        if (t.kind != TOK_WORD) {
            SrcLoc loc = token_loc(&lx, &t);
            if (t.kind == TOK_LBRACKET)
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "unexpected '[' (expected a directive)");
            else if (t.kind == TOK_RBRACKET)
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "unbalanced ']': no matching '['");
            else {
                char shown[64];
                tok_show(&t, shown, sizeof shown);
                diag_set(P->err, WEDGE_EXIT_INPUT, loc, "expected a directive, got the string %s", shown);
            }
            return false;
        }
        if (!statement(P, &lx, &t)) return false;
    }
}

/* ---- finishing: name resolution, copying into the arena ---- */

static bool texture_defined(const Parser *P, const char *name)
{
    return name_map_get(&P->float_textures, name) >= 0 || name_map_get(&P->spectrum_textures, name) >= 0;
}

/* pbrt-v4 resolves texture references after parsing (forward references are fine) and
 * stops on an undefined one. */
static bool check_texture_refs(Parser *P, const ParamSet *ps)
{
    for (int i = 0; i < ps->count; ++i) {
        const Param *p = &ps->items[i];
        if (p->type == PARAM_TEXTURE && !texture_defined(P, p->strings[0])) {
            diag_set(P->err, WEDGE_EXIT_INPUT, p->loc, "texture \"%s\" not defined", p->strings[0]);
            return false;
        }
    }
    return true;
}

static bool named_material_defined(const Parser *P, const char *name)
{
    return name_map_get(&P->named_materials, name) >= 0;
}

static bool resolve_names(Parser *P)
{
    for (int i = 0; i < P->materials.n; ++i) {
        if (!check_texture_refs(P, &P->materials.v[i].params)) return false;
        if (strcmp(P->materials.v[i].type, "mix")) continue;
        const Param *mats = params_find(&P->materials.v[i].params, "materials");
        for (int k = 0; mats && mats->type == PARAM_STRING && k < mats->count; ++k)
            if (!named_material_defined(P, mats->strings[k])) {
                diag_set(P->err, WEDGE_EXIT_INPUT, mats->loc, "named material \"%s\" not defined", mats->strings[k]);
                return false;
            }
    }
    for (int i = 0; i < P->textures.n; ++i)
        if (!check_texture_refs(P, &P->textures.v[i].params)) return false;
    for (int i = 0; i < P->shapes.n; ++i)
        if (!check_texture_refs(P, &P->shapes.v[i].params)) return false;
    for (int i = 0; i < P->shapes.n; ++i) {
        const char *name = P->shape_material_names.v[i];
        if (!name) continue;
        int found = name_map_get(&P->named_materials, name);
        if (found < 0) {
            diag_set(P->err, WEDGE_EXIT_INPUT, P->shape_material_locs.v[i], "named material \"%s\" not defined",
                     name);
            return false;
        }
        P->shapes.v[i].material = found;
    }
    for (int i = 0; i < P->instances.n; ++i) {
        const char *name = P->instance_names.v[i];
        P->instances.v[i].object = name_map_get(&P->object_names, name);
        if (P->instances.v[i].object < 0) {
            diag_set(P->err, WEDGE_EXIT_INPUT, P->instances.v[i].loc, "object \"%s\" not defined", name);
            return false;
        }
    }
    return true;
}

#define COPY_OUT(P, vec, dst, cnt)                                                       \
    do {                                                                                 \
        (cnt) = (vec).n;                                                                 \
        (dst) = NULL;                                                                    \
        if ((vec).n) {                                                                   \
            (dst) = arena_alloc((P)->arena, (size_t)(vec).n * sizeof *(vec).v);          \
            if (!(dst)) return oom(P);                                                   \
            memcpy((void *)(dst), (vec).v, (size_t)(vec).n * sizeof *(vec).v);           \
        }                                                                                \
    } while (0)

static bool finish(Parser *P)
{
    if (!P->in_world) {
        /* pbrt-v4: "End of files before WorldBegin" is an error. */
        diag_set(P->err, WEDGE_EXIT_INPUT, P->eof_loc, "end of file before WorldBegin");
        return false;
    }
    if (P->stack.n > 0) {
        Pushed *top = &P->stack.v[P->stack.n - 1];
        diag_set(P->err, WEDGE_EXIT_INPUT, top->loc, "%s without matching %s", kind_begin(top->kind),
                 top->kind == 'A' ? "AttributeEnd" : top->kind == 'T' ? "TransformEnd" : "ObjectEnd");
        return false;
    }
    if (!resolve_names(P)) return false;
    SceneDesc *s = P->scene;
    COPY_OUT(P, P->materials, s->materials, s->material_count);
    COPY_OUT(P, P->textures, s->textures, s->texture_count);
    COPY_OUT(P, P->area_lights, s->area_lights, s->area_light_count);
    COPY_OUT(P, P->lights, s->lights, s->light_count);
    COPY_OUT(P, P->shapes, s->shapes, s->shape_count);
    COPY_OUT(P, P->objects, s->objects, s->object_count);
    COPY_OUT(P, P->instances, s->instances, s->instance_count);
    COPY_OUT(P, P->source_files, s->source_files, s->source_file_count);
    return true;
}

static void parser_free(Parser *P)
{
    free(P->materials.v);
    free(P->textures.v);
    free(P->area_lights.v);
    free(P->lights.v);
    free(P->shapes.v);
    free(P->objects.v);
    free(P->instances.v);
    free(P->instance_names.v);
    free(P->shape_material_names.v);
    free(P->shape_material_locs.v);
    free(P->coord_systems.v);
    free(P->stack.v);
    free(P->include_stack.v);
    free(P->source_files.v);
    free(P->source_ids.v);
    name_map_free(&P->warned_kinds);
    name_map_free(&P->named_materials);
    name_map_free(&P->float_textures);
    name_map_free(&P->spectrum_textures);
    name_map_free(&P->object_names);
    name_map_free(&P->coord_sys_names);
    free(P->fscratch.v);
    free(P->iscratch.v);
    free(P->sscratch.v);
    free(P->bscratch.v);
    free(P->pscratch.v);
}

/* pbrt-v4 defaults for everything the file may leave out. */
static void scene_defaults(SceneDesc *s)
{
    Mat4 id = mat4_identity();
    s->camera.type = "perspective";
    s->camera.camera_from_world.m[0] = s->camera.camera_from_world.m[1] = id;
    s->camera.fov_deg = 90.0f;
    s->camera.focal_distance = 1e6f;
    s->camera.shutter_open = 0.0f;
    s->camera.shutter_close = 1.0f;
    s->film.type = "rgb";
    s->film.xres = 1280;
    s->film.yres = 720;
    s->film.filename = "pbrt.exr";
    s->film.crop[0] = 0.0f;
    s->film.crop[1] = 1.0f;
    s->film.crop[2] = 0.0f;
    s->film.crop[3] = 1.0f;
    s->sampler.type = "zsobol";
    s->sampler.spp = 16;
    s->integrator.type = "volpath";
    s->integrator.max_depth = 5;
    s->filter.type = "gaussian";
    s->color_space = "srgb";
    s->transform_start_time = 0.0f;
    s->transform_end_time = 1.0f;
}

static bool parse_main(const char *text, size_t len, const char *display_path, const char *base_dir,
                       FileId *main_id, SceneDesc *scene, Diag *err)
{
    Parser P;
    memset(&P, 0, sizeof P);
    P.scene = scene;
    P.err = err;
    P.arena = &scene->arena;
    P.current_object = -1;
    P.gs.ctm[0] = P.gs.ctm[1] = mat4_identity();
    P.gs.active = ACTIVE_ALL;
    P.gs.material = -1;
    P.gs.area_light = -1;
    P.gs.color_space = "srgb";
    scene->path = arena_strdup(&scene->arena, display_path ? display_path : "<string>");
    bool ok = scene->path != NULL;
    const char *path = scene->path;
    if (ok && main_id) {
        ok = note_source_file(&P, path, *main_id) && VEC_PUSH(&P, P.include_stack, *main_id);
    }
    /* Locations in the main text use display_path; Include and data files resolve against
     * base_dir (the scene file's directory, or the caller's choice for in-memory text). */
    const char *dir = base_dir ? arena_strdup(&scene->arena, base_dir) : find_base_dir(&P, path);
    if (ok && !dir) ok = oom(&P);
    if (ok) ok = parse_text(&P, text, len, path, dir) && finish(&P);
    parser_free(&P);
    return ok;
}

bool scene_parse_string(const char *text, size_t len, const char *display_path, const char *base_dir,
                        SceneDesc *scene, Diag *err)
{
    memset(scene, 0, sizeof *scene);
    scene_defaults(scene);
    err->exit_code = 0;
    err->message[0] = '\0';
    if (!parse_main(text, len, display_path, base_dir ? base_dir : ".", NULL, scene, err)) {
        scene_desc_free(scene);
        return false;
    }
    scene_analyze_effects(scene);
    return true;
}

bool scene_parse_file(const char *path, SceneDesc *scene, Diag *err)
{
    memset(scene, 0, sizeof *scene);
    err->exit_code = 0;
    err->message[0] = '\0';
    size_t len = 0;
    int err_no = 0;
    FileId id = {0, 0};
    char *text = read_file(path, &len, &err_no, &id);
    if (!text) {
        diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){path, 0, 0}, "cannot open scene file: %s",
                 err_no == EINVAL ? "not a regular file" : strerror(err_no));
        return false;
    }
    scene_defaults(scene);
    bool ok = parse_main(text, len, path, NULL, &id, scene, err);
    free(text);
    if (!ok) {
        scene_desc_free(scene);
        return false;
    }
    scene_analyze_effects(scene);
    return true;
}
