#include "core/transform.h"

#include <math.h>
#include <string.h>

Mat4 mat4_identity(void)
{
    Mat4 r;
    memset(&r, 0, sizeof r);
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
    return r;
}

Mat4 mat4_mul(const Mat4 *a, const Mat4 *b)
{
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) s += a->m[i][k] * b->m[k][j];
            r.m[i][j] = s;
        }
    return r;
}

Mat4 mat4_transpose(const Mat4 *a)
{
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = a->m[j][i];
    return r;
}

bool mat4_equal(const Mat4 *a, const Mat4 *b)
{
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (a->m[i][j] != b->m[i][j]) return false;
    return true;
}

bool mat4_is_identity(const Mat4 *a)
{
    Mat4 id = mat4_identity();
    return mat4_equal(a, &id);
}

/* Gauss-Jordan elimination with partial pivoting. */
bool mat4_inverse(const Mat4 *a, Mat4 *out)
{
    double w[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            w[i][j] = a->m[i][j];
            w[i][j + 4] = (i == j) ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (fabs(w[r][c]) > fabs(w[pivot][c])) pivot = r;
        if (!(fabs(w[pivot][c]) > 1e-300) || !isfinite(w[pivot][c])) {
            *out = mat4_identity();
            return false;
        }
        if (pivot != c)
            for (int j = 0; j < 8; ++j) {
                double t = w[c][j];
                w[c][j] = w[pivot][j];
                w[pivot][j] = t;
            }
        double inv = 1.0 / w[c][c];
        for (int j = 0; j < 8; ++j) w[c][j] *= inv;
        for (int r = 0; r < 4; ++r) {
            if (r == c || w[r][c] == 0.0) continue;
            double f = w[r][c];
            for (int j = 0; j < 8; ++j) w[r][j] -= f * w[c][j];
        }
    }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out->m[i][j] = w[i][j + 4];
    return true;
}

Mat4 mat4_translate(double dx, double dy, double dz)
{
    Mat4 r = mat4_identity();
    r.m[0][3] = dx;
    r.m[1][3] = dy;
    r.m[2][3] = dz;
    return r;
}

Mat4 mat4_scale(double sx, double sy, double sz)
{
    Mat4 r = mat4_identity();
    r.m[0][0] = sx;
    r.m[1][1] = sy;
    r.m[2][2] = sz;
    return r;
}

Mat4 mat4_rotate(double angle_deg, double ax, double ay, double az)
{
    double len = sqrt(ax * ax + ay * ay + az * az);
    Mat4 r = mat4_identity();
    if (!(len > 0.0)) return r;
    ax /= len;
    ay /= len;
    az /= len;
    double th = angle_deg * (M_PI / 180.0);
    double s = sin(th), c = cos(th);
    /* Rodrigues' rotation formula, same orientation convention as pbrt-v4. */
    r.m[0][0] = ax * ax + (1 - ax * ax) * c;
    r.m[0][1] = ax * ay * (1 - c) - az * s;
    r.m[0][2] = ax * az * (1 - c) + ay * s;
    r.m[1][0] = ax * ay * (1 - c) + az * s;
    r.m[1][1] = ay * ay + (1 - ay * ay) * c;
    r.m[1][2] = ay * az * (1 - c) - ax * s;
    r.m[2][0] = ax * az * (1 - c) - ay * s;
    r.m[2][1] = ay * az * (1 - c) + ax * s;
    r.m[2][2] = az * az + (1 - az * az) * c;
    return r;
}

static void cross3(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static bool normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(l > 0.0) || !isfinite(l)) return false;
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
    return true;
}

bool mat4_lookat(const double eye[3], const double look[3], const double up[3], Mat4 *out)
{
    double dir[3] = {look[0] - eye[0], look[1] - eye[1], look[2] - eye[2]};
    double upn[3] = {up[0], up[1], up[2]};
    double right[3], new_up[3];
    *out = mat4_identity();
    if (!normalize3(dir) || !normalize3(upn)) return false;
    cross3(upn, dir, right);
    if (!normalize3(right)) return false;
    cross3(dir, right, new_up);
    /* world-from-camera has columns right, up, dir, eye; we return its inverse. */
    Mat4 world_from_camera = mat4_identity();
    for (int i = 0; i < 3; ++i) {
        world_from_camera.m[i][0] = right[i];
        world_from_camera.m[i][1] = new_up[i];
        world_from_camera.m[i][2] = dir[i];
        world_from_camera.m[i][3] = eye[i];
    }
    return mat4_inverse(&world_from_camera, out);
}

vec3 mat4_apply_point(const Mat4 *m, vec3 p)
{
    double x = p.x, y = p.y, z = p.z;
    double rx = m->m[0][0] * x + m->m[0][1] * y + m->m[0][2] * z + m->m[0][3];
    double ry = m->m[1][0] * x + m->m[1][1] * y + m->m[1][2] * z + m->m[1][3];
    double rz = m->m[2][0] * x + m->m[2][1] * y + m->m[2][2] * z + m->m[2][3];
    double rw = m->m[3][0] * x + m->m[3][1] * y + m->m[3][2] * z + m->m[3][3];
    if (rw != 1.0 && rw != 0.0) {
        rx /= rw;
        ry /= rw;
        rz /= rw;
    }
    return v3((float)rx, (float)ry, (float)rz);
}

vec3 mat4_apply_vector(const Mat4 *m, vec3 v)
{
    double x = v.x, y = v.y, z = v.z;
    return v3((float)(m->m[0][0] * x + m->m[0][1] * y + m->m[0][2] * z),
              (float)(m->m[1][0] * x + m->m[1][1] * y + m->m[1][2] * z),
              (float)(m->m[2][0] * x + m->m[2][1] * y + m->m[2][2] * z));
}


bool mat4_swaps_handedness(const Mat4 *m)
{
    const double(*a)[4] = m->m;
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    return det < 0.0;
}
