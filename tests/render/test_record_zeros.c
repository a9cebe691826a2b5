/* What the integrator leaves in a sample record when a sample finds nothing, and the shading
 * normal of meshes whose own normals are zero (issue 22, fifteenth round):
 *  - a camera ray that misses everything in a scene without infinite lights leaves every
 *    radiance field of its record at +0 (record_reset's clear; wave_first_hit adds nothing
 *    there) - and no radiance field of any record is -0: the integrator's sums start at +0,
 *    so wave_vertex_fold may skip adding the +0 of a last ray that found nothing;
 *  - a triangle whose interpolated normal is zero is shaded with its face normal, at the top
 *    level and through an instance (hit_shaded's and shade_hit's zero tests). */
#include "check.h"
#include "render_test_util.h"
#include "render/sample_record.h"

typedef struct {
    long miss, hit, miss_nonzero, negative_zero, nonfinite;
    double n_dot_up; /* smallest n_shading . (0, 1, 0) over the hits */
} Tally;

static bool is_neg_zero(float x) { return x == 0.0f && signbit(x); }

static void tally_add(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py;
    Tally *t = ctx;
    const vec3 f[6] = {r->L, r->emission, r->direct, r->indirect, r->unfiltered, r->unfiltered_direct};
    for (int k = 0; k < 6; ++k) {
        t->negative_zero += is_neg_zero(f[k].x) + is_neg_zero(f[k].y) + is_neg_zero(f[k].z);
        t->nonfinite += !isfinite(f[k].x) + !isfinite(f[k].y) + !isfinite(f[k].z);
    }
    if (!r->hit) {
        ++t->miss;
        for (int k = 0; k < 6; ++k) t->miss_nonzero += f[k].x != 0.0f || f[k].y != 0.0f || f[k].z != 0.0f;
        return;
    }
    double d = r->n_shading.y;
    if (t->hit == 0 || d < t->n_dot_up) t->n_dot_up = d;
    ++t->hit;
}

/* Renders text (1 thread, seed 7) with every record tallied. */
static bool render_tally(const char *text, TestRender *t, Tally *tally)
{
    memset(tally, 0, sizeof *tally);
    RenderOptions o = {0};
    o.threads = 1;
    o.seed = 7;
    SampleSink sink = {tally_add, tally};
    return test_render_sink(text, &o, &sink, t);
}

/* A camera looking straight down at the point (0, 0, 0) from height 1 with a 90 degree field
 * of view: the floor z in [-0.5, 0.5] x in [-2, 2] fills the middle half of the image's
 * rows, the rest sees nothing. */
#define HEADER                                                                                      \
    "LookAt 0 1 0  0 0 0  0 0 1\n"                                                                  \
    "Camera \"perspective\" \"float fov\" [ 90 ]\n"                                                 \
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"                  \
    "Sampler \"stratified\" \"integer pixelsamples\" [ 64 ]\n"                                      \
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"                                              \
    "WorldBegin\n"

#define FLOOR_P "\"point3 P\" [ -2 0 -0.5  2 0 -0.5  2 0 0.5  -2 0 0.5 ] \"integer indices\" [ 0 1 2  0 2 3 ]\n"

static void test_misses_and_quad_light(void)
{
    /* two small quad lights facing down, on either side of the view: most last BSDF rays from
     * the (glossy) floor miss the emitters' box (not traced), and most of the others pass
     * between the two lights (traced, found nothing) */
    const char *text = HEADER
        "AttributeBegin\n"
        "  AreaLightSource \"diffuse\" \"rgb L\" [ 50 50 50 ]\n"
        "  Shape \"trianglemesh\" \"point3 P\" [ 1.45 0.5 -0.05  1.45 0.5 0.05  1.55 0.5 0.05  1.55 0.5 -0.05 ]\n"
        "        \"integer indices\" [ 0 2 1  0 3 2 ]\n"
        "  Shape \"trianglemesh\" \"point3 P\" [ -1.55 0.5 -0.05  -1.55 0.5 0.05  -1.45 0.5 0.05  -1.45 0.5 -0.05 ]\n"
        "        \"integer indices\" [ 0 2 1  0 3 2 ]\n"
        "AttributeEnd\n"
        "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"float roughness\" [ 0.3 ]\n"
        "Shape \"trianglemesh\" " FLOOR_P;
    TestRender t;
    Tally tl;
    if (!render_tally(text, &t, &tl)) {
        CHECK(false);
        return;
    }
    double lit = 0.0;
    for (size_t i = 0; i < (size_t)renderer_width(t.r) * (size_t)renderer_height(t.r); ++i) lit += t.frame.direct[3 * i + 1];
    fprintf(stderr, "quad light: %ld misses (%ld not zero), %ld hits, -0 fields %ld, non-finite %ld, bsdf rays %lld, "
                    "skipped %lld, direct light %.4g\n",
            tl.miss, tl.miss_nonzero, tl.hit, tl.negative_zero, tl.nonfinite, t.stats.rays_bsdf, t.stats.rays_bsdf_skipped,
            lit);
    CHECK(tl.miss > 0 && tl.hit > 0);
    CHECK(tl.miss_nonzero == 0);
    CHECK(tl.negative_zero == 0);
    CHECK(tl.nonfinite == 0);
    CHECK(lit > 0.0);
    /* both kinds of last ray occur */
    CHECK(t.stats.rays_bsdf > 0 && t.stats.rays_bsdf_skipped > t.stats.rays_bsdf);
    test_render_free(&t);
}

/* A floor with an explicit zero normal at every vertex, under a distant light from above
 * (irradiance pi: radiance = reflectance), at the top level or placed by an instance. */
static void test_zero_normals(bool instanced)
{
    char text[4096];
    const char *mesh = "Shape \"trianglemesh\" " FLOOR_P "  \"normal N\" [ 0 0 0  0 0 0  0 0 0  0 0 0 ]\n";
    snprintf(text, sizeof text,
             HEADER "LightSource \"distant\" \"rgb L\" [ 3.14159265 3.14159265 3.14159265 ] \"point3 from\" [ 0 1 0 ] "
                    "\"point3 to\" [ 0 0 0 ]\n"
                    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                    "%s%s%s",
             instanced ? "ObjectBegin \"floor\"\n" : "", mesh,
             instanced ? "ObjectEnd\nAttributeBegin\n  Translate 0 0.1 0\n  ObjectInstance \"floor\"\nAttributeEnd\n" : "");
    TestRender t;
    Tally tl;
    if (!render_tally(text, &t, &tl)) {
        CHECK(false);
        return;
    }
    int w = renderer_width(t.r);
    size_t i = (size_t)8 * (size_t)w + 8;
    double centre = t.frame.color[3 * i + 1] / t.frame.spp[i];
    fprintf(stderr, "zero normals%s: %ld hits, smallest n_shading.y %.6f, centre radiance %.5f\n",
            instanced ? " (instance)" : "", tl.hit, tl.n_dot_up, centre);
    CHECK(tl.hit > 0);
    CHECK(tl.n_dot_up > 0.999999); /* the face normal, towards the camera: +y */
    CHECK_NEAR(centre, 0.5, 1e-5);
    CHECK(tl.negative_zero == 0 && tl.nonfinite == 0);
    test_render_free(&t);
}

int main(void)
{
    test_misses_and_quad_light();
    test_zero_normals(false);
    test_zero_normals(true);
    CHECK_DONE();
}
