/* FSF's unoccluded irradiance and light share (fsf_light.h) with a planar mesh light, which it
 * sums through the mesh's boundary (emitter_boundary.h), against the direct sum over every
 * emitter triangle of luminance(L) times polygon_projected_solid_angle (a moving mesh as its poses
 * at the sweep's nodes, each pose a mesh of its own): at receivers under the
 * mesh (the boundary's), on a wall whose horizon cuts the mesh (its triangles one by one),
 * behind the one-sided mesh (nothing from it), with a second quad light of another shape and a
 * sphere light (the share's small source) in the scene. The same mesh sagging into a curve
 * (a trough across it) is summed through its facing parts (emitter_facing.h) instead, against
 * the same direct sum. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/aaf/aaf_light_sweep.h"
#include "recon/fsf/fsf_light.h"
#include "recon/polygon_irradiance.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

enum { GRID = 12, PIXELS = 600 };

static unsigned g_rng = 777u;
static float uniform(void)
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return (float)((g_rng >> 8) * (1.0 / 16777216.0));
}

static char *scene_text(bool moving, bool curved)
{
    size_t cap = 1 << 18, at = 0;
    char *s = malloc(cap);
    at += (size_t)snprintf(s + at, cap - at,
                           "LookAt 0 2 -5  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
                           "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
                           "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\n"
                           "WorldBegin\n"
                           "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
                           "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 0.5 0.25 ]\n"
                           "  Shape \"trianglemesh\" \"point3 P\" [ 1.5 2 -0.5  2.5 2 -0.5  2.5 2 0.5  1.5 2 0.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                           "AttributeEnd\n"
                           "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n  Translate -2 1.5 1\n"
                           "  Shape \"sphere\" \"float radius\" [ 0.2 ]\nAttributeEnd\n"
                           "AttributeBegin\n%s  AreaLightSource \"diffuse\" \"rgb L\" [ 3 2.5 2 ]\n"
                           "  Shape \"trianglemesh\" \"point3 P\" [",
                           moving ? "  ActiveTransform EndTime\n  Translate 0.5 0.1 0\n  Rotate 10 0 0 1\n  ActiveTransform All\n" : "");
    /* a tilted square of GRID x GRID quads at height ~2, wound so that it shines downwards */
    for (int j = 0; j <= GRID; ++j)
        for (int i = 0; i <= GRID; ++i) {
            double u = (double)i / GRID, v = (double)j / GRID;
            double sag = curved ? 0.3 * sin(M_PI * u) : 0.0;
            at += (size_t)snprintf(s + at, cap - at, " %.9g %.9g %.9g", -1.0 + 1.6 * u, 2.0 + 0.3 * u - 0.1 * v - sag, -0.8 + 1.6 * v);
        }
    at += (size_t)snprintf(s + at, cap - at, " ] \"integer indices\" [");
    for (int j = 0; j < GRID; ++j)
        for (int i = 0; i < GRID; ++i) {
            int a = j * (GRID + 1) + i, b = a + 1, c = a + GRID + 1, d = c + 1;
            at += (size_t)snprintf(s + at, cap - at, " %d %d %d %d %d %d", a, b, c, b, d, c);
        }
    snprintf(s + at, cap - at, " ]\nAttributeEnd\n");
    return s;
}

/* the direct sums: every triangle light alone, in the lights' order */
static void direct(const Renderer *r, int shape, const float p4[4], const float n4[4], double *irr, double *share)
{
    double p[3] = {p4[0], p4[1], p4[2]}, nr[3] = {n4[0], n4[1], n4[2]}, all = 0.0, own = 0.0;
    vec3 pv = v3(p4[0], p4[1], p4[2]), nv = v3(n4[0], n4[1], n4[2]);
    *irr = 0.0;
    for (int e = 0; e < renderer_light_count(r) * AAF_SWEEP_NODES; ++e) {
        /* a moving light as its poses at the sweep's nodes, radiance times the node's weight */
        int l = e / AAF_SWEEP_NODES, node = e % AAF_SWEEP_NODES;
        RenderLightInfo b;
        if (!renderer_light_info(r, l, &b) || b.kind != RENDER_LIGHT_AREA) continue;
        if (b.moving) {
            double w, u = aaf_sweep_node(node, &w);
            if (!renderer_light_info_at(r, l, (float)u, &b)) continue;
            b.radiance = v3_scale(b.radiance, (float)w);
        } else if (node > 0) {
            continue;
        }
        if (!b.is_triangle) { /* a sphere, as a small source above the horizon */
            vec3 to = v3_sub(b.center_world, pv);
            double D = sqrt(v3_length2(to)), cos_t = v3_dot(nv, to) / D, rad = sqrt(b.area_world / (4.0 * M_PI));
            if (cos_t > 0.0) all += (double)v3_luminance(b.radiance) * M_PI * (rad / D) * (rad / D) * cos_t;
            continue;
        }
        if (!b.two_sided && !(v3_dot(v3_sub(pv, b.center_world), b.normal_world) > 0.0f)) continue;
        double v[3][3];
        for (int k = 0; k < 3; ++k) v[k][0] = b.tri_world[k].x, v[k][1] = b.tri_world[k].y, v[k][2] = b.tri_world[k].z;
        double phi = (double)v3_luminance(b.radiance) * polygon_projected_solid_angle(p, nr, v, 3);
        *irr += phi, all += phi;
        if (b.shape == shape) own += phi;
    }
    *share = all > 0.0 ? fmin(own / all, 1.0) : 0.0;
}

static void check_scene(bool moving, bool curved)
{
    char *text = scene_text(moving, curved);
    SceneDesc scene;
    Diag d = {0};
    bool parsed = scene_parse_string(text, strlen(text), "<test>", NULL, &scene, &d);
    CHECK(parsed);
    if (!parsed) {
        fprintf(stderr, "%s\n", d.message);
        free(text);
        return;
    }
    RenderOptions ro;
    memset(&ro, 0, sizeof ro);
    ro.spp = 4;
    ro.threads = 2;
    Renderer *r = NULL;
    CHECK(renderer_create(&scene, &ro, &r, &d));
    if (!r) {
        fprintf(stderr, "%s\n", d.message);
        scene_desc_free(&scene);
        free(text);
        return;
    }
    int mesh_shape = -1;
    for (int l = 0; l < renderer_light_count(r); ++l) {
        RenderLightInfo b;
        if (renderer_light_info(r, l, &b) && b.kind == RENDER_LIGHT_AREA && b.is_triangle) mesh_shape = b.shape;
    }
    CHECK(renderer_light_count(r) == 2 + 1 + 2 * GRID * GRID);
    /* receivers: a third on the floor under the mesh, a third on a wall at x = -0.4 facing +x
     * (its horizon cuts the mesh, x from -1 to 0.6), a third above the mesh facing down (behind it) */
    unsigned char *hit = malloc(PIXELS);
    float *pos4 = calloc(4 * PIXELS, sizeof(float)), *nrm4 = calloc(4 * PIXELS, sizeof(float));
    float *irr = malloc(PIXELS * sizeof(float)), *share = malloc(PIXELS * sizeof(float));
    for (int i = 0; i < PIXELS; ++i) {
        int kind = i % 3;
        hit[i] = 1;
        float *p = pos4 + 4 * i, *n = nrm4 + 4 * i;
        if (kind == 0) p[0] = -1.5f + 3.0f * uniform(), p[1] = 0.0f, p[2] = -1.5f + 3.0f * uniform(), n[1] = 1.0f;
        else if (kind == 1) p[0] = -0.4f, p[1] = 1.9f * uniform(), p[2] = -1.0f + 2.0f * uniform(), n[0] = 1.0f;
        else p[0] = -0.8f + 1.2f * uniform(), p[1] = 2.6f + uniform(), p[2] = -0.6f + 1.2f * uniform(), n[1] = -1.0f;
    }
    hit[5] = 0; /* no surface: 0 */
    fsf_irradiance_and_share(r, mesh_shape, PIXELS, hit, pos4, nrm4, irr, share);
    double worst_irr = 0.0, worst_share = 0.0;
    int lit[3] = {0, 0, 0};
    for (int i = 0; i < PIXELS; ++i) {
        double want_irr = 0.0, want_share = 0.0;
        if (hit[i]) direct(r, mesh_shape, pos4 + 4 * i, nrm4 + 4 * i, &want_irr, &want_share);
        worst_irr = fmax(worst_irr, fabs(irr[i] - want_irr) / fmax(want_irr, 1e-6));
        worst_share = fmax(worst_share, fabs(share[i] - want_share));
        lit[i % 3] += want_share > 0.5;
    }
    printf("%s%s mesh, %d receivers: worst relative irradiance difference %.2e, worst share difference %.2e; mostly lit by the mesh: "
           "%d floor, %d wall, %d behind\n", moving ? "moving" : "static", curved ? " curved" : "", PIXELS, worst_irr, worst_share, lit[0], lit[1], lit[2]);
    CHECK(worst_irr < 2e-6);   /* float outputs of double sums that differ in rounding only */
    CHECK(worst_share < 2e-6);
    CHECK(lit[0] > 150 && lit[1] > 50 && lit[2] == 0); /* the three kinds of receiver were what they are meant to be */
    CHECK(irr[5] == 0.0f && share[5] == 0.0f);
    free(hit), free(pos4), free(nrm4), free(irr), free(share);
    renderer_destroy(r);
    scene_desc_free(&scene);
    free(text);
}

int main(void)
{
    check_scene(false, false);
    check_scene(true, false);
    check_scene(false, true);
    check_scene(true, true);
    return check_failures ? 1 : 0;
}
