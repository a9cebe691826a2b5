/* sincos_run, the sky's vectorised sine and cosine (issue 22).
 *  - Accuracy: over the angles the sky uses, [0, 2 pi] (every 97th float, the floats next to
 *    each multiple of pi/4, and 2 pi u on a grid of u), and over the whole domain |x| < 120
 *    (every 1009th float and its negative), the error of each result against the double-precision sin and
 *    cos in units in the last place of the exact value is at most 0.5607 (glibc's stated
 *    bound for its sincosf) and at most the library's sincosf's own largest error on the
 *    same angles (the property the renderer relies on: no less accurate than what it
 *    replaced).
 *  - Identity: with glibc 2.28 or later (the sincosf this follows) every result equals the
 *    library's bit for bit on the same angles, so images stay as they were.
 * Teeth: S3 cut to 28 bits fails the identity (one angle in the sky's set); the quadrant's
 * swap or the sine's sign dropped, or the reduction by a float pi/2, fails the accuracy
 * bounds. */
#define _GNU_SOURCE /* sincosf */
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "check.h"
#include "render/sincos_run.h"

enum { RUN = 1024 };

typedef struct {
    double ours, library; /* largest error, ulp */
    long count, differ;
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
        float ls, lc;
        sincosf(x[i], &ls, &lc);
        double eo = fmax(ulp_error(s[i], es), ulp_error(c[i], ec));
        double el = fmax(ulp_error(ls, es), ulp_error(lc, ec));
        if (eo > t->ours) t->ours = eo;
        if (el > t->library) t->library = el;
        t->differ += memcmp(&ls, &s[i], sizeof ls) != 0 || memcmp(&lc, &c[i], sizeof lc) != 0;
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

static void check_tally(const Tally *t, const char *what)
{
    printf("%s: %ld angles, largest error %.4f ulp (library sincosf %.4f), %ld differ from the library\n", what,
           t->count, t->ours, t->library, t->differ);
    CHECK(t->ours <= 0.5607);
    CHECK(t->ours <= t->library);
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 28))
    CHECK(t->differ == 0);
#endif
}

int main(void)
{
    const float two_pi = 2.0f * 3.14159265358979323846f;
    Tally sky = {0};
    tally_range(&sky, 0.0f, two_pi, 97u, false);
    /* the floats around each multiple of pi/4, where the quadrant changes or a result is near 0 */
    float x[RUN];
    int n = 0;
    for (int k = 0; k <= 8; ++k) {
        float v = (float)(k * 0.78539816339744830962);
        for (int d = -8; d <= 8; ++d) {
            float w = v;
            for (int s = 0; s < (d < 0 ? -d : d); ++s) w = nextafterf(w, d < 0 ? -INFINITY : INFINITY);
            if (w >= 0.0f) x[n++] = w;
        }
    }
    tally_run(&sky, x, n);
    /* phi = 2 pi u as the sky forms it, u on a grid with both ends */
    for (int i = 0; i < RUN; ++i) x[i] = 2.0f * 3.14159265358979323846f * (i == RUN - 1 ? 0x1.fffffep-1f : (float)i / (RUN - 1));
    tally_run(&sky, x, RUN);
    check_tally(&sky, "[0, 2 pi]");

    Tally domain = {0};
    tally_range(&domain, 0.0f, 119.9f, 1009u, true);
    check_tally(&domain, "|x| < 120");
    CHECK_DONE();
}
