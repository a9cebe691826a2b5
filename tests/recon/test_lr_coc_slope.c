/* LR's CoC slope with the camera's factors taken once (src/recon/lr/lr_coc_slope.h) against
 * recon_coc_slope_px, bit for bit: depths from behind the camera to infinity and NaN, around
 * the focal plane, on several cameras (a pinhole and degenerate ones among them, a huge lens
 * whose slope overflows to the FLT_MAX clamp). */
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "../check.h"
#include "recon/lr/lr_coc_slope.h"

static uint32_t bits_of(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static unsigned next_u32(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

int main(void)
{
    const float cams[][3] = {/* lens radius, focal distance, pixel angle */
                             {0.05f, 4.0f, 1.0f / 512.0f}, {0.2f, 1.5f, 0.0013f}, {1e-4f, 100.0f, 3e-3f},
                             {3e30f, 0.5f, 1e-9f}, {0.0f, 4.0f, 0.002f}, {0.05f, 0.0f, 0.002f},
                             {0.05f, 4.0f, 0.0f}, {NAN, 4.0f, 0.002f}};
    int mismatches = 0, tested = 0, clamped = 0, nonzero = 0;
    unsigned rng = 7u;
    for (size_t c = 0; c < sizeof cams / sizeof cams[0]; ++c) {
        ReconCamera cam;
        memset(&cam, 0, sizeof cam);
        cam.lens_radius_world = cams[c][0], cam.focal_distance_world = cams[c][1], cam.pixel_angle = cams[c][2];
        LrCocSlope s = lr_coc_slope_of(&cam);
        float fixed[] = {0.0f, -0.0f, -1.0f, 1e-30f, 1e-3f, 0.5f, cams[c][1], nextafterf(cams[c][1], 0.0f),
                         nextafterf(cams[c][1], INFINITY), 1e30f, FLT_MAX, INFINITY, -INFINITY, NAN};
        for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; ++i, ++tested)
            mismatches += bits_of(lr_coc_slope_px(&s, fixed[i])) != bits_of(recon_coc_slope_px(&cam, fixed[i]));
        for (int i = 0; i < 200000; ++i, ++tested) {
            float z = ldexpf((float)(next_u32(&rng) & 0xffff) / 65536.0f + 0.5f, (int)(next_u32(&rng) % 40) - 12);
            float want = recon_coc_slope_px(&cam, z);
            mismatches += bits_of(lr_coc_slope_px(&s, z)) != bits_of(want);
            clamped += fabsf(want) == FLT_MAX;
            nonzero += want != 0.0f;
        }
    }
    CHECK(tested > 1000000);
    CHECK(mismatches == 0);
    CHECK(clamped > 0);   /* the overflow clamp was reached */
    CHECK(nonzero > 0);
    CHECK_DONE();
}
