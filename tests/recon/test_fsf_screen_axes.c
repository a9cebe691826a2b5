/* fsf_screen_axes_block against fsf_screen_axes, receiver by receiver: the same result and,
 * where it is true, the same floats bit for bit (the block runs the same float operations in
 * vector lanes). Random Jacobians, normals and light axes at scales from 1e-4 to 1e2 metres
 * per pixel, and the degenerate receivers each branch of fsf_screen_axes handles: a singular
 * Jacobian (det 0, or below float's range), an axis along the normal (no tangent component:
 * length 0), a step along a tiny second column (1e-20 m: below v3_length's plain range, its
 * rescaled path), NaN guides.
 * Blocks of every size from 1 to FSF_AXES_BLOCK; the light's two axes in every lane (the shadow
 * parameters) and, in every other block, each receiver's own random axes (the indirect light's
 * tangents). */
#include "check.h"
#include "recon/fsf/fsf_screen_axes.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

enum { RECEIVERS = 3000 };

static uint32_t rng(uint32_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 17, *s ^= *s << 5;
    return *s;
}

static float uniform(uint32_t *s, float lo, float hi) { return lo + (hi - lo) * (float)(rng(s) >> 8) * (1.0f / 16777216.0f); }

static vec3 random_vec(uint32_t *s, float scale)
{
    return v3(scale * uniform(s, -1, 1), scale * uniform(s, -1, 1), scale * uniform(s, -1, 1));
}

/* Receiver r's Jacobian and normal: mostly random, every 5th of one of the degenerate kinds. */
static void receiver(uint32_t *s, int r, const vec3 axis[2], vec3 *jx, vec3 *jy, vec3 *n)
{
    float scale = powf(10.0f, uniform(s, -4.0f, 2.0f));
    *jx = random_vec(s, scale), *jy = random_vec(s, scale), *n = v3_normalize(random_vec(s, 1.0f));
    if (r % 5 != 0) return;
    switch ((r / 5) % 5) {
    case 0: *jy = v3_scale(*jx, 2.0f); break;             /* singular */
    case 1: *n = axis[r % 2]; break;                      /* an axis along the normal */
    case 2: *jy = v3_scale(*jy, 1e-20f / scale); break;  /* a step below the plain range (det still > 0) */
    case 3: *jx = v3_scale(*jx, 1e-17f / scale), *jy = v3_scale(*jy, 1e-17f / scale); break; /* det underflows */
    default: jx->y = NAN; break;
    }
}

int main(void)
{
    uint32_t s = 12345;
    const vec3 light_axis[2] = {v3_normalize(v3(0.8f, 0.1f, -0.3f)), v3_normalize(v3(-0.2f, 0.9f, 0.4f))};
    long compared = 0, true_both = 0, differ = 0, rescaled = 0;
    for (int r0 = 0, count = 1, b = 0; r0 < RECEIVERS; r0 += count, count = count % FSF_AXES_BLOCK + 1, ++b) {
        FsfAxesBlock blk = {.count = 0};
        vec3 jx[FSF_AXES_BLOCK], jy[FSF_AXES_BLOCK], n[FSF_AXES_BLOCK], axis[FSF_AXES_BLOCK][2];
        for (int k = 0; k < count; ++k) {
            for (int a = 0; a < 2; ++a) axis[k][a] = b % 2 ? v3_normalize(random_vec(&s, 1.0f)) : light_axis[a];
            receiver(&s, r0 + k, axis[k], &jx[k], &jy[k], &n[k]);
            fsf_axes_lane(&blk, (size_t)k, jx[k], jy[k], n[k], axis[k]);
        }
        fsf_screen_axes_block(&blk);
        const FsfScreenAxes *block = blk.out;
        const bool *ok = blk.ok;
        for (int k = 0; k < count; ++k) {
            FsfScreenAxes one;
            bool one_ok = fsf_screen_axes(jx[k], jy[k], n[k], axis[k], &one);
            ++compared;
            if (one_ok != ok[k]) {
                ++differ;
                continue;
            }
            if (!one_ok) continue;
            ++true_both;
            bool same = memcmp(one.dir, block[k].dir, sizeof one.dir) == 0 && memcmp(one.step_m, block[k].step_m, sizeof one.step_m) == 0;
            for (int a = 0; a < 2; ++a) {
                const vec3 *p = &one.step_world[a], *q = &block[k].step_world[a];
                same = same && memcmp(&p->x, &q->x, sizeof(float)) == 0 && memcmp(&p->y, &q->y, sizeof(float)) == 0 &&
                       memcmp(&p->z, &q->z, sizeof(float)) == 0;
                float plain = sqrtf(v3_dot(one.step_world[a], one.step_world[a]));
                rescaled += !(plain > V3_LENGTH_PLAIN_MIN && plain < V3_LENGTH_PLAIN_MAX);
            }
            differ += !same;
        }
    }
    printf("%ld receivers: %ld with axes in both, %ld axes through v3_length's rescaled path, %ld differ\n", compared,
           true_both, rescaled, differ);
    CHECK(differ == 0);
    CHECK(true_both > compared / 2); /* the comparison covers the usual case ... */
    CHECK(rescaled >= 5);            /* ... and the rescaled lengths */
    CHECK(true_both < compared);     /* and the degenerate ones say false */
    CHECK_DONE();
}
