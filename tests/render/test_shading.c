/* Glossy materials, textures and the image environment through the whole renderer
 * (integrator + materials + lights), against closed forms:
 *  - white furnace: a sphere inside a uniform environment of radiance 1 reflects at most
 *    radiance 1 for every glossy material; a smooth dielectric sphere (lossless: every
 *    path leaves it again) shows exactly 1;
 *  - a smooth conductor with normal-incidence reflectance 1 is a mirror: the camera sees
 *    an emitter of radiance L through it with radiance R L (R = 0.9999, pbrt-v4's clamp),
 *    and the sample records mark that light as unfiltered (delta lobe);
 *  - a Lambert plane textured with an imagemap (point filter) under a distant light of
 *    irradiance pi shows the texel values (radiance = reflectance E / pi), and scale / mix
 *    textures over it give tex * s and (1 - a) t1 + a t2;
 *  - an image environment seen by the camera (exactly its texel) and lighting a Lambert
 *    plane: uniform map (rho c s) and a map bright around +z, whose irradiance is a sum
 *    over its rows (orientation, importance sampling and MIS through the renderer). */
#include <unistd.h>

#include "check.h"
#include "io/image_io.h"
#include "render_test_util.h"

#define MT_PI_ 3.14159265358979323846

/* ---- sample-record statistics through a sink (1 thread: no locking needed) ---- */

typedef struct {
    long n, unfilterable;
    double direct, unfiltered, phong_min;
} RecStats;

static void rec_add(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py;
    RecStats *s = ctx;
    if (!r->hit) return;
    ++s->n;
    s->unfilterable += r->unfilterable;
    s->direct += r->direct.y;
    s->unfiltered += r->unfiltered.y;
    if (s->n == 1 || r->phong_exponent < s->phong_min) s->phong_min = r->phong_exponent;
}

/* Renders text (1 thread, seed 5) with every sample record fed to sink. */
static bool render_into(const char *text, TestRender *t, SampleSink sink)
{
    RenderOptions o = {0};
    o.threads = 1;
    o.seed = 5;
    return test_render_sink(text, &o, &sink, t);
}

static bool render_with_sink(const char *text, TestRender *t, RecStats *rs)
{
    return render_into(text, t, (SampleSink){rec_add, rs});
}

/* ---- white furnace ---- */

/* Mean radiance (green) of a sphere filling the whole frame inside a uniform environment. */
static double furnace_sphere(const char *material, int max_depth, bool *finite)
{
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 0 -3  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 20 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 12 ] \"integer yresolution\" [ 12 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ %d ]\n"
             "WorldBegin\n"
             "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
             "%s\n"
             "Shape \"sphere\" \"float radius\" [ 1 ]\n",
             max_depth, material);
    TestRender t;
    if (!test_render(text, NULL, &t)) {
        CHECK(false);
        *finite = false;
        return -1.0;
    }
    *finite = test_frame_finite(&t.frame);
    size_t n = (size_t)t.frame.width * t.frame.height;
    double sum = 0.0, hits = 0.0;
    for (size_t i = 0; i < n; ++i) sum += t.frame.color[3 * i + 1], hits += t.frame.hits[i];
    double spp = 0.0;
    for (size_t i = 0; i < n; ++i) spp += t.frame.spp[i];
    CHECK_NEAR(hits, spp, 0.5); /* every camera ray hits the sphere */
    test_render_free(&t);
    return sum / spp;
}

static void test_white_furnace(void)
{
    static const char *const materials[] = {
        "Material \"conductor\" \"spectrum reflectance\" [ 400 1 700 1 ] \"float roughness\" [ 0.3 ]",
        "Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ] \"float roughness\" [ 0.05 ]",
        "Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ] \"float uroughness\" [ 0.5 ] \"float vroughness\" [ 0.05 ]",
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 1 1 1 ] \"float roughness\" [ 0.2 ]",
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 1 1 1 ] \"float roughness\" [ 0 ]",
        "Material \"dielectric\" \"float roughness\" [ 0.3 ]",
        "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" [ 0.1 ]",
        /* zero (or negative) roughness on one axis only: rough along the other (pbrt-v4 keeps
         * alpha >= 1e-4 per axis unless both are smooth); these rendered black */
        "Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ] \"float uroughness\" [ 0 ] \"float vroughness\" [ 0.3 ]",
        "Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ] \"float uroughness\" [ -0.2 ] \"float vroughness\" [ 0.3 ]",
        "Material \"dielectric\" \"float uroughness\" [ 0.3 ] \"float vroughness\" [ 0 ]",
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 1 1 1 ] \"float uroughness\" [ 0 ] \"float vroughness\" [ 0.3 ]",
    };
    for (size_t i = 0; i < sizeof materials / sizeof materials[0]; ++i) {
        bool finite = false;
        double L = furnace_sphere(materials[i], 8, &finite);
        fprintf(stderr, "furnace %-100.100s L = %.4f\n", materials[i], L);
        CHECK(finite);
        /* 12x12x64 samples: the statistical error of the mean is far below 1% here */
        CHECK(L <= 1.01);
        CHECK(L >= 0.3); /* something is reflected */
    }
    /* A smooth dielectric sphere loses nothing: every path that enters leaves again (no
     * total internal reflection in a sphere), so with enough depth the radiance is 1. */
    bool finite = false;
    double L = furnace_sphere("Material \"dielectric\" \"float eta\" [ 1.5 ]", 24, &finite);
    fprintf(stderr, "furnace smooth dielectric L = %.5f (1)\n", L);
    CHECK(finite);
    CHECK_NEAR(L, 1.0, 0.01);
    /* a mix of two conductors stays below 1 too */
    L = furnace_sphere("MakeNamedMaterial \"a\" \"string type\" \"conductor\" \"rgb reflectance\" [ 1 1 1 ] "
                       "\"float roughness\" [ 0.1 ]\n"
                       "MakeNamedMaterial \"b\" \"string type\" \"dielectric\"\n"
                       "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [ \"a\" \"b\" ] "
                       "\"float amount\" [ 0.5 ]\nNamedMaterial \"m\"",
                       24, &finite);
    fprintf(stderr, "furnace mix L = %.5f\n", L);
    CHECK(finite);
    CHECK(L <= 1.01 && L >= 0.3);
}

/* Roughness from a float texture gives the same image as the same constant (the texture is
 * evaluated per hit; the sample sequence is unchanged). */
static void test_roughness_texture(void)
{
    static const char *const pair[2] = {
        "Material \"conductor\" \"rgb reflectance\" [ 0.9 0.8 0.5 ] \"float roughness\" [ 0.2 ]",
        "Texture \"r\" \"float\" \"constant\" \"float value\" [ 0.2 ]\n"
        "Texture \"r2\" \"float\" \"scale\" \"texture tex\" \"r\" \"float scale\" [ 1 ]\n"
        "Material \"conductor\" \"rgb reflectance\" [ 0.9 0.8 0.5 ] \"texture roughness\" \"r2\"",
    };
    bool finite = false;
    double a = furnace_sphere(pair[0], 4, &finite);
    double b = furnace_sphere(pair[1], 4, &finite);
    CHECK(a == b);
}

/* ---- mirror ---- */

static void test_conductor_mirror(void)
{
    /* Camera above a mirror floor (z = 0) looking down; a two-sided emitter of radiance L
     * above the camera fills every reflected direction. maxdepth 1: only what the first
     * hit reflects directly. */
    const char *text = "LookAt 0 0 1  0 0 0  0 1 0\n"
                       "Camera \"perspective\" \"float fov\" [ 30 ]\n"
                       "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
                       "Sampler \"independent\" \"integer pixelsamples\" [ 4 ]\n"
                       "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
                       "WorldBegin\n"
                       "AttributeBegin\n"
                       " AreaLightSource \"diffuse\" \"rgb L\" [ 2 3 4 ] \"bool twosided\" true\n"
                       " Shape \"trianglemesh\" \"point3 P\" [ -10 -10 2  10 -10 2  10 10 2  -10 10 2 ] "
                       "\"integer indices\" [ 0 1 2 0 2 3 ]\n"
                       "AttributeEnd\n"
                       "Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ] \"float roughness\" [ 0 ]\n"
                       "Shape \"trianglemesh\" \"point3 P\" [ -10 -10 0  10 -10 0  10 10 0  -10 10 0 ] "
                       "\"integer indices\" [ 0 1 2 0 2 3 ]\n";
    TestRender t;
    RecStats rs = {0};
    if (!render_with_sink(text, &t, &rs)) {
        CHECK(false);
        return;
    }
    const double R = 0.9999; /* pbrt-v4 clamps the reflectance parameterisation below 1 */
    const double L[3] = {2, 3, 4};
    for (int y = 0; y < 8; y += 3)
        for (int x = 0; x < 8; x += 3) {
            double rgb[3];
            test_pixel(&t, x, y, rgb);
            for (int c = 0; c < 3; ++c) CHECK_NEAR(rgb[c], R * L[c], 1e-4 * L[c]);
        }
    /* every sample hit the mirror: all of it is delta light, to be passed through */
    CHECK(rs.n == 8 * 8 * 4);
    CHECK(rs.unfilterable == rs.n);
    CHECK_NEAR(rs.unfiltered, rs.direct, 1e-6 * rs.direct);
    CHECK(rs.phong_min > 1000.0); /* a delta lobe's exponent is the maximum */
    test_render_free(&t);
}

/* ---- textures ---- */

/* Plane [-1,1]^2 at z = 0 with uv = (x+1)/2, (y+1)/2, seen from above; a distant light
 * straight down with L = pi, so radiance = reflectance (Lambert: rho / pi * E). */
static bool render_textured(const char *textures, TestRender *t)
{
    char text[4096];
    snprintf(text, sizeof text,
             "LookAt 0 0 10  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 8 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 4 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n"
             "LightSource \"distant\" \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 3.14159265 "
             "3.14159265 3.14159265 ]\n"
             "%s\n"
             "Material \"diffuse\" \"texture reflectance\" \"top\"\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "
             "\"point2 uv\" [ 0 0  1 0  1 1  0 1 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n",
             textures);
    return test_render(text, NULL, t);
}

static void test_textures(void)
{
    /* a 2x2 linear EXR: top row (v = 1) red-ish and green-ish, bottom row blue-ish and grey */
    const float texels[4][3] = {{0.8f, 0.1f, 0.1f}, {0.1f, 0.7f, 0.2f}, {0.2f, 0.1f, 0.6f}, {0.3f, 0.3f, 0.3f}};
    char path[256];
    snprintf(path, sizeof path, "/tmp/wedge_test_shading_%d.exr", (int)getpid());
    ExrChannel ch[3] = {{"R", &texels[0][0], 3}, {"G", &texels[0][1], 3}, {"B", &texels[0][2], 3}};
    Diag err = {0};
    if (!exr_write(path, 2, 2, ch, 3, NULL, 0, &err)) {
        fprintf(stderr, "%s\n", err.message);
        CHECK(false);
        return;
    }
    /* pbrt's LookAt makes image right = world -x here (a left-handed camera frame), image
     * top = world +y. So image column < 4 sees u > 0.5 (texel column 1), row < 4 sees v > 0.5
     * (texel row 0, the top of the image file). */
    const int px[4][2] = {{6, 1}, {1, 1}, {6, 6}, {1, 6}}; /* pixel showing texel k */
    char tex[1024];
    for (int variant = 0; variant < 3; ++variant) {
        if (variant == 0)
            snprintf(tex, sizeof tex,
                     "Texture \"top\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"point\"", path);
        else if (variant == 1)
            snprintf(tex, sizeof tex,
                     "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"point\"\n"
                     "Texture \"half\" \"float\" \"constant\" \"float value\" [ 0.5 ]\n"
                     "Texture \"top\" \"spectrum\" \"scale\" \"texture tex\" \"img\" \"texture scale\" \"half\"",
                     path);
        else
            snprintf(tex, sizeof tex,
                     "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"point\"\n"
                     "Texture \"top\" \"spectrum\" \"mix\" \"rgb tex1\" [ 1 1 1 ] \"texture tex2\" \"img\" "
                     "\"float amount\" [ 0.25 ]",
                     path);
        TestRender t;
        if (!render_textured(tex, &t)) {
            CHECK(false);
            continue;
        }
        for (int k = 0; k < 4; ++k) {
            double rgb[3];
            test_pixel(&t, px[k][0], px[k][1], rgb);
            for (int c = 0; c < 3; ++c) {
                double want = texels[k][c];
                if (variant == 1) want *= 0.5;
                if (variant == 2) want = 0.75 * 1.0 + 0.25 * want;
                CHECK_NEAR(rgb[c], want, 1e-4);
            }
        }
        CHECK(t.scene.warning_count == 0);
        test_render_free(&t);
    }
    /* a mix material of black and white Lambert picks white with probability "amount"
     * (pbrt-v4 MixMaterial: a per-hit choice, not a blend) */
    {
        TestRender t;
        const char *mix = "Texture \"top\" \"spectrum\" \"constant\" \"rgb value\" [ 1 1 1 ]\n"
                          "MakeNamedMaterial \"black\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
                          "MakeNamedMaterial \"white\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 1 1 1 ]\n"
                          "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [ \"black\" \"white\" ] "
                          "\"float amount\" [ 0.25 ]\n"
                          "NamedMaterial \"m\"\n"
                          "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0.001  1 -1 0.001  1 1 0.001  -1 1 0.001 ] "
                          "\"integer indices\" [ 0 1 2 0 2 3 ]";
        if (render_textured(mix, &t)) {
            /* 8x8x4 samples, each 0 or 1: the mean's standard deviation is 0.027 */
            double m = test_mean(&t);
            fprintf(stderr, "mix material mean %.4f (0.25)\n", m);
            CHECK_NEAR(m, 0.25, 0.09);
            CHECK(t.scene.warning_count == 0);
            test_render_free(&t);
        } else {
            CHECK(false);
        }
    }

    /* a missing file is an error at the Texture statement */
    TestRender t;
    memset(&t, 0, sizeof t);
    const char *bad = "WorldBegin\nTexture \"top\" \"spectrum\" \"imagemap\" \"string filename\" \"/nonexistent/x.exr\"\n"
                      "Material \"diffuse\" \"texture reflectance\" \"top\"\nShape \"sphere\"\n";
    if (scene_parse_string(bad, strlen(bad), "<bad>", NULL, &t.scene, &err)) {
        RenderOptions o = {0};
        CHECK(!renderer_create(&t.scene, &o, &t.r, &err));
        CHECK(err.exit_code == WEDGE_EXIT_INPUT);
        CHECK(strstr(err.message, "<bad>:2:") != NULL);
        CHECK(strstr(err.message, "/nonexistent/x.exr") != NULL);
        if (!strstr(err.message, "/nonexistent/x.exr")) fprintf(stderr, "message: %s\n", err.message);
        scene_desc_free(&t.scene);
    }
    unlink(path);
}

/* ---- image environment ---- */

static void test_envmap_light(void)
{
    /* A uniform lat-long map (2:1) of radiance c scaled by "scale" s. A diffuse plane of
     * reflectance rho facing +z
     * sees the upper hemisphere: radiance rho c s (its lower half is hidden by the plane).
     * The camera also sees the map directly where it misses the plane. */
    float *rgb = malloc(16 * 8 * 3 * sizeof(float));
    for (int i = 0; i < 16 * 8; ++i) rgb[3 * i] = 0.5f, rgb[3 * i + 1] = 1.0f, rgb[3 * i + 2] = 2.0f;
    char path[256];
    snprintf(path, sizeof path, "/tmp/wedge_test_shading_env_%d.exr", (int)getpid());
    ExrChannel ch[3] = {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}};
    Diag err = {0};
    if (!exr_write(path, 16, 8, ch, 3, NULL, 0, &err)) {
        CHECK(false);
        free(rgb);
        return;
    }
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 0 10  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 8 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n"
             "LightSource \"infinite\" \"string filename\" \"%s\" \"float scale\" [ 0.5 ]\n"
             "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -0.5 -1 0  0.5 -1 0  0.5 1 0  -0.5 1 0 ] "
             "\"integer indices\" [ 0 1 2 0 2 3 ]\n",
             path);
    TestRender t;
    if (!test_render(text, NULL, &t)) {
        CHECK(false);
    } else {
        const double c[3] = {0.5, 1.0, 2.0};
        double on[3], off[3];
        test_pixel(&t, 4, 4, on);  /* on the plane */
        test_pixel(&t, 0, 4, off); /* beside it: the map itself */
        for (int k = 0; k < 3; ++k) {
            CHECK_NEAR(off[k], 0.5 * c[k], 1e-5);
            CHECK_NEAR(on[k], 0.6 * 0.5 * c[k], 0.03 * 0.6 * 0.5 * c[k]);
        }
        CHECK(t.scene.warning_count == 0);
        test_render_free(&t);
    }
    unlink(path);
    free(rgb);
}

/* A lat-long map (2:1, row 0 at +z) brighter near the +z pole: the plane facing +z gets the
 * irradiance E = sum over the upper rows of 2 pi L_row (sin^2 theta_1 - sin^2 theta_0) / 2
 * (piecewise-constant rows, nearest-texel lookups), so its radiance is rho E / pi. This
 * exercises the map's orientation and its importance sampling against BSDF sampling. */
static void test_envmap_banded(void)
{
    enum { W = 32, H = 16 };
    float *rgb = malloc(W * H * 3 * sizeof(float));
    double E = 0.0;
    for (int y = 0; y < H; ++y) {
        float L = y < 3 ? 20.0f : (y < 8 ? 0.5f : 0.1f);
        for (int x = 0; x < W; ++x) rgb[3 * (y * W + x)] = rgb[3 * (y * W + x) + 1] = rgb[3 * (y * W + x) + 2] = L;
        if (y < H / 2) {
            double t0 = MT_PI_ * y / H, t1 = MT_PI_ * (y + 1) / H;
            E += 2.0 * MT_PI_ * L * (sin(t1) * sin(t1) - sin(t0) * sin(t0)) / 2.0;
        }
    }
    char path[256];
    snprintf(path, sizeof path, "/tmp/wedge_test_shading_band_%d.exr", (int)getpid());
    ExrChannel ch[3] = {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}};
    Diag err = {0};
    bool ok = exr_write(path, W, H, ch, 3, NULL, 0, &err);
    free(rgb);
    if (!ok) {
        CHECK(false);
        return;
    }
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 0 10  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 4 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 256 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n"
             "LightSource \"infinite\" \"string filename\" \"%s\"\n"
             "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n",
             path);
    TestRender t;
    if (test_render(text, NULL, &t)) {
        double want = 0.5 * E / MT_PI_;
        double m = test_mean(&t);
        fprintf(stderr, "banded environment: plane radiance %.4f (%.4f)\n", m, want);
        CHECK_NEAR(m, want, 0.02 * want);
        test_render_free(&t);
    } else {
        CHECK(false);
    }
    unlink(path);
}

/* ---- a delta light's direct light beside an area light ---- */

typedef struct {
    long samples, over;        /* hits; hits whose unfiltered light exceeds their direct light */
    double unfiltered;         /* sum of unfiltered (green) */
} SplitStats;

static void split_add(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py;
    SplitStats *s = ctx;
    if (!r->hit) return;
    ++s->samples;
    s->over += r->unfiltered_direct.y > r->direct.y || r->unfiltered.y != 0.0f;
    s->unfiltered += r->unfiltered_direct.y;
}

/* A Lambert plane (reflectance 0.5) filling the frame under a distant light straight down
 * (L = 1: radiance 0.5 / pi), plus area_light. */
static bool render_split(const char *area_light, SplitStats *s)
{
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 0 10  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 8 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n"
             "LightSource \"distant\" \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 1 1 1 ]\n"
             "%s\n"
             "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] \"integer indices\" [ 0 1 2  0 2 3 ]\n",
             area_light);
    TestRender t;
    bool ok = render_into(text, &t, (SampleSink){split_add, s});
    test_render_free(&t);
    return ok;
}

/* A point, spot or distant light's direct light is set apart from the soft-shadow filters
 * (SampleRecord.unfiltered_direct) when the scene has an area light, whose direct light they filter:
 * its shadows are hard. With a two-sided area light off to the side (not shadowing the
 * plane), the mean unfiltered light per sample is the distant light's radiance 0.5 / pi
 * (light selection makes it noisy: 1.5% at 4096 samples, hence 5%), never more than the
 * sample's direct light, and none of it in `unfiltered` (which gbuffer_add may attribute to
 * indirect light). Without an area light nothing filters direct light, and none is set apart. */
static void test_delta_light_unfiltered(void)
{
    SplitStats with = {0}, without = {0};
    CHECK(render_split("AttributeBegin\n Translate 2.5 0 3\n AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]"
                       " \"bool twosided\" true\n Shape \"trianglemesh\" \"point3 P\" [ -0.2 -0.2 0  -0.2 0.2 0  0.2 0.2 0"
                       "  0.2 -0.2 0 ] \"integer indices\" [ 0 1 2  0 2 3 ]\nAttributeEnd",
                       &with));
    double want = 0.5 / MT_PI_, mean = with.samples ? with.unfiltered / (double)with.samples : 0.0;
    CHECK(with.samples == 8 * 8 * 64 && with.over == 0);
    CHECK_NEAR(mean, want, 0.05 * want);
    CHECK(render_split("", &without));
    CHECK(without.samples == 8 * 8 * 64 && without.unfiltered == 0.0);
    fprintf(stderr, "delta light: mean unfiltered %.5f (want %.5f)\n", mean, want);
}

int main(void)
{
    test_delta_light_unfiltered();
    test_white_furnace();
    test_roughness_texture();
    test_conductor_mirror();
    test_textures();
    test_envmap_light();
    test_envmap_banded();
    CHECK_DONE();
}
