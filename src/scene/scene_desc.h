/* The validated, in-memory description of a pbrt-v4 scene: what the parser produces and
 * everything downstream (geometry, render, app) reads. It knows nothing of Embree.
 * All memory belongs to SceneDesc.arena; scene_desc_free releases it. */
#ifndef WEDGE_SCENE_SCENE_DESC_H
#define WEDGE_SCENE_SCENE_DESC_H

#include <stdbool.h>
#include <stdint.h>

#include "scene/effects.h"
#include "core/arena.h"
#include "core/diag.h"
#include "core/transform.h"

/* ---- parameter lists ("float fov" [ 45 ]) ---- */

typedef enum {
    PARAM_INTEGER,
    PARAM_FLOAT,
    PARAM_POINT2,
    PARAM_VECTOR2,
    PARAM_POINT3,   /* also "point" */
    PARAM_VECTOR3,  /* also "vector" */
    PARAM_NORMAL3,  /* also "normal" */
    PARAM_RGB,      /* also "color" (pbrt-v3) */
    PARAM_SPECTRUM, /* floats: (lambda_nm, value) pairs or one constant; or strings: a named spectrum / file */
    PARAM_BLACKBODY,/* floats: one temperature in Kelvin */
    PARAM_BOOL,
    PARAM_STRING,
    PARAM_TEXTURE,  /* strings: one texture name */
} ParamType;

typedef struct {
    ParamType type;
    const char *name;
    int count;             /* number of scalar values (floats, ints, strings or bools) */
    const float *floats;   /* PARAM_FLOAT, POINT2/3, VECTOR2/3, NORMAL3, RGB, SPECTRUM (numeric), BLACKBODY */
    const int32_t *ints;   /* PARAM_INTEGER */
    const char *const *strings; /* PARAM_STRING/TEXTURE/SPECTRUM(named) */
    const bool *bools;     /* PARAM_BOOL */
    SrcLoc loc;            /* location of the parameter's type-and-name string */
    bool used;             /* set by the getters; unused parameters become warnings */
} Param;

typedef struct {
    Param *items;
    int count;
} ParamSet;

/* Lookups mark the parameter used. They return the default when the parameter is absent.
 * Type mismatches are caught by the parser, not here. */
const Param *params_find(const ParamSet *ps, const char *name);
float params_float(const ParamSet *ps, const char *name, float def);
int params_int(const ParamSet *ps, const char *name, int def);
bool params_bool(const ParamSet *ps, const char *name, bool def);
const char *params_string(const ParamSet *ps, const char *name, const char *def);
/* Array access: returns the values and their count (scalars, not tuples), or NULL/0. */
const float *params_floats(const ParamSet *ps, const char *name, int *count);
const int32_t *params_ints(const ParamSet *ps, const char *name, int *count);
/* Any colour-valued parameter (rgb, spectrum, blackbody) as linear Rec.709 rgb.
 * Returns false (rgb untouched) when absent. "texture" parameters are not colours. */
bool params_rgb(const ParamSet *ps, const char *name, float rgb[3]);
/* The texture name of a "texture NAME" parameter, or NULL. */
const char *params_texture(const ParamSet *ps, const char *name);
/* A light's emission ("L", "I") as rgb with pbrt-v4's photometric normalisation: rgb values
 * are returned as given; spectrum and blackbody emissions are divided by their luminance
 * (pbrt-v4 divides the light's scale by SpectrumToPhotometric), so that only "scale" /
 * "power" set their brightness. Returns false when absent. */
bool params_illuminant_rgb(const ParamSet *ps, const char *name, float rgb[3]);
/* Number of parameters no getter has asked for yet. */
int params_count_unused(const ParamSet *ps);

/* ---- scene entities ---- */

/* A transform that may change over the shutter: [0] at start time, [1] at end time. */
typedef struct {
    Mat4 m[2];
} XformPair;
static inline bool xform_pair_animated(const XformPair *x) { return !mat4_equal(&x->m[0], &x->m[1]); }

typedef struct {
    const char *type;  /* "perspective" (others are rejected with an error naming the type) */
    ParamSet params;
    XformPair camera_from_world;
    float fov_deg;          /* pbrt-v4 default 90; applies to the shorter image axis */
    float lens_radius;      /* world units; 0 = pinhole */
    float focal_distance;   /* world units; pbrt-v4 default 1e6 */
    float shutter_open, shutter_close; /* defaults 0 and 1 */
    float frame_aspect;     /* 0 = from the film */
    bool has_screen_window;
    float screen_window[4]; /* xmin xmax ymin ymax */
    SrcLoc loc;
} CameraDesc;

typedef struct {
    const char *type;       /* "rgb" or "gbuffer" ("spectral" accepted with a warning) */
    ParamSet params;
    int xres, yres;         /* pbrt-v4 defaults 1280 x 720 */
    const char *filename;   /* default "pbrt.exr" */
    float crop[4];          /* xmin xmax ymin ymax in [0,1]; default 0 1 0 1 */
    SrcLoc loc;
} FilmDesc;

typedef struct {
    const char *type;       /* any pbrt-v4 sampler name; default "zsobol" */
    ParamSet params;
    int spp;                /* "pixelsamples", default 16 */
    SrcLoc loc;
} SamplerDesc;

typedef struct {
    const char *type;       /* any name; default "volpath" */
    ParamSet params;
    int max_depth;          /* default 5 */
    SrcLoc loc;
} IntegratorDesc;

typedef struct {
    const char *name;       /* NULL for an anonymous Material */
    const char *type;       /* "diffuse", "coateddiffuse", "conductor", "dielectric", "mix", ... */
    ParamSet params;
    SrcLoc loc;
} MaterialDesc;

typedef struct {
    const char *name;
    const char *value_type; /* "float" or "spectrum" */
    const char *tex_class;  /* "constant", "checkerboard", "imagemap", "scale", "mix", ... */
    ParamSet params;
    Mat4 world_from_texture;
    const char *base_dir;   /* directory of the file that declared it (for imagemap filenames) */
    SrcLoc loc;
} TextureDesc;

typedef struct {
    const char *type;       /* "diffuse" */
    ParamSet params;        /* L, scale, twosided */
    SrcLoc loc;
} AreaLightDesc;

typedef struct {
    const char *type;       /* "point", "spot", "distant", "infinite" (others: warning, skipped) */
    ParamSet params;
    XformPair world_from_light;
    const char *base_dir;
    SrcLoc loc;
} LightDesc;

typedef struct {
    const char *type;       /* "trianglemesh", "bilinearmesh", "sphere", "disk", "plymesh", "loopsubdiv" */
    ParamSet params;        /* validated: counts and index ranges checked by the parser */
    XformPair world_from_object; /* for shapes inside ObjectBegin: instance-from-object */
    bool reverse_orientation;
    int material;           /* index into materials; -1 = pbrt-v4 default (diffuse 0.5) */
    int area_light;         /* index into area_lights, or -1 */
    int object;             /* index into objects when defined inside ObjectBegin, else -1 */
    const char *base_dir;   /* directory of the file that declared it (for plymesh filenames) */
    SrcLoc loc;
} ShapeDesc;

typedef struct {
    const char *name;
    int first_shape, shape_count; /* shapes[first_shape .. first_shape + shape_count) */
    SrcLoc loc;
} ObjectDesc;

typedef struct {
    int object;                   /* index into objects */
    XformPair world_from_instance;
    SrcLoc loc;
} InstanceDesc;


typedef struct {
    const char *type;       /* pixel filter name ("gaussian" default); kept, renderer decides */
    ParamSet params;
    SrcLoc loc;
} FilterDesc;

/* The most samples per pixel a scene may ask for (wedge render --spp has the same bound). */
#define SCENE_SPP_MAX 16777216

typedef struct {
    Arena arena;
    const char *path;       /* the scene file ("<default>" for the embedded scene) */
    CameraDesc camera;
    FilmDesc film;
    SamplerDesc sampler;
    IntegratorDesc integrator;
    const char *color_space;
    FilterDesc filter;
    ParamSet options;        /* every "Option" statement's parameter, in order */
    float transform_start_time, transform_end_time; /* TransformTimes; default 0 and 1 */

    MaterialDesc *materials; int material_count;
    TextureDesc *textures;   int texture_count;
    AreaLightDesc *area_lights; int area_light_count;
    LightDesc *lights;       int light_count;
    ShapeDesc *shapes;       int shape_count;
    ObjectDesc *objects;     int object_count;
    InstanceDesc *instances; int instance_count;

    const char **warnings;   int warning_count; /* full "PATH:LINE:COL: warning: ..." lines */
    /* Every scene text file read (the main file and each Include/Import, as opened), in
     * reading order, each once; data files (PLY, images) are not listed. Empty for
     * scene_parse_string's own text. Used to key reference caches. */
    const char **source_files; int source_file_count;
    EffectMask effects;      /* filled by scene_analyze_effects (scene/effects.h) */
} SceneDesc;

/* Parses a scene file (and its includes). On failure returns false, fills err (exit code 2)
 * and leaves *scene empty. Never exits, never crashes on any input. */
bool scene_parse_file(const char *path, SceneDesc *scene, Diag *err);
/* Parses scene text held in memory; display_path names it in messages, base_dir resolves
 * Include/Import and data files (NULL = current directory). */
bool scene_parse_string(const char *text, size_t len, const char *display_path,
                        const char *base_dir, SceneDesc *scene, Diag *err);
void scene_desc_free(SceneDesc *scene);

/* Decides which distribution effects the scene has (DESIGN.md section 2). */
void scene_analyze_effects(SceneDesc *scene);
/* Adds a formatted warning line to the scene (deduplicated: one per distinct text). */
void scene_warn(SceneDesc *scene, SrcLoc loc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
