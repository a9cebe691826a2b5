/* The pbrt-v4 perspective camera with a thin lens, possibly moving during the shutter.
 *
 * Raster space: pixel (x, y) covers [x, x+1) x [y, y+1), (0, 0) at the top-left, mapped to
 * screen (xmin, ymax) exactly as pbrt-v4's rasterFromScreen. Screen space is the image plane
 * at z = 1 scaled by 1/tan(fov/2), so the screen window [-1, 1] spans fov on the image's
 * shorter axis. Camera space is pbrt's left-handed one (+z forward, see mat4_lookat). */
#ifndef WEDGE_RENDER_CAMERA_H
#define WEDGE_RENDER_CAMERA_H

#include <stdbool.h>

#include "core/animated_xform.h"
#include "core/diag.h"
#include "core/vec.h"
#include "scene/scene_desc.h"

typedef struct {
    int width_px, height_px;
    float screen_min[2], screen_max[2]; /* screen window: x then y */
    float tan_half_fov;
    float x_per_px, y_per_px;           /* screen extent of a pixel (camera_generate_ray) */
    float lens_radius_world;            /* 0: pinhole, no lens dimension sampled */
    float focal_distance_world;
    float shutter_open, shutter_close;
    bool moving;                        /* world_from_camera differs at the two times */
    AnimXform world_from_camera;        /* interpolated like pbrt-v4's CameraTransform */
    Mat4 world_from_camera_static;
    Mat4 camera_from_world_static;      /* at shutter open: for depth of a static camera */
    float wfc_f[3][4];                  /* world_from_camera_static in float: the common case */
    float cfw_z_f[4];                   /* z row of camera_from_world_static (depth) */
} Camera;

typedef struct {
    vec3 o_world, d_world;              /* d is unit length */
} CameraRay;

/* Builds the camera for an image of width x height pixels. False (err, exit 2) when the
 * camera transform is singular or the parameters are out of range. */
bool camera_init(Camera *cam, const CameraDesc *desc, int width_px, int height_px, Diag *err);
/* As camera_init, with the scene times of the two camera poses (TransformTimes; camera_init
 * assumes 0 and 1). A camera that moves while the shutter is closed is frozen at the
 * shutter time. */
bool camera_init_times(Camera *cam, const CameraDesc *desc, int width_px, int height_px, double xform_time_start,
                       double xform_time_end, Diag *err);

/* The ray through film position (px_raster, py_raster) for lens point lens_uv (unit disk)
 * at normalised shutter time time01 in [0, 1]. */
CameraRay camera_generate_ray(const Camera *cam, float px_raster, float py_raster, vec2 lens_uv, float time01);
/* camera_generate_ray for count samples at once, in and out as arrays (one per coordinate):
 * ray k starts at (o[0][k], o[1][k], o[2][k]) and goes along unit (d[0][k], d[1][k],
 * d[2][k]), bit for bit what camera_generate_ray(cam, px_raster[k], py_raster[k],
 * (lens_u[k], lens_v[k]), time01[k]) gives. A static camera's rays are computed in one
 * vectorised loop (core/vectorise.h), a moving camera's one by one. lens_u and lens_v are
 * read only with a lens, time01 only for a moving camera (else they may be NULL). */
void camera_generate_rays(const Camera *cam, int count, const float *px_raster, const float *py_raster,
                          const float *lens_u, const float *lens_v, const float *time01, float *const o[3],
                          float *const d[3]);
/* (time01 everywhere: the fraction between the two transform poses, 0 = start, 1 = end.) */

/* World -> camera at normalised time (for camera depth and projections in tests). */
Mat4 camera_from_world_at(const Camera *cam, float time01);

/* Camera-space z (depth along the view axis, world units) of a world point at a time. */
float camera_depth_moving(const Camera *cam, vec3 p_world, float time01);
/* Inline for a static camera (one dot product; every first hit asks) */
static inline float camera_depth(const Camera *cam, vec3 p_world, float time01)
{
    if (!cam->moving)
        return cam->cfw_z_f[0] * p_world.x + cam->cfw_z_f[1] * p_world.y + cam->cfw_z_f[2] * p_world.z + cam->cfw_z_f[3];
    return camera_depth_moving(cam, p_world, time01);
}

/* Projects a world point to raster coordinates (pinhole model) at time time01. False when
 * the point is behind the camera. */
bool camera_project(const Camera *cam, vec3 p_world, float time01, float *px_raster, float *py_raster);

#endif
