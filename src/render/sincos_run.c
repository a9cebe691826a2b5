/* sincos_run: glibc's single-precision sincosf (sysdeps/ieee754/flt-32, from Arm's
 * optimized-routines, Szabolcs Nagy 2018) written as one loop without branches. Its
 * structure for |x| < 120: the quadrant n = round(x / (pi/2)) from x times 2/pi scaled by 2^24
 * (the float-to-int conversion truncates, and adding half of 2^24 before the shift rounds);
 * the reduced angle y = x - n pi/2 in double by one fused multiply-add (pi/2 as a double is
 * good to 55 bits, enough for |x| < 120); then sin and cos of y from two short double
 * polynomials (minimax on [-pi/4, pi/4], coefficients below), swapped and negated by n's
 * quadrant, each rounded to float once. Below 2^-12 sin x is x and cos x is 1 in float.
 *
 * The library's FMA build (the one its ifunc picks when the CPU has FMA and AVX2) contracts
 * the polynomial's multiply-adds into fused ones in a fixed pattern; the loop writes those as
 * fma() in the same places (read off the disassembly of glibc 2.36's __sincosf_fma), so each
 * lane's result is the library's, bit for bit (tests/render/test_sincos_run.c checks the
 * accuracy, and the identity where it holds). The negated cosine table the library uses in
 * quadrants 2 and 3 is the negation of the result: every operation is odd in the
 * coefficients and rounding to nearest is symmetric. */
#include "render/sincos_run.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

static const double TWO_OVER_PI_2P24 = 0x1.45f306dc9c883p+23; /* 2 / pi times 2^24 */
static const double HALF_PI = 0x1.921fb54442d18p+0;
/* cos y ~ C0 + C1 y^2 + C2 y^4 + C3 y^6 + C4 y^8, sin y ~ y + S1 y^3 + S2 y^5 + S3 y^7 */
static const double C0 = 1.0, C1 = -0x1.ffffffd0c621cp-2, C2 = 0x1.55553e1068f19p-5, C3 = -0x1.6c087e89a359dp-10,
                    C4 = 0x1.99343027bf8c3p-16;
static const double S1 = -0x1.555545995a603p-3, S2 = 0x1.1107605230bc4p-7, S3 = -0x1.994eb3774cf24p-13;

__attribute__((target("arch=x86-64-v3"), noinline)) static void sincos_fma_lanes(int count, const float *restrict x,
                                                                                 float *restrict s, float *restrict c)
{
    for (int k = 0; k < count; ++k) {
        double xd = x[k];
        int n = ((int32_t)(xd * TWO_OVER_PI_2P24) + 0x800000) >> 24;
        double y = fma(-(double)n, HALF_PI, xd);
        double ys = y * (double)(1 - ((n + 1) & 2)); /* the sine's sign by quadrant: + - - + (exact) */
        double y2 = y * y;
        double y3 = y2 * ys, y4 = y2 * y2;
        double y5 = y2 * y3, y6 = y2 * y4;
        double s_tail = fma(y2, S3, S2), c_tail = fma(y2, C4, C3);
        double c_head = fma(y2, C1, C0);
        double sv = fma(y3, S1, ys), cv = fma(y4, C2, c_head);
        sv = fma(s_tail, y5, sv);
        cv = fma(c_tail, y6, cv);
        float fs = (float)sv, fc = (float)(cv * (double)(1 - (n & 2)));
        bool odd = n & 1, tiny = fabsf(x[k]) < 0x1p-12f;
        float s_out = odd ? fc : fs, c_out = odd ? fs : fc;
        s[k] = tiny ? x[k] : s_out;
        c[k] = tiny ? 1.0f : c_out;
    }
}

static void sincos_library_lanes(int count, const float *restrict x, float *restrict s, float *restrict c)
{
    for (int k = 0; k < count; ++k) s[k] = sinf(x[k]), c[k] = cosf(x[k]);
}

void sincos_run(int count, const float *x, float *s, float *c)
{
    /* glibc's choice of its FMA build */
    if (__builtin_cpu_supports("fma") && __builtin_cpu_supports("avx2")) sincos_fma_lanes(count, x, s, c);
    else sincos_library_lanes(count, x, s, c);
}
