/* MAAF filter design in one 2D subspace (see maaf_design.h; derivation in docs/algorithms.md,
 * "MAAF"). */
#include "recon/maaf/maaf_design.h"

#include <math.h>
#include <string.h>

static float clampf(float v, float lo, float hi) { return v < lo ? lo : v > hi ? hi : v; }

static int pairs_pick(int all, int own, int fallback)
{
    int n = own > 0 ? own : all > 0 ? all : fallback;
    return n > MAAF_PAIRS_MAX ? MAAF_PAIRS_MAX : n;
}

MaafPairs maaf_pairs_choose(int all, int light, int lens, int bounce)
{
    MaafPairs p = {pairs_pick(all, light, MAAF_PAIRS_LIGHT_DEFAULT), pairs_pick(all, lens, MAAF_PAIRS_LENS_DEFAULT),
                   pairs_pick(all, bounce, MAAF_PAIRS_BOUNCE_DEFAULT)};
    return p;
}

bool maaf_design_2d(float s_min, float s_max, float omega_y_max, int pairs, MaafDesign2D *out)
{
    memset(out, 0, sizeof *out);
    if (!(omega_y_max > 0.0f) || !isfinite(omega_y_max)) return false;
    if (!(s_min == s_min)) s_min = MAAF_SLOPE_MIN; /* NaN: the widest design */
    if (!(s_max == s_max)) s_max = s_min;
    if (s_min > s_max) {
        float t = s_min;
        s_min = s_max;
        s_max = t;
    }
    s_min = clampf(s_min, MAAF_SLOPE_MIN, MAAF_SLOPE_MAX);
    s_max = clampf(s_max, s_min, MAAF_SLOPE_MAX);
    int n = pairs < 1 ? 1 : pairs > MAAF_PAIRS_MAX ? MAAF_PAIRS_MAX : pairs;
    out->pairs = n;
    out->s_min = s_min;
    out->s_max = s_max;
    out->omega_y_max = omega_y_max;
    double bands = 2.0 * n - 1.0, wy = omega_y_max;
    for (int p = 0; p < n; ++p) {
        MaafComponent *c = &out->c[p];
        /* eq. 6: band p spans Omega_y in wy [2p - 1, 2p + 1] / (2N - 1), centre 2p wy / (2N - 1),
         * half height wy / (2N - 1) */
        c->cy = (float)(wy * 2.0 * p / bands);
        c->sy = (float)(wy / bands);
        if (p == 0) {
            /* the central band straddles the origin: the double wedge inside |Omega_y| <= wy/(2N-1)
             * reaches |Omega_x| <= wy / ((2N - 1) s_min) */
            c->cx = 0.0f;
            c->sx = (float)(wy / (bands * s_min));
        } else {
            /* eqs. 7, 8: inside band p (upper half plane) the wedge runs from Omega_x = Omega_y/s_max
             * at the band's bottom edge to Omega_y/s_min at its top edge */
            double lo = wy * (2.0 * p - 1.0) / (bands * s_max), hi = wy * (2.0 * p + 1.0) / (bands * s_min);
            c->cx = (float)(0.5 * (lo + hi));
            c->sx = (float)(0.5 * (hi - lo));
        }
        /* eq. 10: a Gaussian over the whole double wedge, Omega_x std wy/s_min, Omega_y std wy;
         * the central band sits at its peak (gx = gy = 0: exp(-0) = 1 exactly, no call) */
        double gx = c->cx * (double)s_min / wy, gy = c->cy / wy;
        c->weight = p == 0 ? 1.0f : (float)exp(-0.5 * (gx * gx + gy * gy));
    }
    return true;
}

bool maaf_design_2d_signed(float s_min, float s_max, float omega_y_max, int pairs, MaafDesign2D *out)
{
    if (s_min > s_max) {
        float t = s_min;
        s_min = s_max;
        s_max = t;
    }
    if (s_min > 0.0f) return maaf_design_2d(s_min, s_max, omega_y_max, pairs, out);
    if (!(s_max < 0.0f)) {
        memset(out, 0, sizeof *out);
        return false;
    }
    if (!maaf_design_2d(-s_max, -s_min, omega_y_max, pairs, out)) return false;
    for (int p = 0; p < out->pairs; ++p) out->c[p].cx = -out->c[p].cx;
    float lo = -out->s_max, hi = -out->s_min;
    out->s_min = lo;
    out->s_max = hi;
    return true;
}

static double fourier_gauss(double t, double sigma) { return exp(-0.5 * (t * t) / (sigma * sigma)); }

/* The inverse transform of fourier_gauss: (sigma / sqrt(2 pi)) exp(-sigma^2 x^2 / 2). */
static double primal_gauss(double x, double sigma)
{
    return sigma * 0.39894228040143268 * exp(-0.5 * sigma * sigma * x * x);
}

double maaf_fourier_2d(const MaafDesign2D *d, double omega_x, double omega_y)
{
    double w = 0.0;
    for (int p = 0; p < d->pairs; ++p) {
        const MaafComponent *c = &d->c[p];
        w += c->weight * fourier_gauss(omega_x - c->cx, c->sx) * fourier_gauss(omega_y - c->cy, c->sy);
        if (p > 0) /* the mirror -p */
            w += c->weight * fourier_gauss(omega_x + c->cx, c->sx) * fourier_gauss(omega_y + c->cy, c->sy);
    }
    return w;
}

double maaf_primal_2d_direct(const MaafDesign2D *d, double x, double y)
{
    double w = 0.0;
    for (int p = 0; p < d->pairs; ++p) {
        const MaafComponent *c = &d->c[p];
        double env = primal_gauss(x, c->sx) * primal_gauss(y, c->sy);
        /* eq. 12: exp(j phi) + exp(-j phi) = 2 cos(phi); the central filter is its own mirror */
        w += c->weight * env * (p == 0 ? 1.0 : 2.0 * cos(c->cx * x + c->cy * y));
    }
    return w;
}

int maaf_separable_terms(const MaafDesign2D *d, double x, double y, double *a, double *b)
{
    int t = 0;
    for (int p = 0; p < d->pairs; ++p) {
        const MaafComponent *c = &d->c[p];
        double gx = primal_gauss(x, c->sx), gy = primal_gauss(y, c->sy);
        if (p == 0) {
            a[t] = c->weight * gx;
            b[t++] = gy;
            continue;
        }
        /* eq. 13: 2 cos(Cx x + Cy y) = 2 cos(Cx x) cos(Cy y) - 2 sin(Cx x) sin(Cy y) */
        a[t] = 2.0 * c->weight * cos(c->cx * x) * gx;
        b[t++] = cos(c->cy * y) * gy;
        a[t] = -2.0 * c->weight * sin(c->cx * x) * gx;
        b[t++] = sin(c->cy * y) * gy;
    }
    return t;
}

double maaf_primal_2d_separable(const MaafDesign2D *d, double x, double y)
{
    double a[2 * MAAF_PAIRS_MAX], b[2 * MAAF_PAIRS_MAX], w = 0.0;
    int terms = maaf_separable_terms(d, x, y, a, b);
    for (int t = 0; t < terms; ++t) w += a[t] * b[t];
    return w;
}

double maaf_box_coverage(double s_min, double s_max, int pairs)
{
    double n = pairs, bands = 2.0 * n - 1.0;
    return bands * bands * (1.0 / s_min - 1.0 / s_max) / (4.0 * (n * n / s_min - (n - 1.0) * (n - 1.0) / s_max));
}

double maaf_box_area(const MaafDesign2D *d)
{
    double area = 0.0;
    for (int p = 0; p < d->pairs; ++p) area += (p == 0 ? 1.0 : 2.0) * 4.0 * d->c[p].sx * d->c[p].sy;
    return area;
}

double maaf_wedge_area(double s_min, double s_max, double omega_y_max)
{
    /* two triangles, each of height wy and width wy (1/s_min - 1/s_max) at the top */
    return omega_y_max * omega_y_max * (1.0 / s_min - 1.0 / s_max);
}
