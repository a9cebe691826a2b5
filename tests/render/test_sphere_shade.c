/* The shading of a top-level sphere placed by a translation alone (tracer.c's
 * sphere_hit_shade, mostly float, issue 22) against two oracles, over random rays:
 *  - the closed form in double: the ray's nearest root t_ref of |o + t d - c| = r, the point
 *    p_ref = o + t_ref d and the normal (p_ref - c) / r;
 *  - the general path (shade_geom_space in double, through the object's transforms): the
 *    same sphere, translated and then turned a full turn (a rotation matrix not exactly the
 *    identity).
 * Point and normal must agree to a few float ulps of the sphere's own scale (|o - c| and
 * t, not |c|: a sphere far from the world's origin keeps its digits), uv (a material that
 * reads it) to a few ulps of the general path's, and rays leaving a hit pushed off it
 * (surface_offset) must not find the sphere again on the outside and must find its far
 * side on the inside. */
#include <float.h>
#include <math.h>

#include "check.h"
#include "core/rng.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "render_test_util.h"

typedef struct {
    double c[3], c_extra[3], r; /* centre c + c_extra */
    double o_dist; /* ray origins at this distance from the centre */
} Case;

/* The nearest root t > 0 of the ray o + t d (d unit) on the sphere (c, r) in double; false
 * on a miss. */
static bool sphere_root(const double c[3], double r, vec3 o, vec3 d, double *t)
{
    double oc[3] = {o.x - c[0], o.y - c[1], o.z - c[2]}, dd[3] = {d.x, d.y, d.z};
    double b = oc[0] * dd[0] + oc[1] * dd[1] + oc[2] * dd[2];
    double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
    double a = dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2];
    double disc = b * b - a * cc;
    if (disc < 0.0) return false;
    double t0 = (-b - sqrt(disc)) / a, t1 = (-b + sqrt(disc)) / a;
    *t = t0 > 0.0 ? t0 : t1;
    return *t > 0.0;
}

static double max_abs_diff(vec3 a, vec3 b)
{
    return fmax(fabs((double)a.x - b.x), fmax(fabs((double)a.y - b.y), fabs((double)a.z - b.z)));
}

static void check_case(const Case *k, bool uv_read)
{
    /* uv_read: a checkerboard material, so the hit's uv is computed */
    const char *material = uv_read ? "Texture \"t\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 1 1 ] "
                                     "\"rgb tex2\" [ 0 0 0 ]\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\n"
                                   : "Material \"diffuse\"\n";
    char top[1024], gen[1024];
    /* the centre as two translations: their sum (in double) need not be a float */
    snprintf(top, sizeof top,
             "WorldBegin\n%sAttributeBegin Translate %.9g %.9g %.9g Translate %.9g %.9g %.9g Shape \"sphere\" "
             "\"float radius\" [ %.9g ] AttributeEnd\n",
             material, k->c[0], k->c[1], k->c[2], k->c_extra[0], k->c_extra[1], k->c_extra[2], k->r);
    /* a full turn about z: a rotation matrix that is not quite the identity (sin 2 pi is not
     * 0 in double), so the general path, for the same sphere */
    snprintf(gen, sizeof gen,
             "WorldBegin\n%sAttributeBegin Translate %.9g %.9g %.9g Translate %.9g %.9g %.9g Rotate 360 0 0 1 "
             "Shape \"sphere\" \"float radius\" [ %.9g ] AttributeEnd\n",
             material, k->c[0], k->c[1], k->c[2], k->c_extra[0], k->c_extra[1], k->c_extra[2], k->r);
    SceneDesc s_top, s_gen;
    Tracer t_top, t_gen;
    bool built = test_build_tracer(top, &s_top, &t_top);
    CHECK(built);
    if (!built) return;
    if (!test_build_tracer(gen, &s_gen, &t_gen)) {
        CHECK(false);
        tracer_free(&t_top);
        scene_desc_free(&s_top);
        return;
    }
    /* the translated sphere takes the fast path, the turned one the general path */
    CHECK(t_top.layers[0].geom_count == 1 && t_top.layers[0].geoms[0].kind == GEOM_SPHERE &&
          t_top.layers[0].geoms[0].object_translation_only);
    CHECK(t_gen.layers[0].geom_count == 1 && t_gen.layers[0].geoms[0].kind == GEOM_SPHERE &&
          !t_gen.layers[0].geoms[0].object_translation_only);
    for (int g = 0; g < t_top.layers[0].geom_count; ++g) t_top.layers[0].geoms[g].uv_unread = !uv_read;
    for (int l = 0; l < t_gen.layer_count; ++l)
        for (int g = 0; g < t_gen.layers[l].geom_count; ++g) t_gen.layers[l].geoms[g].uv_unread = !uv_read;

    /* the centre and radius as the scene has them (the oracle's sphere) */
    const Geom *geom = &t_top.layers[0].geoms[0];
    const double cd[3] = {geom->geom_from_object.m[0][3], geom->geom_from_object.m[1][3], geom->geom_from_object.m[2][3]};
    const double r = geom->radius;
    Pcg32 rng;
    pcg32_seed(&rng, 31, 7);
    vec3 c = v3((float)cd[0], (float)cd[1], (float)cd[2]);
    long hits = 0, bad_ref = 0, bad_general = 0, bad_uv = 0, bad_out = 0, bad_in = 0;
    double worst_n = 0.0;
    for (int i = 0; i < 4000; ++i) {
        vec3 u = warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng)));
        vec3 o = v3_add(c, v3_scale(u, (float)k->o_dist));
        /* aimed at a point of the sphere's bounding box (most hit, some graze or miss) */
        vec3 aim = v3((2.0f * pcg32_float(&rng) - 1.0f) * (float)r, (2.0f * pcg32_float(&rng) - 1.0f) * (float)r,
                      (2.0f * pcg32_float(&rng) - 1.0f) * (float)r);
        vec3 d = v3_normalize(v3_sub(v3_add(c, aim), o));
        SurfaceHit h, hg;
        bool found = tracer_intersect(&t_top, o, d, INFINITY, 0.0f, &h);
        bool found_g = tracer_intersect(&t_gen, o, d, INFINITY, 0.0f, &hg);
        double t_ref;
        bool found_ref = sphere_root(cd, r, o, d, &t_ref);
        if (!found || !found_g || !found_ref) continue; /* grazing rays may disagree on hit or miss */
        ++hits;
        /* the sphere's own scale: the point's error from t's rounding and the local offset */
        double scale = (double)k->o_dist + t_ref;
        double tol_n = 16.0 * FLT_EPSILON * scale / r + 8.0 * FLT_EPSILON;
        double tol_p = 4.0 * FLT_EPSILON * (fabs(cd[0]) + fabs(cd[1]) + fabs(cd[2]) + r) + r * tol_n;
        vec3 p_ref = v3((float)(o.x + t_ref * d.x), (float)(o.y + t_ref * d.y), (float)(o.z + t_ref * d.z));
        double pr[3] = {o.x + t_ref * d.x - cd[0], o.y + t_ref * d.y - cd[1], o.z + t_ref * d.z - cd[2]};
        vec3 n_ref = v3((float)(pr[0] / r), (float)(pr[1] / r), (float)(pr[2] / r));
        double dn = max_abs_diff(h.ng, n_ref);
        worst_n = fmax(worst_n, dn / tol_n);
        bad_ref += !(max_abs_diff(h.p, p_ref) <= tol_p) || !(dn <= tol_n) || max_abs_diff(h.ns, h.ng) != 0.0;
        bad_general += !(max_abs_diff(h.p, hg.p) <= tol_p) || !(max_abs_diff(h.ng, hg.ng) <= tol_n) ||
                       !(max_abs_diff(h.ns, hg.ns) <= tol_n);
        /* uv: phi / phimax and the polar angle's fraction; their slope in the normal is at most
         * about 1 / (pi sin theta) per unit, so poles aside they follow the normal's error */
        double sin_theta = sqrt(fmax(0.0, 1.0 - (double)h.ng.z * h.ng.z));
        if (sin_theta > 0.05)
            bad_uv += !(fabs((double)h.uv.x - hg.uv.x) <= 4.0 * tol_n / sin_theta + 1e-6 || fabs(h.uv.x - hg.uv.x) > 0.99) ||
                      !(fabs((double)h.uv.y - hg.uv.y) <= 4.0 * tol_n / sin_theta + 1e-6);
        if (!uv_read) bad_uv += h.uv.x != 0.0f || h.uv.y != 0.0f;
        /* leaving the hit: outwards it must not see the sphere, inwards it must see its far side */
        vec3 w = warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng)));
        if (v3_dot(w, h.ng) < 0.0f) w = v3_neg(w);
        if (v3_dot(w, h.ng) > 1e-3f) bad_out += tracer_occluded(&t_top, surface_offset(&h, w), w, INFINITY, 0.0f);
        vec3 win = v3_neg(w);
        if (v3_dot(win, h.ng) < -1e-3f) bad_in += !tracer_occluded(&t_top, surface_offset(&h, win), win, INFINITY, 0.0f);
    }
    printf("centre (%g %g %g) r %g, origins at %g, uv %s: %ld hits; against the closed form %ld off, the general "
           "path %ld, uv %ld; self-hits outwards %ld, inward misses %ld; worst normal error %.3f of the tolerance\n",
           cd[0], cd[1], cd[2], r, k->o_dist, uv_read ? "read" : "unread", hits, bad_ref, bad_general, bad_uv,
           bad_out, bad_in, worst_n);
    CHECK(hits > 2000);
    CHECK(bad_ref == 0);
    CHECK(bad_general == 0);
    CHECK(bad_uv == 0);
    CHECK(bad_out == 0);
    CHECK(bad_in == 0);
    tracer_free(&t_top);
    tracer_free(&t_gen);
    scene_desc_free(&s_top);
    scene_desc_free(&s_gen);
}

int main(void)
{
    static const Case cases[] = {
        {{-1.2, 0.3, 0.7}, {0, 0, 0}, 0.8, 5.0},                     /* near the origin */
        {{3000.1, -2000.3, 1000.7}, {0.013, 0.0271, -0.0093}, 0.5, 4.0}, /* far from it, seen from nearby */
        {{0.01, 0.02, -0.03}, {0, 0, 0}, 0.001, 0.01},                 /* small */
        {{20.0, 5.0, -40.0}, {0, 0, 0}, 6.0, 100.0},                   /* large, seen from afar */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        check_case(&cases[i], false);
        check_case(&cases[i], true);
    }
    return check_failures ? 1 : 0;
}
