/* The lens geometry FSF's defocus filter relies on (fsf_lens.h; docs/algorithms.md section
 * 10, "Defocus"), against the renderer's own thin-lens camera by brute force: for a fixed world point at
 * several depths, the film positions through which camera_generate_ray reaches it from two
 * lens points differ by c (u - u') along x and -c (v - v') along y, c = recon_coc_slope_px;
 * so the filter's coordinate z = y' + eta t with y = fsf_lens_coord, eta = -fsf_lens_slope
 * and t the film offset to the neighbour gives the lens point the centre sees the point
 * through. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "core/transform.h"
#include "recon/fsf/fsf_lens.h"
#include "render/camera.h"

/* The film position whose ray through lens point (u, v) passes through p: Newton's method on
 * the ray's miss distance along the camera's x and y axes (finite-difference Jacobian). */
static bool film_of(const Camera *cam, vec3 p, float u, float v, double *fx, double *fy)
{
    vec3 ex = v3((float)cam->world_from_camera_static.m[0][0], (float)cam->world_from_camera_static.m[1][0],
                 (float)cam->world_from_camera_static.m[2][0]);
    vec3 ey = v3((float)cam->world_from_camera_static.m[0][1], (float)cam->world_from_camera_static.m[1][1],
                 (float)cam->world_from_camera_static.m[2][1]);
    double x = 0.5 * cam->width_px, y = 0.5 * cam->height_px;
    for (int it = 0; it < 30; ++it) {
        double r[3][2];
        const double h = 1e-2;
        for (int k = 0; k < 3; ++k) {
            CameraRay ray = camera_generate_ray(cam, (float)(x + (k == 1 ? h : 0)), (float)(y + (k == 2 ? h : 0)),
                                                (vec2){u, v}, 0.0f);
            vec3 q = v3_sub(p, ray.o_world);
            vec3 miss = v3_sub(q, v3_scale(ray.d_world, v3_dot(q, ray.d_world)));
            r[k][0] = v3_dot(miss, ex), r[k][1] = v3_dot(miss, ey);
        }
        double a = (r[1][0] - r[0][0]) / h, b = (r[2][0] - r[0][0]) / h, c = (r[1][1] - r[0][1]) / h,
               d = (r[2][1] - r[0][1]) / h, det = a * d - b * c;
        if (det == 0.0) return false;
        double dx = (d * r[0][0] - b * r[0][1]) / det, dy = (a * r[0][1] - c * r[0][0]) / det;
        x -= dx, y -= dy;
        if (fabs(dx) + fabs(dy) < 1e-5) break;
    }
    *fx = x, *fy = y;
    return true;
}

int main(void)
{
    CameraDesc cd;
    memset(&cd, 0, sizeof cd);
    cd.fov_deg = 40.0f;
    cd.lens_radius = 0.5f;
    cd.focal_distance = 4.0f;
    cd.shutter_close = 1.0f;
    const double eye[3] = {0.3, 1.0, -4.5}, look[3] = {0.0, 0.5, 0.0}, up[3] = {0.0, 1.0, 0.0};
    Mat4 cfw;
    CHECK(mat4_lookat(eye, look, up, &cfw));
    cd.camera_from_world.m[0] = cd.camera_from_world.m[1] = cfw;
    Camera cam;
    Diag err;
    CHECK(camera_init(&cam, &cd, 96, 64, &err));
    ReconCamera rc = recon_camera_from(&cam);
    /* points in front of, at and behind the focal plane, off the axis */
    const vec3 pts[3] = {v3(-0.4f, 0.8f, -2.0f), v3(0.2f, 0.3f, -0.45f), v3(0.9f, 0.1f, 6.0f)};
    const float lens[4][2] = {{0.0f, 0.0f}, {0.6f, -0.3f}, {-0.5f, 0.7f}, {0.2f, 0.9f}};
    double worst = 0.0;
    int front = 0, behind = 0;
    for (int k = 0; k < 3; ++k) {
        float depth = camera_depth(&cam, pts[k], 0.0f), c = recon_coc_slope_px(&rc, depth);
        front += c < -1.0f, behind += c > 1.0f;
        double x0, y0;
        CHECK(film_of(&cam, pts[k], lens[0][0], lens[0][1], &x0, &y0));
        for (int a = 1; a < 4; ++a) {
            double x1, y1;
            CHECK(film_of(&cam, pts[k], lens[a][0], lens[a][1], &x1, &y1));
            /* film displacement per unit lens: +c along x for u, -c along y for v */
            double ex = (x1 - x0) - (double)c * (lens[a][0] - lens[0][0]);
            double ey = (y1 - y0) + (double)c * (lens[a][1] - lens[0][1]);
            worst = fmax(worst, fmax(fabs(ex), fabs(ey)));
            /* the filter's form: the sample (film x1, lens a) seen from the centre pixel x0
             * (the neighbour is t = x1 - x0 steps away) lands on the centre's lens point */
            float y_s[2], y_c[2], eta = -fsf_lens_slope(&rc, depth);
            fsf_lens_coord(lens[a][0], lens[a][1], y_s);
            fsf_lens_coord(lens[0][0], lens[0][1], y_c);
            if (fabsf(c) > 1.0f) {
                CHECK_NEAR(y_s[0] + eta * (float)(x1 - x0), y_c[0], 1e-3);
                CHECK_NEAR(y_s[1] + eta * (float)(y1 - y0), y_c[1], 1e-3);
            }
        }
        printf("depth %.3f: c = %.3f px per unit lens\n", (double)depth, (double)c);
    }
    printf("largest film difference from c * lens offset: %.2e px\n", worst);
    CHECK(front == 1 && behind == 1); /* the points do cover both sides of the focal plane */
    CHECK(worst < 2e-3);
    CHECK_DONE();
}
