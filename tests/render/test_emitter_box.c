/* The emitters' box (src/render/light_bounds.c) and the last rays it lets the integrator
 * skip (issue 22).
 *  - Oracle: every ray that Embree finds hitting an area light (a quad, a rotated and
 *    scaled sphere, a tilted disk) is one lights_ray_may_reach_emitter lets through: rays
 *    from random origins in random directions, and rays aimed at points sampled on each
 *    emitter (light_sample, edges and all). Teeth: most random rays miss the box and are
 *    judged so, and a ray leaving the box is.
 *  - A moving emitter leaves the box unbounded: every ray may reach it.
 *  - The integrator: on glossy receivers (the box test's last rays: a Lambert last vertex
 *    samples no direction there, lambert_light_only), a render that skips the rays (no
 *    records) equals, value for value, one that traces every first vertex's last ray
 *    (records on, so none is skipped), the skipped and traced rays add up to the same count
 *    and the guarded events are the same; with a black Lambert object too (no light, no ray,
 *    either way); with an infinite light none is skipped. On Lambert receivers too where a cut
 *    sphere emits both ways (LightSet.area_sampling_complete false: MIS and the rays stay).
 *  - A Lambert last vertex without bounce records traces and skips no last ray at all; with
 *    them (MIS against the BSDF sample) it traces one wherever its throughput is positive.
 *  - Shadow geometry without bounce geometry (what a maxdepth-1 filtered frame records):
 *    the box test still runs, the values and ray counts are a plain render's, the shadow
 *    rays are recorded and no bounce ray is; with the bounce geometry, every last ray is
 *    traced and recorded.
 *  - The batched test (lights_rays_may_reach_emitter, one vectorised loop) answers as the
 *    test per ray on every ray: random ones, and the edge cases of the slab test (direction
 *    components of +-0, origins on the box's faces, a zero direction, NaN and infinite
 *    components), in odd counts so that the vector loop's remainder runs too. */
#include <math.h>
#include <stdint.h>

#include "check.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "render_test_util.h"

static const char *EMITTERS =
    "LookAt 0 2 -5  0 0.3 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "WorldBegin\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1  0 3 2 ]\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5 ] \"integer indices\" [ 0 1 2  0 2 3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
    "  Translate -2 1.5 1 Rotate 35 0 1 1 Scale 1.5 1.5 1.5 Shape \"sphere\" \"float radius\" [ 0.3 ] AttributeEnd\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ] \"bool twosided\" true\n"
    "  Translate 2 1 -1 Rotate 60 1 0.2 0 Shape \"disk\" \"float radius\" [ 0.4 ] AttributeEnd\n"
    "AttributeBegin Translate 0 0.7 0 Shape \"sphere\" \"float radius\" [ 0.6 ] AttributeEnd\n";

enum { RANDOM_RAYS = 20000, AIMED_PER_LIGHT = 2000 };

static void test_box_oracle(void)
{
    TestLights b;
    bool built = test_build_lights(EMITTERS, &b);
    CHECK(built);
    if (!built) return;
    const LightSet *L = &b.L;
    Tracer *tr = &b.tr;
    CHECK(L->emitters_bounded);
    Pcg32 rng;
    pcg32_seed(&rng, 11, 5);
    static TracerRay rays[RANDOM_RAYS];
    static SurfaceHit hit[RANDOM_RAYS];
    static bool found[RANDOM_RAYS];
    for (int i = 0; i < RANDOM_RAYS; ++i) {
        vec3 o = v3(12.0f * pcg32_float(&rng) - 6.0f, 6.0f * pcg32_float(&rng) - 0.5f, 12.0f * pcg32_float(&rng) - 6.0f);
        vec3 d = warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng)));
        rays[i] = (TracerRay){o, d, INFINITY, 0.0f, 0u};
    }
    tracer_intersect_batch(tr, rays, RANDOM_RAYS, true, false, hit, found);
    int emitter_hits = 0, wrong = 0, judged_miss = 0;
    for (int i = 0; i < RANDOM_RAYS; ++i) {
        bool may = lights_ray_may_reach_emitter(L, rays[i].o, rays[i].d);
        judged_miss += !may;
        if (found[i] && hit[i].light >= 0) {
            ++emitter_hits;
            wrong += !may;
        }
    }
    printf("random rays: %d hit an emitter, %d judged to miss the box, %d wrongly\n", emitter_hits, judged_miss, wrong);
    CHECK(emitter_hits > 100 && wrong == 0);
    CHECK(judged_miss > RANDOM_RAYS / 2);

    /* rays aimed at points on each emitter, from anywhere around it; u covers the
     * emitter's edges (0 and just below 1) as well as its inside */
    int aimed = 0;
    wrong = 0;
    for (int li = 0; li < L->count; ++li) {
        if (L->lights[li].kind != LIGHT_AREA) continue;
        for (int k = 0; k < AIMED_PER_LIGHT; ++k) {
            vec3 o = v3(12.0f * pcg32_float(&rng) - 6.0f, 6.0f * pcg32_float(&rng) - 0.5f, 12.0f * pcg32_float(&rng) - 6.0f);
            float ux = pcg32_float(&rng), uy = pcg32_float(&rng);
            if (k % 4 == 1) ux = 0.0f;
            if (k % 4 == 2) uy = 0x1.fffffep-1f;
            LightSample ls;
            if (!light_sample(L, tr, li, o, 0.0f, v2(ux, uy), &ls)) continue;
            ++aimed;
            wrong += !lights_ray_may_reach_emitter(L, o, ls.wi);
        }
    }
    printf("aimed rays: %d, %d judged to miss\n", aimed, wrong);
    CHECK(aimed > 2 * AIMED_PER_LIGHT && wrong == 0);
    /* straight down from under the floor, away from every emitter */
    CHECK(!lights_ray_may_reach_emitter(L, v3(0.0f, -1.0f, 0.0f), v3(0.0f, -1.0f, 0.0f)));
    /* from inside the box every ray may reach */
    CHECK(lights_ray_may_reach_emitter(L, v3(0.0f, 2.0f, 0.0f), v3(0.0f, -1.0f, 0.0f)));
    test_lights_free(&b);
}

static const char *MOVING =
    "LookAt 0 2 -5  0 0.3 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "WorldBegin\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
    "  ActiveTransform StartTime Translate 0 3 0 ActiveTransform EndTime Translate 1 3 0 ActiveTransform All\n"
    "  Shape \"sphere\" \"float radius\" [ 0.3 ]\n"
    "AttributeEnd\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1  0 3 2 ]\n";

static void test_moving_emitter(void)
{
    TestLights b;
    bool built = test_build_lights(MOVING, &b);
    CHECK(built);
    if (!built) return;
    CHECK(b.L.has_area && !b.L.emitters_bounded);
    CHECK(lights_ray_may_reach_emitter(&b.L, v3(0.0f, -1.0f, 0.0f), v3(0.0f, -1.0f, 0.0f)));
    test_lights_free(&b);
}

/* maxdepth 1: every bounce ray is a last ray. A quad light over a floor, a coated diffuse
 * and a conductor sphere (glossy receivers: their last rays take the box test). */
static const char *LIT =
    "LookAt 1 2.5 -5  0 0.5 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Sampler \"stratified\"\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "%s"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.6 2.5 -0.6  0.6 2.5 -0.6  0.6 2.5 0.6  -0.6 2.5 0.6 ]\n"
    "        \"integer indices\" [ 0 1 2  0 2 3 ]\n"
    "AttributeEnd\n"
    "Material \"%s\" \"rgb reflectance\" [ 0.5 0.6 0.7 ]%s\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 2 1  0 3 2 ]\n"
    "AttributeBegin Translate -0.9 0.5 0.2 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n"
    "AttributeBegin Material \"conductor\" Translate 0.9 0.7 -0.1 Shape \"sphere\" \"float radius\" [ 0.7 ] AttributeEnd\n";

/* The receivers' material: glossy (coateddiffuse) or Lambert. */
static const char *const GLOSSY = "coateddiffuse", *const GLOSSY_ARGS = " \"float roughness\" [ 0.3 ]";

static void test_skipped_rays_change_nothing(const char *extra, const char *material, const char *args, bool expect_skips)
{
    char text[4096];
    snprintf(text, sizeof text, LIT, extra, material, args);
    TestRender t[2];
    RenderOptions o = {0};
    o.width = 24, o.height = 18, o.threads = 2, o.seed = 3, o.spp = 16;
    bool ok = test_render(text, &o, &t[0]);
    o.record_ray_geometry = true; /* the first vertex's last rays are traced for the records */
    ok = test_render(text, &o, &t[1]) && ok;
    CHECK(ok);
    if (!ok) return;
    size_t n = (size_t)o.width * (size_t)o.height;
    int bad = 0;
    double sum = 0.0;
    for (size_t i = 0; i < 3 * n; ++i) {
        bad += memcmp(&t[0].frame.color[i], &t[1].frame.color[i], sizeof(float)) != 0;
        sum += t[0].frame.color[i];
    }
    printf("skipped %lld of %lld last rays, %d values differ\n", t[0].stats.rays_bsdf_skipped,
           t[0].stats.rays_bsdf + t[0].stats.rays_bsdf_skipped, bad);
    CHECK(bad == 0 && sum > 0.0);
    CHECK(t[0].stats.guarded_events == t[1].stats.guarded_events);
    CHECK(t[1].stats.rays_bsdf_skipped == 0);
    CHECK(t[0].stats.rays_bsdf + t[0].stats.rays_bsdf_skipped == t[1].stats.rays_bsdf);
    CHECK(expect_skips ? t[0].stats.rays_bsdf_skipped > t[0].stats.rays_bsdf : t[0].stats.rays_bsdf_skipped == 0);
    for (int k = 0; k < 2; ++k) test_render_free(&t[k]);
}

/* Lambert receivers and the conductor sphere: without records only the conductor's last rays
 * are sampled (traced or skipped); with the bounce records every receiver's are, and traced. */
static void test_lambert_last_rays(void)
{
    char text[4096], glossy[4096];
    snprintf(text, sizeof text, LIT, "", "diffuse", "");
    snprintf(glossy, sizeof glossy, LIT, "", GLOSSY, GLOSSY_ARGS);
    TestRender t[3];
    RenderOptions o = {0};
    o.width = 24, o.height = 18, o.threads = 2, o.seed = 3, o.spp = 16;
    bool ok = test_render(text, &o, &t[0]);
    ok = test_render(glossy, &o, &t[2]) && ok;
    o.record_ray_geometry = true;
    ok = test_render(text, &o, &t[1]) && ok;
    CHECK(ok);
    if (!ok) return;
    long long lambert = t[0].stats.rays_bsdf + t[0].stats.rays_bsdf_skipped;
    long long glossy_all = t[2].stats.rays_bsdf + t[2].stats.rays_bsdf_skipped;
    printf("Lambert receivers: %lld last rays sampled without records (all glossy: %lld), %lld traced with them\n",
           lambert, glossy_all, t[1].stats.rays_bsdf);
    CHECK(lambert > 0 && 4 * lambert < glossy_all); /* the conductor sphere's alone */
    CHECK(t[1].stats.rays_bsdf > 2 * lambert && t[1].stats.rays_bsdf_skipped == 0);
    for (int k = 0; k < 3; ++k) test_render_free(&t[k]);
}

/* Counts the records that carry shadow and bounce ray geometry. */
typedef struct {
    long long shadow, bounce;
} GeometryCount;

static void count_geometry(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py;
    GeometryCount *c = ctx;
    __atomic_add_fetch(&c->shadow, r->shadow_count > 0, __ATOMIC_RELAXED);
    __atomic_add_fetch(&c->bounce, r->bounce_count > 0, __ATOMIC_RELAXED);
}

/* The shadow geometry alone (renderer_set_record_bounce_geometry off: a maxdepth-1 frame
 * whose filters read only the shadow rays) keeps the box test: the same values, the same
 * traced and skipped last rays and the same shadow rays as a render without records, with
 * every area-light shadow ray recorded and no bounce ray; with the bounce geometry on, no
 * last ray is skipped and the bounce rays are recorded. */
static void test_shadow_geometry_keeps_box_test(void)
{
    char text[4096];
    snprintf(text, sizeof text, LIT, "", GLOSSY, GLOSSY_ARGS);
    RenderOptions o = {0};
    o.width = 24, o.height = 18, o.threads = 2, o.seed = 5, o.spp = 16;
    TestRender plain;
    bool ok = test_render(text, &o, &plain);
    CHECK(ok);
    if (!ok) return;
    o.record_ray_geometry = true;
    for (int bounce = 0; bounce < 2; ++bounce) {
        SceneDesc scene;
        Renderer *r = NULL;
        Frame f;
        Diag err = {0};
        bool made = scene_parse_string(text, strlen(text), "<test>", NULL, &scene, &err);
        CHECK(made);
        if (!made) break;
        scene_analyze_effects(&scene);
        made = renderer_create(&scene, &o, &r, &err) && frame_init(&f, renderer_width(r), renderer_height(r));
        CHECK(made);
        if (!made) {
            renderer_destroy(r);
            scene_desc_free(&scene);
            break;
        }
        renderer_set_record_bounce_geometry(r, bounce);
        GeometryCount c = {0, 0};
        SampleSink sink = {count_geometry, &c};
        render_pass(r, 0, NULL, renderer_spp(r), &f, &sink);
        RenderStats st = renderer_stats(r);
        size_t n = (size_t)o.width * (size_t)o.height;
        int bad = 0;
        for (size_t i = 0; i < 3 * n; ++i) bad += memcmp(&plain.frame.color[i], &f.color[i], sizeof(float)) != 0;
        printf("bounce geometry %s: %d values differ, traced %lld skipped %lld last rays (plain: %lld %lld), "
               "records with shadow %lld bounce %lld\n",
               bounce ? "on" : "off", bad, st.rays_bsdf, st.rays_bsdf_skipped, plain.stats.rays_bsdf,
               plain.stats.rays_bsdf_skipped, c.shadow, c.bounce);
        CHECK(bad == 0);
        CHECK(st.rays_shadow == plain.stats.rays_shadow && c.shadow > 0);
        if (bounce) {
            CHECK(st.rays_bsdf_skipped == 0 && st.rays_bsdf == plain.stats.rays_bsdf + plain.stats.rays_bsdf_skipped);
            CHECK(c.bounce > 0);
        } else {
            CHECK(st.rays_bsdf == plain.stats.rays_bsdf && st.rays_bsdf_skipped == plain.stats.rays_bsdf_skipped);
            CHECK(st.rays_bsdf_skipped > st.rays_bsdf && c.bounce == 0);
        }
        frame_free(&f);
        renderer_destroy(r);
        scene_desc_free(&scene);
    }
    test_render_free(&plain);
}

/* The slab test written out independently, one ray at a time (the oracle of the batched one,
 * which lights_ray_may_reach_emitter also calls): t in [0, inf), NaNs passed over. */
static bool slab_test_reference(vec3 lo, vec3 hi, vec3 o, vec3 d)
{
    float o3[3] = {o.x, o.y, o.z}, d3[3] = {d.x, d.y, d.z}, lo3[3] = {lo.x, lo.y, lo.z}, hi3[3] = {hi.x, hi.y, hi.z};
    float t_near = 0.0f, t_far = INFINITY;
    for (int a = 0; a < 3; ++a) {
        float inv = 1.0f / d3[a];
        float t0 = (lo3[a] - o3[a]) * inv, t1 = (hi3[a] - o3[a]) * inv;
        float tn = t0 < t1 ? t0 : t1, tf = t0 < t1 ? t1 : t0;
        if (tn > t_near) t_near = tn;
        if (tf < t_far) t_far = tf;
    }
    return t_near <= t_far;
}

static void test_batch_equals_single(void)
{
    TestLights b;
    bool built = test_build_lights(EMITTERS, &b);
    CHECK(built);
    if (!built) return;
    const LightSet *L = &b.L;
    enum { N = 4099 };
    static float o[3][N], d[3][N];
    static int may[N];
    Pcg32 rng;
    pcg32_seed(&rng, 7, 3);
    vec3 lo = L->emitter_lo, hi = L->emitter_hi;
    const float special[] = {0.0f, -0.0f, INFINITY, -INFINITY, NAN, 1.0f, -1.0f};
    for (int k = 0; k < N; ++k) {
        vec3 oo = v3(12.0f * pcg32_float(&rng) - 6.0f, 6.0f * pcg32_float(&rng) - 0.5f, 12.0f * pcg32_float(&rng) - 6.0f);
        vec3 dd = warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng)));
        float oc[3] = {oo.x, oo.y, oo.z}, dc[3] = {dd.x, dd.y, dd.z};
        float loc[3] = {lo.x, lo.y, lo.z}, hic[3] = {hi.x, hi.y, hi.z};
        int axis = k % 3;
        switch (k % 5) {
        case 1: dc[axis] = special[(k / 5) % 7]; break;               /* axis-parallel and odd directions */
        case 2: oc[axis] = (k / 5) % 2 ? loc[axis] : hic[axis];     /* on a face's plane ... */
                dc[axis] = (k / 10) % 3 == 0 ? 0.0f : dc[axis];       /* ... sometimes parallel to it */
                break;
        case 3: dc[0] = dc[1] = dc[2] = 0.0f; break;                  /* no direction */
        case 4: oc[axis] = special[(k / 5) % 7]; break;               /* odd origins */
        default: break;
        }
        for (int a = 0; a < 3; ++a) o[a][k] = oc[a], d[a][k] = dc[a];
    }
    const float *op[3] = {o[0], o[1], o[2]}, *dp[3] = {d[0], d[1], d[2]};
    int counts[] = {N, 1, 15, 17, 255};
    int wrong = 0, reach = 0;
    for (int c = 0; c < 5; ++c) {
        lights_rays_may_reach_emitter(L, counts[c], op, dp, may);
        for (int k = 0; k < counts[c]; ++k) {
            bool single = slab_test_reference(lo, hi, v3(o[0][k], o[1][k], o[2][k]), v3(d[0][k], d[1][k], d[2][k]));
            wrong += (may[k] != 0) != single;
            reach += c == 0 && single;
        }
    }
    printf("batched box test: %d of %d rays may reach, %d answers differ\n", reach, N, wrong);
    CHECK(wrong == 0);
    CHECK(reach > N / 10 && reach < N - N / 10); /* both answers occur */
    test_lights_free(&b);
}

int main(void)
{
    test_box_oracle();
    test_batch_equals_single();
    test_moving_emitter();
    test_skipped_rays_change_nothing("", GLOSSY, GLOSSY_ARGS, true);
    test_skipped_rays_change_nothing("AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
                                     "  Translate 0 0.4 -1.2 Shape \"sphere\" \"float radius\" [ 0.4 ] AttributeEnd\n",
                                     GLOSSY, GLOSSY_ARGS, true);
    test_skipped_rays_change_nothing("LightSource \"infinite\" \"rgb L\" [ 0.2 0.2 0.2 ]\n", GLOSSY, GLOSSY_ARGS, false);
    /* Lambert receivers and a cut sphere that emits both ways, its opening towards the floor
     * (cone sampling misses its far cap's inside): light sampling alone would lose that light,
     * so the last vertices keep MIS and their rays, which the box test still skips */
    test_skipped_rays_change_nothing("AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ] \"bool twosided\" true\n"
                                     "  Translate 1.5 1.2 1 Rotate 90 1 0 0 Shape \"sphere\" \"float radius\" [ 0.35 ]"
                                     " \"float zmax\" [ 0.1 ] AttributeEnd\n",
                                     "diffuse", "", true);
    test_lambert_last_rays();
    test_shadow_geometry_keeps_box_test();
    CHECK_DONE();
}
