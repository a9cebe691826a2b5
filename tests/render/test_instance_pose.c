/* tracer_world_from_instance keeps a moving instance's poses at time01 = 0 and 1 once the
 * build is done (tracer.h: Instance.pose_at_end) and returns them from then on. The kept
 * poses must be the motion's two ends, as the scene gives them (the translation at
 * shutter open and at shutter close, in world units), and agree with Embree's own
 * interpolation just inside the ends (which is not kept), for a scene of ordinary size and
 * for one so small that the tracer rescales what Embree sees (normalise_scale), where the
 * poses must still come back in world units. Swapping the two kept ends fails both checks. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "render/tracer.h"
#include "scene/scene_desc.h"

/* A sphere translated from (1, 2, 3) * s to (4, 5, 6) * s and turned by 60 degrees about z
 * over the shutter; s scales the scene. */
static const char *SCENE =
    "LookAt 0 0 -5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    " ActiveTransform StartTime\n Translate %g %g %g\n"
    " ActiveTransform EndTime\n Translate %g %g %g\n Rotate 60 0 0 1\n"
    " ActiveTransform All\n"
    " Shape \"sphere\" \"float radius\" [ %g ]\n"
    "AttributeEnd\n";

static double max_abs_diff(const Mat4 *a, const Mat4 *b)
{
    double d = 0.0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) d = fmax(d, fabs((double)a->m[i][j] - (double)b->m[i][j]));
    return d;
}

static void check_scale(double s)
{
    char text[2048];
    snprintf(text, sizeof text, SCENE, 1 * s, 2 * s, 3 * s, 4 * s, 5 * s, 6 * s, 0.5 * s);
    SceneDesc scene;
    Diag err = {0};
    CHECK(scene_parse_string(text, strlen(text), "<test>", NULL, &scene, &err));
    Tracer tr;
    memset(&tr, 0, sizeof tr);
    CHECK(tracer_build(&tr, &scene, 1, &err));
    if (check_failures) return;
    if (s < 1e-3) CHECK(tr.tracer_from_world != 1.0f); /* the small scene is rescaled */
    int moving = 0;
    for (int i = 0; i < tr.instance_count; ++i) {
        if (!tr.instances[i].moving) continue;
        ++moving;
        CHECK(tr.instances[i].pose_kept);
        Mat4 p0 = tracer_world_from_instance(&tr, i, 0.0f), p1 = tracer_world_from_instance(&tr, i, 1.0f);
        /* the ends the scene gives, translation first (world units) */
        const double t0[3] = {1 * s, 2 * s, 3 * s}, t1[3] = {4 * s, 5 * s, 6 * s};
        for (int k = 0; k < 3; ++k) {
            CHECK_NEAR(p0.m[k][3], t0[k], 1e-5 * s);
            CHECK_NEAR(p1.m[k][3], t1[k], 1e-5 * s);
        }
        /* the rotation: none at shutter open, 60 degrees about z at close */
        CHECK_NEAR(p0.m[0][0], 1.0, 1e-5);
        CHECK_NEAR(p1.m[0][0], 0.5, 1e-5);
        CHECK_NEAR(p1.m[1][0], sqrt(3.0) / 2.0, 1e-5);
        /* Embree's interpolation just inside each end (asked for, not kept) */
        Mat4 q0 = tracer_world_from_instance(&tr, i, 1e-6f), q1 = tracer_world_from_instance(&tr, i, 1.0f - 1e-6f);
        double scale = 1.0 + 6.0 * s;
        fprintf(stderr, "scale %g: kept end poses vs Embree next to them: %.3g %.3g (of %.3g)\n", s,
                max_abs_diff(&p0, &q0), max_abs_diff(&p1, &q1), scale);
        CHECK(max_abs_diff(&p0, &q0) <= 1e-5 * scale);
        CHECK(max_abs_diff(&p1, &q1) <= 1e-5 * scale);
    }
    CHECK(moving == 1);
    tracer_free(&tr);
    scene_desc_free(&scene);
}

int main(void)
{
    check_scale(1.0);
    check_scale(1e-5); /* bounds below 2^-10: normalise_scale rebuilds with tracer_from_world != 1 */
    return check_failures ? 1 : 0;
}
