/* Equal-error interpolation of a baseline convergence curve (see converge_speedup.h). */
#include "app/converge_speedup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int by_spp(const void *a, const void *b)
{
    const CurvePoint *p = a, *q = b;
    return (p->spp > q->spp) - (p->spp < q->spp);
}

/* Interpolates log spp and log seconds at log error along the segment (a, b). */
static EqualErrorCost along(const CurvePoint *a, const CurvePoint *b, double error, bool extrapolated)
{
    double t = (log(error) - log(a->error)) / (log(b->error) - log(a->error));
    EqualErrorCost c;
    c.spp = exp(log(a->spp) + t * (log(b->spp) - log(a->spp)));
    c.seconds = exp(log(a->seconds) + t * (log(b->seconds) - log(a->seconds)));
    c.extrapolated = extrapolated;
    c.valid = isfinite(c.spp) && isfinite(c.seconds) && c.spp > 0 && c.seconds > 0;
    return c;
}

EqualErrorCost equal_error_cost(const CurvePoint *baseline, int count, double error)
{
    EqualErrorCost none = {0, 0, false, false};
    if (!(error > 0) || !isfinite(error)) return none;
    CurvePoint *pts = malloc(sizeof *pts * (size_t)(count > 0 ? count : 1));
    if (!pts) return none;
    int n = 0;
    for (int i = 0; i < count; ++i) {
        const CurvePoint *p = &baseline[i];
        if (p->spp > 0 && p->seconds > 0 && p->error > 0 && isfinite(p->spp) && isfinite(p->seconds) && isfinite(p->error))
            pts[n++] = *p;
    }
    qsort(pts, (size_t)n, sizeof *pts, by_spp);
    EqualErrorCost result = none;
    /* Inside the measured range: the first segment whose ends bracket the error. */
    for (int i = 0; i + 1 < n && !result.valid; ++i) {
        double lo = fmin(pts[i].error, pts[i + 1].error), hi = fmax(pts[i].error, pts[i + 1].error);
        if (lo < hi && error >= lo && error <= hi) result = along(&pts[i], &pts[i + 1], error, false);
    }
    if (!result.valid && n >= 2) {
        /* Outside: below the smallest error extend the high-spp end, else the low-spp end. */
        double min_err = pts[0].error;
        for (int i = 1; i < n; ++i) min_err = fmin(min_err, pts[i].error);
        if (error <= min_err) {
            for (int i = n - 1; i >= 1 && !result.valid; --i)
                if (pts[i].error != pts[i - 1].error) result = along(&pts[i - 1], &pts[i], error, true);
        } else {
            for (int i = 0; i + 1 < n && !result.valid; ++i)
                if (pts[i].error != pts[i + 1].error) result = along(&pts[i], &pts[i + 1], error, true);
        }
    }
    free(pts);
    return result;
}

double loglog_slope(const double *x, const double *y, int count)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (int i = 0; i < count; ++i) {
        if (!(x[i] > 0) || !(y[i] > 0)) continue;
        double lx = log(x[i]), ly = log(y[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
        ++n;
    }
    double den = n * sxx - sx * sx;
    if (n < 2 || !(fabs(den) > 0)) return NAN;
    return (n * sxy - sx * sy) / den;
}
