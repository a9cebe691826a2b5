/* The blur probe (see blur_probe.h). */
#include "recon/blur_probe.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "recon/probe_grid.h"

/* Independent of --seed: info and render (and every MPI rank) must measure the same value. */
static const uint64_t BLUR_PROBE_SEED = 0x626c7572u; /* "blur" */
/* A pass number no render uses, so the probe's samples are not the render's first ones. */
enum { BLUR_PROBE_PASS = 977 };

float blur_extent_px(const ReconCamera *cam, const SampleRecord *rec)
{
    if (!rec->hit) return 0.0f;
    float motion_px = hypotf(rec->motion_px[0], rec->motion_px[1]);
    float coc_diameter_px = 2.0f * fabsf(recon_coc_slope_px(cam, rec->depth_cam));
    float b = fmaxf(motion_px, coc_diameter_px);
    /* a hit at the lens plane: its circle of confusion overflows; it is blurred as much as a
     * sample can be, so it saturates (recon_blur_probe counts these) */
    return b < FLT_MAX ? b : FLT_MAX;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

bool recon_blur_probe(const Renderer *r, BlurProbe *out)
{
    *out = (BlurProbe){0};
    /* first hits only: no bounces, no recorded ray geometry (the probe reads hit, depth and
     * motion) */
    IntegratorScene first_hit = *renderer_integrator_scene(r);
    first_hit.max_depth = 1;
    first_hit.record_ray_geometry = false;
    first_hit.record_motion = true;
    first_hit.skip_first_hit_fields = false; /* it reads depth_cam, whatever the render's users declared */
    const IntegratorScene *isc = &first_hit;
    ReconCamera cam = recon_camera_from(renderer_camera(r));
    int w = renderer_width(r), h = renderer_height(r);
    int nx = w < BLUR_PROBE_GRID ? w : BLUR_PROBE_GRID, ny = h < BLUR_PROBE_GRID ? h : BLUR_PROBE_GRID;
    int per_wave = WAVE_SAMPLES / BLUR_PROBE_SPP;
    Wave *wave = wave_create();
    SampleRecord *rec = malloc(sizeof *rec * WAVE_SAMPLES);
    float *blur_px = malloc(sizeof *blur_px * (size_t)(nx * ny * BLUR_PROBE_SPP));
    WavePixel *pix = malloc(sizeof *pix * (size_t)per_wave);
    if (!wave || !rec || !blur_px || !pix) {
        wave_free(wave), free(rec), free(blur_px), free(pix);
        return false;
    }
    /* a fixed sampler kind too: the scene's or --sampler's choice must not change the choice */
    WaveSampling ws = {SAMPLER_STRATIFIED, BLUR_PROBE_SEED, BLUR_PROBE_PASS};
    IntegratorStats st = {0};
    int hits = 0, traced = 0, total = nx * ny;
    for (int first = 0; first < total; first += per_wave) {
        int count = total - first < per_wave ? total - first : per_wave;
        probe_grid_pixels(pix, first, count, nx, ny, w, h, BLUR_PROBE_SPP);
        int n = integrate_wave(isc, wave, &ws, pix, count, rec, &st);
        for (int j = 0; j < n; ++j) {
            ++traced;
            if (!rec[j].hit) continue;
            float b = blur_extent_px(&cam, &rec[j]);
            out->samples_unbounded += b == FLT_MAX;
            blur_px[hits++] = b;
        }
    }
    if (hits) {
        qsort(blur_px, (size_t)hits, sizeof *blur_px, cmp_float);
        out->median_blur_px = hits % 2 ? blur_px[hits / 2] : 0.5f * (blur_px[hits / 2 - 1] + blur_px[hits / 2]);
    }
    out->samples_hit = hits;
    out->samples = traced;
    wave_free(wave), free(rec), free(blur_px), free(pix);
    return true;
}
