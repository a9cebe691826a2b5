/* A render whose users read the radiance alone keeps it alone (RadianceRecord,
 * integrate_wave_radiance; issue 22): it must give what the whole record gives, bit for bit,
 * and drop nothing. Checked on scenes with every light kind (an area triangle and an area
 * sphere the camera sees, point, spot, distant, and an environment or none), diffuse,
 * rough and nearly smooth and smooth conductor, coated and dielectric surfaces, three
 * bounces, camera rays that miss, a pixel filter with negative lobes (weights other than 1),
 * and lights so bright that the integrator guards values, where each is added and in the
 * sums at the end:
 *  - the wave: every sample's L, emission, direct, indirect and filter weight from
 *    integrate_wave_radiance equal integrate_wave's, for an undeclared user and for one that
 *    declared the radiance alone, and so do the ray counts (and the guarded events, with the
 *    same declaration), whatever the records held before (filled with garbage first);
 *  - the renderer: a render declared radiance-only gives the colour, direct, indirect,
 *    emission and spp sums of an undeclared render and of the same declaration with a sink
 *    (which takes whole records) bit for bit, and the latter's counts;
 *  - integrate_wave for an undeclared user clears the motion and ray geometry entries it
 *    does not fill (record_reset), whatever the records held before.
 * The scenes are checked to have what could be dropped: misses with and without an
 * environment's emission, emitters seen directly, direct and indirect light, weights other
 * than 1, guarded events. Their environment shares the pick with a triangle light: where a
 * constant sky is the pick's only light, a frame no method filters takes it by another
 * estimator than an undeclared one (IntegratorScene.sky_bounce_alone, docs/design.md 12.30),
 * which test_closed_forms checks against the closed form. */
#include <stdatomic.h>

#include "check.h"
#include "render/integrator.h"
#include "render/render_reads.h"
#include "render_test_util.h"

#define HEADER                                                                                                         \
    "LookAt 0 1.2 -5  0 0.9 0  0 1 0\n"                                                                                \
    "Camera \"perspective\" \"float fov\" [ 55 ]\n"                                                                    \
    "Film \"rgb\" \"integer xresolution\" [ 20 ] \"integer yresolution\" [ 14 ]\n"                                     \
    "Sampler \"zsobol\" \"integer pixelsamples\" [ 16 ]\n"                                                             \
    "PixelFilter \"mitchell\"\n"                                                                                       \
    "Integrator \"path\" \"integer maxdepth\" [ 3 ]\n"                                                                 \
    "WorldBegin\n"

/* the floor ends at z = 3 and the walls are missing: the upper part of the image is a miss */
#define GEOMETRY                                                                                                       \
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.5 0.4 ]\n"                                        \
    "  Shape \"trianglemesh\" \"point3 P\" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"   \
    "AttributeEnd\n"                                                                                                   \
    "AttributeBegin Material \"conductor\" \"float roughness\" [ 0.02 ]\n"                                              \
    "  Translate -1.1 0.5 0 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n"                                  \
    "AttributeBegin Material \"conductor\" \"float roughness\" [ 0 ]\n"                                                \
    "  Translate 1.2 0.45 0.6 Shape \"sphere\" \"float radius\" [ 0.45 ] AttributeEnd\n"                               \
    "AttributeBegin Material \"coateddiffuse\" \"rgb reflectance\" [ 0.2 0.5 0.7 ] \"float roughness\" [ 0.3 ]\n"      \
    "  Translate 0.1 0.4 1.0 Shape \"sphere\" \"float radius\" [ 0.4 ] AttributeEnd\n"                                 \
    "AttributeBegin Material \"dielectric\" \"float eta\" [ 1.5 ]\n"                                                   \
    "  Translate 0 0.3 -1.3 Shape \"sphere\" \"float radius\" [ 0.3 ] AttributeEnd\n"                                  \
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 4 3 2 ]\n"                                                 \
    "  Translate 0.6 1.9 0.2 Shape \"sphere\" \"float radius\" [ 0.2 ] AttributeEnd\n"                                 \
    "LightSource \"point\" \"point3 from\" [ 1.5 2 -1.5 ] \"rgb I\" [ 2 2 2 ]\n"                                       \
    "LightSource \"spot\" \"point3 from\" [ -1 3 -1 ] \"point3 to\" [ -1 0 0 ] \"float coneangle\" [ 30 ] "             \
    "\"rgb I\" [ 5 4 3 ]\n"                                                                                            \
    "LightSource \"distant\" \"point3 from\" [ 1 3 -2 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 0.5 0.5 0.6 ]\n"

#define TRIANGLE_LIGHT(L)                                                                                              \
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ " L " ]\n"                                                 \
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5 ]\n"                      \
    "  \"integer indices\" [ 0 2 1 0 3 2 ] AttributeEnd\n"

static const char *SCENE_ENV =
    HEADER "LightSource \"infinite\" \"rgb L\" [ 0.3 0.4 0.5 ]\n" TRIANGLE_LIGHT("6 6 6") GEOMETRY;
static const char *SCENE_NO_ENV = HEADER TRIANGLE_LIGHT("6 6 6") GEOMETRY;
/* Values the integrator guards: a point light of intensity 3e38 half a unit above the floor,
 * whose radiance there is not finite (guarded where each light's value is added), and two
 * more seen in the nearly smooth conductor sphere, whose values there are finite but their
 * sum is not (guarded in the sums, at the end of the wave) */
#define HOT_LIGHT(P) "LightSource \"point\" \"point3 from\" [ " P " ] \"rgb I\" [ 3e38 3e38 3e38 ]\n"
static const char *SCENE_HOT =
    HEADER TRIANGLE_LIGHT("6 6 6") GEOMETRY HOT_LIGHT("0.3 0.5 0.2") HOT_LIGHT("-0.5 1.2 -2") HOT_LIGHT("-0.5 1.2 -2");

static bool same_floats(const float *a, const float *b, size_t n) { return memcmp(a, b, n * sizeof(float)) == 0; }

static bool same_stats(IntegratorStats a, IntegratorStats b)
{
    return a.rays_primary == b.rays_primary && a.rays_shadow == b.rays_shadow && a.rays_indirect == b.rays_indirect &&
           a.rays_bsdf == b.rays_bsdf && a.rays_bsdf_skipped == b.rays_bsdf_skipped &&
           a.guarded_events == b.guarded_events;
}

/* What a scene's records hold that a radiance-only render could drop. */
typedef struct {
    long misses, misses_lit, hits_emitting, weights_not_1, direct_lit, indirect_lit;
} Present;

static bool nonzero3(vec3 v) { return v.x != 0.0f || v.y != 0.0f || v.z != 0.0f; }

static bool same_rays(IntegratorStats a, IntegratorStats b)
{
    return a.rays_primary == b.rays_primary && a.rays_shadow == b.rays_shadow && a.rays_indirect == b.rays_indirect &&
           a.rays_bsdf == b.rays_bsdf && a.rays_bsdf_skipped == b.rays_bsdf_skipped;
}

/* Every pixel's samples, a wave at a time (pixels grouped up to WAVE_SAMPLES samples), through
 * integrate_wave_radiance and through integrate_wave for an undeclared user (r_all) and for
 * one that declared the radiance alone (r_rad: the same flags as the radiance-only wave, the
 * whole records), the records filled with garbage first. An undeclared user's count of
 * guarded events includes the records' unfiltered parts, which the radiance alone does not
 * have: only the ray counts are compared with it. */
static void check_waves(const Renderer *r_all, const Renderer *r_rad, Present *seen, IntegratorStats *st_out)
{
    const IntegratorScene *isc_all = renderer_integrator_scene(r_all), *isc_rad = renderer_integrator_scene(r_rad);
    CHECK(!isc_all->skip_first_hit_fields && isc_rad->skip_first_hit_fields);
    int w = renderer_width(r_all), h = renderer_height(r_all), spp = renderer_spp(r_all);
    CHECK(spp <= WAVE_SAMPLES);
    Wave *wave = wave_create();
    SampleRecord *recs = malloc(WAVE_SAMPLES * sizeof *recs), *recs_decl = malloc(WAVE_SAMPLES * sizeof *recs_decl);
    RadianceRecord *rads = malloc(WAVE_SAMPLES * sizeof *rads);
    WavePixel *pix = malloc((size_t)WAVE_SAMPLES * sizeof *pix);
    IntegratorStats st_all = {0}, st_decl = {0}, st_rad = {0};
    WaveSampling ws = {renderer_sampler(r_all), 0, 0};
    long mismatches = 0, stale = 0;
    for (int i0 = 0; i0 < w * h;) {
        int count = 0, samples = 0;
        for (; i0 < w * h && samples + spp <= WAVE_SAMPLES; ++i0, ++count, samples += spp)
            pix[count] = (WavePixel){i0 % w, i0 / w, 0, spp, 0, spp};
        /* a NaN in every float, true in every bool */
        memset(recs, 0xA5, WAVE_SAMPLES * sizeof *recs);
        memset(recs_decl, 0xA5, WAVE_SAMPLES * sizeof *recs_decl);
        memset(rads, 0xA5, WAVE_SAMPLES * sizeof *rads);
        int n_all = integrate_wave(isc_all, wave, &ws, pix, count, recs, &st_all);
        int n_decl = integrate_wave(isc_rad, wave, &ws, pix, count, recs_decl, &st_decl);
        /* given the undeclared user's scene: it skips what it skips whatever sc says */
        int n_rad = integrate_wave_radiance(isc_all, wave, &ws, pix, count, rads, &st_rad);
        CHECK(n_all == samples && n_decl == samples && n_rad == samples);
        for (int j = 0; j < n_all; ++j) {
            const SampleRecord *a = &recs[j], *d = &recs_decl[j];
            const RadianceRecord *b = &rads[j];
            if (memcmp(&a->radiance, &b->radiance, sizeof b->radiance) != 0 || a->filter_weight != b->filter_weight ||
                memcmp(&d->radiance, &b->radiance, sizeof b->radiance) != 0 || d->filter_weight != b->filter_weight)
                ++mismatches;
            /* an undeclared user's record clears what it does not fill (no motion, no ray
             * geometry recorded here) */
            if (a->motion_px[0] != 0.0f || a->motion_px[1] != 0.0f || a->shadow_count != 0 || a->bounce_count != 0 ||
                memcmp(&a->shadow[0], &(ShadowRayRecord){0}, sizeof a->shadow[0]) != 0 ||
                memcmp(&a->bounce[0], &(BounceRayRecord){0}, sizeof a->bounce[0]) != 0)
                ++stale;
            seen->misses += !a->hit;
            seen->misses_lit += !a->hit && nonzero3(a->emission);
            seen->hits_emitting += a->hit && nonzero3(a->emission);
            seen->weights_not_1 += a->filter_weight != 1.0f;
            seen->direct_lit += nonzero3(a->direct);
            seen->indirect_lit += nonzero3(a->indirect);
        }
    }
    CHECK(mismatches == 0);
    CHECK(stale == 0);
    CHECK(same_stats(st_decl, st_rad) && same_rays(st_all, st_rad));
    CHECK(st_all.guarded_events >= st_rad.guarded_events);
    *st_out = st_rad;
    free(pix), free(rads), free(recs_decl), free(recs);
    wave_free(wave);
}

/* The render's threads call the sink for different pixels at once: an atomic count. */
static void count_record(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py, (void)r;
    atomic_fetch_add((atomic_long *)ctx, 1);
}

static bool same_frame_radiance(const Frame *a, const Frame *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return same_floats(a->color, b->color, 3 * n) && same_floats(a->direct, b->direct, 3 * n) &&
           same_floats(a->indirect, b->indirect, 3 * n) && same_floats(a->emission, b->emission, 3 * n) &&
           same_floats(a->spp, b->spp, n);
}

/* The renderer: a render declared radiance-only (the radiance alone), the same declaration
 * with a sink (whole records: a sink reads them) and an undeclared render; frames and counts. */
static void check_frames(const TestRender *all, const TestRender *radiance, const char *text)
{
    atomic_long records = 0;
    SampleSink sink = {count_record, &records};
    RenderOptions o_radiance = {.reads = RENDER_READS_RADIANCE};
    TestRender decl;
    if (!test_render_sink(text, &o_radiance, &sink, &decl)) {
        CHECK(false);
        return;
    }
    CHECK(records == decl.stats.samples && records > 0);
    CHECK(same_frame_radiance(&all->frame, &radiance->frame) && same_frame_radiance(&decl.frame, &radiance->frame));
    CHECK(radiance->frame.guides_skipped && !all->frame.guides_skipped);
    RenderStats x = decl.stats, y = radiance->stats, z = all->stats;
    CHECK(x.rays_primary == y.rays_primary && x.rays_shadow == y.rays_shadow && x.rays_indirect == y.rays_indirect &&
          x.rays_bsdf == y.rays_bsdf && x.rays_bsdf_skipped == y.rays_bsdf_skipped &&
          x.guarded_events == y.guarded_events && x.samples == y.samples);
    CHECK(z.rays_primary == y.rays_primary && z.rays_shadow == y.rays_shadow && z.samples == y.samples);
    test_render_free(&decl);
}

static void check_scene(const char *text, const char *what, Present *seen, IntegratorStats *st)
{
    TestRender all, radiance;
    RenderOptions o_radiance = {.reads = RENDER_READS_RADIANCE};
    if (!test_render(text, NULL, &all) || !test_render(text, &o_radiance, &radiance)) {
        CHECK(false);
        return;
    }
    check_waves(all.r, radiance.r, seen, st);
    fprintf(stderr, "%s: misses %ld (lit %ld), emitters seen %ld, weights != 1 %ld, direct %ld, indirect %ld, guarded %lld\n",
            what, seen->misses, seen->misses_lit, seen->hits_emitting, seen->weights_not_1, seen->direct_lit,
            seen->indirect_lit, st->guarded_events);
    check_frames(&all, &radiance, text);
    test_render_free(&all), test_render_free(&radiance);
}

int main(void)
{
    Present env = {0}, dark = {0}, hot = {0};
    IntegratorStats st_env, st_dark, st_hot;
    check_scene(SCENE_ENV, "environment", &env, &st_env);
    check_scene(SCENE_NO_ENV, "no environment", &dark, &st_dark);
    check_scene(SCENE_HOT, "overflowing light", &hot, &st_hot);
    /* the scenes have what could be dropped */
    CHECK(env.misses > 0 && env.misses_lit == env.misses);
    CHECK(dark.misses > 0 && dark.misses_lit == 0);
    CHECK(env.hits_emitting > 0 && dark.hits_emitting > 0);
    CHECK(env.weights_not_1 > 0);
    CHECK(env.direct_lit > 0 && env.indirect_lit > 0 && dark.direct_lit > 0 && dark.indirect_lit > 0);
    CHECK(st_env.guarded_events == 0 && st_hot.guarded_events > 0);
    CHECK_DONE();
}
