/* Transform statements against hand-computed matrices (pbrt-v4 semantics: the CTM is
 * post-multiplied, so the last statement applies to the object first). */
#include "scene_test_util.h"

static void check_mat(const Mat4 *m, const double e[4][4], int line)
{
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!(fabs(m->m[i][j] - e[i][j]) <= 1e-12)) {
                fprintf(stderr, "line %d: m[%d][%d] = %.17g, expected %.17g\n", line, i, j, m->m[i][j], e[i][j]);
                ++check_failures;
            }
}
#define CHECK_MAT(m, ...)                                \
    do {                                                 \
        const double e_[4][4] = __VA_ARGS__;             \
        check_mat((m), e_, __LINE__);                    \
    } while (0)

int main(void)
{
    SceneDesc s;

    /* LookAt from (0,0,-5) at the origin, +y up: camera_from_world is a translation by +5 z. */
    CHECK(parse_ok("LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n", &s));
    CHECK_MAT(&s.camera.camera_from_world.m[0], {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 5}, {0, 0, 0, 1}});
    CHECK(!xform_pair_animated(&s.camera.camera_from_world));
    scene_desc_free(&s);

    /* LookAt along +x with +z up: dir = x, right = up x dir = y, new up = dir x right = z;
     * camera_from_world has rows right, up, dir. */
    CHECK(parse_ok("LookAt 0 0 0  1 0 0  0 0 1\nCamera \"perspective\"\nWorldBegin\n", &s));
    CHECK_MAT(&s.camera.camera_from_world.m[0], {{0, 1, 0, 0}, {0, 0, 1, 0}, {1, 0, 0, 0}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* Rotate 90 about z then Translate 1 0 0: M = Rz(90) T(1,0,0); the object origin goes to
     * (1,0,0) and then to (0,1,0). */
    CHECK(parse_ok("WorldBegin\nRotate 90 0 0 1\nTranslate 1 0 0\nShape \"sphere\"\n", &s));
    CHECK(s.shape_count == 1);
    CHECK_MAT(&s.shapes[0].world_from_object.m[0], {{0, -1, 0, 0}, {1, 0, 0, 1}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* Transform and ConcatTransform take the matrix column by column (pbrt's layout). */
    CHECK(parse_ok("WorldBegin\nScale 2 2 2\nConcatTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  3 4 5 1 ]\n"
                   "Shape \"sphere\"\nTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  3 4 5 1 ]\nShape \"sphere\"\n", &s));
    CHECK_MAT(&s.shapes[0].world_from_object.m[0], {{2, 0, 0, 6}, {0, 2, 0, 8}, {0, 0, 2, 10}, {0, 0, 0, 1}});
    CHECK_MAT(&s.shapes[1].world_from_object.m[0], {{1, 0, 0, 3}, {0, 1, 0, 4}, {0, 0, 1, 5}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* ActiveTransform: start and end matrices diverge; All applies to both. */
    CHECK(parse_ok("WorldBegin\nActiveTransform StartTime\nTranslate 1 0 0\nActiveTransform EndTime\n"
                   "Translate 0 2 0\nActiveTransform All\nScale 2 2 2\nShape \"sphere\"\n", &s));
    CHECK_MAT(&s.shapes[0].world_from_object.m[0], {{2, 0, 0, 1}, {0, 2, 0, 0}, {0, 0, 2, 0}, {0, 0, 0, 1}});
    CHECK_MAT(&s.shapes[0].world_from_object.m[1], {{2, 0, 0, 0}, {0, 2, 0, 2}, {0, 0, 2, 0}, {0, 0, 0, 1}});
    CHECK(xform_pair_animated(&s.shapes[0].world_from_object));
    scene_desc_free(&s);

    /* ActiveTransform is part of the attribute state; Identity only resets active times. */
    CHECK(parse_ok("WorldBegin\nTranslate 1 1 1\nAttributeBegin\nActiveTransform EndTime\nAttributeEnd\n"
                   "ActiveTransform StartTime\nIdentity\nActiveTransform All\nShape \"sphere\"\n", &s));
    CHECK_MAT(&s.shapes[0].world_from_object.m[0], {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    CHECK_MAT(&s.shapes[0].world_from_object.m[1], {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* ObjectInstance: the shape keeps its instance-from-object matrix (the CTM inside
     * ObjectBegin), each instance its world-from-instance (the CTM at ObjectInstance). */
    CHECK(parse_ok("WorldBegin\nObjectBegin \"o\"\nTranslate 0 0 1\nShape \"sphere\"\nObjectEnd\n"
                   "Translate 5 0 0\nObjectInstance \"o\"\nAttributeBegin\nRotate 90 0 0 1\nObjectInstance \"o\"\n"
                   "AttributeEnd\nShape \"disk\"\n", &s));
    CHECK(s.object_count == 1 && s.instance_count == 2 && s.shape_count == 2);
    CHECK_STR(s.objects[0].name, "o");
    CHECK(s.objects[0].first_shape == 0 && s.objects[0].shape_count == 1);
    CHECK(s.shapes[0].object == 0 && s.shapes[1].object == -1);
    CHECK(s.instances[0].object == 0 && s.instances[1].object == 0);
    CHECK_MAT(&s.shapes[0].world_from_object.m[0], {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 1}, {0, 0, 0, 1}});
    CHECK_MAT(&s.instances[0].world_from_instance.m[0], {{1, 0, 0, 5}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    CHECK_MAT(&s.instances[1].world_from_instance.m[0], {{0, -1, 0, 5}, {1, 0, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    /* ObjectEnd restored the CTM: the disk after the instances sees Translate 5 0 0 only. */
    CHECK_MAT(&s.shapes[1].world_from_object.m[0], {{1, 0, 0, 5}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* Named coordinate systems: "camera" is the inverse of camera_from_world; user systems
     * restore the CTM saved by CoordinateSystem; WorldBegin resets the CTM. */
    CHECK(parse_ok("Translate 7 7 7\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                   "Shape \"sphere\"\nCoordSysTransform \"camera\"\nShape \"sphere\"\n"
                   "Identity\nTranslate 0 3 0\nCoordinateSystem \"mine\"\nIdentity\nCoordSysTransform \"mine\"\n"
                   "Shape \"sphere\"\n", &s));
    CHECK_MAT(&s.camera.camera_from_world.m[0], {{1, 0, 0, 7}, {0, 1, 0, 7}, {0, 0, 1, 12}, {0, 0, 0, 1}});
    CHECK_MAT(&s.shapes[0].world_from_object.m[0], {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    CHECK_MAT(&s.shapes[1].world_from_object.m[0], {{1, 0, 0, -7}, {0, 1, 0, -7}, {0, 0, 1, -12}, {0, 0, 0, 1}});
    CHECK_MAT(&s.shapes[2].world_from_object.m[0], {{1, 0, 0, 0}, {0, 1, 0, 3}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* Attribute stack: AttributeEnd restores transform, orientation and material;
     * TransformEnd restores only the transform. */
    CHECK(parse_ok("WorldBegin\nAttributeBegin\nReverseOrientation\nMaterial \"conductor\"\nTranslate 1 0 0\n"
                   "Shape \"sphere\"\nAttributeEnd\nShape \"sphere\"\n"
                   "TransformBegin\nTranslate 0 1 0\nReverseOrientation\nTransformEnd\nShape \"sphere\"\n", &s));
    CHECK(s.shapes[0].reverse_orientation && s.shapes[0].material == 0);
    CHECK(!s.shapes[1].reverse_orientation && s.shapes[1].material == -1);
    CHECK(s.shapes[0].world_from_object.m[0].m[0][3] == 1.0 && s.shapes[1].world_from_object.m[0].m[0][3] == 0.0);
    CHECK(s.shapes[2].reverse_orientation && s.shapes[2].world_from_object.m[0].m[1][3] == 0.0);
    CHECK(has_warning(&s, "TransformBegin/TransformEnd are deprecated"));
    scene_desc_free(&s);

    /* Camera motion: the camera's own transform pair. */
    CHECK(parse_ok("ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\nCamera \"perspective\"\n"
                   "WorldBegin\n", &s));
    CHECK_MAT(&s.camera.camera_from_world.m[0], {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    CHECK_MAT(&s.camera.camera_from_world.m[1], {{1, 0, 0, 1}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}});
    scene_desc_free(&s);

    /* TransformTimes is recorded. */
    CHECK(parse_ok("TransformTimes 0.25 0.75\nWorldBegin\n", &s));
    CHECK(s.transform_start_time == 0.25f && s.transform_end_time == 0.75f);
    scene_desc_free(&s);
    CHECK_DONE();
}
