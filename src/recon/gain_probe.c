/* The gain probe (see gain_probe.h). */
#include "recon/gain_probe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/env_knob.h"
#include "recon/auto_fallback.h"
#include "recon/camera_gain.h"
#include "recon/gbuffer.h"
#include "recon/probe_grid.h"
#include "recon/probe_motion_rule.h"

/* Independent of --seed, like the blur probe's. */
static const uint64_t GAIN_PROBE_SEED = 0x6761696eu; /* "gain" */
/* Pass numbers no render uses, one per set: two independent sampler sets per pixel. */
enum { GAIN_PROBE_PASS_A = 978, GAIN_PROBE_PASS_B = 979 };

/* What the estimate reads of a sample: luminances of its radiance, of the direct and indirect
 * light the shading filters would take (the G-buffer's split of the unfiltered parts
 * subtracted) and of the albedos they demodulate by. */
static FilterGainSample gain_sample(const SampleRecord *r)
{
    FilterGainSample s = {v3_luminance(r->L), 0.0f, 0.0f, 0.0f, 0.0f};
    if (!r->hit || r->unfilterable) return s;
    float ud[3], ui[3];
    gbuffer_unfiltered_split(r, ud, ui);
    vec3 unf_direct = {ud[0], ud[1], ud[2]}, unf_indirect = {ui[0], ui[1], ui[2]};
    s.direct_filterable = v3_luminance(r->direct) - v3_luminance(unf_direct);
    s.albedo_direct = v3_luminance(gbuffer_sample_lobed(r) ? r->albedo_diffuse : r->albedo);
    s.indirect_filterable = v3_luminance(r->indirect) - v3_luminance(unf_indirect);
    s.albedo_indirect = v3_luminance(r->albedo);
    return s;
}

bool recon_gain_probe(const Renderer *r, bool split_direct, bool split_indirect, CameraBlurKinds camera, GainProbe *out)
{
    *out = (GainProbe){0};
    IntegratorScene isc = *renderer_integrator_scene(r);
    isc.record_ray_geometry = false;
    isc.record_bounce_geometry = false;
    isc.record_motion = camera.motion; /* the motion's length (the radiance is the same either way) */
    ReconCamera cam = recon_camera_from(renderer_camera(r));
    isc.skip_first_hit_fields = false; /* the mixed rule and the albedos read them */
    int w = renderer_width(r), h = renderer_height(r);
    int nx = w / GAIN_PROBE_STRIDE, ny = h / GAIN_PROBE_STRIDE;
    nx = nx < 1 ? 1 : nx > GAIN_PROBE_GRID ? GAIN_PROBE_GRID : nx;
    ny = ny < 1 ? 1 : ny > GAIN_PROBE_GRID ? GAIN_PROBE_GRID : ny;
    enum { PIXEL_SAMPLES = 2 * GAIN_PROBE_SET_SPP };
    int per_wave = WAVE_SAMPLES / GAIN_PROBE_SET_SPP; /* one set of each pixel per wave */
    /* the probe pixels as a small image of their own, whose guides say which are mixed */
    GBuffer g;
    if (!gbuffer_init(&g, nx, ny, recon_camera_from(renderer_camera(r)))) return false;
    Wave *wave = wave_create();
    SampleRecord *rec = malloc(sizeof *rec * WAVE_SAMPLES);
    FilterGainSample *samples = malloc(sizeof *samples * (size_t)(nx * ny * PIXEL_SAMPLES));
    bool *off_first = calloc((size_t)(nx * ny * PIXEL_SAMPLES), sizeof *off_first);
    float *footprint_of = malloc(sizeof *footprint_of * (size_t)(nx * ny * PIXEL_SAMPLES));
    /* for a lens filter set by the pixel's sharpest slope: each sample's signed slope (NaN on a
     * miss) and motion length, px */
    float *coc_slope_of = malloc(sizeof *coc_slope_of * (size_t)(nx * ny * PIXEL_SAMPLES));
    float *motion_of = malloc(sizeof *motion_of * (size_t)(nx * ny * PIXEL_SAMPLES));
    /* under LR's rule the footprints wait until every sample's motion is known */
    ProbeMotionSample *moving = camera.lr_motion_rule ? malloc(sizeof *moving * (size_t)(nx * ny * PIXEL_SAMPLES)) : NULL;
    WavePixel *pix = malloc(sizeof *pix * (size_t)per_wave);
    if (!wave || !rec || !samples || !off_first || !footprint_of || !coc_slope_of || !motion_of || !pix ||
        (camera.lr_motion_rule && !moving) || !gbuffer_track_split(&g, split_direct, split_indirect)) {
        gbuffer_free(&g), wave_free(wave), free(rec), free(samples), free(off_first), free(footprint_of), free(coc_slope_of), free(motion_of), free(pix), free(moving);
        return false;
    }
    IntegratorStats st = {0};
    int total = nx * ny;
    for (int set = 0; set < 2; ++set) {
        WaveSampling ws = {renderer_sampler(r), GAIN_PROBE_SEED, set ? GAIN_PROBE_PASS_B : GAIN_PROBE_PASS_A};
        for (int first = 0; first < total; first += per_wave) {
            int count = total - first < per_wave ? total - first : per_wave;
            probe_grid_pixels(pix, first, count, nx, ny, w, h, GAIN_PROBE_SET_SPP);
            int n = integrate_wave(&isc, wave, &ws, pix, count, rec, &st);
            for (int j = 0; j < n; ++j) {
                int i = first + j / GAIN_PROBE_SET_SPP;
                gbuffer_add(&g, i % nx, i / nx, &rec[j]);
                size_t k = (size_t)i * PIXEL_SAMPLES + (size_t)(set * GAIN_PROBE_SET_SPP + j % GAIN_PROBE_SET_SPP);
                samples[k] = gain_sample(&rec[j]);
                off_first[k] = !gbuffer_on_first_surface(&g, (size_t)i, &rec[j]);
                /* the camera filters' footprint for this sample, 1 .. AUTO_CAMERA_FOOTPRINT_MAX */
                footprint_of[k] = (float)camera_footprint(camera_sample_area_px(&cam, &rec[j], camera), AUTO_CAMERA_EFFICIENCY,
                                                          AUTO_CAMERA_FOOTPRINT_MAX);
                coc_slope_of[k] = rec[j].hit ? recon_coc_slope_px(&cam, rec[j].depth_cam) : NAN;
                motion_of[k] = camera.motion && rec[j].hit ? (float)hypot(rec[j].motion_px[0], rec[j].motion_px[1]) : 0.0f;
                if (moving)
                    moving[k] = (ProbeMotionSample){(float)pix[j / GAIN_PROBE_SET_SPP].px + 0.5f, (float)pix[j / GAIN_PROBE_SET_SPP].py + 0.5f,
                                                    {rec[j].hit ? rec[j].motion_px[0] : 0.0f, rec[j].hit ? rec[j].motion_px[1] : 0.0f},
                                                    coc_slope_of[k]};
            }
            out->samples += n;
        }
    }
    if (moving) {
        /* a sample whose motion LR would not shear is blurred by its lens alone */
        size_t n = (size_t)total * PIXEL_SAMPLES;
        bool *shears = malloc(sizeof *shears * n);
        if (!shears || !probe_motion_filterable(moving, (int)n, w, h, shears)) {
            gbuffer_free(&g), wave_free(wave), free(rec), free(samples), free(off_first), free(footprint_of), free(coc_slope_of), free(motion_of), free(pix), free(moving), free(shears);
            return false;
        }
        for (size_t k = 0; k < n; ++k) {
            if (shears[k]) continue;
            double coc_px = camera.defocus && isfinite(coc_slope_of[k]) ? 2.0 * fabs((double)coc_slope_of[k]) : 0.0;
            footprint_of[k] = (float)camera_footprint(camera_blur_area_px(coc_px, 0.0), AUTO_CAMERA_EFFICIENCY, AUTO_CAMERA_FOOTPRINT_MAX);
            motion_of[k] = 0.0f;
        }
        free(shears);
    }
    for (int i = 0; i < total; ++i) g.frame.spp[i] = (float)PIXEL_SAMPLES;
    gbuffer_resolve_guides(&g);
    for (int i = 0; i < total; ++i) {
        FilterGainSample *s = samples + (size_t)i * PIXEL_SAMPLES;
        bool *off = off_first + (size_t)i * PIXEL_SAMPLES;
        float *footprint = footprint_of + (size_t)i * PIXEL_SAMPLES;
        float *coc_slope = coc_slope_of + (size_t)i * PIXEL_SAMPLES, *motion = motion_of + (size_t)i * PIXEL_SAMPLES;
        /* the finite samples, set A's then set B's, in place (a NaN would make every sum NaN) */
        int kept[2] = {0, 0}, n = 0;
        for (int k = 0; k < PIXEL_SAMPLES; ++k) {
            if (!filter_gain_sample_finite(&s[k])) {
                out->samples_nonfinite++;
                continue;
            }
            s[n] = s[k], off[n] = off[k], footprint[n] = footprint[k], coc_slope[n] = coc_slope[k], motion[n] = motion[k], ++n;
            kept[k >= GAIN_PROBE_SET_SPP]++;
        }
        bool split = gbuffer_pixel_split(&g, (size_t)i);
        if (split) filter_gain_split_pixel(s, off, n, split_direct, split_indirect);
        filter_gain_add_pixel_sets(&out->totals, s, kept[0], kept[1], g.mixed[i] != 0 && !split,
                                   camera.defocus && camera.sharpest_lens
                                       ? camera_pixel_footprint_sharpest_lens(coc_slope, motion, n, AUTO_CAMERA_EFFICIENCY,
                                                                              AUTO_CAMERA_FOOTPRINT_MAX)
                                       : camera_pixel_footprint(footprint, n));
    }
    long long rays = st.rays_primary + st.rays_shadow + st.rays_indirect + st.rays_bsdf;
    out->rays_per_sample = out->samples ? (double)rays / out->samples : 0.0;
    gbuffer_free(&g), wave_free(wave), free(rec), free(samples), free(off_first), free(footprint_of), free(coc_slope_of), free(motion_of), free(pix), free(moving);
    return true;
}

CameraBlurKinds recon_gain_probe_blur(const ReconChoice *c)
{
    CameraBlurKinds camera = recon_select_fallback_blur(c);
    /* MAAF's lens filter takes its width from the pixel's sharpest slope (camera_gain.h) */
    const ReconMethodClass *lens = c->method[EFFECT_DEFOCUS];
    camera.sharpest_lens = camera.defocus && lens && strcmp(lens->name, "maaf") == 0;
    /* LR keeps no motion filter where a layer's speeds disagree (probe_motion_rule.h) */
    const ReconMethodClass *shutter = c->method[EFFECT_MOTION];
    camera.lr_motion_rule = camera.motion && shutter && strcmp(shutter->name, "lr") == 0;
    return camera;
}

/* Whether two effects' filters are one method (both set). */
static bool same_method(const ReconMethodClass *a, const ReconMethodClass *b)
{
    return a && b && strcmp(a->name, b->name) == 0;
}

/* Whether effect e's filter runs a method none of the camera candidates runs (it then records its
 * own per-sample data beside theirs: AutoFallbackFrame's own sinks). */
static bool own_sink_beside_cameras(const ReconChoice *c, Effect e, CameraBlurKinds cameras)
{
    const ReconMethodClass *m = c->method[e];
    if (!m) return false;
    bool shares = (cameras.defocus && same_method(c->method[EFFECT_DEFOCUS], m)) ||
                  (cameras.motion && same_method(c->method[EFFECT_MOTION], m));
    return !shares;
}

bool recon_gain_probe_judge(const Renderer *r, int spp, ReconChoice *c)
{
    if (!recon_select_wants_fallback(c) || !env_knob_switch("WEDGE_AUTO_FALLBACK", true)) return true;
    GainProbe probe;
    if (!recon_gain_probe(r, recon_choice_splits_pixels(c, EFFECT_SOFT_SHADOWS), recon_choice_splits_pixels(c, EFFECT_INDIRECT),
                          recon_gain_probe_blur(c), &probe))
        return false;
    AutoFallback fb;
    AutoFallbackFrame frame = recon_select_fallback_frame(c, spp);
    CameraBlurKinds cameras = recon_select_fallback_blur(c);
    if (frame.cameras > 0) {
        frame.direct_own_sink = frame.direct && own_sink_beside_cameras(c, EFFECT_SOFT_SHADOWS, cameras);
        frame.indirect_own_sink = frame.indirect && own_sink_beside_cameras(c, EFFECT_INDIRECT, cameras);
        frame.shading_one_method = same_method(c->method[EFFECT_SOFT_SHADOWS], c->method[EFFECT_INDIRECT]);
    }
    auto_fallback_decide(&probe.totals, probe.rays_per_sample, &frame, &fb);
    fb.samples_nonfinite = probe.samples_nonfinite;
    recon_select_fallback(c, &fb);
    return true;
}
