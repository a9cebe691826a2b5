/* Effect analysis on small scenes that each have exactly one effect (or none). */
#include "scene_test_util.h"

/* Returns the effects as a 4-character string of 0/1: soft_shadows defocus motion indirect. */
static const char *effects_of(const char *text)
{
    static char out[5];
    SceneDesc s;
    if (!parse_ok(text, &s)) return "error";
    for (int e = 0; e < EFFECT_COUNT; ++e) out[e] = effect_in(s.effects, (Effect)e) ? '1' : '0';
    out[EFFECT_COUNT] = 0;
    scene_desc_free(&s);
    return out;
}

#define DIRECT "Integrator \"path\" \"integer maxdepth\" 1\n"
#define QUAD "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 1 1 0 0 1 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"

int main(void)
{
    /* Nothing: pinhole, no motion, direct lighting only, point light. */
    CHECK_STR(effects_of(DIRECT "WorldBegin\nLightSource \"point\"\n" QUAD), "0000");
    /* Only indirect: pbrt-v4's default maxdepth is 5. */
    CHECK_STR(effects_of("WorldBegin\n" QUAD), "0001");
    CHECK_STR(effects_of("Integrator \"path\" \"integer maxdepth\" 2\nWorldBegin\n"), "0001");
    /* Only defocus. */
    CHECK_STR(effects_of("Camera \"perspective\" \"float lensradius\" 0.1 \"float focaldistance\" 3\n" DIRECT
                         "WorldBegin\n" QUAD),
              "0100");
    /* Only soft shadows: an emitting quad, sphere, disk, bilinear patch. */
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n" QUAD), "1000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\"\nShape \"sphere\" \"float radius\" 0.5\n"),
              "1000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000\nShape \"disk\"\n"),
              "1000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\"\nShape \"bilinearmesh\" "
                                "\"point3 P\" [ 0 0 0 1 0 0 0 1 0 1 1 0 ]\n"),
              "1000");
    /* ... but not when the emission or the area is zero. */
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 0 0 0 ]\n" QUAD), "0000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\" \"float scale\" 0\n" QUAD), "0000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\"\nShape \"sphere\" \"float radius\" 0\n"),
              "0000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\"\n"
                                "Shape \"disk\" \"float radius\" 1 \"float innerradius\" 1\n"),
              "0000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\"\nShape \"trianglemesh\" "
                                "\"point3 P\" [ 0 0 0 1 1 1 2 2 2 ] \"integer indices\" [ 0 1 2 ]\n"),
              "0000"); /* collinear triangle */
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAreaLightSource \"diffuse\"\nScale 0 0 0\n" QUAD), "0000");
    /* Area light state ends with its attribute block. */
    CHECK_STR(effects_of(DIRECT "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\"\nAttributeEnd\n" QUAD),
              "0000");
    /* Only motion: a moving shape, a moving instance, a moving camera. */
    CHECK_STR(effects_of(DIRECT "WorldBegin\nActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n" QUAD),
              "0010");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nObjectBegin \"q\"\n" QUAD "ObjectEnd\nActiveTransform StartTime\n"
                                "Rotate 10 0 1 0\nActiveTransform All\nObjectInstance \"q\"\n"),
              "0010");
    CHECK_STR(effects_of("ActiveTransform EndTime\nTranslate 0 0 1\nActiveTransform All\nCamera \"perspective\"\n"
                         DIRECT "WorldBegin\n" QUAD),
              "0010");
    /* ... but not with a zero-length shutter, nor when both times are equal. */
    CHECK_STR(effects_of("Camera \"perspective\" \"float shutteropen\" 0.5 \"float shutterclose\" 0.5\n" DIRECT
                         "WorldBegin\nActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n" QUAD),
              "0000");
    CHECK_STR(effects_of(DIRECT "WorldBegin\nActiveTransform StartTime\nTranslate 1 0 0\nActiveTransform EndTime\n"
                                "Translate 1 0 0\nActiveTransform All\n" QUAD),
              "0000");
    /* One vocabulary: the names, in this order, and back. */
    const char *names[EFFECT_COUNT] = {"soft_shadows", "defocus", "motion", "indirect"};
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        Effect back;
        CHECK_STR(effect_name((Effect)e), names[e]);
        CHECK(effect_from_name(names[e], &back) && back == (Effect)e);
    }
    Effect none;
    CHECK(!effect_from_name("shadows", &none));
    CHECK_STR(effect_name(EFFECT_COUNT), "?");
    /* Defaults as pbrt-v4. */
    SceneDesc s;
    CHECK(parse_ok("WorldBegin\n", &s));
    CHECK(s.camera.fov_deg == 90.0f && s.film.xres == 1280 && s.film.yres == 720 && s.sampler.spp == 16);
    CHECK(s.integrator.max_depth == 5 && s.camera.focal_distance == 1e6f && s.camera.lens_radius == 0.0f);
    CHECK(s.camera.shutter_open == 0.0f && s.camera.shutter_close == 1.0f);
    CHECK_STR(s.film.filename, "pbrt.exr");
    scene_desc_free(&s);
    CHECK_DONE();
}
