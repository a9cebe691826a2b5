/* LR's error split into squared bias and variance per pixel class (issue 17, lr18).
 *
 *   lr-bias-split REF.exr CLASS.exr CHANNEL B1,B2,... FRAME.exr...
 *
 * FRAME are renders of one configuration with different seeds (N >= 2); CLASS is an EXR
 * holding the classifying channel CHANNEL (e.g. lr.extent_px or lr.layers, from --aovs).
 * Per pixel and colour channel, with t_k the frames and r the reference, the error that
 * `wedge compare` reports, mean_k (t_k - r)^2 / (r^2 + 0.01), is split exactly into
 *     squared bias  (tbar - r)^2 - s^2 / N      and variance  s^2 (N - 1) / N
 * (s^2 the frames' unbiased variance; the bias term is unbiased for (E t - r)^2). Pixels are
 * binned by the class value against the bounds B1 < B2 < ...: class k holds B_k <= v < B_k+1.
 * CHANNEL "@y" classes pixels by their row instead; "@diff" by the relative difference between the
 * reference and the image CLASS.exr (the scene rendered without some objects: their footprint);
 * with LR_BIAS_DIFF_ROWS=T, by the row plus 1000 where that difference is at least T. Prints per class: pixel share, relMSE, its
 * share of the whole, squared bias, variance. Environment: LR_BIAS_ROWS=1 also prints each row's
 * signed mean deviation, squared bias, variance and mean class value; LR_BIAS_MAP=FILE writes
 * the per-pixel squared bias (R), variance (G) and class (B): an EXR, or a PNG heat map
 * (sqrt of bias and variance against 0.01, the class / 8) when FILE ends in .png.
 * Build (from the tree, after a Release build in build/):
 *   cc -O2 -std=c11 -Isrc tools/lr-bias-split.c build/libwedge_io.a build/libwedge_core.a \
 *      $(pkg-config --libs OpenEXR) -lpng -ldeflate -lOpenColorIO -lstdc++ -lm -o lr-bias-split */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"

enum { MAX_CLASSES = 32 };

static float *read_rgb_or_die(const char *path, int *w, int *h)
{
    float *rgb = NULL;
    Diag err = {0};
    if (!exr_read_rgb(path, w, h, &rgb, &err)) {
        fprintf(stderr, "lr-bias-split: cannot read %s\n", path);
        exit(2);
    }
    return rgb;
}

int main(int argc, char **argv)
{
    if (argc < 7) {
        fprintf(stderr, "usage: lr-bias-split REF.exr CLASS.exr CHANNEL B1,B2,... FRAME.exr FRAME.exr...\n");
        return 1;
    }
    int w, h, cw, ch;
    float *ref = read_rgb_or_die(argv[1], &w, &h);
    float *cls = NULL;
    Diag err = {0};
    if (strcmp(argv[3], "@y") == 0) { /* the pixel's row as its class */
        cls = malloc((size_t)w * h * sizeof *cls);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) cls[(size_t)y * w + x] = (float)y;
    } else if (strcmp(argv[3], "@diff") == 0) {
        /* CLASS is an image of the scene without some of its objects (e.g. without the moving
         * ones): the class is the largest relative difference over the channels between the
         * reference and it, |r - o| / (r + 0.01), so that the objects' footprint (with their
         * blur and shadows) is told from the rest */
        int ow, oh;
        float *other = read_rgb_or_die(argv[2], &ow, &oh);
        if (ow != w || oh != h) {
            fprintf(stderr, "lr-bias-split: %s is %dx%d, the reference %dx%d\n", argv[2], ow, oh, w, h);
            return 2;
        }
        cls = malloc((size_t)w * h * sizeof *cls);
        for (size_t p = 0; p < (size_t)w * h; ++p) {
            float worst = 0.0f;
            for (int j = 0; j < 3; ++j) {
                float r = ref[p * 3 + j], d = fabsf(r - other[p * 3 + j]) / (fabsf(r) + 0.01f);
                worst = d > worst ? d : worst;
            }
            cls[p] = worst;
        }
        const char *rows = getenv("LR_BIAS_DIFF_ROWS");
        if (rows) /* the row, plus 1000 inside the footprint (difference at least the given threshold) */
            for (size_t p = 0; p < (size_t)w * h; ++p) cls[p] = (float)(p / (size_t)w) + (cls[p] >= atof(rows) ? 1000.0f : 0.0f);
        free(other);
    } else if (!exr_read_channel(argv[2], argv[3], &cw, &ch, &cls, &err) || cw != w || ch != h) {
        fprintf(stderr, "lr-bias-split: no channel %s of %dx%d in %s\n", argv[3], w, h, argv[2]);
        return 2;
    }
    double bounds[MAX_CLASSES];
    int nb = 0;
    for (char *tok = strtok(argv[4], ","); tok && nb < MAX_CLASSES - 1; tok = strtok(NULL, ",")) bounds[nb++] = atof(tok);
    int nframes = argc - 5;
    size_t npx = (size_t)w * h;
    double *sum = calloc(npx * 3, sizeof *sum), *sum2 = calloc(npx * 3, sizeof *sum2);
    double *err_sum = calloc(npx * 3, sizeof *err_sum);
    for (int k = 0; k < nframes; ++k) {
        int fw, fh;
        float *t = read_rgb_or_die(argv[5 + k], &fw, &fh);
        if (fw != w || fh != h) {
            fprintf(stderr, "lr-bias-split: %s is %dx%d, the reference %dx%d\n", argv[5 + k], fw, fh, w, h);
            return 2;
        }
        for (size_t i = 0; i < npx * 3; ++i) {
            double d = (double)t[i] - ref[i];
            sum[i] += t[i], sum2[i] += (double)t[i] * t[i];
            err_sum[i] += d * d;
        }
        free(t);
    }
    int nclass = nb + 1;
    double px[MAX_CLASSES] = {0}, e[MAX_CLASSES] = {0}, b2[MAX_CLASSES] = {0}, var[MAX_CLASSES] = {0};
    double n = nframes;
    for (size_t p = 0; p < npx; ++p) {
        int c = 0;
        while (c < nb && cls[p] >= bounds[c]) ++c;
        px[c] += 1.0;
        for (int j = 0; j < 3; ++j) {
            size_t i = p * 3 + j;
            double r = ref[i], norm = r * r + 0.01;
            double mean = sum[i] / n, s2 = (sum2[i] - n * mean * mean) / (n - 1.0);
            if (s2 < 0.0) s2 = 0.0;
            e[c] += err_sum[i] / n / norm;
            b2[c] += ((mean - r) * (mean - r) - s2 / n) / norm;
            var[c] += s2 * (n - 1.0) / n / norm;
        }
    }
    const char *map_path = getenv("LR_BIAS_MAP");
    if (map_path) { /* per pixel: squared bias (R), variance (G) and the class value (B), summed over channels */
        float *map = calloc(npx * 3, sizeof *map);
        for (size_t p = 0; p < npx; ++p) {
            for (int j = 0; j < 3; ++j) {
                size_t i = p * 3 + j;
                double r = ref[i], norm = r * r + 0.01;
                double mean = sum[i] / n, s2 = (sum2[i] - n * mean * mean) / (n - 1.0);
                map[p * 3] += (float)(((mean - r) * (mean - r) - s2 / n) / norm);
                map[p * 3 + 1] += (float)(s2 * (n - 1.0) / n / norm);
            }
            map[p * 3 + 2] = cls[p];
        }
        bool ok;
        if (path_is_png(map_path)) { /* a heat map: sqrt of bias and variance against 0.01, the class / 8 */
            for (size_t p = 0; p < npx * 3; ++p) {
                double v = (p % 3 == 2) ? map[p] / 8.0 : sqrt(map[p] > 0.0f ? map[p] / 0.01 : 0.0);
                map[p] = (float)(v < 1.0 ? v : 1.0);
            }
            ok = png_write_display(map_path, w, h, map, &err);
        } else {
            ExrChannel chans[3] = {{"R", map, 3}, {"G", map + 1, 3}, {"B", map + 2, 3}};
            ok = exr_write(map_path, w, h, chans, 3, NULL, 0, &err);
        }
        if (!ok) fprintf(stderr, "lr-bias-split: cannot write %s\n", map_path);
        free(map);
    }
    if (getenv("LR_BIAS_ROWS")) { /* per row: signed mean deviation, squared bias, variance, mean class value */
        for (int y = 0; y < h; ++y) {
            double sd = 0.0, sb = 0.0, sv = 0.0, sc = 0.0, sr = 0.0;
            for (int x = 0; x < w; ++x) {
                size_t p = (size_t)y * w + x;
                sc += cls[p];
                for (int j = 0; j < 3; ++j) {
                    size_t i = p * 3 + j;
                    double r = ref[i], norm = r * r + 0.01, mean = sum[i] / n;
                    double s2 = (sum2[i] - n * mean * mean) / (n - 1.0);
                    sd += mean - r, sr += r;
                    sb += ((mean - r) * (mean - r) - s2 / n) / norm, sv += s2 * (n - 1.0) / n / norm;
                }
            }
            printf("row %3d  ref %.4f  dev %+.5f  bias %.3e  var %.3e  class %.2f\n", y, sr / (3 * w), sd / (3 * w), sb / (3 * w), sv / (3 * w), sc / w);
        }
    }
    double denom = 3.0 * (double)npx, e_all = 0.0, b_all = 0.0, v_all = 0.0;
    for (int c = 0; c < nclass; ++c) e_all += e[c], b_all += b2[c], v_all += var[c];
    printf("class            pixels   relMSE      share  sq.bias     variance   (relMSE in the class)\n");
    printf("%-15s %6.1f%%  %.4e  100.0%%  %.4e  %.4e\n", "all", 100.0, e_all / denom, b_all / denom, v_all / denom);
    for (int c = 0; c < nclass; ++c) {
        char name[64];
        if (c == 0) snprintf(name, sizeof name, "< %g", bounds[0]);
        else if (c == nb) snprintf(name, sizeof name, ">= %g", bounds[nb - 1]);
        else snprintf(name, sizeof name, "[%g, %g)", bounds[c - 1], bounds[c]);
        double pd = px[c] > 0.0 ? 3.0 * px[c] : 1.0;
        printf("%-15s %6.1f%%  %.4e  %5.1f%%  %.4e  %.4e   (whole-frame shares: bias %.4e var %.4e)\n", name,
               100.0 * px[c] / npx, e[c] / pd, 100.0 * e[c] / e_all, b2[c] / pd, var[c] / pd, b2[c] / denom, var[c] / denom);
    }
    free(sum), free(sum2), free(err_sum), free(ref), free(cls);
    return 0;
}
