/* Every directive: what it stores in the SceneDesc, and the warnings for what is ignored. */
#include "scene_test_util.h"

static int count_warnings(const SceneDesc *s, const char *text)
{
    int n = 0;
    for (int i = 0; i < s->warning_count; ++i) n += strstr(s->warnings[i], text) != NULL;
    return n;
}

int main(void)
{
    SceneDesc s;
    /* Rendering options. */
    CHECK(parse_ok("Option \"integer seed\" 7\n"
                   "ColorSpace \"srgb\"\n"
                   "Camera \"perspective\" \"float fov\" 45 \"float lensradius\" 0.5 \"float focaldistance\" 4\n"
                   "  \"float frameaspectratio\" 2 \"float screenwindow\" [ -1 1 -0.5 0.5 ]\n"
                   "  \"float shutteropen\" 0.2 \"float shutterclose\" 0.6\n"
                   "Film \"gbuffer\" \"integer xresolution\" 320 \"integer yresolution\" 200\n"
                   "  \"string filename\" \"out.exr\" \"float cropwindow\" [ 0.25 0.75 0 0.5 ]\n"
                   "Sampler \"halton\" \"integer pixelsamples\" 64\n"
                   "PixelFilter \"box\" \"float xradius\" 0.5\n"
                   "Integrator \"path\" \"integer maxdepth\" 3\n"
                   "Accelerator \"bvh\" \"integer maxnodeprims\" 4\n"
                   "Accelerator \"kdtree\"\n"
                   "WorldBegin\nWorldEnd\n",
                   &s));
    CHECK_STR(s.camera.type, "perspective");
    CHECK(s.camera.fov_deg == 45.0f && s.camera.lens_radius == 0.5f && s.camera.focal_distance == 4.0f);
    CHECK(s.camera.frame_aspect == 2.0f && s.camera.has_screen_window && s.camera.screen_window[2] == -0.5f);
    CHECK(s.camera.shutter_open == 0.2f && s.camera.shutter_close == 0.6f);
    CHECK(s.camera.loc.line == 3 && s.camera.loc.col == 1);
    CHECK_STR(s.film.type, "gbuffer");
    CHECK(s.film.xres == 320 && s.film.yres == 200);
    CHECK_STR(s.film.filename, "out.exr");
    CHECK(s.film.crop[0] == 0.25f && s.film.crop[1] == 0.75f && s.film.crop[3] == 0.5f);
    CHECK_STR(s.sampler.type, "halton");
    CHECK(s.sampler.spp == 64);
    CHECK_STR(s.filter.type, "box");
    CHECK(params_float(&s.filter.params, "xradius", 0) == 0.5f);
    CHECK_STR(s.integrator.type, "path");
    CHECK(s.integrator.max_depth == 3);
    CHECK_STR(s.color_space, "srgb");
    CHECK(s.options.count == 1 && params_int(&s.options, "seed", 0) == 7);
    CHECK(count_warnings(&s, "Accelerator ignored") == 1); /* once per kind */
    CHECK_STR(s.warnings[0], "t.pbrt:11:1: warning: Accelerator ignored: wedge always builds an Embree BVH");
    CHECK(count_warnings(&s, "WorldEnd is a pbrt-v3 statement; ignored") == 1);
    CHECK(s.warning_count == 2);
    scene_desc_free(&s);

    /* Stratified sampler: spp = xsamples * ysamples; swapped shutter; spectral film and
     * other colour spaces are substituted with warnings. */
    CHECK(parse_ok("Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 5\n"
                   "Camera \"perspective\" \"float shutteropen\" 1 \"float shutterclose\" 0\n"
                   "Film \"spectral\"\nColorSpace \"aces2065-1\"\nWorldBegin\n",
                   &s));
    CHECK(s.sampler.spp == 15);
    CHECK(s.camera.shutter_open == 0.0f && s.camera.shutter_close == 1.0f);
    CHECK(has_warning(&s, "t.pbrt:2:1: warning: shutter close time 0 < shutter open time 1: swapped"));
    CHECK(has_warning(&s, "t.pbrt:3:6: warning: film \"spectral\" is not supported"));
    CHECK(has_warning(&s, "t.pbrt:4:12: warning: colour space \"aces2065-1\" not supported"));
    scene_desc_free(&s);

    /* Materials, textures, lights. */
    CHECK(parse_ok("WorldBegin\n"
                   "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"rgb tex1\" [ 1 0 0 ]\n"
                   "Texture \"amount\" \"float\" \"constant\" \"float value\" 0.5\n"
                   "Texture \"old\" \"color\" \"imagemap\" \"string filename\" \"a.png\"\n"
                   "Texture \"noise\" \"float\" \"fbm\"\n"
                   "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"texture reflectance\" \"checks\"\n"
                   "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\"\n"
                   "  \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.1\n"
                   "Material \"dielectric\" \"float eta\" 1.33\n"
                   "Shape \"sphere\"\n"
                   "NamedMaterial \"red\"\n"
                   "Shape \"sphere\"\n"
                   "Material \"mix\" \"string materials\" [ \"red\" \"gold\" ] \"float amount\" 0.3\n"
                   "Material \"interface\"\n"
                   "Material \"coateddiffuse\" \"rgb reflectance\" [ .2 .3 .4 ] \"float roughness\" 0\n"
                   "Shape \"sphere\"\n"
                   "LightSource \"point\" \"rgb I\" [ 1 2 3 ] \"point3 from\" [ 0 1 0 ]\n"
                   "LightSource \"spot\" \"blackbody I\" 5000 \"float coneangle\" 20\n"
                   "LightSource \"distant\" \"rgb L\" [ 1 1 1 ] \"point3 to\" [ 0 -1 0 ]\n"
                   "LightSource \"infinite\" \"rgb L\" [ .1 .1 .1 ]\n"
                   "LightSource \"goniometric\"\n"
                   "LightSource \"projection\"\n"
                   "AttributeBegin\n"
                   "Translate 0 5 0\n"
                   "AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ] \"bool twosided\" true\n"
                   "Shape \"disk\" \"float radius\" 2\n"
                   "AttributeEnd\n"
                   "Shape \"cylinder\"\nShape \"cylinder\"\nShape \"curve\"\n"
                   "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMediumInterface \"fog\" \"\"\n",
                   &s));
    CHECK(s.texture_count == 4);
    CHECK_STR(s.textures[0].name, "checks");
    CHECK_STR(s.textures[0].value_type, "spectrum");
    CHECK_STR(s.textures[0].tex_class, "checkerboard");
    CHECK_STR(s.textures[2].value_type, "spectrum"); /* pbrt-v3 "color" */
    CHECK(has_warning(&s, "t.pbrt:5:1: warning: pbrt-v4 texture class \"fbm\" is not supported"));
    CHECK(s.material_count == 6);
    CHECK_STR(s.materials[0].name, "red");
    CHECK_STR(s.materials[0].type, "diffuse");
    CHECK_STR(params_texture(&s.materials[0].params, "reflectance"), "checks");
    CHECK_STR(s.materials[1].type, "conductor");
    CHECK(s.materials[2].name == NULL);
    CHECK_STR(s.materials[2].type, "dielectric");
    CHECK(s.shape_count == 4);
    CHECK(s.shapes[0].material == 2);               /* anonymous dielectric */
    CHECK(s.shapes[1].material == 0);               /* NamedMaterial "red" */
    CHECK(s.shapes[2].material == 5);               /* the last Material statement */
    CHECK_STR(s.materials[3].type, "mix");
    CHECK(params_find(&s.materials[3].params, "materials")->count == 2);
    CHECK(s.light_count == 4);
    CHECK_STR(s.lights[0].type, "point");
    CHECK_STR(s.lights[3].type, "infinite");
    CHECK(has_warning(&s, "t.pbrt:21:1: warning: unsupported light \"goniometric\" ignored"));
    CHECK(has_warning(&s, "unsupported light \"projection\" ignored"));
    CHECK(s.area_light_count == 1);
    CHECK(s.shapes[3].area_light == 0 && s.shapes[2].area_light == -1);
    CHECK(params_bool(&s.area_lights[0].params, "twosided", false));
    CHECK(s.shapes[3].world_from_object.m[0].m[1][3] == 5.0);
    CHECK(count_warnings(&s, "unsupported shape \"cylinder\" ignored") == 1);
    CHECK(count_warnings(&s, "unsupported shape \"curve\" ignored") == 1);
    CHECK(count_warnings(&s, "participating media are not supported") == 1);
    scene_desc_free(&s);

    /* Attribute defaults; implicit indices of a single triangle. */
    CHECK(parse_ok("WorldBegin\nAttribute \"shape\" \"float radius\" 3\nAttribute \"shape\" \"float radius\" 4\n"
                   "Shape \"sphere\"\n"
                   "Shape \"sphere\" \"float radius\" 1\n"
                   "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n",
                   &s));
    CHECK(params_float(&s.shapes[0].params, "radius", 0) == 3.0f); /* the first Attribute value wins */
    CHECK(params_float(&s.shapes[1].params, "radius", 0) == 1.0f);
    CHECK(s.warning_count == 0); /* attribute defaults are never "unused" (pbrt-v4) */
    int n = 0;
    const int32_t *idx = params_ints(&s.shapes[2].params, "indices", &n);
    CHECK(idx && n == 3 && idx[0] == 0 && idx[1] == 1 && idx[2] == 2);
    scene_desc_free(&s);

    /* Area lights are not carried into object instances (as pbrt-v4). */
    CHECK(parse_ok("WorldBegin\nAreaLightSource \"diffuse\"\nObjectBegin \"o\"\nShape \"sphere\"\nObjectEnd\n", &s));
    CHECK(s.shapes[0].area_light == -1);
    CHECK(has_warning(&s, "area lights are not supported inside ObjectBegin"));
    scene_desc_free(&s);

    /* Many distinct warnings are capped. */
    {
        char *big = malloc(400 * 64 + 64);
        CHECK(big != NULL);
        if (big) {
            int len = sprintf(big, "WorldBegin\n");
            for (int i = 0; i < 400; ++i) len += sprintf(big + len, "Shape \"sphere\" \"float x%d\" 1\n", i);
            CHECK(parse_ok(big, &s));
            CHECK(s.warning_count == 201);
            CHECK_STR(s.warnings[200], "warning: too many warnings; further warnings suppressed");
            scene_desc_free(&s);
            free(big);
        }
    }
    /* Rotate about the zero axis: no direction to rotate about (pbrt-v4 gets NaN); the
     * identity, with a warning naming the statement (issue 20 item 9) */
    CHECK(parse_ok("WorldBegin\nRotate 30 0 0 0\nShape \"sphere\"\n", &s));
    CHECK(s.warning_count == 1);
    if (s.warning_count == 1)
        CHECK_STR(s.warnings[0], "t.pbrt:2:1: warning: Rotate 30 about the zero axis (0, 0, 0) has no direction: ignored");
    CHECK(mat4_is_identity(&s.shapes[0].world_from_object.m[0]));
    scene_desc_free(&s);
    CHECK_DONE();
}
