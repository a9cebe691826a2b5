/* pbrt-v4 perspective camera (PerspectiveCamera::GenerateRay) with a thin lens. */
#include "render/camera.h"

#include <math.h>

#include "core/vectorise.h"
#include "render/tracer.h"
#include "render/warp.h"

bool camera_init(Camera *cam, const CameraDesc *desc, int width_px, int height_px, Diag *err)
{
    return camera_init_times(cam, desc, width_px, height_px, 0.0, 1.0, err);
}

bool camera_init_times(Camera *cam, const CameraDesc *desc, int width_px, int height_px, double xform_time_start,
                       double xform_time_end, Diag *err)
{
    *cam = (Camera){0};
    cam->width_px = width_px;
    cam->height_px = height_px;
    if (!(desc->fov_deg > 0.0f && desc->fov_deg < 180.0f)) {
        diag_set(err, WEDGE_EXIT_INPUT, desc->loc, "camera fov must be in (0, 180) degrees, got %g",
                 (double)desc->fov_deg);
        return false;
    }
    if (desc->lens_radius < 0.0f || !(desc->focal_distance > 0.0f)) {
        diag_set(err, WEDGE_EXIT_INPUT, desc->loc, "camera lensradius must be >= 0 and focaldistance > 0");
        return false;
    }
    /* Screen window: [-frame, frame] x [-1, 1] for wide images, the transpose for tall ones,
     * so fov covers the shorter axis (pbrt-v4 CameraBase). */
    float frame = desc->frame_aspect > 0.0f ? desc->frame_aspect : (float)width_px / (float)height_px;
    if (frame > 1.0f) {
        cam->screen_min[0] = -frame, cam->screen_max[0] = frame;
        cam->screen_min[1] = -1.0f, cam->screen_max[1] = 1.0f;
    } else {
        cam->screen_min[0] = -1.0f, cam->screen_max[0] = 1.0f;
        cam->screen_min[1] = -1.0f / frame, cam->screen_max[1] = 1.0f / frame;
    }
    if (desc->has_screen_window) {
        cam->screen_min[0] = desc->screen_window[0], cam->screen_max[0] = desc->screen_window[1];
        cam->screen_min[1] = desc->screen_window[2], cam->screen_max[1] = desc->screen_window[3];
    }
    /* per pixel, not per sample: off every camera ray's dependency chain */
    cam->x_per_px = (cam->screen_max[0] - cam->screen_min[0]) / (float)cam->width_px;
    cam->y_per_px = (cam->screen_max[1] - cam->screen_min[1]) / (float)cam->height_px;
    cam->tan_half_fov = tanf(desc->fov_deg * (WEDGE_PI / 180.0f) * 0.5f);
    cam->lens_radius_world = desc->lens_radius;
    cam->focal_distance_world = desc->focal_distance;
    cam->shutter_open = desc->shutter_open;
    cam->shutter_close = desc->shutter_close;

    /* pbrt-v4 interpolates world-from-camera (the inverse of each end's CTM). */
    Mat4 wfc[2];
    for (int i = 0; i < 2; ++i) {
        if (!mat4_inverse(&desc->camera_from_world.m[i], &wfc[i])) {
            diag_set(err, WEDGE_EXIT_INPUT, desc->loc, "camera transform is singular");
            return false;
        }
    }
    /* rays start on the lens: it must lie where the ray tracer can represent points */
    if (!(desc->lens_radius < TRACER_COORD_MAX)) {
        diag_set(err, WEDGE_EXIT_INPUT, desc->loc,
                 "camera \"float lensradius\" %g is beyond the coordinates the ray tracer can represent (below %g)",
                 (double)desc->lens_radius, (double)TRACER_COORD_MAX);
        return false;
    }
    for (int i = 0; i < 2; ++i) {
        vec3 eye = mat4_apply_point(&wfc[i], v3(0.0f, 0.0f, 0.0f));
        float reach = fmaxf(fabsf(eye.x), fmaxf(fabsf(eye.y), fabsf(eye.z))) + desc->lens_radius;
        if (!(reach < TRACER_COORD_MAX)) {
            diag_set(err, WEDGE_EXIT_INPUT, desc->loc,
                     "the camera is at (%g, %g, %g) (set by LookAt or the transform before Camera), beyond the "
                     "coordinates the ray tracer can represent (magnitude below %g): move the scene towards the origin",
                     (double)eye.x, (double)eye.y, (double)eye.z, (double)TRACER_COORD_MAX);
            return false;
        }
    }
    anim_xform_init(&cam->world_from_camera, &wfc[0], &wfc[1]);
    cam->moving = cam->world_from_camera.animated && desc->shutter_open < desc->shutter_close;
    cam->world_from_camera_static = wfc[0];
    cam->camera_from_world_static = desc->camera_from_world.m[0];
    if (cam->world_from_camera.animated) {
        /* The static matrices describe the camera at shutter open (the whole exposure when
         * the shutter is closed): that time as a fraction between the two poses. */
        double span = xform_time_end - xform_time_start;
        double u_open = span > 0.0 ? (desc->shutter_open - xform_time_start) / span : 0.0;
        u_open = fmin(1.0, fmax(0.0, u_open));
        cam->world_from_camera_static = anim_xform_at(&cam->world_from_camera, u_open);
        if (!mat4_inverse(&cam->world_from_camera_static, &cam->camera_from_world_static)) {
            diag_set(err, WEDGE_EXIT_INPUT, desc->loc, "camera transform is singular");
            return false;
        }
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) cam->wfc_f[i][j] = (float)cam->world_from_camera_static.m[i][j];
    for (int j = 0; j < 4; ++j) cam->cfw_z_f[j] = (float)cam->camera_from_world_static.m[2][j];
    return true;
}

static Mat4 world_from_camera_at(const Camera *cam, float time01)
{
    if (!cam->moving) return cam->world_from_camera_static;
    return anim_xform_at(&cam->world_from_camera, time01);
}

float camera_depth_moving(const Camera *cam, vec3 p_world, float time01)
{
    Mat4 cfw = camera_from_world_at(cam, time01);
    return mat4_apply_point(&cfw, p_world).z;
}

Mat4 camera_from_world_at(const Camera *cam, float time01)
{
    if (!cam->moving) return cam->camera_from_world_static;
    Mat4 wfc = anim_xform_at(&cam->world_from_camera, time01), cfw;
    if (!mat4_inverse(&wfc, &cfw)) return cam->camera_from_world_static;
    return cfw;
}

/* The world-space ray of a camera-space ray (d_cam need not be unit) at time01 for a moving
 * camera: out of line, so the common static case keeps a small stack frame. */
static __attribute__((noinline)) CameraRay moving_camera_ray(const Camera *cam, vec3 o_cam, vec3 d_cam, float time01)
{
    Mat4 wfc = world_from_camera_at(cam, time01);
    CameraRay r;
    r.o_world = mat4_apply_point(&wfc, o_cam);
    r.d_world = v3_normalize(mat4_apply_vector(&wfc, d_cam));
    return r;
}

CameraRay camera_generate_ray(const Camera *cam, float px_raster, float py_raster, vec2 lens_uv, float time01)
{
    /* raster -> screen (pbrt-v4 rasterFromScreen inverted) -> camera-space point at z = 1:
     * one multiply-add per axis with the pixel's screen extent found by camera_init */
    float sx = cam->screen_min[0] + px_raster * cam->x_per_px;
    float sy = cam->screen_max[1] - py_raster * cam->y_per_px;
    /* not normalised: the lens construction is scale-invariant and the world direction
     * is normalised once at the end */
    vec3 d_cam = v3(sx * cam->tan_half_fov, sy * cam->tan_half_fov, 1.0f);
    vec3 o_cam = v3(0.0f, 0.0f, 0.0f);
    if (cam->lens_radius_world > 0.0f) {
        /* Thin lens: every ray through the lens meets the pinhole ray on the plane of focus
         * z = focaldistance (pbrt-v4 PerspectiveCamera::GenerateRay). */
        vec3 p_lens = v3(cam->lens_radius_world * lens_uv.x, cam->lens_radius_world * lens_uv.y, 0.0f);
        float ft = cam->focal_distance_world / d_cam.z;
        vec3 p_focus = v3_scale(d_cam, ft);
        o_cam = p_lens;
        d_cam = v3_sub(p_focus, p_lens);
    }
    if (cam->moving) return moving_camera_ray(cam, o_cam, d_cam, time01);
    /* static camera: a float 3x4 transform */
    const float(*m)[4] = cam->wfc_f;
    CameraRay r;
    r.o_world = v3(m[0][0] * o_cam.x + m[0][1] * o_cam.y + m[0][2] * o_cam.z + m[0][3],
                   m[1][0] * o_cam.x + m[1][1] * o_cam.y + m[1][2] * o_cam.z + m[1][3],
                   m[2][0] * o_cam.x + m[2][1] * o_cam.y + m[2][2] * o_cam.z + m[2][3]);
    r.d_world = v3_normalize(v3(m[0][0] * d_cam.x + m[0][1] * d_cam.y + m[0][2] * d_cam.z,
                                m[1][0] * d_cam.x + m[1][1] * d_cam.y + m[1][2] * d_cam.z,
                                m[2][0] * d_cam.x + m[2][1] * d_cam.y + m[2][2] * d_cam.z));
    return r;
}

/* camera_generate_ray's static-camera arithmetic for a batch, written out per coordinate so
 * that GCC vectorises the loop: the same operations in the same order, so the same bits.
 * Returns whether some direction's length fell outside v3_normalize's plain range (those
 * rays are then redone by camera_generate_ray). `lens` is a constant where it is inlined
 * (static_rays): one loop without a branch each for the pinhole and the thin lens. */
static inline bool static_rays_loop(const Camera *cam, bool lens, int count, const float *restrict px_raster,
                                    const float *restrict py_raster, const float *restrict lens_u,
                                    const float *restrict lens_v, float *restrict o_x, float *restrict o_y,
                                    float *restrict o_z, float *restrict d_x, float *restrict d_y, float *restrict d_z)
{
    /* the camera's numbers in locals: the stores below cannot change them */
    float m00 = cam->wfc_f[0][0], m01 = cam->wfc_f[0][1], m02 = cam->wfc_f[0][2], m03 = cam->wfc_f[0][3];
    float m10 = cam->wfc_f[1][0], m11 = cam->wfc_f[1][1], m12 = cam->wfc_f[1][2], m13 = cam->wfc_f[1][3];
    float m20 = cam->wfc_f[2][0], m21 = cam->wfc_f[2][1], m22 = cam->wfc_f[2][2], m23 = cam->wfc_f[2][3];
    float sx0 = cam->screen_min[0], sy0 = cam->screen_max[1], xpp = cam->x_per_px, ypp = cam->y_per_px;
    float tan_half = cam->tan_half_fov, radius = cam->lens_radius_world, focus = cam->focal_distance_world;
    int outside = 0;
    for (int k = 0; k < count; ++k) {
        float sx = sx0 + px_raster[k] * xpp, sy = sy0 - py_raster[k] * ypp;
        float dx = sx * tan_half, dy = sy * tan_half, dz = 1.0f;
        float ox = 0.0f, oy = 0.0f, oz = 0.0f;
        if (lens) {
            float lx = radius * lens_u[k], ly = radius * lens_v[k];
            float ft = focus / dz;
            ox = lx, oy = ly;
            dx = dx * ft - lx, dy = dy * ft - ly, dz = dz * ft - 0.0f;
        }
        o_x[k] = m00 * ox + m01 * oy + m02 * oz + m03;
        o_y[k] = m10 * ox + m11 * oy + m12 * oz + m13;
        o_z[k] = m20 * ox + m21 * oy + m22 * oz + m23;
        float wx = m00 * dx + m01 * dy + m02 * dz;
        float wy = m10 * dx + m11 * dy + m12 * dz;
        float wz = m20 * dx + m21 * dy + m22 * dz;
        float l = sqrtf(wx * wx + wy * wy + wz * wz), inv = 1.0f / l;
        outside |= !((l > V3_LENGTH_PLAIN_MIN) & (l < V3_LENGTH_PLAIN_MAX));
        d_x[k] = wx * inv, d_y[k] = wy * inv, d_z[k] = wz * inv;
    }
    return outside != 0;
}

/* (The loop vectorises because sqrtf is an instruction: -fno-math-errno, CMakeLists.txt.) */
static WEDGE_VECTORISED bool static_rays(const Camera *cam, int count, const float *px_raster, const float *py_raster,
                                         const float *lens_u, const float *lens_v, float *const o[3], float *const d[3])
{
    if (cam->lens_radius_world > 0.0f)
        return static_rays_loop(cam, true, count, px_raster, py_raster, lens_u, lens_v, o[0], o[1], o[2], d[0], d[1],
                                d[2]);
    return static_rays_loop(cam, false, count, px_raster, py_raster, lens_u, lens_v, o[0], o[1], o[2], d[0], d[1], d[2]);
}

void camera_generate_rays(const Camera *cam, int count, const float *px_raster, const float *py_raster,
                          const float *lens_u, const float *lens_v, const float *time01, float *const o[3],
                          float *const d[3])
{
    bool lens = cam->lens_radius_world > 0.0f;
    if (!cam->moving && !static_rays(cam, count, px_raster, py_raster, lens_u, lens_v, o, d)) return;
    /* a moving camera, or a direction out of the plain range (never for a sane camera) */
    for (int k = 0; k < count; ++k) {
        CameraRay r = camera_generate_ray(cam, px_raster[k], py_raster[k],
                                          lens ? v2(lens_u[k], lens_v[k]) : v2(0.0f, 0.0f),
                                          cam->moving ? time01[k] : 0.0f);
        o[0][k] = r.o_world.x, o[1][k] = r.o_world.y, o[2][k] = r.o_world.z;
        d[0][k] = r.d_world.x, d[1][k] = r.d_world.y, d[2][k] = r.d_world.z;
    }
}

bool camera_project(const Camera *cam, vec3 p_world, float time01, float *px_raster, float *py_raster)
{
    Mat4 cfw = camera_from_world_at(cam, time01);
    vec3 p = mat4_apply_point(&cfw, p_world);
    if (!(p.z > 0.0f)) return false;
    float sx = p.x / (p.z * cam->tan_half_fov), sy = p.y / (p.z * cam->tan_half_fov);
    *px_raster = (sx - cam->screen_min[0]) / (cam->screen_max[0] - cam->screen_min[0]) * (float)cam->width_px;
    *py_raster = (cam->screen_max[1] - sy) / (cam->screen_max[1] - cam->screen_min[1]) * (float)cam->height_px;
    return true;
}
