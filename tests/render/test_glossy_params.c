/* pbrt-v4 glossy material parameters: defaults, remapping, named spectra, textures by
 * name, the conductor reflectance/eta conflict, and warnings for what is not modelled. */
#include "check.h"
#include "render/glossy_params.h"
#include "scene/spectrum.h"

static const char *SCENE =
    "WorldBegin\n"
    "Texture \"rt\" \"float\" \"constant\" \"float value\" 0.2\n"
    "Texture \"ct\" \"spectrum\" \"constant\" \"rgb value\" [0.1 0.2 0.3]\n"
    "MakeNamedMaterial \"cu\" \"string type\" \"conductor\"\n"
    "MakeNamedMaterial \"au\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" "
    "\"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.01\n"
    "MakeNamedMaterial \"refl\" \"string type\" \"conductor\" \"rgb reflectance\" [0.9 0.5 0.1] "
    "\"float uroughness\" 0.04 \"float vroughness\" 0.16 \"bool remaproughness\" false\n"
    "MakeNamedMaterial \"coat\" \"string type\" \"coateddiffuse\" \"texture reflectance\" \"ct\" "
    "\"texture roughness\" \"rt\" \"rgb albedo\" [0.5 0.5 0.5] \"float thickness\" 0.1\n"
    "MakeNamedMaterial \"coat0\" \"string type\" \"coateddiffuse\"\n"
    "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BK7\" \"float roughness\" 0.3\n"
    "MakeNamedMaterial \"water\" \"string type\" \"dielectric\" \"float eta\" 1.33\n"
    "MakeNamedMaterial \"both\" \"string type\" \"conductor\" \"rgb reflectance\" [0.5 0.5 0.5] \"spectrum eta\" "
    "\"metal-Cu-eta\"\n";

static const MaterialDesc *find(const SceneDesc *s, const char *name)
{
    for (int i = 0; i < s->material_count; ++i)
        if (s->materials[i].name && !strcmp(s->materials[i].name, name)) return &s->materials[i];
    return NULL;
}

static bool any_warning(const SceneDesc *s, const char *text)
{
    for (int i = 0; i < s->warning_count; ++i)
        if (strstr(s->warnings[i], text)) return true;
    return false;
}

int main(void)
{
    SceneDesc scene;
    Diag err = {0};
    if (!scene_parse_string(SCENE, strlen(SCENE), "<test>", NULL, &scene, &err)) {
        fprintf(stderr, "parse failed: %s\n", err.message);
        return 1;
    }
    GlossyParams gp;
    float rgb[3];

    CHECK(glossy_material_type("conductor") && glossy_material_type("dielectric") &&
          glossy_material_type("coateddiffuse") && !glossy_material_type("diffuse") && !glossy_material_type(NULL));

    /* conductor defaults: copper, smooth */
    CHECK(glossy_params_read(&scene, find(&scene, "cu"), &gp, &err));
    CHECK(gp.kind == GLOSSY_CONDUCTOR && !gp.conductor_uses_reflectance);
    CHECK(spectrum_named_rgb("metal-Cu-eta", rgb));
    CHECK_NEAR(gp.eta_rgb.x, rgb[0], 0);
    CHECK(spectrum_named_rgb("metal-Cu-k", rgb));
    CHECK_NEAR(gp.k_rgb.z, rgb[2], 0);
    GlossyBsdf b = glossy_params_bsdf(&gp, gp.uroughness, gp.vroughness, gp.color);
    CHECK(glossy_is_delta(&b));

    /* named gold, roughness 0.01 remapped to alpha 0.1 */
    CHECK(glossy_params_read(&scene, find(&scene, "au"), &gp, &err));
    CHECK(spectrum_named_rgb("metal-Au-eta", rgb));
    CHECK_NEAR(gp.eta_rgb.y, rgb[1], 0);
    b = glossy_params_bsdf(&gp, gp.uroughness, gp.vroughness, gp.color);
    CHECK_NEAR(b.distrib.alpha_x, 0.1, 1e-6);
    CHECK_NEAR(b.distrib.alpha_y, 0.1, 1e-6);

    /* reflectance, anisotropic, no remap */
    CHECK(glossy_params_read(&scene, find(&scene, "refl"), &gp, &err));
    CHECK(gp.conductor_uses_reflectance && !gp.color_tex);
    b = glossy_params_bsdf(&gp, gp.uroughness, gp.vroughness, gp.color);
    CHECK_NEAR(b.distrib.alpha_x, 0.04, 1e-7);
    CHECK_NEAR(b.distrib.alpha_y, 0.16, 1e-7);
    CHECK_NEAR(glossy_albedo(&b, v3(0, 0, 1)).glossy.x, 0.9, 1e-5);

    /* coateddiffuse with textures by name; albedo warns */
    CHECK(glossy_params_read(&scene, find(&scene, "coat"), &gp, &err));
    CHECK(gp.kind == GLOSSY_COATED_DIFFUSE);
    CHECK_STR(gp.color_tex, "ct");
    CHECK_STR(gp.uroughness_tex, "rt");
    CHECK_STR(gp.vroughness_tex, "rt");
    CHECK_NEAR(gp.eta, 1.5, 0);
    CHECK_NEAR(gp.fdr_ext, fresnel_diffuse_reflectance(1.5f), 0);
    CHECK(any_warning(&scene, "coateddiffuse \"albedo\" (scattering inside the coat) is not modelled"));
    CHECK(glossy_params_read(&scene, find(&scene, "coat0"), &gp, &err));
    CHECK(!gp.color_tex && !gp.uroughness_tex);
    CHECK_NEAR(gp.color.y, 0.5, 0);
    CHECK_NEAR(gp.uroughness, 0.0, 0);

    /* dielectrics: a named glass spectrum gives its green-channel IOR */
    CHECK(glossy_params_read(&scene, find(&scene, "glass"), &gp, &err));
    CHECK(gp.kind == GLOSSY_DIELECTRIC);
    CHECK(spectrum_named_rgb("glass-BK7", rgb));
    CHECK_NEAR(gp.eta, rgb[1], 0);
    CHECK(gp.eta > 1.49f && gp.eta < 1.53f);
    CHECK(glossy_params_read(&scene, find(&scene, "water"), &gp, &err));
    CHECK_NEAR(gp.eta, 1.33, 1e-6);

    /* pbrt-v4 refuses reflectance together with eta */
    CHECK(!glossy_params_read(&scene, find(&scene, "both"), &gp, &err));
    CHECK(strstr(err.message, "error: conductor: give either \"reflectance\" or \"eta\" and \"k\", not both") != NULL);
    CHECK(err.exit_code == WEDGE_EXIT_INPUT);

    scene_desc_free(&scene);
    CHECK_DONE();
}
