/* Every parameter type through the parser and the ParamSet getters, colour conversions
 * (rgb, spectrum, blackbody, named spectra) against closed forms, unused-parameter warnings. */
#include "scene_test_util.h"
#include "scene/spectrum.h"

static const Param *find(const ParamSet *ps, const char *name)
{
    for (int i = 0; i < ps->count; ++i)
        if (!strcmp(ps->items[i].name, name)) return &ps->items[i];
    return NULL;
}

int main(void)
{
    SceneDesc s;
    /* All thirteen types plus the pbrt-v3 spellings, on a material (kept whatever the type). */
    const char *text =
        "WorldBegin\n"
        "Texture \"checks\" \"spectrum\" \"constant\"\n"
        "Material \"mystery\"\n"
        "  \"integer i\" [ 1 -2 3 ] \"float f\" 2.5 \"point2 p2\" [ 1 2 ] \"vector2 v2\" [ 3 4 ]\n"
        "  \"point3 p3\" [ 1 2 3 ] \"vector3 v3\" [ 4 5 6 ] \"normal3 n3\" [ 0 0 1 ] \"normal n\" [ 0 1 0 ]\n"
        "  \"point p\" [ 7 8 9 ] \"vector v\" [ 1 1 1 ] \"rgb c\" [ .1 .2 .3 ] \"color c3\" [ .4 .5 .6 ]\n"
        "  \"spectrum sc\" 0.7 \"spectrum sp\" [ 300 0.25 900 0.25 ] \"spectrum sn\" \"metal-Cu-eta\"\n"
        "  \"blackbody bb\" 6500 \"bool b1\" true \"bool b2\" \"false\" \"bool b3\" [ \"true\" false ]\n"
        "  \"string s\" \"a\\\"b\" \"string ss\" [ \"x\" \"y\" ] \"texture t\" \"checks\"\n";
    if (!parse_ok(text, &s)) CHECK_DONE();
    CHECK(s.material_count == 1);
    const ParamSet *ps = &s.materials[0].params;
    CHECK(ps->count == 22);
    CHECK(find(ps, "i")->type == PARAM_INTEGER && find(ps, "i")->count == 3 && find(ps, "i")->ints[1] == -2);
    CHECK(find(ps, "p2")->type == PARAM_POINT2 && find(ps, "v2")->type == PARAM_VECTOR2);
    CHECK(find(ps, "p3")->type == PARAM_POINT3 && find(ps, "p")->type == PARAM_POINT3);
    CHECK(find(ps, "v3")->type == PARAM_VECTOR3 && find(ps, "v")->type == PARAM_VECTOR3);
    CHECK(find(ps, "n3")->type == PARAM_NORMAL3 && find(ps, "n")->type == PARAM_NORMAL3);
    CHECK(find(ps, "c")->type == PARAM_RGB && find(ps, "c3")->type == PARAM_RGB);
    CHECK(find(ps, "sc")->type == PARAM_SPECTRUM && find(ps, "sc")->count == 1 && find(ps, "sc")->floats);
    CHECK(find(ps, "sn")->type == PARAM_SPECTRUM && find(ps, "sn")->strings &&
          !strcmp(find(ps, "sn")->strings[0], "metal-Cu-eta"));
    CHECK(find(ps, "bb")->type == PARAM_BLACKBODY && find(ps, "bb")->floats[0] == 6500.0f);
    CHECK(find(ps, "b3")->count == 2 && find(ps, "b3")->bools[0] && !find(ps, "b3")->bools[1]);
    CHECK(find(ps, "t")->type == PARAM_TEXTURE);
    CHECK(find(ps, "sn")->loc.line == 7 && find(ps, "sn")->loc.col == 57);

    /* Getters: values, defaults, marking used, type-strictness. */
    CHECK(!find(ps, "f")->used);
    CHECK(params_float(ps, "f", 0) == 2.5f);
    CHECK(find(ps, "f")->used);
    CHECK(params_float(ps, "absent", 7) == 7.0f);
    CHECK(params_float(ps, "i", 9) == 9.0f); /* an integer is not a float (as in pbrt-v4) */
    CHECK(params_int(ps, "i", 0) == 1);
    CHECK(params_bool(ps, "b1", false) == true);
    CHECK(params_bool(ps, "b2", true) == false);
    CHECK_STR(params_string(ps, "s", NULL), "a\"b");
    CHECK_STR(params_texture(ps, "t"), "checks");
    CHECK(params_texture(ps, "s") == NULL);
    int n = 0;
    const float *v = params_floats(ps, "p3", &n);
    CHECK(v && n == 3 && v[2] == 3.0f);
    const int32_t *iv = params_ints(ps, "i", &n);
    CHECK(iv && n == 3 && iv[2] == 3);
    CHECK(params_floats(ps, "s", &n) == NULL && n == 0);
    CHECK(params_find(ps, "ss") && params_find(ps, "ss")->count == 2);
    float rgb[3] = {-1, -1, -1};
    CHECK(!params_rgb(ps, "absent", rgb) && rgb[0] == -1.0f);
    CHECK(params_rgb(ps, "c", rgb) && rgb[0] == 0.1f && rgb[1] == 0.2f && rgb[2] == 0.3f);
    CHECK(!params_rgb(ps, "t", rgb)); /* textures are not colours */
    /* A constant spectrum is grey of the same value, both as one number and as pairs. */
    CHECK(params_rgb(ps, "sc", rgb));
    CHECK_NEAR(rgb[0], 0.7, 1e-6);
    CHECK_NEAR(rgb[2], 0.7, 1e-6);
    CHECK(params_rgb(ps, "sp", rgb));
    CHECK_NEAR(rgb[0], 0.25, 1e-5);
    CHECK_NEAR(rgb[1], 0.25, 1e-5);
    CHECK_NEAR(rgb[2], 0.25, 1e-5);
    CHECK(params_rgb(ps, "sn", rgb));
    float cu[3];
    CHECK(spectrum_named_rgb("metal-Cu-eta", cu) && rgb[0] == cu[0]);
    CHECK(params_count_unused(ps) > 0);
    scene_desc_free(&s);

    /* Colour science closed forms. The XYZ -> sRGB matrix maps the equal-energy white
     * (X = Y = Z) to (1.2048, 0.9483, 0.9088) (row sums of the matrix); the matching-function
     * fit has nearly equal integrals, so illuminant E lands there within the fit's error. */
    float e[3], one = 1.0f;
    CHECK(spectrum_samples_to_rgb_illuminant(&one, 1, e));
    CHECK_NEAR(e[0], 1.2047843, 0.03);
    CHECK_NEAR(e[1], 0.9483008, 0.03);
    CHECK_NEAR(e[2], 0.9088427, 0.03);
    CHECK_NEAR(rgb_luminance(e), 1.0, 0.02); /* Y of the constant 1 is normalised to 1 */
    /* Blackbodies: peak-normalised (the spectrum's maximum is 1, so Y < 1); hot is bluer
     * than cold; about 6500 K is close to the D65 white point of sRGB. */
    float bb_cold[3], bb_d65[3], bb_hot[3];
    spectrum_blackbody_rgb(2000, bb_cold);
    spectrum_blackbody_rgb(6504, bb_d65);
    spectrum_blackbody_rgb(12000, bb_hot);
    CHECK(bb_cold[0] > bb_cold[1] && bb_cold[1] > bb_cold[2]);
    CHECK(bb_hot[2] > bb_hot[0]);
    CHECK(rgb_luminance(bb_d65) < 1.0f && rgb_luminance(bb_d65) > 0.3f);
    CHECK_NEAR(bb_d65[0] / bb_d65[1], 1.0, 0.08);
    CHECK_NEAR(bb_d65[2] / bb_d65[1], 1.0, 0.08);
    spectrum_blackbody_rgb(-5, rgb);
    CHECK(rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0);
    /* Named spectra: BK7 from its Sellmeier fit (n_d = 1.5168 at 587.6 nm), normal dispersion. */
    float bk7[3];
    CHECK(spectrum_named_rgb("glass-BK7", bk7));
    CHECK(bk7[0] < bk7[1] && bk7[1] < bk7[2]);
    CHECK(bk7[0] > 1.51f && bk7[2] < 1.53f);
    CHECK(spectrum_named_rgb("stdillum-D65", rgb) && rgb[0] == 1.0f && rgb[2] == 1.0f);
    CHECK(spectrum_named_rgb("stdillum-A", rgb) && rgb[0] > rgb[2]);
    CHECK_NEAR(rgb_luminance(rgb), 1.0, 1e-5);
    CHECK(!spectrum_named_rgb("metal-Unobtainium-eta", rgb));
    spectrum_unknown_substitute("metal-Unobtainium-eta", rgb);
    CHECK(rgb[0] == 1.5f);
    spectrum_unknown_substitute("metal-Unobtainium-k", rgb);
    CHECK(rgb[0] == 0.0f);

    /* Illuminant getter: rgb unchanged; spectra and blackbodies normalised to luminance 1. */
    CHECK(parse_ok("WorldBegin\nLightSource \"point\" \"blackbody I\" 3000\n"
                   "LightSource \"point\" \"rgb I\" [ 2 3 4 ]\n", &s));
    CHECK(s.light_count == 2);
    CHECK(params_illuminant_rgb(&s.lights[0].params, "I", rgb));
    CHECK_NEAR(rgb_luminance(rgb), 1.0, 1e-5);
    CHECK(params_illuminant_rgb(&s.lights[1].params, "I", rgb) && rgb[0] == 2 && rgb[1] == 3 && rgb[2] == 4);
    scene_desc_free(&s);

    /* Unknown named spectrum: warning, substitution by the getter. */
    CHECK(parse_ok("WorldBegin\nMaterial \"conductor\" \"spectrum eta\" \"metal-Xx-eta\"\n", &s));
    CHECK(s.warning_count == 1);
    CHECK_STR(s.warnings[0],
              "t.pbrt:2:22: warning: unknown named spectrum \"metal-Xx-eta\" (or unreadable spectrum file): using "
              "constant 1.5 instead");
    CHECK(params_rgb(&s.materials[0].params, "eta", rgb) && rgb[1] == 1.5f);
    scene_desc_free(&s);

    /* A spectrum file (relative to the scene file) becomes numeric pairs. */
    CHECK(parse_ok("WorldBegin\nMaterial \"diffuse\" \"spectrum reflectance\" \"flat.spd\"\n", &s));
    CHECK(s.warning_count == 0);
    {
        const Param *r = params_find(&s.materials[0].params, "reflectance");
        CHECK(r && r->count == 4 && r->floats && !r->strings && r->floats[2] == 700.0f);
        CHECK(params_rgb(&s.materials[0].params, "reflectance", rgb));
        /* flat 0.25 on 400-700 nm, zero outside: the visible core keeps most of the energy */
        CHECK(rgb[1] > 0.2f && rgb[1] < 0.25f);
    }
    scene_desc_free(&s);

    /* Unused parameters (pbrt-style warnings) for known types; none for the known ones. */
    CHECK(parse_ok("Camera \"perspective\" \"float fov\" 30 \"float foo\" 1\nWorldBegin\n"
                   "Shape \"sphere\" \"float radius\" 1 \"integer bar\" 2\n", &s));
    CHECK(s.warning_count == 2);
    CHECK_STR(s.warnings[0], "t.pbrt:1:37: warning: unused parameter \"float foo\"");
    CHECK_STR(s.warnings[1], "t.pbrt:3:33: warning: unused parameter \"integer bar\"");
    scene_desc_free(&s);
    CHECK_DONE();
}
