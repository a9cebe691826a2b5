/* sincos_lane and sincos_run, the renderer's own sine and cosine (issue 22; the constant
 * sky's uniform directions and warp_uniform_sphere take them).
 *  - Accuracy: against double-precision sin and cos, in units of the float spacing at the
 *    exact value, at most 0.5 + 1e-3 ulp (the header's derivation: half a unit from the final
 *    rounding plus some 1e-4 of truncation and double rounding), and never worse than the
 *    library's sincosf on the same angles, over the angles the sky uses ([0, 2 pi]: every
 *    97th float, the floats next to each multiple of pi/4, 2 pi u on a grid of u), the floats
 *    closest to multiples of pi/2 below 120 (where the reduction cancels most), and the whole
 *    domain |x| < 120 (every 1009th float and its negative).
 *  - The run equals the one-angle call bit for bit (the vectorised copies of sincos_run against
 *    the scalar sincos_one): what keeps light_sample_sky_batch equal to light_sample.
 * Teeth: the reduction by a double pi/2 alone (no low part) fails the accuracy near the
 * multiples of pi/2; the quadrant's swap or a sign dropped, or a Taylor term left out, fails
 * the accuracy bound. */
#define _GNU_SOURCE /* sincosf */
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "check.h"
#include "render/sincos_run.h"

enum { RUN = 1024 };

static const double OURS_MAX_ULP = 0.501;

typedef struct {
    double ours, library; /* largest error, ulp */
    long count, run_differs;
} Tally;

/* |got - exact| in units of the float spacing at exact */
static double ulp_error(float got, double exact)
{
    double a = fabs(exact);
    double ulp = a < FLT_MIN ? ldexp(1.0, -149) : ldexp(1.0, ilogb(a) - 23);
    return fabs((double)got - exact) / ulp;
}

static void tally_run(Tally *t, const float *x, int n)
{
    float s[RUN], c[RUN];
    sincos_run(n, x, s, c);
    for (int i = 0; i < n; ++i) {
        double es = sin((double)x[i]), ec = cos((double)x[i]);
        float ls, lc, one_s, one_c;
        sincosf(x[i], &ls, &lc);
        sincos_one(x[i], &one_s, &one_c);
        double eo = fmax(ulp_error(s[i], es), ulp_error(c[i], ec));
        double el = fmax(ulp_error(ls, es), ulp_error(lc, ec));
        if (eo > t->ours) t->ours = eo;
        if (el > t->library) t->library = el;
        t->run_differs += memcmp(&one_s, &s[i], sizeof one_s) != 0 || memcmp(&one_c, &c[i], sizeof one_c) != 0;
    }
    t->count += n;
}

/* the floats from lo to hi (0 <= lo <= hi), every stride-th, and their negatives if mirror */
static void tally_range(Tally *t, float lo, float hi, unsigned stride, bool mirror)
{
    float x[RUN];
    int n = 0;
    unsigned bits_lo, bits_hi;
    memcpy(&bits_lo, &lo, sizeof lo);
    memcpy(&bits_hi, &hi, sizeof hi);
    for (unsigned b = bits_lo; b <= bits_hi; b += stride) { /* nonnegative floats are ordered as their bits */
        float v;
        memcpy(&v, &b, sizeof v);
        x[n++] = v;
        if (mirror) x[n++] = -v;
        if (n >= RUN - 1) tally_run(t, x, n), n = 0;
    }
    tally_run(t, x, n);
}

/* the 17 floats nearest each of the angles k step, k = k0..k1, and their negatives */
static void tally_near_multiples(Tally *t, double step, int k0, int k1)
{
    float x[RUN];
    int n = 0;
    for (int k = k0; k <= k1; ++k) {
        float v = (float)(k * step);
        for (int d = -8; d <= 8; ++d) {
            float w = v;
            for (int s = 0; s < (d < 0 ? -d : d); ++s) w = nextafterf(w, d < 0 ? -INFINITY : INFINITY);
            x[n++] = w;
            x[n++] = -w;
            if (n >= RUN - 2) tally_run(t, x, n), n = 0;
        }
    }
    tally_run(t, x, n);
}

static void check_tally(const Tally *t, const char *what)
{
    printf("%s: %ld angles, largest error %.4f ulp (library sincosf %.4f); run against lane: %ld differ\n", what,
           t->count, t->ours, t->library, t->run_differs);
    CHECK(t->ours <= OURS_MAX_ULP);
    CHECK(t->ours <= t->library);
    CHECK(t->run_differs == 0);
}

int main(void)
{
    const double quarter_pi = 0.78539816339744830962;
    Tally sky = {0};
    tally_range(&sky, 0.0f, 2.0f * 3.14159265358979323846f, 97u, false);
    tally_near_multiples(&sky, quarter_pi, 0, 8);
    /* phi = 2 pi u as the sky forms it, u on a grid with both ends */
    float x[RUN];
    for (int i = 0; i < RUN; ++i)
        x[i] = 2.0f * 3.14159265358979323846f * (i == RUN - 1 ? 0x1.fffffep-1f : (float)i / (RUN - 1));
    tally_run(&sky, x, RUN);
    check_tally(&sky, "[0, 2 pi]");

    Tally cancel = {0};
    tally_near_multiples(&cancel, 2.0 * quarter_pi, 1, 76); /* 76 pi/2 < 120 */
    check_tally(&cancel, "next to k pi/2 below 120");

    Tally domain = {0};
    tally_range(&domain, 0.0f, 119.9f, 1009u, true);
    check_tally(&domain, "|x| < 120");
    CHECK_DONE();
}
