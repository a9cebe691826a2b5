/* emitter_facing_phi against the sum over the triangles one at a time (Lambert's formula for each,
 * clipped to the horizon, a one-sided triangle counting only from its front): curved meshes seen
 * from receivers all around them, the horizon cutting them, close to their surface and inside
 * them. Meshes: a tilted torus (one-sided and two-sided), a latitude-longitude sphere whose pole
 * rings are degenerate triangles, a bumpy grid whose bumps face every way, and a mesh whose
 * triangles are wound at random (no two neighbours cancel). The two sums must agree to 1e-9 of
 * the emitter's projected solid angle. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/emitter_facing.h"

static uint64_t rng = 0x2545f4914f6cdd1dull;

static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) * 0x1p-53;
}

static void random_unit(double u[3])
{
    double z = 2.0 * uniform() - 1.0, phi = 2.0 * M_PI * uniform(), r = sqrt(fmax(0.0, 1.0 - z * z));
    u[0] = r * cos(phi), u[1] = r * sin(phi), u[2] = z;
}

typedef struct {
    int count;
    double (*tri)[3][3];
} Mesh;

/* a grid of nu x nv quads over (u, v) in [0, 1)^2 (wrapping where asked), each as two triangles */
static Mesh grid(int nu, int nv, bool wrap_u, bool wrap_v, void (*at)(double u, double v, double p[3]))
{
    Mesh m = {2 * nu * nv, malloc(2 * (size_t)nu * nv * sizeof(double[3][3]))};
    int t = 0;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double p[4][3];
            int i1 = wrap_u && i + 1 == nu ? 0 : i + 1, j1 = wrap_v && j + 1 == nv ? 0 : j + 1;
            at((double)i / nu, (double)j / nv, p[0]);
            at((double)i1 / nu, (double)j / nv, p[1]);
            at((double)i1 / nu, (double)j1 / nv, p[2]);
            at((double)i / nu, (double)j1 / nv, p[3]);
            memcpy(m.tri[t][0], p[0], sizeof p[0]), memcpy(m.tri[t][1], p[1], sizeof p[0]), memcpy(m.tri[t][2], p[2], sizeof p[0]);
            ++t;
            memcpy(m.tri[t][0], p[0], sizeof p[0]), memcpy(m.tri[t][1], p[2], sizeof p[0]), memcpy(m.tri[t][2], p[3], sizeof p[0]);
            ++t;
        }
    return m;
}

static void torus_at(double u, double v, double p[3])
{
    double a = 2.0 * M_PI * u, b = 2.0 * M_PI * v, R = 0.6, r = 0.2;
    double x = (R + r * cos(b)) * cos(a), z = (R + r * cos(b)) * sin(a), y = r * sin(b);
    double c = cos(0.5), s = sin(0.5); /* tilted about x */
    p[0] = x + 0.2, p[1] = y * c - z * s + 2.0, p[2] = y * s + z * c + 0.3;
}

/* the poles: u = 0 and u = 1 are single points, so their rows' triangles have no area */
static void sphere_at(double u, double v, double p[3])
{
    double th = M_PI * u, ph = 2.0 * M_PI * v;
    p[0] = 0.5 * sin(th) * cos(ph), p[1] = 1.5 + 0.5 * cos(th), p[2] = 0.5 * sin(th) * sin(ph);
}

static void bumps_at(double u, double v, double p[3])
{
    p[0] = -1.0 + 2.0 * u, p[2] = -1.0 + 2.0 * v;
    p[1] = 1.5 + 0.25 * sin(9.0 * u) * cos(7.0 * v) + 0.1 * sin(23.0 * u + 5.0 * v);
}

/* The worst |facing - by triangle| over receivers, relative to the largest by-triangle sum seen. */
static double check_mesh(const char *what, Mesh m, bool two_sided, int receivers, double *largest)
{
    EmitterFacing *f = emitter_facing_create(m.count, (const double(*)[3][3])m.tri, two_sided);
    EmitterFacingAt *at = f ? emitter_facing_at_create(f) : NULL;
    CHECK(f && at);
    double worst = 0.0;
    *largest = 0.0;
    int nonzero = 0;
    for (int k = 0; f && at && k < receivers; ++k) {
        double p[3], n[3];
        /* receivers in a box about the mesh (some inside it, some by its surface), a few on a
         * triangle's corner, the rest anywhere around */
        if (k % 50 == 7) {
            memcpy(p, m.tri[(int)(uniform() * m.count)][(int)(uniform() * 3)], sizeof p);
        } else {
            double lo = k % 3 == 0 ? -3.0 : -1.2, hi = k % 3 == 0 ? 3.0 : 1.2;
            p[0] = lo + (hi - lo) * uniform(), p[1] = 1.6 + lo + (hi - lo) * uniform(), p[2] = lo + (hi - lo) * uniform();
        }
        random_unit(n);
        double want = emitter_facing_phi_by_triangle(f, p, n), got = emitter_facing_phi(f, at, p, n, NULL, NULL);
        worst = fmax(worst, fabs(got - want));
        *largest = fmax(*largest, want);
        nonzero += want > 0.0;
    }
    printf("%-28s %6d triangles, %d receivers (%d see it): worst difference %.2e of the largest sum %.3f\n", what, m.count,
           receivers, nonzero, worst / fmax(*largest, 1e-300), *largest);
    CHECK(nonzero > receivers / 4);
    emitter_facing_at_destroy(at);
    emitter_facing_destroy(f);
    return worst / fmax(*largest, 1e-300);
}

int main(void)
{
    double largest, worst = 0.0;
    Mesh torus = grid(60, 30, true, true, torus_at);
    worst = fmax(worst, check_mesh("torus, one-sided", torus, false, 1200, &largest));
    worst = fmax(worst, check_mesh("torus, two-sided", torus, true, 1200, &largest));
    Mesh sphere = grid(24, 40, false, true, sphere_at);
    worst = fmax(worst, check_mesh("sphere with degenerate poles", sphere, false, 1200, &largest));
    Mesh bumps = grid(40, 40, false, false, bumps_at);
    worst = fmax(worst, check_mesh("bumpy grid, one-sided", bumps, false, 1200, &largest));
    worst = fmax(worst, check_mesh("bumpy grid, two-sided", bumps, true, 1200, &largest));
    /* the torus with every triangle's winding flipped or not at random: no edge cancels */
    for (int t = 0; t < torus.count; ++t)
        if (uniform() < 0.5) {
            double s[3];
            memcpy(s, torus.tri[t][1], sizeof s);
            memcpy(torus.tri[t][1], torus.tri[t][2], sizeof s);
            memcpy(torus.tri[t][2], s, sizeof s);
        }
    worst = fmax(worst, check_mesh("torus, wound at random", torus, false, 1000, &largest));
    CHECK(worst < 1e-9);
    CHECK(emitter_facing_create(0, NULL, false) == NULL);
    free(torus.tri), free(sphere.tri), free(bumps.tri);
    CHECK_DONE();
}
