/* sinf and cosf over a run of angles in one vectorised loop (issue 22): the constant sky's
 * uniform directions (light_sample_sky_batch) took the library's sincosf lane by lane. */
#ifndef WEDGE_RENDER_SINCOS_RUN_H
#define WEDGE_RENDER_SINCOS_RUN_H

/* For k < count, with |x[k]| < 120 (radians): s[k] = sin(x[k]) and c[k] = cos(x[k]) as
 * floats. Where the CPU has FMA and AVX2 this is glibc's sincosf (2.28 and later) done
 * vectorised, the same operations in the same order, so the same values where the library
 * is that one (at most 0.56 ulp from the exact sine and cosine); elsewhere it calls the
 * library's sinf and cosf lane by lane. */
void sincos_run(int count, const float *x, float *s, float *c);

#endif
