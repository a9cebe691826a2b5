/* A coherent occlusion stream that enters an ObjectBegin prototype runs a kernel the linked
 * Embree miscompiles (it can loop for ever: docs/design.md 12.31, test_coherent_instances),
 * so a scene with prototypes sends its shadow rays incoherent (Tracer.shadow_coherent_ok).
 * The rule must catch every prototype, whatever it holds and however it is instanced, and
 * leave the coherent hint (10-15% of a frame) to every other scene: static spheres at the
 * top level, moving triangles and a moving sphere, whose own instanced layers do not enter
 * that kernel. */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "render_test_util.h"
#include "render/tracer.h"
#include "scene/scene_desc.h"

static const char *HEADER = "LookAt 0 0 -5  0 0 0  0 1 0\n"
                            "Camera \"perspective\" \"float fov\" [ 40 ]\n"
                            "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
                            "WorldBegin\n"
                            "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 1  1 -1 1  0 1 1 ] \"integer indices\" [ 0 1 2 ]\n";

static int shadow_coherent(const char *world)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", HEADER, world);
    SceneDesc scene;
    Tracer tr;
    if (!test_build_tracer(text, &scene, &tr)) return -1;
    int result = tr.shadow_coherent_ok;
    tracer_free(&tr);
    scene_desc_free(&scene);
    return result;
}

int main(void)
{
    /* no prototype: coherent */
    CHECK(shadow_coherent("") == 1);
    CHECK(shadow_coherent("Shape \"sphere\" \"float radius\" [ 0.5 ]\nShape \"disk\"\n") == 1);
    CHECK(shadow_coherent("AttributeBegin\n ActiveTransform EndTime\n Translate 1 0 0\n ActiveTransform All\n"
                          " Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] \"integer indices\" [ 0 1 2 ]\n"
                          "AttributeEnd\n") == 1);
    CHECK(shadow_coherent("AttributeBegin\n ActiveTransform EndTime\n Translate 1 0 0\n ActiveTransform All\n"
                          " Shape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n") == 1);
    /* a prototype, of triangles, a disk or a sphere, instanced still or moving: incoherent */
    CHECK(shadow_coherent("ObjectBegin \"tri\"\n"
                          " Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] \"integer indices\" [ 0 1 2 ]\n"
                          "ObjectEnd\nObjectInstance \"tri\"\n") == 0);
    CHECK(shadow_coherent("ObjectBegin \"d\"\n Shape \"disk\"\nObjectEnd\nObjectInstance \"d\"\n") == 0);
    CHECK(shadow_coherent("ObjectBegin \"s\"\n Shape \"sphere\"\nObjectEnd\n"
                          "AttributeBegin\n ActiveTransform EndTime\n Translate 0 2 0\n ActiveTransform All\n"
                          " ObjectInstance \"s\"\nAttributeEnd\n") == 0);
    return check_failures ? 1 : 0;
}
