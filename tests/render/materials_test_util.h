/* Helpers for the BSDF / microfacet / environment-map tests: a chi-square comparison of a
 * direction sampler against the density it claims, on a (theta, phi) grid of the sphere.
 * Expected bin counts come from integrating the density over each bin with a midpoint
 * sub-grid, independently of the sampler. */
#ifndef WEDGE_TESTS_MATERIALS_TEST_UTIL_H
#define WEDGE_TESTS_MATERIALS_TEST_UTIL_H

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/rng.h"
#include "core/vec.h"

#define MT_PI 3.14159265358979323846

typedef bool (*mt_sample_fn)(void *ctx, Pcg32 *rng, vec3 *w);  /* false: no sample */
typedef double (*mt_pdf_fn)(void *ctx, vec3 w);                 /* solid-angle density */

static inline vec3 mt_dir(double theta, double phi)
{
    return v3((float)(sin(theta) * cos(phi)), (float)(sin(theta) * sin(phi)), (float)cos(theta));
}

/* Integral of pdf over the sphere by the same sub-grid quadrature the chi-square uses. */
static inline double mt_integrate_sphere(mt_pdf_fn pdf, void *ctx, int n_theta, int n_phi)
{
    double sum = 0.0, dt = MT_PI / n_theta, dp = 2.0 * MT_PI / n_phi;
    for (int i = 0; i < n_theta; ++i) {
        double t = (i + 0.5) * dt;
        for (int j = 0; j < n_phi; ++j) sum += pdf(ctx, mt_dir(t, (j + 0.5) * dp)) * sin(t) * dt * dp;
    }
    return sum;
}

typedef struct {
    double chi2;
    int dof;
    double sampled_fraction;   /* samples returned / attempts */
    double pdf_integral;       /* integral of pdf over the sphere (quadrature) */
    double threshold;          /* chi2 limit used (about 5 sigma above dof) */
} MtChi2;

/* Draws n samples, bins them on an n_theta x n_phi grid, compares with pdf integrated over
 * each bin (sub x sub midpoint nodes). Bins expecting fewer than 5 samples are pooled. */
static inline MtChi2 mt_chi2(mt_sample_fn sample, mt_pdf_fn pdf, void *ctx, int n, int n_theta, int n_phi,
                             int sub, uint64_t seed)
{
    MtChi2 r = {0};
    int nb = n_theta * n_phi;
    double *obs = calloc((size_t)nb, sizeof *obs), *expc = calloc((size_t)nb, sizeof *expc);
    Pcg32 rng;
    pcg32_seed(&rng, seed, 7);
    int got = 0;
    for (int s = 0; s < n; ++s) {
        vec3 w;
        if (!sample(ctx, &rng, &w)) continue;
        ++got;
        double z = fmin(fmax((double)w.z, -1.0), 1.0);
        double t = acos(z), p = atan2((double)w.y, (double)w.x);
        if (p < 0) p += 2.0 * MT_PI;
        int i = (int)(t / MT_PI * n_theta), j = (int)(p / (2.0 * MT_PI) * n_phi);
        if (i >= n_theta) i = n_theta - 1;
        if (j >= n_phi) j = n_phi - 1;
        obs[i * n_phi + j] += 1.0;
    }
    double dt = MT_PI / n_theta, dp = 2.0 * MT_PI / n_phi, total = 0.0;
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            double e = 0.0;
            for (int a = 0; a < sub; ++a) {
                double t = (i + (a + 0.5) / sub) * dt;
                for (int b = 0; b < sub; ++b) {
                    double p = (j + (b + 0.5) / sub) * dp;
                    e += pdf(ctx, mt_dir(t, p)) * sin(t);
                }
            }
            e *= dt * dp / (sub * sub);
            total += e;
            expc[i * n_phi + j] = e * n;
        }
    double pooled_o = 0.0, pooled_e = 0.0;
    for (int k = 0; k < nb; ++k) {
        if (expc[k] < 5.0) {
            pooled_o += obs[k], pooled_e += expc[k];
            continue;
        }
        double d = obs[k] - expc[k];
        r.chi2 += d * d / expc[k];
        r.dof++;
    }
    if (pooled_e >= 5.0) {
        double d = pooled_o - pooled_e;
        r.chi2 += d * d / pooled_e;
        r.dof++;
    } else if (pooled_o > 20.0) {
        r.chi2 += 1e9; /* many samples where the pdf says there is (almost) nothing */
    }
    /* A sampler may fail (e.g. a reflection below the surface): the fraction of attempts
     * that produced a direction must equal the pdf's total mass (checked in mt_chi2_ok). */
    r.sampled_fraction = (double)got / n;
    r.pdf_integral = total;
    r.dof -= 1;
    r.threshold = r.dof + 5.0 * sqrt(2.0 * r.dof);
    free(obs);
    free(expc);
    return r;
}

static inline bool mt_chi2_ok(const char *what, MtChi2 r)
{
    bool ok = r.chi2 <= r.threshold && fabs(r.sampled_fraction - r.pdf_integral) < 0.01;
    fprintf(stderr, "%-44s chi2 %10.1f dof %5d (limit %7.1f)  sampled %.4f  int pdf %.4f %s\n", what, r.chi2, r.dof,
            r.threshold, r.sampled_fraction, r.pdf_integral, ok ? "" : "  <-- FAIL");
    return ok;
}

#endif
