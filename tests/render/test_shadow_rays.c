/* The shadow rays a wave makes ahead for its lanes (shadow_rays.h) against shadow_ray_make, the
 * one-ray definition, lane by lane and bit for bit (origin, direction, length):
 *  - an emitting mesh's lanes (mesh_shadow_rays), each lane its own triangle of a curved patch
 *    (every triangle's normal differs, so a lane that pushed its far end along another lane's
 *    or the first triangle's normal, or by another offset, gives other bits), receivers on both
 *    sides of the patch with random geometric normals and offsets;
 *  - the same lanes grouped by triangle (triangle_shadow_rays, the light's normal and offset);
 *  - a constant sky's lanes (sky_shadow_rays: no far end) and a point light's
 *    (point_shadow_rays: no offset at the light).
 * A lane marked redo is one shadow_ray_make must compute itself; the test's lanes are all in
 * v3_length's plain range and at finite distances (but the sky's), so none may be. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/shadow_rays.h"
#include "render/tracer.h"
#include "render_test_util.h"

enum { COLS = 6, ROWS = 5 };

static void patch_at(void *ctx, int c, int r, double p[3])
{
    (void)ctx;
    double a = -0.8 + 1.6 * c / COLS;
    p[0] = 1.5 * sin(a), p[1] = 0.4 * r, p[2] = 2.0 - 1.5 * cos(a);
}

static bool build(TestLights *b)
{
    char text[12288];
    size_t len = 0;
    bool ok = test_appendf(text, sizeof text, &len,
                           "LookAt 0 2 -5  0 0.3 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\nWorldBegin\n"
                           "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 2 1 ] \"bool twosided\" true\n"
                           "Shape \"trianglemesh\" ") &&
              test_grid_mesh(text, sizeof text, COLS, ROWS, patch_at, NULL);
    len = strlen(text);
    ok = ok && test_appendf(text, sizeof text, &len, "\nAttributeEnd\n");
    return ok && test_build_lights(text, b);
}

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* A random receiver: a point around the patch, a unit geometric normal in any direction (so
 * the origin is pushed to either side) and an offset over three decades. */
static SurfaceHit random_receiver(Pcg32 *rng)
{
    SurfaceHit h;
    memset(&h, 0, sizeof h);
    double a = 1.6 * pcg32_float(rng) - 0.8, rad = pcg32_float(rng) < 0.5 ? 0.5 * pcg32_float(rng) : 1.7 + pcg32_float(rng);
    h.p = v3((float)(rad * sin(a)), 2.0f * pcg32_float(rng), (float)(2.0 - rad * cos(a)));
    vec3 n = v3(2.0f * pcg32_float(rng) - 1.0f, 2.0f * pcg32_float(rng) - 1.0f, 2.0f * pcg32_float(rng) - 1.0f);
    h.ng = v3_length2(n) > 1e-4f ? v3_normalize(n) : v3(0.0f, 1.0f, 0.0f);
    h.err = 1e-5f * powf(1000.0f, pcg32_float(rng));
    return h;
}

static void lane_receiver(const SurfaceHit *h, int k, WaveTriangleSamples *g)
{
    g->p[0][k] = h->p.x, g->p[1][k] = h->p.y, g->p[2][k] = h->p.z;
    g->ng[0][k] = h->ng.x, g->ng[1][k] = h->ng.y, g->ng[2][k] = h->ng.z;
    g->err[k] = h->err;
}

static void lane_sample(const LightSample *ls, int k, WaveTriangleSamples *g)
{
    g->wi[0][k] = ls->wi.x, g->wi[1][k] = ls->wi.y, g->wi[2][k] = ls->wi.z;
    g->dist[k] = ls->dist;
    g->pl[0][k] = ls->p_light.x, g->pl[1][k] = ls->p_light.y, g->pl[2][k] = ls->p_light.z;
}

/* Lanes of g (or of a point light's ps) whose ray differs from shadow_ray_make's, or is redo. */
static int lanes_differing(int count, const float (*o)[WAVE_SAMPLES], const float (*dir)[WAVE_SAMPLES],
                           const float *len, const int *redo, const SurfaceHit *hits, const LightSample *samples)
{
    int bad = 0;
    for (int k = 0; k < count; ++k) {
        vec3 wo, wdir;
        float wlen;
        bool made = shadow_ray_make(&hits[k], &samples[k], &wo, &wdir, &wlen);
        bool same = made && !redo[k] && same_bits(o[0][k], wo.x) && same_bits(o[1][k], wo.y) &&
                    same_bits(o[2][k], wo.z) && same_bits(dir[0][k], wdir.x) && same_bits(dir[1][k], wdir.y) &&
                    same_bits(dir[2][k], wdir.z) && same_bits(len[k], wlen);
        bad += !same;
    }
    return bad;
}

static WaveTriangleSamples g;
static WaveDeltaSamples ds;
static SurfaceHit hits[WAVE_SAMPLES];
static LightSample samples[WAVE_SAMPLES];

/* The mesh's lanes, all triangles at once and then one triangle at a time. */
static void check_mesh(const TestLights *b, Pcg32 *rng)
{
    const LightSet *L = &b->L;
    int tri_seen[2 * COLS * ROWS] = {0};
    for (int round = 0; round < 8; ++round) {
        memset(&g, 0, sizeof g);
        int n = 0;
        while (n < WAVE_SAMPLES) {
            SurfaceHit h = random_receiver(rng);
            int t = (int)(pcg32_float(rng) * (float)L->count) % L->count;
            LightSample ls;
            if (!light_sample(L, &b->tr, t, h.p, 0.0f, v2(pcg32_float(rng), pcg32_float(rng)), &ls)) continue;
            CHECK(ls.err_light > 0.0f && v3_length2(ls.n_light) > 0.0f); /* the ray's end is pushed */
            hits[n] = h, samples[n] = ls, g.tri[n] = t, tri_seen[t] = 1;
            lane_receiver(&h, n, &g), lane_sample(&ls, n, &g);
            ++n;
        }
        g.count = n, g.mesh = true;
        mesh_shadow_rays(L->lights, &g);
        int bad = lanes_differing(n, g.o, g.dir, g.len, g.redo, hits, samples);
        if (bad) fprintf(stderr, "mesh round %d: %d of %d lanes differ from shadow_ray_make\n", round, bad, n);
        CHECK(bad == 0);
        /* the same lanes, one triangle's at a time, through the single light's loop */
        for (int t = 0; t < L->count; ++t) {
            static WaveTriangleSamples one;
            static SurfaceHit h1[WAVE_SAMPLES];
            static LightSample s1[WAVE_SAMPLES];
            memset(&one, 0, sizeof one);
            int m = 0;
            for (int k = 0; k < n; ++k) {
                if (g.tri[k] != t) continue;
                h1[m] = hits[k], s1[m] = samples[k];
                lane_receiver(&hits[k], m, &one), lane_sample(&samples[k], m, &one);
                ++m;
            }
            if (!m) continue;
            one.count = m;
            triangle_shadow_rays(L->lights[t].tri_n, L->lights[t].tri_err, &one);
            int bad1 = lanes_differing(m, one.o, one.dir, one.len, one.redo, h1, s1);
            if (bad1) fprintf(stderr, "triangle %d: %d of %d lanes differ\n", t, bad1, m);
            CHECK(bad1 == 0);
        }
    }
    int seen = 0;
    for (int t = 0; t < L->count; ++t) seen += tri_seen[t];
    CHECK(seen == L->count);
}

/* A constant sky's lanes: unbounded rays along wi. */
static void check_sky(Pcg32 *rng)
{
    memset(&g, 0, sizeof g);
    for (int k = 0; k < WAVE_SAMPLES; ++k) {
        hits[k] = random_receiver(rng);
        LightSample ls;
        memset(&ls, 0, sizeof ls);
        ls.wi = v3_normalize(v3(2.0f * pcg32_float(rng) - 1.0f, pcg32_float(rng) + 0.01f, 2.0f * pcg32_float(rng) - 1.0f));
        ls.dist = INFINITY;
        samples[k] = ls;
        lane_receiver(&hits[k], k, &g), lane_sample(&ls, k, &g);
    }
    g.count = WAVE_SAMPLES, g.sky = true;
    sky_shadow_rays(&g);
    int bad = lanes_differing(WAVE_SAMPLES, g.o, g.dir, g.len, g.redo, hits, samples);
    if (bad) fprintf(stderr, "sky: %d lanes differ\n", bad);
    CHECK(bad == 0);
}

/* A point light's lanes: the ray ends at the light's position itself. */
static void check_point(Pcg32 *rng)
{
    memset(&ds, 0, sizeof ds);
    vec3 target = v3(0.3f, 3.0f, 1.2f);
    float p[3][WAVE_SAMPLES], ng[3][WAVE_SAMPLES], err[WAVE_SAMPLES];
    for (int k = 0; k < WAVE_SAMPLES; ++k) {
        SurfaceHit h = random_receiver(rng);
        LightSample ls;
        memset(&ls, 0, sizeof ls);
        vec3 d = v3_sub(target, h.p);
        ls.dist = v3_length(d), ls.wi = v3_scale(d, 1.0f / ls.dist), ls.p_light = target;
        hits[k] = h, samples[k] = ls;
        p[0][k] = h.p.x, p[1][k] = h.p.y, p[2][k] = h.p.z;
        ng[0][k] = h.ng.x, ng[1][k] = h.ng.y, ng[2][k] = h.ng.z, err[k] = h.err;
        ds.wi[0][k] = ls.wi.x, ds.wi[1][k] = ls.wi.y, ds.wi[2][k] = ls.wi.z, ds.dist[k] = ls.dist;
    }
    point_shadow_rays(WAVE_SAMPLES, (const float (*)[WAVE_SAMPLES])p, (const float (*)[WAVE_SAMPLES])ng, err, target,
                      &ds);
    int bad = lanes_differing(WAVE_SAMPLES, ds.o, ds.dir, ds.len, ds.redo, hits, samples);
    if (bad) fprintf(stderr, "point: %d lanes differ\n", bad);
    CHECK(bad == 0);
}

int main(void)
{
    TestLights b;
    if (!build(&b)) {
        CHECK(false);
        CHECK_DONE();
    }
    CHECK(b.L.count == 2 * COLS * ROWS);
    Pcg32 rng;
    pcg32_seed(&rng, 11u, 3u);
    check_mesh(&b, &rng);
    check_sky(&rng);
    check_point(&rng);
    test_lights_free(&b);
    CHECK_DONE();
}
