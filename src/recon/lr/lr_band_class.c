/* The still band's class per pixel (lr_band_class.h, docs/algorithms.md 8.39, 8.40). */
#include "recon/lr/lr_band_class.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

/* the floor of a second difference's variance relative to m^2 + BRIGHT_FLOOR2, the brightness
 * floor (r + g + b, squared) of lr_noise_share.c */
#define VAR_FLOOR_REL 1e-4
#define BRIGHT_FLOOR2 0.03

double lr_band_curvature_z(const float *m, const float *v, int w, int h, int x, int y)
{
    if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) return -1.0;
    ptrdiff_t c = (ptrdiff_t)y * w + x, row = w;
    double d_rows = 0.0, v_rows = 0.0, d_cols = 0.0, v_cols = 0.0;
    for (ptrdiff_t j = -1; j <= 1; ++j) {
        ptrdiff_t a = c + j, b = c + j * row; /* a pixel of the row, a pixel of the column */
        d_rows += (double)m[a - row] + m[a + row] - 2.0 * m[a];
        v_rows += (double)v[a - row] + v[a + row] + 4.0 * v[a];
        d_cols += (double)m[b - 1] + m[b + 1] - 2.0 * m[b];
        v_cols += (double)v[b - 1] + v[b + 1] + 4.0 * v[b];
    }
    double floor_var = VAR_FLOOR_REL * ((double)m[c] * m[c] + BRIGHT_FLOOR2);
    double z = fmax(d_rows * d_rows / (v_rows + floor_var), d_cols * d_cols / (v_cols + floor_var));
    return isfinite(z) ? z : -1.0;
}

int lr_band_class_of(double z)
{
    if (z < 0.0) return LR_BAND_FRAME;
    return z > LR_BAND_Z_EDGE ? LR_BAND_NARROW : z <= LR_BAND_Z_FLAT ? LR_BAND_WIDE : LR_BAND_FRAME;
}

bool lr_band_classes(const LrSamples *img, unsigned char *cls)
{
    int n = img->spp, w = img->width, h = img->height;
    if (n < 2) return false;
    size_t np = (size_t)w * (size_t)h;
    float *mean = malloc(sizeof(float) * np * 2);
    if (!mean) return false;
    float *var = mean + np; /* of the mean */
    for (size_t i = 0; i < np; ++i) {
        const float *b = &img->bright[i * (size_t)n];
        double sum = 0.0, sum2 = 0.0;
        for (int k = 0; k < n; ++k) sum += b[k], sum2 += (double)b[k] * b[k]; /* a NaN sample: the score is -1 */
        mean[i] = (float)(sum / n);
        var[i] = (float)(fmax(0.0, (sum2 - sum * sum / n) / (n - 1)) / n);
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            cls[(size_t)y * (size_t)w + (size_t)x] = (unsigned char)lr_band_class_of(lr_band_curvature_z(mean, var, w, h, x, y));
    free(mean);
    return true;
}

unsigned lr_band_tile_classes(const LrSamples *img, const LrConfig *cfg, int tx, int ty)
{
    if (!cfg->band_class) return 0;
    int x0, y0, x1, y1;
    lr_tile_pixels(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
    unsigned present = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) present |= 1u << cfg->band_class[(size_t)y * (size_t)img->width + (size_t)x];
    return present;
}

/* Whether two filters are the same in every field (the screen filter is made from them). */
static bool same_filter(const LrFilter *a, const LrFilter *b)
{
    return a->clip_x == b->clip_x && a->clip_y == b->clip_y && a->clamped == b->clamped && a->inv_sigma_x_px == b->inv_sigma_x_px &&
           a->eta_px == b->eta_px && a->xi_px == b->xi_px && a->inv_sigma_u == b->inv_sigma_u && a->inv_sigma_t == b->inv_sigma_t &&
           a->inv_sigma_y_px == b->inv_sigma_y_px && a->rho_px == b->rho_px && a->inv_sigma_v == b->inv_sigma_v &&
           a->aperture_x_px == b->aperture_x_px && a->shutter_x_px == b->shutter_x_px && a->aperture_y_px == b->aperture_y_px;
}

bool lr_band_screen(const LrConfig *cfg, const LrLayer *layer, int cls, const LrScreen *frame, LrScreen *out, LrFilter *filter)
{
    if (cls == LR_BAND_FRAME || layer->slopes.d_min_px != 0.0f || layer->slopes.d_max_px != 0.0f) return false;
    LrConfig band = *cfg;
    band.filter.sigma_pixel_still_px = cls == LR_BAND_NARROW ? LR_BAND_NARROW_PX : LR_BAND_WIDE_PX;
    *filter = lr_layer_filter(&band, &layer->slopes, layer->contrast);
    /* a layer blurred by its lens past the band (8.2) gets the frame's filter at every band:
     * its screen filter (the costly part, a round table above all) is not made again */
    if (same_filter(filter, &layer->filter)) return false;
    lr_screen_make(filter, &band, layer->cos_psi, layer->sin_psi, out);
    return !lr_screen_same(out, frame);
}
