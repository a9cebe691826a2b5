/* Environment map: both parameterisations are bijections (round trips) and the octahedral
 * one is equal-area (uniform square -> uniform sphere); a constant map has the uniform
 * pdf 1/(4 pi); pdfs integrate to 1; sampling matches the pdf (chi-square); sample / eval
 * consistency; perfect importance sampling for the equal-area layout; the light transform;
 * bad aspect ratios are errors. */
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "io/image_io.h"
#include "materials_test_util.h"
#include "render/envmap.h"

static vec3 random_dir(Pcg32 *r)
{
    double z = 1.0 - 2.0 * pcg32_float(r), phi = 2.0 * MT_PI * pcg32_float(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return v3((float)(s * cos(phi)), (float)(s * sin(phi)), (float)z);
}

static bool square_sample(void *ctx, Pcg32 *rng, vec3 *w)
{
    (void)ctx;
    *w = envmap_equal_area_to_dir(v2(pcg32_float(rng), pcg32_float(rng)));
    return true;
}
static double uniform_pdf(void *ctx, vec3 w)
{
    (void)ctx, (void)w;
    return 1.0 / (4.0 * MT_PI);
}

static bool env_sample(void *ctx, Pcg32 *rng, vec3 *w)
{
    vec3 Le;
    float pdf;
    return envmap_sample(ctx, v2(pcg32_float(rng), pcg32_float(rng)), w, &Le, &pdf);
}
static double env_pdf(void *ctx, vec3 w) { return envmap_pdf(ctx, w); }

/* A test image: smooth gradient, a black band and a very bright small spot. */
static float *make_image(int w, int h)
{
    float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float *p = rgb + 3 * ((size_t)y * w + x);
            float g = 0.2f + (float)x / w + 0.5f * (float)y / h;
            p[0] = g, p[1] = 0.5f * g, p[2] = 0.1f;
            if (y == h / 2) p[0] = p[1] = p[2] = 0.0f;
            if (x == w / 4 && y == h / 4) p[0] = 200.0f, p[1] = 100.0f, p[2] = 50.0f;
        }
    return rgb;
}

static void check_consistency(const Envmap *e, uint64_t seed)
{
    Pcg32 rng;
    pcg32_seed(&rng, seed, 1);
    int bad = 0;
    double ratio_min = 1e30, ratio_max = 0.0;
    for (int i = 0; i < 5000; ++i) {
        vec3 w, Le;
        float pdf;
        if (!envmap_sample(e, v2(pcg32_float(&rng), pcg32_float(&rng)), &w, &Le, &pdf)) continue;
        if (fabsf(v3_length(w) - 1.0f) > 1e-5f) ++bad;
        float p2 = envmap_pdf(e, w);
        vec3 L2 = envmap_Le(e, w);
        if (fabsf(p2 - pdf) > 1e-4f * pdf) ++bad;
        if (fabsf(L2.x - Le.x) > 1e-6f * Le.x) ++bad;
        double ratio = (Le.x + Le.y + Le.z) / pdf;
        ratio_min = fmin(ratio_min, ratio), ratio_max = fmax(ratio_max, ratio);
    }
    CHECK(bad == 0);
    if (e->layout == ENVMAP_EQUAL_AREA) CHECK(ratio_max <= ratio_min * (1.0 + 1e-4)); /* L / pdf constant */
}

int main(void)
{
    Pcg32 rng;
    pcg32_seed(&rng, 42, 1);
    Diag err = {0};

    /* ---- parameterisations ---- */
    int bad = 0;
    for (int i = 0; i < 20000; ++i) {
        vec3 w = random_dir(&rng);
        vec3 a = envmap_equal_area_to_dir(envmap_dir_to_equal_area(w));
        vec3 b = envmap_latlong_to_dir(envmap_dir_to_latlong(w));
        if (v3_length(v3_sub(a, w)) > 1e-5f || v3_length(v3_sub(b, w)) > 2e-5f) ++bad;
        vec2 uv = v2(pcg32_float(&rng), pcg32_float(&rng));
        vec2 uv2 = envmap_dir_to_equal_area(envmap_equal_area_to_dir(uv));
        if (fabsf(uv2.x - uv.x) > 2e-5f || fabsf(uv2.y - uv.y) > 2e-5f) ++bad;
        if (fabsf(v3_length(envmap_equal_area_to_dir(uv)) - 1.0f) > 1e-5f) ++bad;
    }
    CHECK(bad == 0);
    /* landmarks: centre is +z, corners are -z, edge midpoints are the equator */
    CHECK_NEAR(envmap_equal_area_to_dir(v2(0.5f, 0.5f)).z, 1.0, 1e-6);
    CHECK_NEAR(envmap_equal_area_to_dir(v2(0.0f, 0.0f)).z, -1.0, 1e-6);
    CHECK_NEAR(envmap_equal_area_to_dir(v2(1.0f, 1.0f)).z, -1.0, 1e-6);
    CHECK_NEAR(envmap_equal_area_to_dir(v2(1.0f, 0.5f)).x, 1.0, 1e-6);
    CHECK_NEAR(envmap_latlong_to_dir(v2(0.3f, 0.0f)).z, 1.0, 1e-6);
    CHECK_NEAR(envmap_latlong_to_dir(v2(0.25f, 0.5f)).y, 1.0, 1e-6);
    /* equal area: uniform points of the square are uniform on the sphere */
    CHECK(mt_chi2_ok("equal-area map of uniform square", mt_chi2(square_sample, uniform_pdf, NULL, 200000, 40, 80, 2, 5)));

    /* ---- constant maps ---- */
    {
        float *c = malloc(16 * 16 * 3 * sizeof(float));
        for (int i = 0; i < 16 * 16 * 3; ++i) c[i] = 0.7f;
        Envmap e;
        CHECK(envmap_init(&e, 16, 16, c, 2.0f, &err));
        CHECK(e.layout == ENVMAP_EQUAL_AREA);
        for (int i = 0; i < 1000; ++i) {
            vec3 w = random_dir(&rng);
            CHECK_NEAR(envmap_pdf(&e, w) * 4.0 * MT_PI, 1.0, 1e-5);
            CHECK_NEAR(envmap_Le(&e, w).y, 1.4, 1e-6);
        }
        CHECK_NEAR(envmap_mean_radiance(&e).x, 1.4, 1e-6);
        envmap_free(&e);
        free(c);

        float *l = malloc(64 * 32 * 3 * sizeof(float));
        for (int i = 0; i < 64 * 32 * 3; ++i) l[i] = 1.0f;
        CHECK(envmap_init(&e, 64, 32, l, 1.0f, &err));
        CHECK(e.layout == ENVMAP_LATLONG);
        /* at row centres the lat-long pdf is uniform up to the discretisation of sin */
        for (int y = 0; y < 32; ++y) {
            vec3 w = envmap_latlong_to_dir(v2(0.3f, (y + 0.5f) / 32.0f));
            CHECK_NEAR(envmap_pdf(&e, w) * 4.0 * MT_PI, 1.0, 2e-3);
        }
        CHECK_NEAR(mt_integrate_sphere(env_pdf, &e, 320, 640), 1.0, 1e-3);
        envmap_free(&e);
        free(l);
    }

    /* ---- a structured map, both layouts ---- */
    {
        float *img = make_image(32, 32);
        Envmap e;
        CHECK(envmap_init(&e, 32, 32, img, 1.0f, &err));
        CHECK_NEAR(mt_integrate_sphere(env_pdf, &e, 400, 800), 1.0, 2e-3);
        CHECK(mt_chi2_ok("envmap equal-area 32x32", mt_chi2(env_sample, env_pdf, &e, 200000, 40, 80, 8, 6)));
        check_consistency(&e, 7);
        /* the sampled estimate of the irradiance-like integral matches quadrature */
        double mc = 0.0, quad = 4.0 * MT_PI * envmap_mean_radiance(&e).x;
        int n = 100000;
        for (int i = 0; i < n; ++i) {
            vec3 w, Le;
            float pdf;
            if (envmap_sample(&e, v2(pcg32_float(&rng), pcg32_float(&rng)), &w, &Le, &pdf)) mc += Le.x / pdf;
        }
        CHECK_NEAR(mc / n / quad, 1.0, 0.02);
        /* the bright pixel is where its direction says */
        vec3 wspot = envmap_equal_area_to_dir(v2((8 + 0.5f) / 32.0f, (8 + 0.5f) / 32.0f));
        CHECK_NEAR(envmap_Le(&e, wspot).x, 200.0, 0);
        /* transform: a rotation moves the spot */
        Mat4 rot = mat4_rotate(90.0, 1.0, 0.0, 0.0);
        envmap_set_transform(&e, &rot);
        vec3 wrot = mat4_apply_vector(&rot, wspot);
        CHECK_NEAR(envmap_Le(&e, wrot).x, 200.0, 0);
        CHECK(envmap_Le(&e, wspot).x < 10.0f);
        CHECK_NEAR(mt_integrate_sphere(env_pdf, &e, 400, 800), 1.0, 2e-3);
        check_consistency(&e, 8);
        envmap_free(&e);
        free(img);

        img = make_image(16, 8);
        CHECK(envmap_init(&e, 16, 8, img, 1.0f, &err));
        CHECK_NEAR(mt_integrate_sphere(env_pdf, &e, 400, 800), 1.0, 2e-3);
        /* bins aligned with the pixels: theta edges at k pi / 8, phi edges at k pi / 8 */
        CHECK(mt_chi2_ok("envmap lat-long 16x8", mt_chi2(env_sample, env_pdf, &e, 200000, 40, 80, 6, 9)));
        check_consistency(&e, 10);
        envmap_free(&e);
        free(img);
    }

    /* ---- black map: still a valid (uniform) distribution, zero radiance ---- */
    {
        float z[4 * 4 * 3] = {0};
        Envmap e;
        CHECK(envmap_init(&e, 4, 4, z, 1.0f, &err));
        vec3 w, Le;
        float pdf;
        CHECK(envmap_sample(&e, v2(0.3f, 0.6f), &w, &Le, &pdf));
        CHECK_NEAR(pdf * 4.0 * MT_PI, 1.0, 1e-5);
        CHECK_NEAR(Le.x + Le.y + Le.z, 0.0, 0);
        envmap_free(&e);
    }

    /* ---- errors and hostile values ---- */
    {
        float px[3 * 2 * 3] = {0};
        Envmap e;
        CHECK(!envmap_init(&e, 3, 2, px, 1.0f, &err));
        CHECK(err.exit_code == WEDGE_EXIT_INPUT);
        CHECK(strstr(err.message, "environment map is 3x2: expected a square image") != NULL);
        float nanpx[2 * 2 * 3] = {NAN, 1.0f, 1.0f, INFINITY, -5.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
        CHECK(envmap_init(&e, 2, 2, nanpx, 1.0f, &err));
        for (int i = 0; i < 200; ++i) {
            vec3 w = random_dir(&rng);
            vec3 L = envmap_Le(&e, w);
            float p = envmap_pdf(&e, w);
            CHECK(isfinite(L.x) && isfinite(L.y) && isfinite(L.z) && L.x >= 0 && L.y >= 0 && isfinite(p));
        }
        envmap_free(&e);
        CHECK(!envmap_load(&e, "/nonexistent/wedge_no_such_env.exr", 1.0f, &err));
        /* a square EXR round trip: radiance = file value * scale, at the pixel's direction */
        const char *dir = getenv("WEDGE_BUILD_DIR");
        char path[1024];
        snprintf(path, sizeof path, "%s/materials_env_%d.exr", dir ? dir : "/tmp", (int)getpid());
        float img[4 * 4 * 3];
        for (int i = 0; i < 4 * 4 * 3; ++i) img[i] = 0.25f * (float)(i % 7);
        ExrChannel ch[3] = {{"R", img + 0, 3}, {"G", img + 1, 3}, {"B", img + 2, 3}};
        CHECK(exr_write(path, 4, 4, ch, 3, NULL, 0, &err));
        CHECK(envmap_load(&e, path, 2.0f, &err));
        CHECK(e.layout == ENVMAP_EQUAL_AREA && e.width == 4);
        vec3 w = envmap_equal_area_to_dir(v2(2.5f / 4.0f, 1.5f / 4.0f)); /* pixel (2, 1) */
        CHECK_NEAR(envmap_Le(&e, w).x, 2.0f * img[3 * (1 * 4 + 2) + 0], 1e-6);
        CHECK_NEAR(envmap_Le(&e, w).z, 2.0f * img[3 * (1 * 4 + 2) + 2], 1e-6);
        envmap_free(&e);
        /* a 3:1 file is refused, naming the file */
        CHECK(exr_write(path, 6, 2, ch, 3, NULL, 0, &err));
        CHECK(!envmap_load(&e, path, 1.0f, &err));
        CHECK(strstr(err.message, path) != NULL && strstr(err.message, "environment map is 6x2") != NULL);
        unlink(path);
    }
    CHECK_DONE();
}
