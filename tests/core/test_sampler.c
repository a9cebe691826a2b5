/* Samplers: range, determinism, stratification, (0,2)-net structure and convergence rate. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "half_plane_area.h"
#include "core/sampler.h"

#define MAX_N 2112 /* up to a 2 x 1031 grid: rows + cols past the sampler's grid tables */
#define DIMS 12 /* scalar dimensions tested per sample: 1D, 2D, 1D, 2D, ... */

/* Generates all n samples of one pixel, requesting a fixed pattern of dimensions
 * (1D, 2D, 1D, 2D, ...) up to DIMS scalars; out[i][d] is scalar dimension d of sample i. */
static void draw_sample(PixelSampler *s, int i, float out[DIMS])
{
    sampler_start_sample(s, i);
    int d = 0;
    while (d < DIMS) {
        if ((d % 3) == 0) {
            out[d++] = sampler_1d(s);
        } else {
            vec2 p = sampler_2d(s);
            out[d++] = p.x;
            out[d++] = p.y;
        }
    }
}

static void fill_pixel(SamplerKind kind, uint64_t seed, int px, int py, int pass, int n, float out[][DIMS])
{
    PixelSampler s;
    sampler_start_pixel(&s, kind, seed, px, py, pass, n);
    for (int i = 0; i < n; ++i) draw_sample(&s, i, out[i]);
}
/* Dimension d is the first (x) coordinate of a 2D request when d % 3 == 1. */
static int is_2d_x(int d) { return d % 3 == 1; }

static float g_samples[MAX_N][DIMS];
static float g_other[MAX_N][DIMS];

/* Every value in [0, 1), for many spp, and also for dimensions past the padded range. */
static void test_range(SamplerKind kind)
{
    for (int n = 1; n <= 70; n += (n < 20 ? 1 : 7)) {
        PixelSampler s;
        sampler_start_pixel(&s, kind, 7, 3, 5, 0, n);
        for (int i = 0; i < n; ++i) {
            sampler_start_sample(&s, i);
            for (int d = 0; d < 50; ++d) {
                float a = sampler_1d(&s);
                vec2 b = sampler_2d(&s);
                CHECK(a >= 0.0f && a < 1.0f);
                CHECK(b.x >= 0.0f && b.x < 1.0f && b.y >= 0.0f && b.y < 1.0f);
            }
        }
    }
}

static void test_determinism(SamplerKind kind)
{
    const int n = 16;
    fill_pixel(kind, 42, 10, 20, 1, n, g_samples);
    fill_pixel(kind, 42, 10, 20, 1, n, g_other);
    CHECK(memcmp(g_samples, g_other, sizeof(float) * DIMS * n) == 0);

    /* A different pixel, pass or seed gives different values. Count the differing values
     * rather than requiring all: two independent floats coincide with negligible odds. */
    const int variants[4][4] = {{11, 20, 1, 42}, {10, 21, 1, 42}, {10, 20, 2, 42}, {10, 20, 1, 43}};
    for (int v = 0; v < 4; ++v) {
        fill_pixel(kind, (uint64_t)variants[v][3], variants[v][0], variants[v][1], variants[v][2], n, g_other);
        int same = 0;
        for (int i = 0; i < n; ++i)
            for (int d = 0; d < DIMS; ++d) same += g_samples[i][d] == g_other[i][d];
        CHECK(same <= 2);
    }

    /* Sample i does not depend on which samples were generated before it. */
    PixelSampler s;
    sampler_start_pixel(&s, kind, 42, 10, 20, 1, n);
    sampler_start_sample(&s, 9);
    CHECK(sampler_1d(&s) == g_samples[9][0]);
    vec2 p = sampler_2d(&s);
    CHECK(p.x == g_samples[9][1] && p.y == g_samples[9][2]);
}

/* The sampler caches permutations and per-dimension tables per pixel; values must not
 * depend on what is cached: every sample equals the same sample drawn by a fresh sampler,
 * whatever order the samples are visited in, for spp with and without the cached path
 * (up to 16) and for indices past spp; also when a dimension index is requested as 1D in
 * one sample and as 2D in another (the tables are per request kind). */
static void test_cache_is_pure(SamplerKind kind)
{
    /* 32, 64, 100, 256: multi-jitter's per-dimension grid tables (built by whichever
     * sample meets the dimension first, in reverse or fresh below); 37, 68 (a 4 x 17 grid),
     * 300, 1000: the lazily filled tables of grids with a side past 16; 2062 (2 x 1031):
     * past those, per sample */
    const int counts[] = {1, 2, 3, 4, 6, 9, 16, 17, 32, 37, 64, 68, 100, 256, 300, 1000, 2062};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; ++c) {
        int n = counts[c];
        fill_pixel(kind, 7, 3, 4, 0, n, g_samples);
        PixelSampler s;
        sampler_start_pixel(&s, kind, 7, 3, 4, 0, n);
        int mismatches = 0;
        for (int pass = 0; pass < 2; ++pass)
            for (int k = 0; k < n; ++k) {
                int i = pass ? k : n - 1 - k; /* reverse order, then forward */
                sampler_start_sample(&s, i);
                for (int d = 0; d < DIMS;) {
                    if ((d % 3) == 0) {
                        mismatches += sampler_1d(&s) != g_samples[i][d++];
                    } else {
                        vec2 p = sampler_2d(&s);
                        mismatches += p.x != g_samples[i][d++];
                        mismatches += p.y != g_samples[i][d++];
                    }
                }
            }
        CHECK(mismatches == 0);

        /* past spp (a second block of strata) and with the request kinds swapped */
        for (int i = n; i < n + 3; ++i) {
            PixelSampler fresh;
            sampler_start_pixel(&fresh, kind, 7, 3, 4, 0, n);
            sampler_start_sample(&fresh, i);
            vec2 a = sampler_2d(&fresh);
            float b = sampler_1d(&fresh);
            sampler_start_sample(&s, i);
            vec2 a2 = sampler_2d(&s);
            CHECK(a.x == a2.x && a.y == a2.y && b == sampler_1d(&s));
        }
        for (int i = 0; i < n; ++i) {
            PixelSampler fresh;
            sampler_start_pixel(&fresh, kind, 7, 3, 4, 0, n);
            sampler_start_sample(&fresh, i);
            vec2 a = sampler_2d(&fresh); /* dimensions 0-1 as 2D, where fill_pixel asked 1D, 2D */
            sampler_start_sample(&s, i);
            vec2 a2 = sampler_2d(&s);
            CHECK(a.x == a2.x && a.y == a2.y);
            sampler_start_sample(&s, i);
            CHECK(sampler_1d(&s) == g_samples[i][0]);
        }
    }
}

/* Exactly one of the n values of dimension d in each interval [k/n, (k+1)/n). */
static int stratified_1d(float v[][DIMS], int n, int d)
{
    int count[MAX_N] = {0};
    for (int i = 0; i < n; ++i) {
        int k = (int)floor((double)v[i][d] * n);
        if (k < 0 || k >= n) return 0;
        ++count[k];
    }
    for (int k = 0; k < n; ++k)
        if (count[k] != 1) return 0;
    return 1;
}

/* Exactly one point (v[i][d], v[i][d+1]) in each cell of a cols x rows grid. */
static int stratified_grid(float v[][DIMS], int n, int d, int cols, int rows)
{
    int count[MAX_N] = {0};
    for (int i = 0; i < n; ++i) {
        int cx = (int)floor((double)v[i][d] * cols), cy = (int)floor((double)v[i][d + 1] * rows);
        if (cx < 0 || cx >= cols || cy < 0 || cy >= rows) return 0;
        ++count[cy * cols + cx];
    }
    for (int k = 0; k < cols * rows; ++k)
        if (count[k] != 1) return 0;
    return 1;
}

static void test_stratified(void)
{
    for (int pixel = 0; pixel < 20; ++pixel) {
        /* n = 16: 1D strata of width 1/16 in every scalar dimension (including both
         * coordinates of each 2D dimension) and a 4 x 4 jittered grid per 2D dimension. */
        fill_pixel(SAMPLER_STRATIFIED, 1, pixel, 3 * pixel, 0, 16, g_samples);
        for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples, 16, d));
        for (int d = 0; d < DIMS; ++d)
            if (is_2d_x(d)) CHECK(stratified_grid(g_samples, 16, d, 4, 4));
        /* n = 12 (not a square): 1D strata of width 1/12 everywhere, a 4 x 3 grid per 2D. */
        fill_pixel(SAMPLER_STRATIFIED, 1, pixel, 3 * pixel, 0, 12, g_samples);
        for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples, 12, d));
        for (int d = 0; d < DIMS; ++d)
            if (is_2d_x(d)) CHECK(stratified_grid(g_samples, 12, d, 4, 3));
        /* A prime count: still one point per 1/n stratum in every projection. */
        fill_pixel(SAMPLER_STRATIFIED, 1, pixel, 3 * pixel, 0, 13, g_samples);
        for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples, 13, d));
    }

    /* Sample indices past spp start a new, again stratified set (progressive use). */
    PixelSampler s;
    sampler_start_pixel(&s, SAMPLER_STRATIFIED, 1, 4, 4, 0, 16);
    for (int i = 0; i < 16; ++i) {
        sampler_start_sample(&s, 16 + i);
        g_samples[i][0] = sampler_1d(&s);
    }
    CHECK(stratified_1d(g_samples, 16, 0));

    /* Padding decorrelates dimensions: the sample that lands in the first 1D stratum of
     * dimension 0 is not always the one in the first stratum of dimension 3. */
    int same_order = 0;
    for (int pixel = 0; pixel < 20; ++pixel) {
        fill_pixel(SAMPLER_STRATIFIED, 1, pixel, 0, 0, 16, g_samples);
        int eq = 1;
        for (int i = 0; i < 16; ++i)
            eq &= (int)(g_samples[i][0] * 16) == (int)(g_samples[i][3] * 16);
        same_order += eq;
    }
    CHECK(same_order == 0);
}

/* Chi-square over `pixels` pixels of n = rows x cols stratified samples (2D dimension 1-2)
 * against the uniform distribution of the difference, modulo the side, between the
 * sub-strata of two neighbours: with `across_rows` = 0 the sub-columns of columns 0 and 1 in
 * row 0 (rows - 1 degrees of freedom), else the sub-rows of rows 0 and 1 in column 0
 * (cols - 1). A permutation shared by the columns (rows) and not rotated makes the
 * difference constant. */
static double neighbour_offset_chi2(int n, int rows, int cols, uint64_t seed, int pixels, int across_rows)
{
    int side = across_rows ? cols : rows, hist[MAX_N] = {0};
    for (int p = 0; p < pixels; ++p) {
        fill_pixel(SAMPLER_STRATIFIED, seed, p % 100, p / 100, 0, n, g_samples);
        int sub[2] = {-1, -1};
        for (int i = 0; i < n; ++i) {
            int x_stratum = (int)(g_samples[i][1] * n), y_stratum = (int)(g_samples[i][2] * n);
            int column = x_stratum / rows, row = y_stratum / cols;
            int which = across_rows ? row : column, other = across_rows ? column : row;
            if (other == 0 && which < 2) sub[which] = across_rows ? y_stratum % cols : x_stratum % rows;
        }
        CHECK(sub[0] >= 0 && sub[1] >= 0);
        if (sub[0] >= 0 && sub[1] >= 0) hist[(sub[1] - sub[0] + side) % side]++;
    }
    double chi2 = 0.0, expected = (double)pixels / side;
    for (int v = 0; v < side; ++v) chi2 += (hist[v] - expected) * (hist[v] - expected) / expected;
    return chi2;
}

/* Past the tables (spp > 16) the multi-jitter structure still holds: one point per stratum
 * of width 1/n in every scalar dimension and one per cell of the rows x cols grid of every 2D
 * dimension. And neighbouring grid columns are not correlated: over pixels, the difference
 * (mod rows) between the sub-columns that columns 0 and 1 give their row-0 points is uniform
 * (a permutation shared by the columns, as in Kensler's correlated multi-jitter, would make it
 * always 0; chi-square with rows - 1 degrees of freedom, bound far above its 1e-4 quantile). */
static void test_multi_jitter_past_tables(void)
{
    const int counts[][3] = {{32, 4, 8}, {36, 6, 6}, {100, 10, 10}, {144, 12, 12}, {68, 4, 17}};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; ++k) {
        int n = counts[k][0], rows = counts[k][1], cols = counts[k][2];
        for (int pixel = 0; pixel < 10; ++pixel) {
            fill_pixel(SAMPLER_STRATIFIED, 3, pixel, 5 * pixel, 0, n, g_samples);
            for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples, n, d));
            for (int d = 0; d < DIMS; ++d)
                if (is_2d_x(d)) CHECK(stratified_grid(g_samples, n, d, cols, rows));
        }
    }
    double chi2 = neighbour_offset_chi2(36, 6, 6, 9, 3000, 0);
    printf("multi-jitter past the tables: column offset chi-square %.1f (5 dof)\n", chi2);
    CHECK(chi2 < 35.0);
}

/* The grid of n points: rows the largest divisor of n not above sqrt(n). */
static void grid_of(int n, int *rows, int *cols)
{
    int r = 1;
    for (int k = 1; k * k <= n; ++k)
        if (n % k == 0) r = k;
    *rows = r, *cols = n / r;
}

/* Grids with a side above 16 (the AAF counts: primes, 2 p, and everything above 256):
 * 1 x 37, 2 x 17, 15 x 20, 25 x 40, and 2 x 1031, whose rows + cols exceed the sampler's
 * lazily filled grid tables (computed per sample instead). In every pixel and 2D dimension
 * each 1D x stratum and each y stratum holds exactly one of the n samples and each grid cell
 * exactly one (so sub-columns in a column and sub-rows in a row are distinct); the 1D
 * dimensions stay stratified too. */
static void test_multi_jitter_large_sides(void)
{
    const int counts[] = {37, 34, 300, 1000, 2062};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; ++k) {
        int n = counts[k], rows, cols;
        grid_of(n, &rows, &cols);
        CHECK(rows > 16 || cols > 16);
        int bad_1d = 0, bad_grid = 0;
        for (int pixel = 0; pixel < 6; ++pixel) {
            fill_pixel(SAMPLER_STRATIFIED, 13, pixel, 7 * pixel, 0, n, g_samples);
            for (int d = 0; d < DIMS; ++d) bad_1d += !stratified_1d(g_samples, n, d);
            for (int d = 0; d < DIMS; ++d)
                if (is_2d_x(d)) bad_grid += !stratified_grid(g_samples, n, d, cols, rows);
        }
        printf("multi-jitter %d = %d x %d: %d unstratified dimensions, %d unstratified grids\n", n, rows, cols,
               bad_1d, bad_grid);
        CHECK(bad_1d == 0 && bad_grid == 0);
    }

    /* The rows' sub-row permutations are rotated apart: in a 15 x 20 grid (sides past 16)
     * the difference (mod cols) between the sub-rows that rows 0 and 1 give their column-0
     * points is uniform over pixels; one permutation shared unrotated would make it always
     * the same. Chi-square with cols - 1 = 19 degrees of freedom: mean 19, sd 6.2; bound at
     * 10 sd above the mean, far beyond chance, far below a constant (chi2 = 19 pixels). */
    double chi2 = neighbour_offset_chi2(300, 15, 20, 17, 2000, 1);
    printf("multi-jitter 15 x 20: row offset chi-square %.1f (19 dof)\n", chi2);
    CHECK(chi2 < 19.0 + 10.0 * sqrt(2.0 * 19.0));
}

/* Each sample is uniform on the unit square, whatever its index, on grids with a side past
 * 16: over many pixels the x and y strata of sample 0 of a 2D dimension are uniform over
 * [0, n) (chi-square with n - 1 degrees of freedom, bound at 6 sd above its mean), and the
 * mean over all samples of f(x, y) = x y is 1/4 within 5 standard errors, the standard
 * error measured from the pixels' estimates. */
static void test_large_sides_uniform(void)
{
    const int counts[] = {37, 34, 300, 1000};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; ++k) {
        int n = counts[k], pixels = n < 100 ? 40 * n : 4000;
        static int hist_x[MAX_N], hist_y[MAX_N];
        memset(hist_x, 0, sizeof hist_x);
        memset(hist_y, 0, sizeof hist_y);
        double sum = 0.0, sum_sq = 0.0;
        for (int p = 0; p < pixels; ++p) {
            fill_pixel(SAMPLER_STRATIFIED, 23, p % 128, p / 128, 0, n, g_samples);
            hist_x[(int)(g_samples[0][4] * n)]++;
            hist_y[(int)(g_samples[0][5] * n)]++;
            double est = 0.0;
            for (int i = 0; i < n; ++i) est += (double)g_samples[i][4] * g_samples[i][5];
            est /= n;
            sum += est;
            sum_sq += est * est;
        }
        double chi_x = 0.0, chi_y = 0.0, expected = (double)pixels / n;
        for (int v = 0; v < n; ++v) {
            chi_x += (hist_x[v] - expected) * (hist_x[v] - expected) / expected;
            chi_y += (hist_y[v] - expected) * (hist_y[v] - expected) / expected;
        }
        double dof = n - 1, chi_bound = dof + 6.0 * sqrt(2.0 * dof);
        double mean = sum / pixels, se = sqrt(fmax(sum_sq / pixels - mean * mean, 0.0) / (pixels - 1));
        printf("uniform %d spp: chi-square of sample 0's strata x %.1f, y %.1f (%d dof); E[xy] - 1/4 = %.2g "
               "(standard error %.2g)\n",
               n, chi_x, chi_y, n - 1, mean - 0.25, se);
        CHECK(chi_x < chi_bound && chi_y < chi_bound);
        CHECK(se > 0.0 && fabs(mean - 0.25) < 5.0 * se);
    }
}

/* (0, k, 2)-net in base 2: for every split a + b = k, each elementary interval
 * [i/2^a, (i+1)/2^a) x [j/2^b, (j+1)/2^b) holds exactly one of the n = 2^k points. */
static int is_02_net(float v[][DIMS], int k, int d)
{
    int n = 1 << k;
    for (int a = 0; a <= k; ++a)
        if (!stratified_grid(v, n, d, 1 << a, 1 << (k - a))) return 0;
    return 1;
}

static void test_sobol_nets(void)
{
    const int ks[2] = {4, 6};
    for (int t = 0; t < 2; ++t) {
        int k = ks[t], n = 1 << k;
        for (int pixel = 0; pixel < 20; ++pixel) {
            fill_pixel(SAMPLER_SOBOL, 5, pixel, 7, pixel % 3, n, g_samples);
            for (int d = 0; d < DIMS; ++d)
                if (is_2d_x(d)) CHECK(is_02_net(g_samples, k, d));
            /* 1D dimensions: the scrambled van der Corput points are one per 1/n stratum
             * (and so are the 2D coordinates, the 1D projections of a (0,2)-net). */
            for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples, n, d));
        }
    }
}

static void test_permute(void)
{
    unsigned char seen[300];
    for (uint32_t n = 1; n <= 300; n += (n < 40 ? 1 : 13))
        for (uint64_t seed = 0; seed < 8; ++seed) {
            memset(seen, 0, sizeof seen);
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t p = sampler_permute(i, n, hash_u64(seed));
                CHECK(p < n);
                if (p < n) seen[p]++;
            }
            for (uint32_t i = 0; i < n; ++i) CHECK(seen[i] == 1);
        }
    /* Different seeds give different permutations: over many seeds every position of a
     * 16-element permutation takes every value, roughly uniformly (chi-square-like bound:
     * 4000 seeds, expected 250 per cell, allow +-30%, i.e. over 7 standard deviations). */
    static int hist[16][16];
    for (uint64_t seed = 0; seed < 4000; ++seed)
        for (uint32_t i = 0; i < 16; ++i) hist[i][sampler_permute(i, 16, hash_u64(seed + 1000))]++;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j) CHECK(hist[i][j] > 175 && hist[i][j] < 325);
}

/* Integrand with a closed form: f(x, y) = x y e^(x+y) = (x e^x)(y e^y); the integral of
 * x e^x over [0, 1] is [(x - 1) e^x]_0^1 = 1, so the integral over the unit square is 1. */
static double f_smooth(double x, double y) { return x * y * exp(x + y); }

/* RMS error of the n-sample estimate over many pixels, using the 2D dimension that follows
 * `skip` scalar dimensions (skip = 1 exercises the padding shuffle; skip >= the padded range
 * gives independent random numbers). */
static double rms_error(SamplerKind kind, int n, int skip, int pixels)
{
    double sum_sq = 0.0;
    for (int p = 0; p < pixels; ++p) {
        PixelSampler s;
        sampler_start_pixel(&s, kind, 99, p % 64, p / 64, 0, n);
        double est = 0.0;
        for (int i = 0; i < n; ++i) {
            sampler_start_sample(&s, i);
            for (int d = 0; d < skip; ++d) (void)sampler_1d(&s);
            vec2 u = sampler_2d(&s);
            est += f_smooth(u.x, u.y);
        }
        est /= n;
        sum_sq += (est - 1.0) * (est - 1.0);
    }
    return sqrt(sum_sq / pixels);
}

/* Least-squares slope of log(rms) against log(n) for n = 4, 8, ..., 256. */
static double error_slope(SamplerKind kind, int skip)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int m = 0;
    for (int n = 4; n <= 256; n *= 2, ++m) {
        double x = log((double)n), y = log(rms_error(kind, n, skip, 1024));
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

/* Multi-jitter as Chiu, Shirley and Wang build it, with an independent uniform permutation
 * per column and per row (Fisher-Yates), the sampler's construction before the rotated
 * shared permutations: the estimate of f_smooth from one pixel's n points. */
static void random_permutation(int *perm, int m, Pcg32 *rng)
{
    for (int k = 0; k < m; ++k) perm[k] = k;
    for (int k = m - 1; k > 0; --k) {
        int j = (int)pcg32_below(rng, (uint32_t)k + 1u), t = perm[k];
        perm[k] = perm[j], perm[j] = t;
    }
}

static double independent_mj_estimate(int n, int rows, int cols, Pcg32 *rng)
{
    static int sub_x[MAX_N], sub_y[MAX_N]; /* cell r cols + c */
    int perm[MAX_N];
    for (int c = 0; c < cols; ++c) {
        random_permutation(perm, rows, rng);
        for (int r = 0; r < rows; ++r) sub_x[r * cols + c] = perm[r];
    }
    for (int r = 0; r < rows; ++r) {
        random_permutation(perm, cols, rng);
        for (int c = 0; c < cols; ++c) sub_y[r * cols + c] = perm[c];
    }
    double est = 0.0;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            double x = (c * rows + sub_x[r * cols + c] + pcg32_float(rng)) / n;
            double y = (r * cols + sub_y[r * cols + c] + pcg32_float(rng)) / n;
            est += f_smooth(x, y);
        }
    return est / n;
}

/* Mean squared error of f_smooth over `pixels` pixels and its standard error: the sampler's
 * 2D dimension after one 1D (reference = 0), or independent_mj_estimate (reference = 1). */
static void mse_large(int n, int reference, int pixels, double *mse, double *se)
{
    int rows, cols;
    grid_of(n, &rows, &cols);
    Pcg32 rng;
    pcg32_seed(&rng, 1234u + (uint64_t)n, 7u);
    double sum = 0.0, sum_sq = 0.0;
    for (int p = 0; p < pixels; ++p) {
        double est;
        if (reference) {
            est = independent_mj_estimate(n, rows, cols, &rng);
        } else {
            PixelSampler s;
            sampler_start_pixel(&s, SAMPLER_STRATIFIED, 31, p % 64, p / 64, 0, n);
            est = 0.0;
            for (int i = 0; i < n; ++i) {
                sampler_start_sample(&s, i);
                (void)sampler_1d(&s);
                vec2 u = sampler_2d(&s);
                est += f_smooth(u.x, u.y);
            }
            est /= n;
        }
        double e2 = (est - 1.0) * (est - 1.0);
        sum += e2;
        sum_sq += e2 * e2;
    }
    *mse = sum / pixels;
    *se = sqrt(fmax(sum_sq / pixels - *mse * *mse, 0.0) / (pixels - 1));
}

/* On grids with a side past 16 the shared rotated permutations integrate a smooth function
 * no worse than independent random permutations per column and row (the mean squared
 * errors differ by less than 4 standard errors of their difference, or ours is lower), and
 * the error falls with n. */
static void test_large_sides_integrate(void)
{
    const int counts[] = {34, 37, 300, 1000};
    double mse[4];
    for (size_t k = 0; k < 4; ++k) {
        int n = counts[k], pixels = n < 100 ? 4096 : 1024;
        double ours_se, ref, ref_se;
        mse_large(n, 0, pixels, &mse[k], &ours_se);
        mse_large(n, 1, pixels, &ref, &ref_se);
        printf("f_smooth at %d spp: rms error %.3g (independent permutations per column and row %.3g, "
               "ratio %.3f)\n",
               n, sqrt(mse[k]), sqrt(ref), sqrt(mse[k] / ref));
        CHECK(mse[k] < ref + 4.0 * sqrt(ours_se * ours_se + ref_se * ref_se));
    }
    CHECK(mse[2] < fmin(mse[0], mse[1]));
    CHECK(mse[3] < mse[2]);
}

/* Expected rates for a smooth (C^1) integrand in 2D:
 *  - independent samples: variance sigma^2 / n, RMS error ~ n^-0.5;
 *  - stratified with one point per cell of side h ~ n^-1/2: inside a cell f varies by
 *    O(h), so each cell's term has variance O(h^2) / n^2 and the n cells sum to
 *    O(h^2 / n) = O(n^-2): RMS error ~ n^-1 (multi-jitter on rectangular 2 x 4, 4 x 8,
 *    8 x 16 grids for the non-square n has the same cell size order);
 *  - Owen-scrambled (0, m, 2)-nets: variance O(n^-3 (log n)) for smooth f (Owen 1997,
 *    "Scrambled net variance for integrals of smooth functions"): RMS ~ n^-1.5.
 * Both samplers must therefore beat -0.75 clearly, while independent numbers must not. */
static void test_convergence(void)
{
    double slope_strat = error_slope(SAMPLER_STRATIFIED, 1);
    double slope_sobol = error_slope(SAMPLER_SOBOL, 1);
    double slope_random = error_slope(SAMPLER_SOBOL, SAMPLER_PADDED_DIMS + 1);
    printf("error slopes: stratified %.3f, sobol %.3f, independent (past padded dims) %.3f\n",
           slope_strat, slope_sobol, slope_random);
    CHECK(slope_strat < -0.75);
    CHECK(slope_sobol < -0.75);
    CHECK(slope_sobol < slope_strat); /* n^-1.5 versus n^-1 */
    CHECK(slope_random > -0.65 && slope_random < -0.35);
}

/* Reference for the hash-based scramble: a true Owen scramble (Owen 1995), where the flip
 * of bit d depends on the d leading bits through an independent random bit per node of the
 * binary tree (here a splitmix hash of (node, depth, seed)). Brute force, 24 bits. */
static uint32_t owen_reference(uint32_t v, uint64_t seed)
{
    uint32_t out = 0;
    for (int d = 0; d < 24; ++d) {
        uint32_t prefix = d ? v >> (32 - d) : 0;
        uint32_t flip = (uint32_t)hash_u64(seed ^ hash_u64(((uint64_t)d << 32) | prefix)) & 1u;
        out |= (((v >> (31 - d)) & 1u) ^ flip) << (31 - d);
    }
    return out;
}

/* Sobol' points straight from the generator matrices: dimension 0 is the identity matrix
 * read backwards (radical inverse), dimension 1 the Pascal matrix mod 2, entry (row r,
 * column c) = binomial(c, r) mod 2 = 1 iff (r & c) == r (Lucas' theorem). */
static uint32_t sobol_reference(uint32_t i, int dim)
{
    uint32_t out = 0;
    for (int c = 0; c < 32; ++c) {
        if (!((i >> c) & 1u)) continue;
        if (dim == 0) {
            out ^= 1u << (31 - c);
        } else {
            for (int r = 0; r <= c; ++r)
                if ((r & c) == r) out ^= 1u << (31 - r);
        }
    }
    return out;
}

/* Our scrambled Sobol' points must integrate like truly Owen-scrambled Sobol' points: same
 * RMS error within the statistical uncertainty of 2048 pixels (a few %; allow 15%). A weak
 * hash would leave structure and show up as a larger error. */
static void test_owen_quality(void)
{
    const int pixels = 2048;
    for (int n = 16; n <= 256; n *= 4) {
        double sum_sq = 0.0;
        for (int p = 0; p < pixels; ++p) {
            uint64_t seed = hash_u64((uint64_t)p + 777);
            double est = 0.0;
            for (int i = 0; i < n; ++i) {
                double x = (owen_reference(sobol_reference((uint32_t)i, 0), seed) >> 8) * 0x1p-24;
                double y = (owen_reference(sobol_reference((uint32_t)i, 1), ~seed) >> 8) * 0x1p-24;
                est += f_smooth(x, y);
            }
            est /= n;
            sum_sq += (est - 1.0) * (est - 1.0);
        }
        double ref = sqrt(sum_sq / pixels), ours = rms_error(SAMPLER_SOBOL, n, 1, pixels);
        printf("n = %3d: rms error, hashed Owen %.3g, reference Owen %.3g (ratio %.3f)\n", n, ours, ref,
               ours / ref);
        CHECK(ours / ref > 0.85 && ours / ref < 1.15);
    }
}

/* Unbiasedness at any sample count: every sample of a scrambled (or jittered) set is
 * uniform on [0, 1), so over many pixels the mean of each dimension is 1/2 and E[x y] of a 2D
 * pair is 1/4, also when spp is not a power of 2 (9 spp: the first 9 Sobol' points, whose
 * unscrambled leading bits are unbalanced 5:4). The scramble used to leave the leading bit
 * unflipped, giving 0.463 at 9 spp. 20000 pixels: the standard error of a mean is below
 * 0.3 / sqrt(20000 n) < 7e-4; allow 5 of them. */
static void test_unbiased_any_count(SamplerKind kind)
{
    const int pixels = 20000;
    int counts[] = {3, 9, 12, 13, 24, 36, 37};
    for (int c = 0; c < 7; ++c) {
        int n = counts[c];
        double sum[DIMS] = {0}, sum_xy = 0.0, sum_pad = 0.0;
        for (int p = 0; p < pixels; ++p) {
            fill_pixel(kind, 5, p % 200, p / 200, 0, n, g_samples);
            for (int i = 0; i < n; ++i) {
                for (int d = 0; d < DIMS; ++d) sum[d] += g_samples[i][d];
                sum_xy += (double)g_samples[i][1] * g_samples[i][2];
                sum_pad += (double)g_samples[i][0] * g_samples[i][3]; /* two padded 1D dims */
            }
        }
        double total = (double)pixels * n, tol = 5.0 * 0.3 / sqrt(total);
        double worst = 0.0;
        for (int d = 0; d < DIMS; ++d) worst = fmax(worst, fabs(sum[d] / total - 0.5));
        printf("%s spp %d: largest |mean - 1/2| %.2g, E[xy] - 1/4 = %.2g, across dims %.2g (tolerance %.2g)\n",
               sampler_kind_name(kind), n, worst, sum_xy / total - 0.25, sum_pad / total - 0.25, tol);
        CHECK(worst < tol);
        CHECK(fabs(sum_xy / total - 0.25) < tol);
        CHECK(fabs(sum_pad / total - 0.25) < tol);
    }
}

/* All n samples of one pixel continued from its first `before` (sampler_continue_pixel),
 * visited backwards so that the continuation's part is set up before the first part's. */
static void fill_pixel_continued(SamplerKind kind, uint64_t seed, int px, int py, int before, int n, float out[][DIMS])
{
    PixelSampler s;
    sampler_continue_pixel(&s, kind, seed, px, py, 0, before, n);
    for (int i = n; i-- > 0;) draw_sample(&s, i, out[i]);
}

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Whether dimension d of samples [0, n) of a and b hold the same values in some order. */
static int same_values(float a[][DIMS], float b[][DIMS], int n, int d)
{
    float va[MAX_N], vb[MAX_N];
    for (int i = 0; i < n; ++i) va[i] = a[i][d], vb[i] = b[i][d];
    qsort(va, (size_t)n, sizeof(float), compare_floats);
    qsort(vb, (size_t)n, sizeof(float), compare_floats);
    return memcmp(va, vb, (size_t)n * sizeof(float)) == 0;
}

/* Continuing a pixel's samples (an adaptive second pass):
 *  - the first `before` samples are exactly the set that sampler_start_pixel(before) gives;
 *  - Sobol': the whole is the first n points of each dimension's scrambled sequence, i.e.
 *    the same values as one set of n (in another order), a (0, 6, 2)-net at n = 64;
 *  - stratified: the continuation is itself stratified (n - before strata). */
static void test_continuation_sets(void)
{
    const int cases[][2] = {{16, 64}, {9, 64}, {16, 38}, {4, 17}, {16, 17}, {9, 100}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        int before = cases[c][0], n = cases[c][1];
        for (int pixel = 0; pixel < 8; ++pixel) {
            for (int k = 0; k < 2; ++k) {
                SamplerKind kind = k ? SAMPLER_SOBOL : SAMPLER_STRATIFIED;
                fill_pixel_continued(kind, 5, pixel, 2 * pixel, before, n, g_samples);
                fill_pixel(kind, 5, pixel, 2 * pixel, 0, before, g_other);
                CHECK(memcmp(g_samples, g_other, sizeof(float) * DIMS * (size_t)before) == 0);
                if (kind == SAMPLER_STRATIFIED) {
                    int m = n - before;
                    for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples + before, m, d));
                    continue;
                }
                fill_pixel(kind, 5, pixel, 2 * pixel, 0, n, g_other);
                for (int d = 0; d < DIMS; ++d) CHECK(same_values(g_samples, g_other, n, d));
                if (n == 64)
                    for (int d = 0; d < DIMS; ++d)
                        if (is_2d_x(d)) CHECK(is_02_net(g_samples, 6, d));
                /* the continuation has padding permutations of its own: the order of its
                 * samples differs from the single set's */
                int same_place = 0;
                for (int i = before; i < n; ++i) same_place += g_samples[i][1] == g_other[i][1];
                CHECK(same_place < n - before);
            }
        }
    }
    /* before >= n: an ordinary set of n */
    fill_pixel_continued(SAMPLER_SOBOL, 5, 1, 2, 20, 16, g_samples);
    fill_pixel(SAMPLER_SOBOL, 5, 1, 2, 0, 16, g_other);
    CHECK(memcmp(g_samples, g_other, sizeof(float) * DIMS * 16) == 0);
}

/* RMS error of f_smooth over `pixels` pixels: 2D dimension 1 of `before` samples of pass 0
 * followed either by a continuation to n (continued = 1) or by an independent set of
 * n - before samples of pass 1 (continued = 0, the adaptive second pass before continuation). */
static double rms_error_two_passes(SamplerKind kind, int before, int n, int continued, int pixels)
{
    double sum_sq = 0.0;
    for (int p = 0; p < pixels; ++p) {
        PixelSampler s;
        double est = 0.0;
        for (int part = 0; part < 2; ++part) {
            int first = part ? before : 0, end = part ? n : before;
            if (part == 0 || continued)
                sampler_continue_pixel(&s, kind, 99, p % 64, p / 64, 0, before, n);
            else
                sampler_start_pixel(&s, kind, 99, p % 64, p / 64, 1, n - before);
            for (int i = first; i < end; ++i) {
                sampler_start_sample(&s, (part && !continued) ? i - before : i);
                (void)sampler_1d(&s);
                vec2 u = sampler_2d(&s);
                est += f_smooth(u.x, u.y);
            }
        }
        est /= n;
        sum_sq += (est - 1.0) * (est - 1.0);
    }
    return sqrt(sum_sq / pixels);
}

/* What continuation buys: with Sobol', 16 samples continued to 64 integrate a smooth
 * function exactly as one set of 64 does (the same points), while 16 + an independent 48 leave the
 * first 16 points' larger error in the sum (expected RMS about 2x higher: the 16 points'
 * error, n^-1.5 of a net, weighs 1/4). Stratified sets do not extend, so there the two
 * ways must integrate alike. 4096 pixels: a few % of statistical uncertainty. */
static void test_continuation_integrates_better(void)
{
    const int pixels = 4096;
    double sob_cont = rms_error_two_passes(SAMPLER_SOBOL, 16, 64, 1, pixels);
    double sob_indep = rms_error_two_passes(SAMPLER_SOBOL, 16, 64, 0, pixels);
    double sob_one = rms_error(SAMPLER_SOBOL, 64, 1, pixels);
    double str_cont = rms_error_two_passes(SAMPLER_STRATIFIED, 16, 64, 1, pixels);
    double str_indep = rms_error_two_passes(SAMPLER_STRATIFIED, 16, 64, 0, pixels);
    printf("16 -> 64 spp, rms error: sobol continued %.3g, independent second set %.3g, one set of 64 %.3g; "
           "stratified continued %.3g, independent %.3g\n",
           sob_cont, sob_indep, sob_one, str_cont, str_indep);
    CHECK(sob_cont < 0.7 * sob_indep);
    CHECK(fabs(sob_cont - sob_one) <= 1e-6 * sob_one); /* the same points, summed in another order */
    CHECK(str_cont < 1.15 * str_indep && str_indep < 1.15 * str_cont);
}

/* Small permutations are exactly uniform: over many seeds each of the n! orderings of
 * n = 3 and n = 4 elements appears equally often (expected count 2400 and 600 per
 * ordering; allow 5 standard deviations, sd = sqrt(count)). A biased shuffle (a modulo
 * draw, a too-short random number split over many draws) shows up here. */
static void test_small_permutations_uniform(void)
{
    const int seeds = 14400;
    for (uint32_t n = 2; n <= 4; ++n) {
        int count[256] = {0};
        int orderings = n == 2 ? 2 : (n == 3 ? 6 : 24);
        for (int k = 0; k < seeds; ++k) {
            uint64_t seed = hash_u64((uint64_t)k * 7919u + n);
            int code = 0;
            for (uint32_t i = 0; i < n; ++i) code = code * 4 + (int)sampler_permute(i, n, seed);
            count[code]++;
        }
        int distinct = 0, worst = 0;
        double expect = (double)seeds / orderings;
        for (int c = 0; c < 256; ++c) {
            if (!count[c]) continue;
            ++distinct;
            int dev = (int)fabs(count[c] - expect);
            if (dev > worst) worst = dev;
        }
        CHECK(distinct == orderings);
        CHECK(worst < 5.0 * sqrt(expect));
    }
}

/* The padded multi-jitter tables at 4 spp (a 2 x 2 grid): which 1D x and y stratum each of
 * the 4 samples of a 2D dimension gets. There are 4! (2!)^2 (2!)^2 = 384 valid assignments
 * (x strata a permutation, one sample per grid cell, distinct sub-strata in every row and
 * column), and padded multi-jitter with uniform permutations makes them equally likely.
 * 384 * 60 pixel-dimensions: 60 expected per assignment, sd below 7.8; allow 5 sd. */
static void test_multi_jitter_assignments_uniform(void)
{
    enum { OUTCOMES = 1 << 16 };
    static int count[OUTCOMES];
    int trials = 0;
    for (int py = 0; trials < 384 * 60; ++py)
        for (int px = 0; px < 64 && trials < 384 * 60; ++px) {
            fill_pixel(SAMPLER_STRATIFIED, 11, px, py, 0, 4, g_samples);
            for (int d = 0; d < DIMS && trials < 384 * 60; ++d) {
                if (!is_2d_x(d)) continue;
                int code = 0; /* 2 bits per stratum: x and y of samples 0..3 */
                for (int i = 0; i < 4; ++i)
                    code = code << 4 | (int)(g_samples[i][d] * 4.0f) << 2 | (int)(g_samples[i][d + 1] * 4.0f);
                count[code]++;
                ++trials;
            }
        }
    int distinct = 0, worst = 0;
    for (int c = 0; c < OUTCOMES; ++c) {
        if (!count[c]) continue;
        ++distinct;
        int dev = abs(count[c] - 60);
        if (dev > worst) worst = dev;
    }
    CHECK(distinct == 384);
    CHECK(worst < 39);
}

/* Every spp up to 16 (the per-pixel table path) and a second block of indices: one value
 * per 1/n stratum in every scalar dimension, one point per cell of the rows x cols grid in
 * every 2D dimension (rows = largest divisor of n not above sqrt(n)). */
static void test_stratified_every_small_count(void)
{
    for (int n = 1; n <= 16; ++n) {
        int rows = 1;
        for (int r = 1; r * r <= n; ++r)
            if (n % r == 0) rows = r;
        int cols = n / rows;
        for (int block = 0; block < 2; ++block) {
            PixelSampler s;
            sampler_start_pixel(&s, SAMPLER_STRATIFIED, 3, 5, 7, 0, n);
            for (int i = 0; i < n; ++i) {
                sampler_start_sample(&s, block * n + i);
                for (int d = 0; d < DIMS;) {
                    if ((d % 3) == 0) {
                        g_samples[i][d++] = sampler_1d(&s);
                    } else {
                        vec2 p = sampler_2d(&s);
                        g_samples[i][d++] = p.x;
                        g_samples[i][d++] = p.y;
                    }
                }
            }
            for (int d = 0; d < DIMS; ++d) CHECK(stratified_1d(g_samples, n, d));
            for (int d = 0; d < DIMS; ++d)
                if (is_2d_x(d)) CHECK(stratified_grid(g_samples, n, d, cols, rows));
        }
    }
}

/* The unit modulo m nearest m / phi (the sampler's lattice step, computed here on its own). */
static int golden_unit(int m)
{
    int best = 1;
    double target = m * 0.6180339887498949;
    for (int a = 1; a < m; ++a) {
        int g = a, b = m;
        while (b) {
            int t = g % b;
            g = b, b = t;
        }
        if (g == 1 && fabs(a - target) < fabs(best - target)) best = a;
    }
    return best;
}

/* Mean squared errors of f_smooth and of a half-plane indicator (random angle, line through a
 * random point: a shadow or silhouette edge) over `pixels` pixels at n spp, from the sampler's
 * 2D dimension after one 1D, or (reference) from multi-jitter with independent shuffles per
 * column and row, which is what every count up to 16 had before the lattice rows. */
static void small_count_mse(int n, int reference, int pixels, double *mse_smooth, double *mse_edge)
{
    int rows, cols;
    grid_of(n, &rows, &cols);
    Pcg32 rng, edges;
    pcg32_seed(&rng, 77u + (uint64_t)n, 3u);
    pcg32_seed(&edges, 5u, 9u); /* the same edges for both */
    double sum_smooth = 0.0, sum_edge = 0.0;
    float xs[16], ys[16];
    for (int p = 0; p < pixels; ++p) {
        if (reference) {
            static int sub_x[16], sub_y[16];
            int perm[16];
            for (int c = 0; c < cols; ++c) {
                random_permutation(perm, rows, &rng);
                for (int r = 0; r < rows; ++r) sub_x[r * cols + c] = perm[r];
            }
            for (int r = 0; r < rows; ++r) {
                random_permutation(perm, cols, &rng);
                for (int c = 0; c < cols; ++c) sub_y[r * cols + c] = perm[c];
            }
            for (int k = 0; k < n; ++k) {
                int r = k / cols, c = k % cols;
                xs[k] = (float)((c * rows + sub_x[k] + pcg32_float(&rng)) / n);
                ys[k] = (float)((r * cols + sub_y[k] + pcg32_float(&rng)) / n);
            }
        } else {
            PixelSampler s;
            sampler_start_pixel(&s, SAMPLER_STRATIFIED, 41, p % 64, p / 64, 0, n);
            for (int i = 0; i < n; ++i) {
                sampler_start_sample(&s, i);
                (void)sampler_1d(&s);
                vec2 u = sampler_2d(&s);
                xs[i] = u.x, ys[i] = u.y;
            }
        }
        double angle = 6.283185307179586 * pcg32_float(&edges), qx = pcg32_float(&edges), qy = pcg32_float(&edges);
        double dx = cos(angle), dy = sin(angle), smooth = 0.0, edge = 0.0;
        for (int k = 0; k < n; ++k) {
            smooth += f_smooth(xs[k], ys[k]);
            edge += (xs[k] - qx) * dx + (ys[k] - qy) * dy > 0;
        }
        sum_smooth += (smooth / n - 1.0) * (smooth / n - 1.0);
        sum_edge += (edge / n - half_plane_area(qx, qy, dx, dy)) * (edge / n - half_plane_area(qx, qy, dx, dy));
    }
    *mse_smooth = sum_smooth / pixels, *mse_edge = sum_edge / pixels;
}

/* Whether a grid side of m cells shares the lattice permutation (the sampler's rule). */
static int lattice_side(int m) { return m >= 5 && m != 6; }

/* A grid side of 5 or more cells (but 6) is the rank-1 lattice i -> step i (mod m), step the
 * unit nearest m / phi, rotated per column or row: at up to 16 spp the rows of 5, 7, 10,
 * 11, 13, 14, 15 spp; past 16 both sides (25 = 5 x 5, 26 = 2 x 13, 35 = 5 x 7, 64, 144,
 * 256). So in every row the sub-rows of consecutive columns differ by the step of cols, and
 * in every column the sub-columns of consecutive rows by that of rows. Every sample is still
 * uniform over the square: at 13 spp (1 x 13) the cell (x stratum, y stratum) of sample 0
 * of a 2D dimension is uniform over the 169 cells (chi-square, 168 degrees of freedom,
 * 60 per cell; the bound 260 is 5 standard deviations of the statistic above its mean).
 * And the lattice integrates better than independent shuffles: the RMS error of a smooth
 * and of an edge integrand is below 0.9x theirs at 11 and 13 spp (measured 0.73-0.80x;
 * 8192 pixels put the ratio within about 2% of its limit). The 1D and grid stratification
 * of these sets is test_stratified_every_small_count's (test_stratified's past 16). */
static void test_small_count_lattice_rows(void)
{
    const int counts[] = {5, 7, 10, 11, 13, 14, 15, 25, 26, 35, 64, 144, 256};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; ++k) {
        int n = counts[k], rows, cols;
        grid_of(n, &rows, &cols);
        PixelSampler s;
        sampler_start_pixel(&s, SAMPLER_STRATIFIED, 8, 3, 4, 0, n);
        for (int i = 0; i < n; ++i) draw_sample(&s, i, g_samples[i]);
        for (int d = 0; d < DIMS; ++d) {
            if (!is_2d_x(d)) continue;
            static int sub_col[256], sub_row[256]; /* cell r cols + c -> its point's sub-strata */
            for (int i = 0; i < n; ++i) {
                int x = (int)(g_samples[i][d] * n), y = (int)(g_samples[i][d + 1] * n);
                sub_col[(y / cols) * cols + x / rows] = x % rows;
                sub_row[(y / cols) * cols + x / rows] = y % cols;
            }
            for (int r = 0; r < rows; ++r)
                for (int c = 0; c < cols; ++c) {
                    int e = r * cols + c;
                    if (lattice_side(cols) && c + 1 < cols)
                        CHECK((sub_row[e + 1] - sub_row[e] + cols) % cols == golden_unit(cols));
                    if (lattice_side(rows) && r + 1 < rows)
                        CHECK((sub_col[e + cols] - sub_col[e] + rows) % rows == golden_unit(rows));
                }
        }
    }
    enum { N = 13, CELLS = N * N, PER_CELL = 60 };
    static int hist[CELLS];
    int trials = 0;
    for (int p = 0; trials < CELLS * PER_CELL; ++p) {
        fill_pixel(SAMPLER_STRATIFIED, 12, p % 64, p / 64, 0, N, g_samples);
        for (int d = 0; d < DIMS && trials < CELLS * PER_CELL; ++d) {
            if (!is_2d_x(d)) continue;
            hist[(int)(g_samples[0][d] * N) * N + (int)(g_samples[0][d + 1] * N)]++;
            ++trials;
        }
    }
    double chi2 = 0.0;
    for (int c = 0; c < CELLS; ++c) chi2 += (hist[c] - PER_CELL) * (hist[c] - PER_CELL) / (double)PER_CELL;
    printf("13 spp: chi-square of sample 0's cell %.1f (168 degrees of freedom)\n", chi2);
    CHECK(chi2 < 260.0);
    for (int n = 11; n <= 13; n += 2) {
        double smooth, edge, ref_smooth, ref_edge;
        small_count_mse(n, 0, 8192, &smooth, &edge);
        small_count_mse(n, 1, 8192, &ref_smooth, &ref_edge);
        printf("%d spp, lattice rows against shuffled: rms error ratio %.3f (smooth), %.3f (edge)\n", n,
               sqrt(smooth / ref_smooth), sqrt(edge / ref_edge));
        CHECK(smooth < 0.81 * ref_smooth);
        CHECK(edge < 0.81 * ref_edge);
    }
}

/* The jitter inside the strata (one hash per request, keyed by sample and dimension) is
 * uniform and independent: with o = v n - floor(v n) the offset of a value in its stratum,
 * E[o] = 1/2 in every dimension, and E[o o'] = 1/4 for two dimensions of one sample (x and
 * y of a 2D request, two different requests) and for one dimension of two consecutive
 * samples. 4 spp over 20000 pixels: 80000 products, sd of each mean below 0.3 / sqrt(80000)
 * = 1.1e-3; allow 5 of them. */
static void test_jitter_independent(void)
{
    const int n = 4, pixels = 20000;
    double sum[DIMS] = {0}, xy = 0.0, across = 0.0, consecutive = 0.0;
    for (int p = 0; p < pixels; ++p) {
        fill_pixel(SAMPLER_STRATIFIED, 11, p % 200, p / 200, 0, n, g_samples);
        for (int i = 0; i < n; ++i) {
            double o[DIMS];
            for (int d = 0; d < DIMS; ++d) {
                double v = (double)g_samples[i][d] * n;
                o[d] = v - floor(v);
                sum[d] += o[d];
            }
            xy += o[1] * o[2];
            across += o[1] * o[4];
            double v0 = (double)g_samples[(i + 1) % n][1] * n;
            consecutive += o[1] * (v0 - floor(v0));
        }
    }
    double total = (double)pixels * n, tol = 5.0 * 0.3 / sqrt(total);
    for (int d = 0; d < DIMS; ++d) CHECK(fabs(sum[d] / total - 0.5) < tol);
    CHECK(fabs(xy / total - 0.25) < tol);
    CHECK(fabs(across / total - 0.25) < tol);
    CHECK(fabs(consecutive / total - 0.25) < tol);
}

/* A dimension skipped with sampler_skip and drawn later with sampler_1d_at (or never) has
 * the value sampler_1d gives in sequence, and the dimensions after it keep their values:
 * tables, past spp (17), past the padded range (dimension 70). */
static void test_skip_and_draw_at(SamplerKind kind)
{
    const int counts[] = {4, 9, 17};
    for (int c = 0; c < 3; ++c) {
        int n = counts[c];
        PixelSampler a, b;
        sampler_start_pixel(&a, kind, 21, 6, 2, 0, n);
        sampler_start_pixel(&b, kind, 21, 6, 2, 0, n);
        int mismatches = 0;
        for (int i = 0; i < n + 2; ++i) {
            sampler_start_sample(&a, i);
            sampler_start_sample(&b, i);
            for (int d = 0; d < 72;) {
                float x = sampler_1d(&a); /* dimension d, in sequence */
                vec2 y = sampler_2d(&a);
                int skipped = b.dim;
                sampler_skip(&b, 1);
                vec2 y2 = sampler_2d(&b);
                mismatches += y.x != y2.x || y.y != y2.y;
                if (i % 2 == 0) mismatches += sampler_1d_at(&b, skipped) != x; /* drawn late, or not at all */
                d += 3;
            }
        }
        CHECK(mismatches == 0);
    }
}

static void test_names(void)
{
    CHECK(sampler_kind_from_pbrt("stratified") == SAMPLER_STRATIFIED);
    CHECK(sampler_kind_from_pbrt("independent") == SAMPLER_STRATIFIED);
    const char *sobols[] = {"sobol", "zsobol", "paddedsobol", "halton", "pmj02bn", "nonsense"};
    for (int i = 0; i < 6; ++i) CHECK(sampler_kind_from_pbrt(sobols[i]) == SAMPLER_SOBOL);
    CHECK(sampler_kind_from_pbrt(NULL) == SAMPLER_SOBOL);
    CHECK_STR(sampler_kind_name(SAMPLER_STRATIFIED), "stratified");
    CHECK_STR(sampler_kind_name(SAMPLER_SOBOL), "sobol");
}

int main(void)
{
    test_names();
    test_permute();
    for (int k = 0; k < 2; ++k) {
        SamplerKind kind = k ? SAMPLER_SOBOL : SAMPLER_STRATIFIED;
        test_range(kind);
        test_determinism(kind);
        test_cache_is_pure(kind);
        test_skip_and_draw_at(kind);
    }
    test_stratified();
    test_multi_jitter_past_tables();
    test_multi_jitter_large_sides();
    test_large_sides_uniform();
    test_large_sides_integrate();
    test_small_permutations_uniform();
    test_stratified_every_small_count();
    test_small_count_lattice_rows();
    test_multi_jitter_assignments_uniform();
    test_jitter_independent();
    test_sobol_nets();
    test_convergence();
    test_owen_quality();
    test_unbiased_any_count(SAMPLER_SOBOL);
    test_unbiased_any_count(SAMPLER_STRATIFIED);
    test_continuation_sets();
    test_continuation_integrates_better();
    CHECK_DONE();
}
