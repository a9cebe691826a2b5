/* Sine and cosine of float angles, our own (issue 22): one angle inline (sincos_lane) and a
 * run of angles in one vectorised loop (sincos_run), with the same bits either way and on
 * every instruction set. The constant sky's uniform directions take a run where the
 * library's sincosf was a call per lane (docs/algorithms.md, "The sky's sine and cosine"). */
#ifndef WEDGE_RENDER_SINCOS_RUN_H
#define WEDGE_RENDER_SINCOS_RUN_H

/* pi/2 = SINCOS_HALF_PI_HI + SINCOS_HALF_PI_LO: the high part has its last 8 bits zero, so
 * n * HI is exact for |n| < 2^8, and the low part carries the next 53 bits. */
#define SINCOS_HALF_PI_HI 0x1.921fb54442d00p+0
#define SINCOS_HALF_PI_LO 0x1.8469898cc5170p-48

/* sin x and cos x for |x| < 120 (radians), each within about half a unit in the last place.
 *  1. n = the integer nearest x / (pi/2), by adding and subtracting 1.5 * 2^52 (which rounds
 *     a double of magnitude below 2^51 to an integer).
 *  2. y = x - n pi/2 in [-pi/4, pi/4] (a hair beyond at the rounding's ties): x - n HI is
 *     exact (the two are within a factor of 2 of each other, or n = 0), then n LO is taken off,
 *     so y keeps double precision even where x is close to a multiple of pi/2.
 *  3. sin y and cos y from their Taylor series in y^2 by Horner's rule, through y^11 and
 *     y^12: the first term left out is below 1e-11 of the result at |y| = pi/4, some 1e-4 of
 *     a float's unit in the last place.
 *  4. x = y + n pi/2: for n = 0, 1, 2, 3 mod 4 (sin x, cos x) is (sin y, cos y),
 *     (cos y, -sin y), (-sin y, -cos y), (-cos y, sin y). Each is rounded to float once.
 * Only + - * and conversions, no fused multiply-adds (C11's -ffp-contract=off), so every
 * compilation of this gives the same bits. */
static inline void sincos_lane(float x, float *s, float *c)
{
    const double two_over_pi = 0.63661977236758134308, round_shift = 0x1.8p52;
    double xd = x;
    double nd = (xd * two_over_pi + round_shift) - round_shift;
    double y = (xd - nd * SINCOS_HALF_PI_HI) - nd * SINCOS_HALF_PI_LO;
    double y2 = y * y;
    double sp = -1.0 / 39916800.0; /* -1/11! */
    sp = sp * y2 + 1.0 / 362880.0;
    sp = sp * y2 - 1.0 / 5040.0;
    sp = sp * y2 + 1.0 / 120.0;
    sp = sp * y2 - 1.0 / 6.0;
    double sin_y = y + y * y2 * sp;
    double cp = 1.0 / 479001600.0; /* 1/12! */
    cp = cp * y2 - 1.0 / 3628800.0;
    cp = cp * y2 + 1.0 / 40320.0;
    cp = cp * y2 - 1.0 / 720.0;
    cp = cp * y2 + 1.0 / 24.0;
    cp = cp * y2 - 0.5;
    double cos_y = 1.0 + y2 * cp;
    int n = (int)nd;
    double s_q = (n & 1) ? cos_y : sin_y, c_q = (n & 1) ? -sin_y : cos_y;
    double sign = (n & 2) ? -1.0 : 1.0;
    *s = (float)(s_q * sign);
    *c = (float)(c_q * sign);
}

/* s[k], c[k] = sincos_lane(x[k]) for k < count, vectorised. */
void sincos_run(int count, const float *x, float *s, float *c);

/* sincos_lane(x) as a call, for one angle in scalar code: inlined there, its double
 * arithmetic made GCC lay out the surrounding function worse (sample_sphere, whose cone path
 * the uniform sphere's branch sits beside, took 8% more of a motion_defocus_soft frame). */
void sincos_one(float x, float *s, float *c);

#endif
