/* Warps from the unit square to the domains the renderer samples (Shirley and Chiu 1997
 * concentric disk; Malley's method for cosine hemispheres; uniform cones; triangles by the
 * square-root parameterisation) and the MIS power heuristic (Veach 1997, eq. 9.13). */
#ifndef WEDGE_RENDER_WARP_H
#define WEDGE_RENDER_WARP_H

#include <math.h>
#include <stdbool.h>

#include "core/vec.h"
#include "render/sincos_run.h"

#ifndef WEDGE_PI
#define WEDGE_PI 3.14159265358979323846f
#endif

/* sin and cos of x for |x| <= pi/4 from their Taylor series up to x^9 and x^10: the
 * remainders, at most (pi/4)^11/11! < 2e-9 and (pi/4)^12/12! < 2e-10, are far below float
 * rounding (6e-8 relative). The concentric map only needs this range, and the library's
 * sincosf is a call that costs several times as much. */
static inline void sincos_quarter_pi(float x, float *s, float *c)
{
    float x2 = x * x;
    *s = x * (1.0f + x2 * (-1.0f / 6.0f + x2 * (1.0f / 120.0f + x2 * (-1.0f / 5040.0f + x2 * (1.0f / 362880.0f)))));
    *c = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24.0f + x2 * (-1.0f / 720.0f + x2 * (1.0f / 40320.0f + x2 * (-1.0f / 3628800.0f)))));
}

/* Concentric map of [0,1)^2 onto the unit disk: preserves stratification and area ratios.
 * In the wedges |x| > |y|, theta = (pi/4) (y/x) and the point is x (cos theta, sin theta);
 * in the others theta = pi/2 - phi with phi = (pi/4) (x/y), so cos theta = sin phi and
 * sin theta = cos phi, and the point is y (sin phi, cos phi). The two cases share their
 * arithmetic and differ in which operands go where: selected without a branch (the wedge
 * of a random u is a coin toss that a branch mispredicts half the time). */
static inline vec2 warp_disk_concentric(vec2 u)
{
    float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    if (ox == 0.0f && oy == 0.0f) return v2(0.0f, 0.0f);
    bool x_wedge = fabsf(ox) > fabsf(oy);
    float r = x_wedge ? ox : oy, other = x_wedge ? oy : ox;
    float s, c;
    sincos_quarter_pi((WEDGE_PI / 4.0f) * (other / r), &s, &c);
    return x_wedge ? v2(r * c, r * s) : v2(r * s, r * c);
}

/* Cosine-weighted direction about +z (Malley: project the disk up); pdf = cos(theta)/pi. */
static inline vec3 warp_cosine_hemisphere(vec2 u)
{
    vec2 d = warp_disk_concentric(u);
    float z2 = 1.0f - d.x * d.x - d.y * d.y;
    return v3(d.x, d.y, sqrtf(z2 > 0.0f ? z2 : 0.0f)); /* fmaxf(0, z2) without the library call */
}

/* warp_disk_concentric and warp_cosine_hemisphere of u[0 .. count), as arrays (vectorised
 * loops, warp_batch.c; the same values). */
void warp_disk_concentric_run(int count, const vec2 *u, float *x, float *y);
void warp_cosine_hemisphere_run(int count, const vec2 *u, float *x, float *y, float *z);

/* Uniform direction on the unit sphere; pdf = 1/(4 pi). */
static inline vec3 warp_uniform_sphere(vec2 u)
{
    float z = 1.0f - 2.0f * u.x;
    float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    float sin_phi, cos_phi;
    sincos_one(2.0f * WEDGE_PI * u.y, &sin_phi, &cos_phi); /* as the sky's runs (sincos_run) */
    return v3(r * cos_phi, r * sin_phi, z);
}

/* A cosine-weighted direction about the unit normal n from a uniform direction d on the unit
 * sphere: the direction of n + d. The point n + d is uniform on the unit sphere centred at n,
 * which touches the origin; seen from the origin, a sphere through it has a point of
 * direction w at distance 2 cos(theta) whose surface meets the line of sight at angle
 * theta, so area density 1 / (4 pi) becomes solid-angle density (2 cos)^2 / cos / (4 pi) =
 * cos(theta) / pi (docs/algorithms.md, "A constant sky sampled by cosine at a Lambert
 * receiver"). Not finite when d = -n (a set of measure zero: warp_cosine_about_pdf's test
 * fails on it). */
static inline vec3 warp_cosine_about(vec3 n, vec3 d)
{
    float sx = n.x + d.x, sy = n.y + d.y, sz = n.z + d.z;
    float inv = 1.0f / sqrtf(sx * sx + sy * sy + sz * sz);
    return v3(sx * inv, sy * inv, sz * inv);
}

/* The solid-angle density of warp_cosine_about's direction w about n: cos(theta) / pi on
 * n's side, 0 elsewhere (and for a NaN w). */
static inline float warp_cosine_about_pdf(vec3 n, vec3 w)
{
    float c = v3_dot(n, w);
    return c > 0.0f ? c * 0.318309886f : 0.0f;
}

/* Barycentrics (b0, b1) of a uniform point on a triangle (b2 = 1 - b0 - b1). */
static inline vec2 warp_triangle(vec2 u)
{
    float su = sqrtf(u.x);
    return v2(1.0f - su, u.y * su);
}

/* Power heuristic with beta = 2 for one sample from each of two strategies. */
static inline float mis_power(float pdf_this, float pdf_other)
{
    float a = pdf_this * pdf_this, b = pdf_other * pdf_other;
    if (!(a + b > 0.0f) || isinf(a)) return isinf(a) ? 1.0f : 0.0f;
    return a / (a + b);
}

#endif
