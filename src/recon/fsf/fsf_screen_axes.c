/* FSF's gather directions from the screen Jacobian (fsf_screen_axes.h). */
#include "recon/fsf/fsf_screen_axes.h"

#include <math.h>

/* A surface neighbour for the Jacobian: hit, not mixed, facing the same way. */
static bool same_surface(const GBuffer *g, size_t i, size_t q)
{
    if (!g->hit[q] || g->mixed[q]) return false;
    const float *a = g->nrm4 + 4 * i, *b = g->nrm4 + 4 * q;
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.9f;
}

/* dP per pixel step along screen x (axis 0) or y (axis 1): central, else one-sided. */
static bool jacobian_column(const GBuffer *g, int x, int y, int axis, vec3 *out)
{
    int w = g->width, h = g->height;
    size_t i = (size_t)y * (size_t)w + (size_t)x;
    int dx = axis == 0, dy = axis == 1;
    bool has_p = x + dx < w && y + dy < h && same_surface(g, i, i + (size_t)(dx + dy * w));
    bool has_m = x - dx >= 0 && y - dy >= 0 && same_surface(g, i, i - (size_t)(dx + dy * w));
    const float *c = g->pos4 + 4 * i;
    const float *p = has_p ? g->pos4 + 4 * (i + (size_t)(dx + dy * w)) : c;
    const float *m = has_m ? g->pos4 + 4 * (i - (size_t)(dx + dy * w)) : c;
    if (!has_p && !has_m) return false;
    float scale = has_p && has_m ? 0.5f : 1.0f;
    *out = v3((p[0] - m[0]) * scale, (p[1] - m[1]) * scale, (p[2] - m[2]) * scale);
    return true;
}

bool fsf_pixel_jacobian(const GBuffer *g, int x, int y, vec3 *jx, vec3 *jy)
{
    return jacobian_column(g, x, y, 0, jx) && jacobian_column(g, x, y, 1, jy);
}

bool fsf_screen_axes(vec3 jx, vec3 jy, vec3 n, const vec3 axis[2], FsfScreenAxes *out)
{
    /* J^T J for the least-squares screen direction of each axis */
    float a11 = v3_dot(jx, jx), a12 = v3_dot(jx, jy), a22 = v3_dot(jy, jy), det = a11 * a22 - a12 * a12;
    if (!(det > 0.0f)) return false;
    for (int a = 0; a < 2; ++a) {
        vec3 ut = v3_madd(axis[a], n, -v3_dot(axis[a], n));
        float b1 = v3_dot(jx, ut), b2 = v3_dot(jy, ut);
        float sx = (a22 * b1 - a12 * b2) / det, sy = (a11 * b2 - a12 * b1) / det, len = sqrtf(sx * sx + sy * sy);
        if (!(len > 0.0f)) return false;
        sx /= len, sy /= len;
        out->step_world[a] = v3_add(v3_scale(jx, sx), v3_scale(jy, sy));
        out->step_m[a] = v3_length(out->step_world[a]);
        if (!(out->step_m[a] > 0.0f)) return false;
        out->dir[a][0] = sx, out->dir[a][1] = sy;
    }
    return true;
}
