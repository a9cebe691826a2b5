/* FSF's indirect-light geometry (fsf_bounce.h) against brute force: a tilted receiver plane
 * seen through an oblique screen mapping, every bounce ray hitting a parallel plane at height
 * h. The shear fsf_bounce_params gives must move a hit's v-plane coordinate exactly as
 * reprojecting the hit point from a neighbour does (sign and size), the slope range must be
 * 1/h (rim samples with their unbounded slopes left out, and a steeper one beyond the band's
 * reach of the pixel's count, misses at 0), and the widths the parallax bound. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "recon/fsf/fsf_band.h"
#include "recon/fsf/fsf_bounce.h"

enum { W = 24, H = 20, SPP = 6 };
static const float H_M = 0.05f; /* the reflector plane's height over the receiver */

static unsigned rng_state = 12345u;
static float rand01(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (float)(rng_state >> 8) / 16777216.0f;
}

/* A cosine-distributed direction about n in the frame (t1, t2, n). */
static vec3 cosine_dir(const FsfBounceFrame *f)
{
    float u1 = rand01(), u2 = rand01(), r = sqrtf(u1), phi = 6.2831853f * u2;
    vec3 d = v3_scale(f->t[0], r * cosf(phi));
    d = v3_madd(d, f->t[1], r * sinf(phi));
    return v3_madd(d, f->n, sqrtf(fmaxf(0.0f, 1.0f - u1)));
}

int main(void)
{
    /* the receiver: P(x, y) = O + x A + y B, A and B neither orthogonal nor axis-aligned */
    vec3 O = v3(0.3f, -0.2f, 1.0f), A = v3(0.010f, 0.002f, 0.003f), B = v3(0.004f, 0.011f, -0.002f);
    vec3 n = v3_cross(A, B);
    n = v3_scale(n, 1.0f / v3_length(n));
    GBuffer g;
    CHECK(gbuffer_init(&g, W, H, (ReconCamera){0}));
    SampleStore *st = NULL;
    Diag d = {0};
    CHECK(sample_store_create(SAMPLE_FIELD_BOUNCE, W, H, SPP, SIZE_MAX, &st, &d));
    if (!st) return 1;
    g.scene_size_world = 1.0f;
    FsfBounceFrame f;
    CHECK(fsf_bounce_frame(A, n, &f));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + (size_t)x;
            vec3 p = v3_add(O, v3_add(v3_scale(A, (float)x), v3_scale(B, (float)y)));
            g.hit[i] = 1;
            float *p4 = g.pos4 + 4 * i, *n4 = g.nrm4 + 4 * i;
            p4[0] = p.x, p4[1] = p.y, p4[2] = p.z, p4[3] = 2.0f;
            n4[0] = n.x, n4[1] = n.y, n4[2] = n.z, n4[3] = 0.0f;
            for (int k = 0; k < SPP; ++k) {
                SampleRecord r = {0};
                r.hit = true, r.bounce_count = 1;
                r.indirect = v3s(1.0f);
                vec3 dir = cosine_dir(&f);
                float h_hit = H_M;
                if (k == SPP - 1) /* grazing, hitting at a tiny height: on the rim, no slope */
                    dir = v3_scale(v3_madd(f.t[0], n, 0.02f), 1.0f / sqrtf(1.0f + 0.0004f)), h_hit = 0.01f;
                if (k == SPP - 3) /* v = (0, 3), a lower reflector: inside the rim, beyond the reach (1.9 v) */
                    dir = v3_scale(v3_madd(f.t[1], n, 1.0f / 3.0f), 1.0f / sqrtf(1.0f + 1.0f / 9.0f)), h_hit = 0.02f;
                r.bounce[0].dir_world = dir;
                r.bounce[0].d_hit_world = h_hit / v3_dot(dir, n);
                if (k == SPP - 2 && (x + y) % 2) r.bounce[0].d_hit_world = INFINITY; /* a miss: k = 0 */
                sample_store_add(st, x, y, &r);
            }
        }
    size_t n_px = (size_t)W * H, cap = SPP;
    float *value4 = malloc(n_px * 4 * sizeof(float)), *yv = malloc(n_px * cap * 2 * sizeof(float));
    float *k_lo = malloc(n_px * sizeof(float)), *k_hi = malloc(n_px * sizeof(float));
    int *count = malloc(n_px * sizeof(int));
    unsigned char *usable = malloc(n_px);
    FsfPixel *px = malloc(n_px * sizeof(FsfPixel));
    for (size_t i = 0; i < n_px; ++i) value4[4 * i] = value4[4 * i + 1] = value4[4 * i + 2] = value4[4 * i + 3] = 1.0f;
    CHECK(fsf_bounce_coords(&g, st, value4, usable, yv, count));
    FsfBounceIn in = {&g, st, yv, usable, 1.0f, FSF_BOUNCE_PARALLAX_V, FSF_BOUNCE_H_MIN_FRAC};
    CHECK(fsf_bounce_params(&in, px, k_lo, k_hi));

    /* the grazing sample is clamped onto the rim; the one at v = (0, 3) is not */
    size_t c = (size_t)(H / 2) * W + W / 2;
    CHECK_NEAR(yv[2 * (c * cap + SPP - 1)], FSF_BOUNCE_V_RIM, 1e-6);
    CHECK_NEAR(yv[2 * (c * cap + SPP - 3) + 1], 3.0f, 1e-4);
    /* the reach: 1 / (e^-2 sqrt(16 / n)) - 1, e^2 - 1 at 16 samples; 1.9 v at SPP */
    CHECK_NEAR(fsf_bounce_reach_sq(16), expf(2.0f) - 1.0f, 1e-3);
    CHECK_NEAR(fsf_bounce_reach_sq(SPP), expf(2.0f) * sqrtf((float)SPP / 16.0f) - 1.0f, 1e-3);
    /* slopes: misses (0) and the plane (1/h); the rim sample's 1/0.01 and the 1/0.02 beyond the
     * reach left out */
    CHECK_NEAR(k_lo[c], 0.0f, 1e-6);
    CHECK_NEAR(k_hi[c], 1.0f / H_M, 1e-3);

    /* reprojection: a hit seen from the neighbour t steps along dir[a] at v' is seen from the
     * centre at v' + eta_a t (fsf_filter.h); the other coordinate does not move */
    const FsfPixel *pc = &px[c];
    vec3 xc = v3(g.pos4[4 * c], g.pos4[4 * c + 1], g.pos4[4 * c + 2]);
    float k_mean = 0.5f * (k_lo[c] + k_hi[c]);
    double worst = 0.0;
    for (int a = 0; a < 2; ++a) {
        /* the receiver step of dir[a], from the plane's mapping */
        vec3 step = v3_add(v3_scale(A, pc->dir[a][0]), v3_scale(B, pc->dir[a][1]));
        /* eta at the slope of the plane alone: the pixel's mean slope scaled */
        float eta_plane = pc->eta_m[a] / k_mean * (1.0f / H_M);
        for (int t = -6; t <= 6; t += 3)
            for (int s = 0; s < 20; ++s) {
                vec3 xq = v3_madd(xc, step, (float)t);
                vec3 dq = cosine_dir(&f);
                vec3 hit = v3_madd(xq, dq, H_M / v3_dot(dq, n));
                float vq[2], vc[2];
                fsf_bounce_coord(&f, dq, vq);
                vec3 dc = v3_sub(hit, xc);
                fsf_bounce_coord(&f, v3_scale(dc, 1.0f / v3_length(dc)), vc);
                bool rim = fmaxf(fmaxf(fabsf(vq[0]), fabsf(vq[1])), fmaxf(fabsf(vc[0]), fabsf(vc[1]))) >= 3.6f;
                if (rim) continue; /* clamped: keep off the rim */
                double e = fabs((double)vc[a] - (vq[a] + eta_plane * (float)t));
                double e_other = fabs((double)vc[1 - a] - vq[1 - a]);
                worst = fmax(worst, fmax(e, e_other));
            }
        /* step along t_a: the shear is k times the step's length */
        CHECK_NEAR(pc->eta_m[a], k_mean * v3_length(step), 1e-3 * k_mean * v3_length(step));
        CHECK(pc->eta_m[a] > 0.0f);
        /* the misses (k = 0) and the plane (1/h) make the spread: FSF eq. 4, then the parallax bound */
        float sigma_eq4 = fsf_bounce_sigma_v(count[c]) / (k_hi[c] - k_lo[c]) / v3_length(step);
        float sigma_par = FSF_BOUNCE_PARALLAX_V / (FSF_RADIUS_SIGMAS * k_hi[c] * v3_length(step));
        CHECK_NEAR(pc->sigma_px[a], fminf(fminf(sigma_eq4, sigma_par), (float)FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS),
                   1e-3);
    }
    printf("reprojection against the shear: largest v difference %.3g\n", worst);
    CHECK(worst < 2e-3); /* float rounding of v (|v| <= 4) */

    free(value4), free(yv), free(k_lo), free(k_hi), free(count), free(usable), free(px);
    sample_store_destroy(st);
    gbuffer_free(&g);
    CHECK_DONE();
}
