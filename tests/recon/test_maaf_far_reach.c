/* The far pixels' reach (maaf_far_reach; docs/algorithms.md 9.27).
 *
 * 1. Closed form: one pixel that saw an occluder at (10, 7) of a 23 x 17 frame; every pixel's
 *    reach is min(cap, max(|dx|, |dy|) - 1), 0 at that pixel itself, for caps 0, 3, 8.
 * 2. Brute force: random maps (densities 0.2%, 2%, 20%) on frames from 1 x 1 to 40 x 31, caps 0,
 *    1, 5, 8, 20: each pixel's reach is the largest r <= cap such that the (2r + 1)^2 window
 *    around it, clipped to the frame, holds no pixel that saw an occluder (0 where even r = 0
 *    fails: the pixel itself saw one). A frame without any gives the cap everywhere.
 * 3. The marks (maaf_far_marks; 9.28): over every combination of occluder, albedo varying, hit
 *    and shadow rays (0, 1, 9) a pixel is marked exactly when it saw an occluder, its albedo
 *    varies, or it is a surface pixel without a shadow ray (a miss without one is not). A
 *    surface pixel at (10, 7) that cast no shadow ray, in a frame whose other pixels are
 *    surfaces with 9 unoccluded rays each, limits every pixel's reach to min(cap, d - 1) as
 *    an occluder there would (on wire_screen such pixels, faces lit at grazing, took the
 *    widest far filter and half their samples). */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_far_reach.h"

static int brute(const unsigned char *seen, int w, int h, int x, int y, int cap)
{
    int best = 0;
    for (int r = 0; r <= cap; ++r) {
        for (int yy = y - r; yy <= y + r; ++yy)
            for (int xx = x - r; xx <= x + r; ++xx)
                if (xx >= 0 && yy >= 0 && xx < w && yy < h && seen[yy * w + xx]) return best;
        best = r;
    }
    return best;
}

int main(void)
{
    enum { W1 = 23, H1 = 17 };
    unsigned char seen[40 * 31], reach[40 * 31];
    memset(seen, 0, sizeof seen);
    seen[7 * W1 + 10] = 1;
    const int caps1[] = {0, 3, 8};
    for (int c = 0; c < 3; ++c) {
        CHECK(maaf_far_reach(seen, W1, H1, caps1[c], reach));
        for (int y = 0; y < H1; ++y)
            for (int x = 0; x < W1; ++x) {
                int dx = abs(x - 10), dy = abs(y - 7), d = dx > dy ? dx : dy, want = d - 1;
                if (want < 0) want = 0;
                if (want > caps1[c]) want = caps1[c];
                CHECK(reach[y * W1 + x] == want);
            }
    }
    srand(7);
    const int caps[] = {0, 1, 5, 8, 20};
    const int dens_per_mille[] = {2, 20, 200};
    const int sizes[][2] = {{1, 1}, {1, 9}, {13, 1}, {40, 31}, {17, 23}};
    long checked = 0;
    for (int s = 0; s < 5; ++s)
        for (int d = 0; d < 3; ++d)
            for (int c = 0; c < 5; ++c) {
                int w = sizes[s][0], h = sizes[s][1];
                for (int i = 0; i < w * h; ++i) seen[i] = rand() % 1000 < dens_per_mille[d];
                CHECK(maaf_far_reach(seen, w, h, caps[c], reach));
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x, ++checked) CHECK(reach[y * w + x] == brute(seen, w, h, x, y, caps[c]));
            }
    memset(seen, 0, sizeof seen);
    CHECK(maaf_far_reach(seen, 40, 31, 8, reach));
    for (int i = 0; i < 40 * 31; ++i) CHECK(reach[i] == 8);
    /* 3. the marks */
    for (int k = 0; k < 24; ++k) {
        int rays_of[3] = {0, 1, 9}, rays = rays_of[k % 3];
        unsigned char occ = (unsigned char)(k / 3 % 2), alb = (unsigned char)(k / 6 % 2), hit = (unsigned char)(k / 12),
                      mark = 7;
        maaf_far_marks(1, &occ, &alb, &hit, &rays, &mark);
        CHECK(mark == (occ || alb || (hit && rays == 0)));
    }
    static unsigned char occ3[W1 * H1], alb3[W1 * H1], hit3[W1 * H1], marks3[W1 * H1];
    static int rays3[W1 * H1];
    for (int i = 0; i < W1 * H1; ++i) occ3[i] = 0, alb3[i] = 0, hit3[i] = 1, rays3[i] = 9;
    rays3[7 * W1 + 10] = 0;
    hit3[0] = 0, rays3[0] = 0; /* a miss: no shadow ray, and nothing to check */
    maaf_far_marks(W1 * H1, occ3, alb3, hit3, rays3, marks3);
    CHECK(maaf_far_reach(marks3, W1, H1, 8, reach));
    for (int y = 0; y < H1; ++y)
        for (int x = 0; x < W1; ++x) {
            int dx = abs(x - 10), dy = abs(y - 7), d = dx > dy ? dx : dy, want = d - 1 < 0 ? 0 : d - 1;
            CHECK(reach[y * W1 + x] == (want > 8 ? 8 : want));
        }
    printf("%ld reaches checked against brute force\n", checked);
    CHECK_DONE();
}
