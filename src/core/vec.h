/* Small fixed-size vectors for the renderer (float: what Embree and OpenCL use). */
#ifndef WEDGE_CORE_VEC_H
#define WEDGE_CORE_VEC_H

#include <math.h>
#include <stdbool.h>

typedef struct { float x, y; } vec2;
typedef struct { float x, y, z; } vec3;

static inline vec2 v2(float x, float y) { vec2 r = {x, y}; return r; }
static inline vec3 v3(float x, float y, float z) { vec3 r = {x, y, z}; return r; }
static inline vec3 v3s(float s) { return v3(s, s, s); }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline vec3 v3_madd(vec3 a, vec3 b, float s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float v3_length2(vec3 a) { return v3_dot(a, a); }
/* Lengths whose square float holds with full precision (about 1e-18 to 1e18): the usual
 * case takes the plain formula; longer or shorter vectors (a cross product of two edges in a
 * scene scaled by 1e9 or 1e-10) are divided by their largest component first, since their
 * square over- or underflows (which made such scenes render black). */
#define V3_LENGTH_PLAIN_MIN 1.0e-18f
#define V3_LENGTH_PLAIN_MAX 1.0e18f
/* x clamped to [0, 1], NaN -> 0 and -0 -> +0 (what fminf(fmaxf(x, 0), 1) gives), without the two
 * library calls GCC emits for those without -ffinite-math-only. */
static inline float clamp01f(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }
/* fmaxf for operands that are never -0 (absolute values, lengths): fmaxf's result (a NaN
 * operand is skipped), but inline; without -ffinite-math-only fmaxf is a library call. */
static inline float fmax_nonneg(float a, float b) { return (a > b || b != b) ? a : b; }
static inline float v3_max_abs(vec3 a) { return fmax_nonneg(fabsf(a.x), fmax_nonneg(fabsf(a.y), fabsf(a.z))); }
static inline float v3_length(vec3 a)
{
    float l = sqrtf(v3_dot(a, a));
    if (l > V3_LENGTH_PLAIN_MIN && l < V3_LENGTH_PLAIN_MAX) return l;
    float m = v3_max_abs(a);
    if (!(m > 0.0f) || !isfinite(m)) return m > 0.0f ? INFINITY : 0.0f;
    vec3 b = v3_scale(a, 1.0f / m);
    return m * sqrtf(v3_dot(b, b));
}
/* Returns a zero vector for a zero-length input instead of NaN. */
static inline vec3 v3_normalize(vec3 a)
{
    float l = sqrtf(v3_dot(a, a));
    if (l > V3_LENGTH_PLAIN_MIN && l < V3_LENGTH_PLAIN_MAX) return v3_scale(a, 1.0f / l);
    float m = v3_max_abs(a); /* rescaled first: see v3_length */
    if (!(m > 0.0f) || !isfinite(m)) return v3(0.0f, 0.0f, 0.0f);
    vec3 b = v3_scale(a, 1.0f / m);
    return v3_scale(b, 1.0f / sqrtf(v3_dot(b, b)));
}
static inline float v3_max_component(vec3 a) { return fmaxf(a.x, fmaxf(a.y, a.z)); }
/* Linear-RGB luminance Y, Rec. 709 / sRGB primaries (the weights of the working space). */
static inline float v3_luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
/* v3_max_component(a) > 0 without its two library calls: fmaxf skips NaN operands, so the
 * maximum is > 0 exactly when some component is. */
static inline bool v3_any_positive(vec3 a) { return a.x > 0.0f || a.y > 0.0f || a.z > 0.0f; }
static inline float v3_get(vec3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }
static inline vec3 v3_lerp(vec3 a, vec3 b, float t) { return v3_add(v3_scale(a, 1.0f - t), v3_scale(b, t)); }

/* Orthonormal basis around unit n (Duff et al. 2017, branchless). */
static inline void v3_basis(vec3 n, vec3 *t, vec3 *b)
{
    float sign = copysignf(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float c = n.x * n.y * a;
    *t = v3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = v3(c, sign + n.y * n.y * a, -n.y);
}

#endif
