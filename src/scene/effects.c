/* Which distribution effects a scene has (DESIGN.md section 2): the renderer skips the
 * work (lens sampling, time dimension, shadow statistics, indirect pass) for the others. */
#include <math.h>
#include <string.h>

#include "scene/scene_desc.h"

/* Area of the triangle (a, b, c) after transforming by m. */
static double world_triangle_area(const Mat4 *m, const float *a, const float *b, const float *c)
{
    vec3 pa = mat4_apply_point(m, v3(a[0], a[1], a[2]));
    vec3 pb = mat4_apply_point(m, v3(b[0], b[1], b[2]));
    vec3 pc = mat4_apply_point(m, v3(c[0], c[1], c[2]));
    double e1[3] = {(double)pb.x - pa.x, (double)pb.y - pa.y, (double)pb.z - pa.z};
    double e2[3] = {(double)pc.x - pa.x, (double)pc.y - pa.y, (double)pc.z - pa.z};
    double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
    return isfinite(area) ? area : 0.0;
}

/* True when the mesh's polygons have positive total area in world space. Stops at the first
 * polygon with area, so it is cheap for ordinary meshes. */
static bool mesh_has_area(const ShapeDesc *s, int corners)
{
    int np = 0, ni = 0;
    const float *p = params_floats(&s->params, "P", &np);
    const int32_t *idx = params_ints(&s->params, "indices", &ni);
    if (!p || !idx) return false;
    const Mat4 *m = &s->world_from_object.m[0];
    for (int f = 0; f + corners <= ni; f += corners) {
        const int32_t *v = idx + f;
        /* Bilinear patches (p00 p10 p01 p11) as the two triangles (p00 p10 p01), (p10 p11 p01). */
        double a = world_triangle_area(m, p + 3 * v[0], p + 3 * v[1], p + 3 * v[2]);
        if (corners == 4) a += world_triangle_area(m, p + 3 * v[1], p + 3 * v[3], p + 3 * v[2]);
        if (a > 0.0) return true;
    }
    return false;
}

static bool linear_part_nonzero(const Mat4 *m)
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (m->m[i][j] != 0.0) return true;
    return false;
}

static bool shape_has_area(const ShapeDesc *s)
{
    const char *t = s->type;
    if (!strcmp(t, "trianglemesh") || !strcmp(t, "loopsubdiv")) return mesh_has_area(s, 3);
    if (!strcmp(t, "bilinearmesh")) return mesh_has_area(s, 4);
    if (!strcmp(t, "plymesh")) return true; /* counted as having faces; the file is read later */
    if (!linear_part_nonzero(&s->world_from_object.m[0])) return false;
    if (!strcmp(t, "sphere")) {
        float r = params_float(&s->params, "radius", 1.0f);
        float zmin = params_float(&s->params, "zmin", -r), zmax = params_float(&s->params, "zmax", r);
        return r > 0.0f && params_float(&s->params, "phimax", 360.0f) > 0.0f && zmax > zmin;
    }
    if (!strcmp(t, "disk")) {
        return params_float(&s->params, "radius", 1.0f) > params_float(&s->params, "innerradius", 0.0f) &&
               params_float(&s->params, "phimax", 360.0f) > 0.0f;
    }
    return false;
}

static bool area_light_emits(const AreaLightDesc *a)
{
    float scale = params_float(&a->params, "scale", 1.0f);
    if (!(scale != 0.0f)) return false;
    if (params_string(&a->params, "filename", NULL)) return true; /* image emission */
    float L[3] = {1.0f, 1.0f, 1.0f}; /* pbrt-v4 default: the colour space's illuminant */
    params_rgb(&a->params, "L", L);
    return L[0] > 0.0f || L[1] > 0.0f || L[2] > 0.0f;
}

static const char *const EFFECT_NAMES[EFFECT_COUNT] = {"soft_shadows", "defocus", "motion", "indirect"};

const char *effect_name(Effect e) { return (unsigned)e < EFFECT_COUNT ? EFFECT_NAMES[e] : "?"; }

bool effect_from_name(const char *s, Effect *out)
{
    for (int e = 0; e < EFFECT_COUNT; ++e)
        if (!strcmp(s, EFFECT_NAMES[e])) {
            *out = (Effect)e;
            return true;
        }
    return false;
}

/* The one analysis of a scene's effects: `wedge info` reports it and the renderer samples
 * exactly these dimensions (renderer_create), so the two cannot disagree. */
void scene_analyze_effects(SceneDesc *scene)
{
    EffectMask e = 0;
    for (int i = 0; i < scene->shape_count; ++i) {
        const ShapeDesc *s = &scene->shapes[i];
        if (s->area_light < 0 || s->area_light >= scene->area_light_count) continue;
        if (area_light_emits(&scene->area_lights[s->area_light]) && shape_has_area(s)) {
            e |= EFFECT_BIT(EFFECT_SOFT_SHADOWS);
            break;
        }
    }
    if (scene->camera.lens_radius > 0.0f) e |= EFFECT_BIT(EFFECT_DEFOCUS);
    if (scene->camera.shutter_close > scene->camera.shutter_open) {
        bool moves = xform_pair_animated(&scene->camera.camera_from_world);
        for (int i = 0; i < scene->shape_count && !moves; ++i)
            moves = xform_pair_animated(&scene->shapes[i].world_from_object);
        for (int i = 0; i < scene->instance_count && !moves; ++i)
            moves = xform_pair_animated(&scene->instances[i].world_from_instance);
        if (moves) e |= EFFECT_BIT(EFFECT_MOTION);
    }
    if (scene->integrator.max_depth >= 2) e |= EFFECT_BIT(EFFECT_INDIRECT);
    scene->effects = e;
}
