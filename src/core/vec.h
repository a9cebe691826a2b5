/* Small fixed-size vectors for the renderer (float: what Embree and OpenCL use). */
#ifndef WEDGE_CORE_VEC_H
#define WEDGE_CORE_VEC_H

#include <math.h>

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
static inline float v3_length(vec3 a) { return sqrtf(v3_dot(a, a)); }
/* Returns a zero vector for a zero-length input instead of NaN. */
static inline vec3 v3_normalize(vec3 a)
{
    float l = v3_length(a);
    return l > 0.0f ? v3_scale(a, 1.0f / l) : v3(0.0f, 0.0f, 0.0f);
}
static inline float v3_max_component(vec3 a) { return fmaxf(a.x, fmaxf(a.y, a.z)); }
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
