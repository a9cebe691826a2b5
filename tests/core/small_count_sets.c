/* RMS integration error of one multi-jittered 2D set of n = 2..16 points, for the choices of
 * sub-row and sub-column permutations compared in docs/sampling.md ("Small counts with rows
 * of 5 or more"). A standalone measurement, not a test and not built by CMake:
 *   cc -O2 -std=c11 tests/core/small_count_sets.c -lm -o /tmp/small_count_sets
 *   /tmp/small_count_sets MODE [MIN_SIDE] [SETS] [STEP]
 * MODE 0: independent shuffles per column and row (the sampler's tables before 2026-11-29);
 * 1: rotated lattice c -> (g c + o) mod m on every side m >= MIN_SIDE (the sampler now: 5);
 * 2: rotated lattice on every side when rows <= 2; 3: a 1 x p grid as a Cranley-Patterson
 * rotated lattice (one shift, no jitter per cell); 4: every count as a 1 x n lattice rotated
 * per set, jittered per cell (STEP overrides g); 5: as 4 without jitter per cell;
 * 6: counts past 16 as the sampler builds them there (one shared permutation rho per side,
 * rotated per column and row), rho the lattice on sides >= MIN_SIDE but 6, else a shuffle
 * (MIN_SIDE 17: the sampler before 2026-11-29; 5: now).
 * Prints n, the RMS error of f = x y e^(x+y) (integral 1) and of the indicator of a
 * half-plane through a uniform point at a uniform angle (exact area by clipping). The
 * estimator is the set's mean; the padding permutation does not change it. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "half_plane_area.h"

static uint64_t state = 0x12345678abcdefull;
static uint64_t next_u64(void) /* SplitMix64 */
{
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static double uniform(void) { return (double)(next_u64() >> 11) * 0x1p-53; }
static unsigned below(unsigned m) { return (unsigned)(((unsigned __int128)next_u64() * m) >> 64); }

static void shuffle(unsigned *p, unsigned m)
{
    for (unsigned k = 0; k < m; ++k) p[k] = k;
    for (unsigned k = m; k-- > 1;) {
        unsigned j = below(k + 1), t = p[k];
        p[k] = p[j], p[j] = t;
    }
}

static unsigned gcd(unsigned a, unsigned b)
{
    while (b) {
        unsigned t = a % b;
        a = b, b = t;
    }
    return a;
}

/* The unit modulo m nearest m / phi, searched as the sampler's golden_step. */
static unsigned golden(unsigned m)
{
    unsigned a = (unsigned)(m * 0.6180339887498949 + 0.5);
    for (unsigned d = 0;; ++d) {
        if (a > d && gcd(a - d, m) == 1) return a - d;
        if (a + d < m && gcd(a + d, m) == 1) return a + d;
    }
}

static double f_smooth(double x, double y) { return x * y * exp(x + y); }

/* One side's sub-stratum permutation of m elements: the lattice c -> (g c + o) mod m rotated
 * by a uniform o, or a uniform shuffle. */
static void side_permutation(unsigned *perm, unsigned m, int lattice, unsigned g)
{
    unsigned o = below(m);
    if (!lattice) {
        shuffle(perm, m);
        return;
    }
    for (unsigned k = 0; k < m; ++k) perm[k] = (g * k + o) % m;
}

static void make_set(unsigned n, int mode, unsigned min_side, unsigned step, double *xs, double *ys)
{
    unsigned rows = (unsigned)floor(sqrt((double)n)), cols;
    while (rows > 1 && n % rows) --rows;
    cols = n / rows;
    if (mode >= 4 || (mode == 3 && rows == 1)) {
        unsigned g = n <= 2 ? 1 : step ? step : golden(n);
        if (mode == 4) {
            unsigned o = below(n);
            for (unsigned c = 0; c < n; ++c) xs[c] = (c + uniform()) / n, ys[c] = ((g * c + o) % n + uniform()) / n;
        } else {
            double u = uniform(), v = uniform();
            for (unsigned c = 0; c < n; ++c) {
                double x = c / (double)n + u, y = (double)(g * c % n) / n + v;
                xs[c] = x - floor(x), ys[c] = y - floor(y);
            }
        }
        return;
    }
    int lattice_x = mode == 1 ? rows >= min_side : mode == 2 && rows <= 2;
    int lattice_y = mode == 1 ? cols >= min_side : mode == 2 && rows <= 2;
    unsigned gx = rows > 2 ? golden(rows) : 1, gy = cols > 2 ? golden(cols) : 1;
    unsigned sub_x[16][16], sub_y[16][16]; /* [column][row], [row][column] */
    for (unsigned c = 0; c < cols; ++c) side_permutation(sub_x[c], rows, lattice_x, gx);
    for (unsigned r = 0; r < rows; ++r) side_permutation(sub_y[r], cols, lattice_y, gy);
    for (unsigned r = 0, k = 0; r < rows; ++r)
        for (unsigned c = 0; c < cols; ++c, ++k) {
            xs[k] = (c * rows + sub_x[c][r] + uniform()) / n;
            ys[k] = (r * cols + sub_y[r][c] + uniform()) / n;
        }
}

/* Mode 6: one set of n <= 256 points with shared rotated sub-stratum permutations. */
static void make_set_past_16(unsigned n, unsigned min_side, double *xs, double *ys)
{
    unsigned rows = (unsigned)floor(sqrt((double)n)), cols;
    while (rows > 1 && n % rows) --rows;
    cols = n / rows;
    unsigned rho_x[16], rho_y[16];
    side_permutation(rho_x, rows, rows >= min_side && rows != 6, rows > 2 ? golden(rows) : 1);
    side_permutation(rho_y, cols, cols >= min_side && cols != 6, cols > 2 ? golden(cols) : 1);
    unsigned o_col[16], o_row[16];
    for (unsigned c = 0; c < cols; ++c) o_col[c] = below(rows);
    for (unsigned r = 0; r < rows; ++r) o_row[r] = below(cols);
    for (unsigned r = 0, k = 0; r < rows; ++r)
        for (unsigned c = 0; c < cols; ++c, ++k) {
            xs[k] = (c * rows + (rho_x[r] + o_col[c]) % rows + uniform()) / n;
            ys[k] = (r * cols + (rho_y[c] + o_row[r]) % cols + uniform()) / n;
        }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s MODE [MIN_SIDE] [SETS] [STEP]\n", argv[0]);
        return 2;
    }
    int mode = atoi(argv[1]), sets = argc > 3 ? atoi(argv[3]) : 100000;
    unsigned min_side = argc > 2 ? (unsigned)atoi(argv[2]) : 5, step = argc > 4 ? (unsigned)atoi(argv[4]) : 0;
    static const unsigned past_16[] = {20, 24, 25, 26, 30, 32, 35, 36, 39, 48, 64, 100, 128, 144, 256};
    unsigned count_total = mode == 6 ? sizeof past_16 / sizeof past_16[0] : 15;
    for (unsigned k = 0; k < count_total; ++k) {
        unsigned n = mode == 6 ? past_16[k] : k + 2;
        static double xs[256], ys[256];
        double sum_smooth = 0.0, sum_edge = 0.0;
        for (int t = 0; t < sets; ++t) {
            if (mode == 6)
                make_set_past_16(n, min_side, xs, ys);
            else
                make_set(n, mode, min_side, step, xs, ys);
            double angle = 6.283185307179586 * uniform(), qx = uniform(), qy = uniform();
            double dx = cos(angle), dy = sin(angle), smooth = 0.0, edge = 0.0;
            for (unsigned i = 0; i < n; ++i) {
                smooth += f_smooth(xs[i], ys[i]);
                edge += (xs[i] - qx) * dx + (ys[i] - qy) * dy > 0;
            }
            double area = half_plane_area(qx, qy, dx, dy);
            sum_smooth += (smooth / n - 1.0) * (smooth / n - 1.0);
            sum_edge += (edge / n - area) * (edge / n - area);
        }
        printf("%u %.4f %.4f\n", n, sqrt(sum_smooth / sets), sqrt(sum_edge / sets));
    }
    return 0;
}
