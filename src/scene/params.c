/* ParamSet getters: how shapes, materials, lights and textures read their parameters.
 * Every successful lookup marks the parameter used; the parser reports the ones nobody
 * asked for (see params_report_unused in parser.c and docs/scene-format.md). */
#include <string.h>

#include "scene/scene_desc.h"
#include "scene/spectrum.h"

/* pbrt-v4 looks parameters up by name; a later duplicate of the same name is rejected by
 * the parser, so the first match is the only one. */
static Param *find_any(const ParamSet *ps, const char *name)
{
    if (!ps || !name) return NULL;
    for (int i = 0; i < ps->count; ++i)
        if (!strcmp(ps->items[i].name, name)) return &ps->items[i];
    return NULL;
}

static bool is_float_typed(ParamType t)
{
    switch (t) {
    case PARAM_FLOAT: case PARAM_POINT2: case PARAM_VECTOR2: case PARAM_POINT3:
    case PARAM_VECTOR3: case PARAM_NORMAL3: case PARAM_RGB: case PARAM_BLACKBODY:
        return true;
    default:
        return false;
    }
}

const Param *params_find(const ParamSet *ps, const char *name)
{
    Param *p = find_any(ps, name);
    if (p) p->used = true;
    return p;
}

float params_float(const ParamSet *ps, const char *name, float def)
{
    Param *p = find_any(ps, name);
    if (!p || p->type != PARAM_FLOAT || p->count < 1) return def;
    p->used = true;
    return p->floats[0];
}

int params_int(const ParamSet *ps, const char *name, int def)
{
    Param *p = find_any(ps, name);
    if (!p || p->type != PARAM_INTEGER || p->count < 1) return def;
    p->used = true;
    return p->ints[0];
}

bool params_bool(const ParamSet *ps, const char *name, bool def)
{
    Param *p = find_any(ps, name);
    if (!p || p->type != PARAM_BOOL || p->count < 1) return def;
    p->used = true;
    return p->bools[0];
}

const char *params_string(const ParamSet *ps, const char *name, const char *def)
{
    Param *p = find_any(ps, name);
    if (!p || p->type != PARAM_STRING || p->count < 1) return def;
    p->used = true;
    return p->strings[0];
}

const float *params_floats(const ParamSet *ps, const char *name, int *count)
{
    Param *p = find_any(ps, name);
    if (!p || !p->floats || !(is_float_typed(p->type) || p->type == PARAM_SPECTRUM)) {
        if (count) *count = 0;
        return NULL;
    }
    p->used = true;
    if (count) *count = p->count;
    return p->floats;
}

const int32_t *params_ints(const ParamSet *ps, const char *name, int *count)
{
    Param *p = find_any(ps, name);
    if (!p || p->type != PARAM_INTEGER || !p->ints) {
        if (count) *count = 0;
        return NULL;
    }
    p->used = true;
    if (count) *count = p->count;
    return p->ints;
}

/* Shared by params_rgb and params_illuminant_rgb: illuminant selects how sampled spectra
 * are white-balanced (see spectrum.h). */
static bool param_colour(const ParamSet *ps, const char *name, float rgb[3], bool illuminant)
{
    Param *p = find_any(ps, name);
    if (!p) return false;
    switch (p->type) {
    case PARAM_RGB:
        if (p->count < 3) return false;
        memcpy(rgb, p->floats, 3 * sizeof(float));
        break;
    case PARAM_BLACKBODY:
        if (p->count < 1) return false;
        spectrum_blackbody_rgb(p->floats[0], rgb);
        break;
    case PARAM_SPECTRUM:
        if (p->strings && p->count >= 1) {
            if (!spectrum_named_rgb(p->strings[0], rgb)) spectrum_unknown_substitute(p->strings[0], rgb);
        } else if (p->floats && p->count >= 1) {
            bool ok = illuminant ? spectrum_samples_to_rgb_illuminant(p->floats, p->count, rgb)
                                 : spectrum_samples_to_rgb(p->floats, p->count, rgb);
            if (!ok) return false;
        } else {
            return false;
        }
        break;
    default:
        return false;
    }
    p->used = true;
    return true;
}

bool params_rgb(const ParamSet *ps, const char *name, float rgb[3])
{
    return param_colour(ps, name, rgb, false);
}

bool params_illuminant_rgb(const ParamSet *ps, const char *name, float rgb[3])
{
    if (!param_colour(ps, name, rgb, true)) return false;
    const Param *p = find_any(ps, name);
    /* pbrt-v4 (lights.cpp) divides a light's scale by the spectrum's photometric luminance;
     * an rgb emission is rgb times the colour space's normalised D65, whose luminance is 1,
     * so only spectrum and blackbody emissions change. */
    if (p->type != PARAM_RGB) {
        float y = rgb_luminance(rgb);
        if (y > 0.0f)
            for (int c = 0; c < 3; ++c) rgb[c] /= y;
    }
    return true;
}

const char *params_texture(const ParamSet *ps, const char *name)
{
    Param *p = find_any(ps, name);
    if (!p || p->type != PARAM_TEXTURE || p->count < 1) return NULL;
    p->used = true;
    return p->strings[0];
}

int params_count_unused(const ParamSet *ps)
{
    int n = 0;
    for (int i = 0; ps && i < ps->count; ++i) n += !ps->items[i].used;
    return n;
}
