/* The Lambert vertices' bounces sampled in lanes (lambert_bounce_lanes, issue 22, docs/design.md
 * 12.32), which replaced the path-by-path Lambert branch of vertex_sample and its caller.
 *  - Bit for bit against that path-by-path code, restated here from the scalar functions it
 *    called (v3_basis for the tangents, the local direction turned into world space,
 *    bsdf_diffuse_pdf, the weight albedo / pi * cos_i / pdf, the throughput's guard3 and its
 *    max_component_nonpositive test, surface_offset): on random lanes with normals of either
 *    sign of z (and z = +0 and -0, where v3_basis's sign flips), receivers seen from below
 *    their lobe axis (cos_o < 0: every direction on the wrong side, pdf 0), throughputs that
 *    overflow, are infinite or NaN (the guard) or have no positive channel (no bounce), and
 *    lanes that are not Lambert (never sampled); an odd count, so the vector loop's remainder
 *    runs.
 *  - Closed form: over a stratified grid of BSDF samples about a tilted normal, every
 *    direction is a unit vector on n's side, the throughput is the albedo (f cos / pdf =
 *    albedo for a cosine-weighted sample), the mean cosine is 2/3 and the mean direction
 *    (2/3) n (a uniform hemisphere would give 1/2 and (1/2) n); the origin is the receiver
 *    pushed by err along the geometric normal's side of the direction.
 * Teeth: the tangents swapped, a pdf without the side test, the guard left out or the
 * origin pushed the wrong way each fail the bit comparison; the local z axis taken as the
 * geometric normal fails the side and the moments. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/lambert_bounce.h"
#include "render/material.h"
#include "render/tracer.h"
#include "render/warp.h"

enum { LANES = 1027, GRID = 64, CAP = GRID * GRID };

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

static vec3 random_unit(Pcg32 *rng)
{
    vec3 u = warp_uniform_sphere(v2(pcg32_float(rng), pcg32_float(rng)));
    return v3_scale(u, 1.0f / sqrtf(v3_dot(u, u)));
}

/* The lanes' inputs and outputs as arrays (CAP lanes: the grid's count, the largest). */
typedef struct {
    float p[3][CAP], ng[3][CAP], err[CAP], n[3][CAP], cos_o[CAP], albedo[3][CAP], beta[3][CAP], local[3][CAP];
    int lambert[CAP];
    float wi[3][CAP], pdf[CAP], beta_next[3][CAP], o[3][CAP];
    int sampled[CAP], guarded[CAP], bounce[CAP];
} Lanes;

static void run_lanes(Lanes *l, int count)
{
    LambertBounceIn in = {.err = l->err, .cos_o = l->cos_o, .lambert = l->lambert};
    LambertBounceOut out = {.pdf = l->pdf, .sampled = l->sampled, .guarded = l->guarded, .bounce = l->bounce};
    for (int c = 0; c < 3; ++c) {
        in.p[c] = l->p[c], in.ng[c] = l->ng[c], in.n[c] = l->n[c];
        in.albedo[c] = l->albedo[c], in.beta[c] = l->beta[c], in.local[c] = l->local[c];
        out.wi[c] = l->wi[c], out.beta_next[c] = l->beta_next[c], out.o[c] = l->o[c];
    }
    lambert_bounce_lanes(count, &in, &out);
}

static vec3 lane3(const float a[3][CAP], int k) { return v3(a[0][k], a[1][k], a[2][k]); }

/* The path-by-path code the lanes replaced, for lane k. */
typedef struct {
    vec3 wi, beta_next, o;
    float pdf;
    bool sampled, guarded, bounce;
} Reference;

static Reference reference(const Lanes *l, int k)
{
    Reference r = {0};
    vec3 n = lane3(l->n, k), local = lane3(l->local, k), t1, t2;
    v3_basis(n, &t1, &t2);
    r.wi = v3_add(v3_add(v3_scale(t1, local.x), v3_scale(t2, local.y)), v3_scale(n, local.z));
    float cos_i = v3_dot(n, r.wi);
    r.pdf = bsdf_diffuse_pdf(l->cos_o[k], cos_i);
    SurfaceHit h = {0};
    h.p = lane3(l->p, k), h.ng = lane3(l->ng, k), h.err = l->err[k];
    r.o = surface_offset(&h, r.wi);
    r.sampled = l->lambert[k] && r.pdf > 0.0f;
    if (!r.sampled) return r;
    vec3 weight = v3_scale(v3_scale(lane3(l->albedo, k), 0.318309886f), cos_i / r.pdf);
    vec3 b = v3_mul(lane3(l->beta, k), weight);
    float z = b.x * 0.0f + b.y * 0.0f + b.z * 0.0f;
    r.guarded = !(z == z);
    r.beta_next = r.guarded ? v3s(0.0f) : b;
    bool nonpositive = !(b.x > 0.0f || b.y > 0.0f || b.z > 0.0f) && !(isnan(b.x) && isnan(b.y) && isnan(b.z));
    r.bounce = !r.guarded && !nonpositive;
    return r;
}

static void set3(float a[3][CAP], int k, vec3 v) { a[0][k] = v.x, a[1][k] = v.y, a[2][k] = v.z; }

static void bits_against_reference(void)
{
    static Lanes l;
    Pcg32 rng;
    pcg32_seed(&rng, 2211u, 7u);
    for (int k = 0; k < LANES; ++k) {
        vec3 n = random_unit(&rng);
        if (k % 97 == 3) n = v3(0.6f, 0.8f, 0.0f);  /* z = +0 */
        if (k % 97 == 4) n = v3(0.6f, -0.8f, -0.0f); /* z = -0 */
        if (k % 97 == 5) n = v3(0.0f, 0.0f, -1.0f);
        set3(l.n, k, n);
        /* the geometric normal near the shading one, either way round */
        vec3 ng = v3_add(n, v3_scale(random_unit(&rng), 0.3f));
        ng = v3_scale(ng, (k % 5 == 0 ? -1.0f : 1.0f) / sqrtf(v3_dot(ng, ng)));
        set3(l.ng, k, ng);
        set3(l.p, k, v3((pcg32_float(&rng) - 0.5f) * 20.0f, pcg32_float(&rng) * 3.0f, pcg32_float(&rng) - 4.0f));
        l.err[k] = 1e-5f + 1e-4f * pcg32_float(&rng);
        /* seen from n's side, except every seventh lane (pdf 0 everywhere) and one cos_o of 0 */
        l.cos_o[k] = k % 7 == 1 ? -pcg32_float(&rng) : pcg32_float(&rng);
        if (k % 211 == 9) l.cos_o[k] = 0.0f;
        set3(l.albedo, k, v3(pcg32_float(&rng), pcg32_float(&rng), k % 11 == 2 ? 0.0f : pcg32_float(&rng)));
        vec3 beta = v3(pcg32_float(&rng) * 2.0f, pcg32_float(&rng), pcg32_float(&rng));
        if (k % 13 == 4) beta = v3(3e38f, 3e38f, 1.0f); /* the product overflows: guarded */
        if (k % 13 == 5) beta.y = INFINITY;
        if (k % 13 == 6) beta.z = NAN;
        if (k % 13 == 7) beta = v3(0.0f, -1.0f, 0.0f); /* nothing positive: no bounce */
        set3(l.beta, k, beta);
        set3(l.local, k, warp_cosine_hemisphere(v2(pcg32_float(&rng), pcg32_float(&rng))));
        if (k % 53 == 8) set3(l.local, k, v3(0.0f, 0.0f, 0.0f)); /* cos_i 0: pdf 0 */
        l.lambert[k] = k % 9 != 0;
    }
    run_lanes(&l, LANES);
    int mismatches = 0, sampled = 0, guarded = 0, bounced = 0, unsampled = 0;
    for (int k = 0; k < LANES; ++k) {
        Reference r = reference(&l, k);
        bool same = same_bits(l.wi[0][k], r.wi.x) && same_bits(l.wi[1][k], r.wi.y) && same_bits(l.wi[2][k], r.wi.z) &&
                    same_bits(l.pdf[k], r.pdf) && same_bits(l.o[0][k], r.o.x) && same_bits(l.o[1][k], r.o.y) &&
                    same_bits(l.o[2][k], r.o.z) && (l.sampled[k] != 0) == r.sampled &&
                    (l.guarded[k] != 0) == r.guarded && (l.bounce[k] != 0) == r.bounce;
        if (r.sampled)
            same = same && same_bits(l.beta_next[0][k], r.beta_next.x) && same_bits(l.beta_next[1][k], r.beta_next.y) &&
                   same_bits(l.beta_next[2][k], r.beta_next.z);
        if (!same && mismatches++ < 5) fprintf(stderr, "lane %d differs from the path-by-path code\n", k);
        sampled += r.sampled, guarded += r.guarded, bounced += r.bounce, unsampled += !r.sampled;
    }
    CHECK(mismatches == 0);
    /* the cases above were all reached */
    CHECK(sampled > LANES / 2);
    CHECK(guarded >= 3 * LANES / 13 / 2);
    CHECK(bounced > LANES / 3 && bounced < sampled);
    CHECK(unsampled > LANES / 9);
}

/* A stratified grid of samples about one tilted normal, albedo a and throughput 1. */
static void closed_form(void)
{
    static Lanes l;
    vec3 n = v3_scale(v3(0.3f, 0.8f, -0.5f), 1.0f / sqrtf(0.98f));
    vec3 ng = v3_scale(v3(0.35f, 0.75f, -0.45f), 1.0f / sqrtf(0.35f * 0.35f + 0.75f * 0.75f + 0.45f * 0.45f));
    vec3 albedo = v3(0.8f, 0.5f, 0.25f), p = v3(1.0f, 2.0f, 3.0f);
    int count = CAP;
    static float lx[CAP], ly[CAP], lz[CAP];
    static vec2 u[CAP];
    for (int i = 0; i < GRID; ++i)
        for (int j = 0; j < GRID; ++j) u[i * GRID + j] = v2((i + 0.5f) / GRID, (j + 0.5f) / GRID);
    warp_cosine_hemisphere_run(count, u, lx, ly, lz);
    for (int k = 0; k < count; ++k) {
        set3(l.n, k, n), set3(l.ng, k, ng), set3(l.p, k, p), set3(l.albedo, k, albedo), set3(l.beta, k, v3s(1.0f));
        l.err[k] = 1e-3f, l.cos_o[k] = 0.5f, l.lambert[k] = 1;
        l.local[0][k] = lx[k], l.local[1][k] = ly[k], l.local[2][k] = lz[k];
    }
    run_lanes(&l, count);
    double cos_sum = 0.0, mean[3] = {0.0, 0.0, 0.0};
    int bad_unit = 0, bad_side = 0, bad_weight = 0, bad_origin = 0, not_bounced = 0;
    for (int k = 0; k < count; ++k) {
        vec3 wi = lane3(l.wi, k), o = lane3(l.o, k), b = lane3(l.beta_next, k);
        float c = v3_dot(n, wi);
        bad_unit += fabsf(v3_dot(wi, wi) - 1.0f) > 1e-5f;
        bad_side += !(c > 0.0f) && l.sampled[k];
        not_bounced += !l.bounce[k];
        /* f cos / pdf = (a / pi) cos / (cos / pi) = a */
        if (l.bounce[k])
            bad_weight += fabsf(b.x - albedo.x) > 1e-5f || fabsf(b.y - albedo.y) > 1e-5f || fabsf(b.z - albedo.z) > 1e-5f;
        float side = v3_dot(ng, wi) >= 0.0f ? 1e-3f : -1e-3f;
        vec3 expected = v3_madd(p, ng, side);
        bad_origin += v3_length(v3_sub(o, expected)) > 1e-6f;
        cos_sum += c, mean[0] += wi.x, mean[1] += wi.y, mean[2] += wi.z;
    }
    CHECK(bad_unit == 0);
    CHECK(bad_side == 0);
    CHECK(bad_weight == 0);
    CHECK(bad_origin == 0);
    CHECK(not_bounced <= count / 500);
    CHECK_NEAR(cos_sum / count, 2.0 / 3.0, 2e-3);
    CHECK_NEAR(mean[0] / count, 2.0 / 3.0 * n.x, 3e-3);
    CHECK_NEAR(mean[1] / count, 2.0 / 3.0 * n.y, 3e-3);
    CHECK_NEAR(mean[2] / count, 2.0 / 3.0 * n.z, 3e-3);
}

int main(void)
{
    bits_against_reference();
    closed_form();
    CHECK_DONE();
}
