/* Equal-error speedup (issue 5; DESIGN.md section 7): how many samples and how much time the
 * Monte Carlo baseline needs to reach the error a method reached, relative to that method.
 * The baseline's error curve is interpolated linearly in log-log coordinates, where Monte
 * Carlo error is (close to) a straight line: relMSE ~ c * spp^slope. */
#ifndef WEDGE_APP_CONVERGE_SPEEDUP_H
#define WEDGE_APP_CONVERGE_SPEEDUP_H

#include <stdbool.h>

typedef struct {
    double spp, seconds, error; /* one point of the baseline curve; all > 0 to be usable */
} CurvePoint;

typedef struct {
    double spp, seconds;  /* the baseline's cost at the target error */
    bool extrapolated;    /* the target error lies outside the baseline's measured range */
    bool valid;           /* false when the baseline has fewer than two usable points */
} EqualErrorCost;

/* Cost of the baseline at `error`. Points may be in any order; they are sorted by spp. The
 * segment used is the first (in spp order) whose errors bracket the target; outside the
 * measured range the nearest end segment is extended (extrapolated = true). A segment with
 * equal errors at its ends cannot be inverted and is skipped. */
EqualErrorCost equal_error_cost(const CurvePoint *baseline, int count, double error);

/* Least-squares slope of log(y) against log(x) over points with x, y > 0 (NaN if < 2). */
double loglog_slope(const double *x, const double *y, int count);

#endif
