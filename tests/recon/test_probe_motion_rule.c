/* The gain probe's copy of LR's motion rule (src/recon/probe_motion_rule.h, branch held4): which
 * probe samples LR would shear along their motion. Synthetic samples on a 64 x 48 frame (16-px
 * tiles, 32-px windows), against what LR's rule says of each case written out here:
 *  - one object translating 20 px: every sample keeps its motion;
 *  - a spinning object (speeds 2..40 px along one direction in one window): none does;
 *  - two objects passing each other the opposite way at the same depth: none does; the same
 *    two on either side of the focal plane (different layers): both do; two directions at
 *    right angles at one speed: none does (no clear direction);
 *  - a wide range of speeds whose slowest streaks past the window (8.32): kept;
 *  - a sample outside the tile's window does not count; static samples and misses stay true;
 *  - and lr_motion_filter_kept is the rule LR's partition applies (the same verdicts as the
 *    closed forms of docs/algorithms.md 8.5 and 8.32). */
#include <math.h>
#include <string.h>

#include "check.h"
#include "recon/lr/lr_partition.h"
#include "recon/probe_motion_rule.h"

enum { W = 64, H = 48, MAX = 256 };

static ProbeMotionSample at(float x, float y, float mx, float my, float coc)
{
    return (ProbeMotionSample){x, y, {mx, my}, coc};
}

static int count_true(const bool *b, int n)
{
    int c = 0;
    for (int k = 0; k < n; ++k) c += b[k];
    return c;
}

int main(void)
{
    ProbeMotionSample s[MAX];
    bool f[MAX];
    LrConfig cfg = lr_config_default();
    CHECK(cfg.tile_px == 16 && cfg.window_px == 32);
    /* the rule itself: 8.5's spread and range tests, 8.32's long streaks */
    CHECK(lr_motion_filter_kept(&cfg, 19.0f, 21.0f, 0.3f));   /* one speed, one direction */
    CHECK(!lr_motion_filter_kept(&cfg, 2.0f, 40.0f, 0.0f));   /* range 38 > 4 and > 0.5 x 21 */
    CHECK(lr_motion_filter_kept(&cfg, 30.0f, 40.0f, 0.0f));   /* range 10 <= 0.5 x 35 */
    CHECK(lr_motion_filter_kept(&cfg, 2.0f, 5.5f, 0.0f));     /* range 3.5 <= 4 px */
    CHECK(!lr_motion_filter_kept(&cfg, 10.0f, 11.0f, 6.0f));  /* across 6 > 0.5 and > 5.25 */
    CHECK(lr_motion_filter_kept(&cfg, 32.0f, 120.0f, 0.0f));  /* slowest streaks past the window */
    CHECK(!lr_motion_filter_kept(&cfg, 31.0f, 120.0f, 0.0f)); /* ... just not */

    /* one object translating 20 px to the right in front of the focal plane */
    int n = 0;
    for (int y = 2; y < 46; y += 4)
        for (int x = 2; x < 62; x += 4) s[n++] = at((float)x + 0.5f, (float)y + 0.5f, 20.0f, 0.0f, -3.0f);
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(count_true(f, n) == n);

    /* a spinning object: the speed along x grows across it, 2 px at one edge to 40 at the other */
    n = 0;
    for (int y = 2; y < 46; y += 4)
        for (int x = 2; x < 62; x += 4) s[n++] = at((float)x + 0.5f, (float)y + 0.5f, 2.0f + 38.0f * (float)x / 62.0f, 0.0f, 0.2f);
    CHECK(probe_motion_filterable(s, n, W, H, f));
    /* each tile's verdict is LR's rule on the speeds of the probe columns inside its window
     * (x = 2.5, 6.5, ... within [x0 - 8, x0 + 24)) */
    for (int k = 0; k < n; ++k) {
        float x0 = floorf(s[k].x / 16.0f) * 16.0f - 8.0f, x1 = x0 + 32.0f;
        float first = 2.5f, last = 58.5f;
        while (first < x0) first += 4.0f;
        while (last >= x1) last -= 4.0f;
        float lo = 2.0f + 38.0f * (first - 0.5f) / 62.0f, hi = 2.0f + 38.0f * (last - 0.5f) / 62.0f;
        CHECK(f[k] == lr_motion_filter_kept(&cfg, lo, hi, 0.0f));
    }
    CHECK(count_true(f, n) < n / 2); /* most of it */

    /* two objects passing each other the opposite way at about the same depth (same layer) */
    n = 0;
    for (int y = 18; y < 30; y += 4)
        for (int x = 18; x < 30; x += 4) {
            s[n++] = at((float)x + 0.5f, (float)y + 0.5f, 25.0f, 0.0f, 0.3f);
            s[n++] = at((float)x + 0.5f, (float)y + 0.5f, -25.0f, 0.0f, 0.4f);
        }
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(count_true(f, n) == 0);
    /* ... on either side of the focal plane: two layers, each with one motion */
    for (int k = 1; k < n; k += 2) s[k].coc_slope_px = -0.4f;
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(count_true(f, n) == n);
    /* ... or far apart in depth on the same side (|c| 0.3 against 6: different layers) */
    for (int k = 1; k < n; k += 2) s[k].coc_slope_px = 6.0f;
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(count_true(f, n) == n);

    /* one speed, two directions at right angles (20 px along x, 20 along y): no clear mean
     * direction (across 14 px, above half the speed along it), though the speeds agree */
    n = 0;
    for (int y = 18; y < 30; y += 4)
        for (int x = 18; x < 30; x += 4) {
            s[n++] = at((float)x + 0.5f, (float)y + 0.5f, 20.0f, 0.0f, 0.3f);
            s[n++] = at((float)x + 0.5f, (float)y + 0.5f, 0.0f, 20.0f, 0.3f);
        }
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(count_true(f, n) == 0);

    /* long streaks: speeds 40..160 px, a wide range, but the slowest passes the window */
    n = 0;
    for (int x = 2; x < 30; x += 4) s[n++] = at((float)x + 0.5f, 20.5f, 40.0f + 4.0f * (float)x, 0.0f, 1.5f);
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(count_true(f, n) == n);

    /* the window: a tile at x 16..31 reads 8..39; a sample moving the other way at x 44 is
     * outside it, while its own tile (32..47) reads 24..55, which holds the one at x 24 */
    n = 0;
    s[n++] = at(20.5f, 20.5f, 20.0f, 0.0f, 0.5f);
    s[n++] = at(24.5f, 20.5f, 20.0f, 0.0f, 0.5f);
    s[n++] = at(44.5f, 20.5f, -20.0f, 0.0f, 0.5f);
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(f[0] && f[1]);
    CHECK(!f[2]);
    s[n++] = at(36.5f, 20.5f, -20.0f, 0.0f, 0.5f); /* inside the first tile's window */
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(!f[0] && !f[1]);

    /* static samples and misses keep true (their blur has no motion to leave out) */
    n = 0;
    s[n++] = at(20.5f, 20.5f, 0.3f, 0.0f, 0.5f);
    s[n++] = at(21.5f, 20.5f, 30.0f, 0.0f, NAN);
    s[n++] = at(22.5f, 20.5f, 30.0f, 0.0f, 0.5f);
    s[n++] = at(23.5f, 20.5f, 2.0f, 0.0f, 0.5f);
    CHECK(probe_motion_filterable(s, n, W, H, f));
    CHECK(f[0] && f[1]);
    CHECK(!f[2] && !f[3]); /* 2..30: range 28 > 4 and > 8 */
    CHECK(probe_motion_filterable(s, 0, W, H, f));
    return check_failures ? 1 : 0;
}
