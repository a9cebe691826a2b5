/* FSF's indirect-light filter as two spatial passes over pixel sums (fsf_flat.h). */
#include "recon/fsf/fsf_flat.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/recon_parallel.h"

typedef struct {
    const float *value4;
    const int *count;
    int width, height;
    const FsfGrid *g;
    const FsfPixel *px;
    const FsfGuides *gd;
    const float *in4; /* the pass's input: S (pass A), G (pass B) */
    float *out4;
    int axis;
} Job;

/* w(t) = exp(-t^2 / (2 sigma^2)) for t = 0 .. r, by the recurrence w(t + 1) = w(t) c^(2 t + 1),
 * c = exp(-1 / (2 sigma^2)): two exponentials a pixel instead of r + 1 (relative error a few
 * float roundings per step, 1e-6 at the cap's 16 steps) */
static void gauss_weights(float sigma, int r, float *w)
{
    w[0] = 1.0f;
    if (r == 0) return;
    float c = expf(-0.5f / (sigma * sigma)), c2 = c * c, step = c;
    for (int t = 1; t <= r; ++t) w[t] = w[t - 1] * step, step *= c2;
}

static void sums_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const Job *j = ctx;
    for (size_t i = begin; i < end; ++i) {
        float acc[4] = {0, 0, 0, 0};
        if (j->gd->usable[i]) {
            float c = (float)j->count[i];
            for (int ch = 0; ch < 3; ++ch) {
                float v = j->value4[4 * i + (size_t)ch];
                acc[ch] = isfinite(v) ? c * v : 0.0f;
            }
            acc[3] = c;
        }
        memcpy(j->out4 + 4 * i, acc, sizeof acc);
    }
}

/* One gather along each pixel's own axis j->axis: pass A (axis 0, divided by its weights' sum)
 * or pass B (axis 1). */
static void gather_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const Job *j = ctx;
    int w = j->width, h = j->height, a = j->axis;
    float wt[FSF_RADIUS_CAP_PX + 1];
    for (size_t i = begin; i < end; ++i) {
        float acc[4] = {0, 0, 0, 0};
        if (j->gd->usable[i]) {
            const FsfPixel *pp = &j->px[i];
            int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
            int r = fsf_tap_radius(j->g, pp->sigma_px[a]);
            gauss_weights(pp->sigma_px[a], r, wt);
            float all = 0.0f;
            for (int t = -r; t <= r; ++t) {
                float wk = wt[t < 0 ? -t : t];
                all += wk;
                int q = fsf_step_pixel(w, h, x, y, pp->dir[a], (float)t);
                if (q < 0 || (t != 0 && !fsf_accept(j->gd, (int)i, q))) continue;
                const float *f = j->in4 + 4 * (size_t)q;
                acc[0] += wk * f[0], acc[1] += wk * f[1], acc[2] += wk * f[2], acc[3] += wk * f[3];
            }
            if (a == 0)
                for (int c = 0; c < 4; ++c) acc[c] /= all;
        }
        memcpy(j->out4 + 4 * i, acc, sizeof acc);
    }
}

bool fsf_filter_flat(const float *value4, const int *count, int width, int height, const FsfGrid *g,
                     const FsfPixel *px, const FsfGuides *gd, float *out4)
{
    size_t n = (size_t)width * (size_t)height;
    float *G = malloc(sizeof(float) * 4 * (n > 0 ? n : 1));
    if (!G) return false;
    Job j = {value4, count, width, height, g, px, gd, NULL, out4, 0};
    recon_parallel_for(n, sums_range, &j); /* S into out4 */
    j.in4 = out4, j.out4 = G, j.axis = 0;
    recon_parallel_for(n, gather_range, &j);
    j.in4 = G, j.out4 = out4, j.axis = 1;
    recon_parallel_for(n, gather_range, &j);
    free(G);
    return true;
}

long long fsf_flat_nonfinite_inputs(const float *value4, const unsigned char *usable, size_t n)
{
    long long bad = 0;
    for (size_t i = 0; i < n; ++i)
        for (int ch = 0; usable[i] && ch < 3; ++ch) bad += !isfinite(value4[4 * i + (size_t)ch]);
    return bad;
}
