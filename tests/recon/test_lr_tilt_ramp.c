/* The tilt's centroid shift (lr_tilt_ramp, docs/algorithms.md 8.35): the slope gradient fitted
 * from a layer's sums against a plane's closed form, and the cases that must give no shift. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "recon/lr/lr_partition.h"

static float uniform01(unsigned *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return (float)(*seed >> 8) / 16777216.0f;
}

/* n lens-centre points in [x0, x0 + w) x [y0, y0 + h) (when diagonal, a band at 45 degrees,
 * h px high, whose x and y correlate: the fit's cross term matters),
 * each seeing the slope c = c0 + gx (x - 8) + gy (y - 8). */
static LrTilt plane_sums(int n, float x0, float y0, float w, float h, bool diagonal, double c0, double gx, double gy)
{
    LrTilt t = {{0}};
    unsigned seed = 12345u;
    for (int i = 0; i < n; ++i) {
        float x = x0 + w * uniform01(&seed), y = y0 + h * uniform01(&seed);
        if (diagonal) y = x + (y - y0) - x0 + y0;
        float c = (float)(c0 + gx * (x - 8.0) + gy * (y - 8.0));
        lr_tilt_add(&t, x, y, c);
    }
    return t;
}

static void test_plane_gradient(void)
{
    /* a floor-like tilt (the bench floors: about -0.21 px of slope per row) and a general one;
     * the shift is (-eta g_x / 4, -rho g_y / 4), in closed form here */
    const double g[][2] = {{0.0, -0.21}, {0.13, 0.07}, {-0.05, 0.3}};
    for (int k = 0; k < 3; ++k)
        for (int diag = 0; diag < 2; ++diag) {
            LrTilt t = plane_sums(2048, 0.0f, 0.0f, 16.0f, diag ? 8.0f : 16.0f, diag, 6.0, g[k][0], g[k][1]);
            float eta = -5.5f, rho = -6.0f, rx, ry;
            lr_tilt_ramp(&t, eta, rho, &rx, &ry);
            CHECK_NEAR(rx, -eta * g[k][0] / 4.0, 2e-3);
            CHECK_NEAR(ry, -rho * g[k][1] / 4.0, 2e-3);
        }
}

static void test_no_shift(void)
{
    float rx = 1.0f, ry = 1.0f;
    /* a flat layer: no gradient, no shift */
    LrTilt flat = plane_sums(512, 0.0f, 0.0f, 16.0f, 16.0f, false, 4.0, 0.0, 0.0);
    lr_tilt_ramp(&flat, -4.0f, -4.0f, &rx, &ry);
    CHECK_NEAR(rx, 0.0, 1e-5);
    CHECK_NEAR(ry, 0.0, 1e-5);
    /* a layer within one row (and a diagonal band 2 px high): its gradient across it cannot be fitted */
    LrTilt thin = plane_sums(512, 0.0f, 0.0f, 16.0f, 2.0f, true, 4.0, 0.0, 0.3);
    lr_tilt_ramp(&thin, -4.0f, -4.0f, &rx, &ry);
    CHECK(rx == 0.0f && ry == 0.0f);
    LrTilt row = plane_sums(512, 0.0f, 3.0f, 16.0f, 0.9f, false, 4.0, 0.0, 0.3);
    rx = ry = 1.0f;
    lr_tilt_ramp(&row, -4.0f, -4.0f, &rx, &ry);
    CHECK(rx == 0.0f && ry == 0.0f);
    /* too few samples */
    LrTilt few = plane_sums(15, 0.0f, 0.0f, 16.0f, 16.0f, false, 4.0, 0.1, 0.3);
    rx = ry = 1.0f;
    lr_tilt_ramp(&few, -4.0f, -4.0f, &rx, &ry);
    CHECK(rx == 0.0f && ry == 0.0f);
    /* no reprojection (eta = rho = 0: the samples keep their own lens offsets, the ramp
     * included): nothing to add */
    LrTilt tilted = plane_sums(512, 0.0f, 0.0f, 16.0f, 16.0f, false, 4.0, 0.1, 0.3);
    lr_tilt_ramp(&tilted, 0.0f, 0.0f, &rx, &ry);
    CHECK(rx == 0.0f && ry == 0.0f);
}

/* The partition gives the shift to static layers only: a moving layer (psi != 0 or a shutter
 * shear) keeps none, and tilt_ramp = false gives none. */
static void test_partition(void)
{
    LrConfig cfg = lr_config_default();
    LrTile t;
    lr_tile_bounds(&cfg, 1.0f, 2.0f, &t);
    int raw_n = lr_tile_raw_count(&t);
    LrLayerStats st[LR_MAX_LAYERS + 1];
    for (int i = 0; i < LR_MAX_LAYERS + 1; ++i) st[i] = (LrLayerStats){0, 1.0f, 0.0f, INFINITY, -INFINITY, INFINITY, -INFINITY, 0.0f, 0.0f, {{0}}};
    /* raw 1: a static floor at c 5..7 px with a tilt of -0.21 px per row; raw 2: the same
     * samples moving 20 px along x */
    st[1] = (LrLayerStats){2048, 1.0f, 0.0f, 5.0f, 7.0f, 0.0f, 0.0f, 0.0f, 1000.0f, plane_sums(2048, 0, 0, 16, 16, false, 6.0, 0.0, -0.21)};
    st[2] = st[1];
    st[2].c_min_px = 7.1f, st[2].c_max_px = 8.0f, st[2].d_min_px = 19.0f, st[2].d_max_px = 21.0f;
    CHECK(raw_n > 3);
    LrTile a = t;
    lr_tile_finish(&cfg, st, &a);
    CHECK(a.layer_count == 2);
    const LrLayer *floor = &a.layer[a.compact[1]], *moving = &a.layer[a.compact[2]];
    CHECK(floor->filter.xi_px == 0.0f && floor->cos_psi == 1.0f);
    CHECK_NEAR(floor->ramp_y_px, -floor->filter.rho_px * -0.21 / 4.0, 2e-3);
    CHECK(fabsf(floor->ramp_y_px) > 0.1f);
    CHECK(moving->filter.xi_px != 0.0f && moving->ramp_x_px == 0.0f && moving->ramp_y_px == 0.0f);
    cfg.tilt_ramp = false;
    LrTile b = t;
    lr_tile_finish(&cfg, st, &b);
    CHECK(b.layer[b.compact[1]].ramp_y_px == 0.0f);
}

int main(void)
{
    test_plane_gradient();
    test_no_shift();
    test_partition();
    CHECK_DONE();
}
