/* FSF's gather directions from the screen Jacobian (fsf_screen_axes.h). */
#include "recon/fsf/fsf_screen_axes.h"

#include <math.h>

#include "core/vectorise.h"

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

/* One axis of fsf_screen_axes over the block, each step the scalar form's expression in its
 * order (no contraction: C11's -ffp-contract=off), per lane; lanes whose step length leaves
 * v3_length's plain range are flagged in `odd` for the caller to redo one at a time. */
typedef struct {
    float dir[2][FSF_AXES_BLOCK], step[3][FSF_AXES_BLOCK], step_m[FSF_AXES_BLOCK];
    unsigned char ok[FSF_AXES_BLOCK], odd[FSF_AXES_BLOCK];
} AxisLanes;

static WEDGE_VECTORISED void axis_lanes(int count, const FsfAxesIn *restrict in, int a, AxisLanes *restrict o)
{
    for (int k = 0; k < count; ++k) {
        float ax = in->axis[a][0][k], ay = in->axis[a][1][k], az = in->axis[a][2][k];
        float jx0 = in->jx[0][k], jx1 = in->jx[1][k], jx2 = in->jx[2][k];
        float jy0 = in->jy[0][k], jy1 = in->jy[1][k], jy2 = in->jy[2][k];
        float n0 = in->n[0][k], n1 = in->n[1][k], n2 = in->n[2][k];
        float a11 = jx0 * jx0 + jx1 * jx1 + jx2 * jx2, a12 = jx0 * jy0 + jx1 * jy1 + jx2 * jy2;
        float a22 = jy0 * jy0 + jy1 * jy1 + jy2 * jy2, det = a11 * a22 - a12 * a12;
        float s = -(ax * n0 + ay * n1 + az * n2);
        float u0 = ax + n0 * s, u1 = ay + n1 * s, u2 = az + n2 * s;
        float b1 = jx0 * u0 + jx1 * u1 + jx2 * u2, b2 = jy0 * u0 + jy1 * u1 + jy2 * u2;
        float sx = (a22 * b1 - a12 * b2) / det, sy = (a11 * b2 - a12 * b1) / det, len = sqrtf(sx * sx + sy * sy);
        sx /= len, sy /= len;
        float w0 = jx0 * sx + jy0 * sy, w1 = jx1 * sx + jy1 * sy, w2 = jx2 * sx + jy2 * sy;
        float m = sqrtf(w0 * w0 + w1 * w1 + w2 * w2);
        o->dir[0][k] = sx, o->dir[1][k] = sy;
        o->step[0][k] = w0, o->step[1][k] = w1, o->step[2][k] = w2, o->step_m[k] = m;
        /* quiet compares and & rather than > and &&: no branch in the loop (gcc vectorises none) */
        o->odd[k] = !(isgreater(m, V3_LENGTH_PLAIN_MIN) & isless(m, V3_LENGTH_PLAIN_MAX));
        o->ok[k] = isgreater(det, 0.0f) & isgreater(len, 0.0f);
    }
}

void fsf_screen_axes_block(FsfAxesBlock *b)
{
    AxisLanes lanes[2];
    int count = b->count;
    FsfScreenAxes *out = b->out;
    bool *ok = b->ok;
    for (int a = 0; a < 2; ++a) axis_lanes(count, &b->in, a, &lanes[a]);
    for (int k = 0; k < count; ++k) {
        ok[k] = true;
        for (int a = 0; a < 2 && ok[k]; ++a) {
            const AxisLanes *l = &lanes[a];
            out[k].dir[a][0] = l->dir[0][k], out[k].dir[a][1] = l->dir[1][k];
            out[k].step_world[a] = v3(l->step[0][k], l->step[1][k], l->step[2][k]);
            /* outside the plain range v3_length rescales first */
            out[k].step_m[a] = l->odd[k] ? v3_length(out[k].step_world[a]) : l->step_m[k];
            ok[k] = l->ok[k] && out[k].step_m[a] > 0.0f;
        }
    }
}
