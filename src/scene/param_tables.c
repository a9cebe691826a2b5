/* The parameters each pbrt-v4 entity understands, used to reject wrongly typed parameters
 * and to warn about unused ones (pbrt-v4 reports parameters no consumer looked up; wedge
 * decides this up front from these tables, so the warning does not depend on which parts
 * of the renderer happen to run). docs/scene-format.md lists the same tables.
 *
 * Table syntax: space-separated "name:codes"; codes is the set of allowed types:
 *   i integer   f float   2 point2/vector2   p point3   v vector3   n normal3
 *   c colour (rgb, spectrum or blackbody)   s string   b bool   t texture
 *   * any number of values (otherwise exactly one value, or one tuple). */
#include <stdio.h>
#include <string.h>

#include "scene/scene_internal.h"

typedef struct {
    const char *kind, *type; /* type NULL: applies to every type of the kind */
    const char *params;
} ParamTable;

static const ParamTable tables[] = {
    {"camera", "perspective",
     "fov:f lensradius:f focaldistance:f frameaspectratio:f screenwindow:f* shutteropen:f shutterclose:f"},
    {"film", NULL,
     "xresolution:i yresolution:i cropwindow:f* pixelbounds:i* filename:s diagonal:f iso:f whitebalance:f "
     "sensor:s savefp16:b maxcomponentvalue:f"},
    {"film", "gbuffer", "coordinatesystem:s"},
    {"film", "spectral", "nbuckets:i lambdamin:f lambdamax:f"},
    {"sampler", NULL, "pixelsamples:i seed:i randomization:s xsamples:i ysamples:i jitter:b dimensions:i"},
    {"integrator", NULL,
     "maxdepth:i regularize:b lightsampler:s visualizestrategies:b visualizeweights:b samplelights:b "
     "samplebsdf:b iterations:i photonsperiteration:i radius:f seed:i mutationsperpixel:i "
     "bootstrapsamples:i chains:i largestepprobability:f sigma:f maxdistance:f cossample:b"},
    {"filter", NULL, "xradius:f yradius:f sigma:f B:f C:f tau:f"},
    {"shape", NULL, "alpha:ft"},
    {"shape", "trianglemesh", "P:p* indices:i* N:n* S:v* uv:2* faceIndices:i*"},
    {"shape", "bilinearmesh", "P:p* indices:i* N:n* uv:2* faceIndices:i*"},
    {"shape", "sphere", "radius:f zmin:f zmax:f phimax:f"},
    {"shape", "disk", "height:f radius:f innerradius:f phimax:f"},
    {"shape", "plymesh", "filename:s displacement:ft displacement.edgelength:f"},
    {"shape", "loopsubdiv", "levels:i P:p* indices:i* scheme:s nverts:i*"},
    {"material", NULL, "type:s displacement:ft normalmap:s"},
    {"material", "diffuse", "reflectance:ct"},
    {"material", "coateddiffuse",
     "reflectance:ct uroughness:ft vroughness:ft roughness:ft thickness:ft eta:fct g:ft albedo:ct "
     "maxdepth:i nsamples:i remaproughness:b"},
    {"material", "coatedconductor",
     "interface.roughness:ft interface.uroughness:ft interface.vroughness:ft thickness:ft interface.eta:fct "
     "g:ft albedo:ct conductor.roughness:ft conductor.uroughness:ft conductor.vroughness:ft "
     "conductor.eta:ct conductor.k:ct reflectance:ct maxdepth:i nsamples:i remaproughness:b"},
    {"material", "conductor", "eta:ct k:ct reflectance:ct roughness:ft uroughness:ft vroughness:ft remaproughness:b"},
    {"material", "dielectric", "eta:fct roughness:ft uroughness:ft vroughness:ft remaproughness:b"},
    {"material", "thindielectric", "eta:fct"},
    {"material", "diffusetransmission", "reflectance:ct transmittance:ct scale:f"},
    {"material", "mix", "materials:s* amount:ft"},
    {"material", "interface", ""},
    {"material", "measured", "filename:s"},
    {"material", "hair", "sigma_a:ct color:ct eumelanin:ft pheomelanin:ft eta:ft beta_m:ft beta_n:ft alpha:ft"},
    {"material", "subsurface",
     "eta:f g:f mfp:ct name:s scale:f sigma_a:ct sigma_s:ct reflectance:ct roughness:ft uroughness:ft "
     "vroughness:ft remaproughness:b"},
    {"texture", NULL, "mapping:s uscale:f vscale:f udelta:f vdelta:f v1:v v2:v"},
    {"texture", "constant", "value:fct"},
    {"texture", "checkerboard", "dimension:i tex1:fct tex2:fct"},
    {"texture", "imagemap", "filename:s maxanisotropy:f filter:s wrap:s scale:f invert:b encoding:s"},
    {"texture", "scale", "tex:fct scale:fct"},
    {"texture", "mix", "tex1:fct tex2:fct amount:ft"},
    {"texture", "directionmix", "tex1:fct tex2:fct dir:v"},
    {"texture", "bilerp", "v00:fc v01:fc v10:fc v11:fc"},
    {"texture", "dots", "inside:fct outside:fct"},
    {"texture", "fbm", "octaves:i roughness:f"},
    {"texture", "wrinkled", "octaves:i roughness:f"},
    {"texture", "marble", "octaves:i roughness:f scale:f variation:f"},
    {"texture", "windy", ""},
    {"texture", "ptex", "filename:s encoding:s scale:f"},
    {"light", NULL, "scale:f power:f"},
    {"light", "point", "I:c from:p"},
    {"light", "spot", "I:c from:p to:p coneangle:f conedeltaangle:f"},
    {"light", "distant", "L:c from:p to:p illuminance:f"},
    {"light", "infinite", "L:c filename:s illuminance:f portal:p*"},
    {"arealight", "diffuse", "L:c scale:f twosided:b filename:s power:f"},
    {"option", NULL,
     "disablepixeljitter:b disabletexturefiltering:b disablewavelengthjitter:b displacementedgescale:f "
     "msereferenceimage:s msereferenceout:s rendercoordsys:s seed:i forcediffuse:b pixelstats:b wavefront:b"},
};

const char *param_type_name(ParamType t)
{
    switch (t) {
    case PARAM_INTEGER: return "integer";
    case PARAM_FLOAT: return "float";
    case PARAM_POINT2: return "point2";
    case PARAM_VECTOR2: return "vector2";
    case PARAM_POINT3: return "point3";
    case PARAM_VECTOR3: return "vector3";
    case PARAM_NORMAL3: return "normal3";
    case PARAM_RGB: return "rgb";
    case PARAM_SPECTRUM: return "spectrum";
    case PARAM_BLACKBODY: return "blackbody";
    case PARAM_BOOL: return "bool";
    case PARAM_STRING: return "string";
    case PARAM_TEXTURE: return "texture";
    }
    return "?";
}

static char type_code(ParamType t)
{
    switch (t) {
    case PARAM_INTEGER: return 'i';
    case PARAM_FLOAT: return 'f';
    case PARAM_POINT2: case PARAM_VECTOR2: return '2';
    case PARAM_POINT3: return 'p';
    case PARAM_VECTOR3: return 'v';
    case PARAM_NORMAL3: return 'n';
    case PARAM_RGB: case PARAM_SPECTRUM: case PARAM_BLACKBODY: return 'c';
    case PARAM_BOOL: return 'b';
    case PARAM_STRING: return 's';
    case PARAM_TEXTURE: return 't';
    }
    return '?';
}

static const char *code_name(char c)
{
    switch (c) {
    case 'i': return "integer";
    case 'f': return "float";
    case '2': return "point2";
    case 'p': return "point3";
    case 'v': return "vector3";
    case 'n': return "normal3";
    case 'c': return "rgb/spectrum/blackbody";
    case 'b': return "bool";
    case 's': return "string";
    case 't': return "texture";
    }
    return "?";
}

/* Values that make one item of the given type (one number, string or bool, or a tuple). */
static int tuple_size(ParamType t)
{
    switch (t) {
    case PARAM_POINT2: case PARAM_VECTOR2: return 2;
    case PARAM_POINT3: case PARAM_VECTOR3: case PARAM_NORMAL3: case PARAM_RGB: return 3;
    default: return 1;
    }
}

/* Finds name in a table's parameter list; returns the codes (up to the next space) or NULL. */
static const char *lookup(const char *list, const char *name, size_t *codes_len)
{
    size_t nlen = strlen(name);
    const char *p = list;
    while (*p) {
        while (*p == ' ') ++p;
        const char *colon = strchr(p, ':');
        if (!colon) break;
        const char *stop = strchr(colon, ' ');
        if (!stop) stop = colon + strlen(colon);
        if ((size_t)(colon - p) == nlen && !memcmp(p, name, nlen)) {
            *codes_len = (size_t)(stop - colon - 1);
            return colon + 1;
        }
        p = stop;
    }
    return NULL;
}

bool params_check_known(SceneDesc *scene, const char *kind, const char *type, const ParamSet *ps, Diag *err)
{
    bool type_known = false;
    for (size_t t = 0; t < sizeof tables / sizeof tables[0]; ++t)
        if (!strcmp(tables[t].kind, kind) && tables[t].type && type && !strcmp(tables[t].type, type))
            type_known = true;
    bool kind_has_generic = false;
    for (size_t t = 0; t < sizeof tables / sizeof tables[0]; ++t)
        if (!strcmp(tables[t].kind, kind) && !tables[t].type) kind_has_generic = true;
    /* Types with no table of their own (any sampler/integrator/filter name, unsupported
     * shapes) are checked against the kind's generic table only if they have one. */
    if (!type_known && !kind_has_generic) return true;

    for (int i = 0; i < ps->count; ++i) {
        const Param *p = &ps->items[i];
        const char *codes = NULL;
        size_t ncodes = 0;
        for (size_t t = 0; t < sizeof tables / sizeof tables[0] && !codes; ++t) {
            if (strcmp(tables[t].kind, kind)) continue;
            if (tables[t].type && (!type || strcmp(tables[t].type, type))) continue;
            codes = lookup(tables[t].params, p->name, &ncodes);
        }
        if (!codes) {
            /* Materials, lights and textures of types we do not know: do not guess. */
            if (!type_known && strcmp(kind, "film") && strcmp(kind, "sampler") && strcmp(kind, "integrator") &&
                strcmp(kind, "filter") && strcmp(kind, "option"))
                continue;
            scene_warn(scene, p->loc, "unused parameter \"%s %s\"", param_type_name(p->type), p->name);
            continue;
        }
        char have = type_code(p->type);
        bool array = memchr(codes, '*', ncodes) != NULL;
        if (!memchr(codes, have, ncodes)) {
            char expected[128] = "";
            for (size_t k = 0; k < ncodes; ++k) {
                if (codes[k] == '*') continue;
                if (expected[0]) strncat(expected, " or ", sizeof expected - strlen(expected) - 1);
                strncat(expected, code_name(codes[k]), sizeof expected - strlen(expected) - 1);
            }
            diag_set(err, WEDGE_EXIT_INPUT, p->loc, "parameter \"%s %s\" has the wrong type (expected %s)",
                     param_type_name(p->type), p->name, expected);
            return false;
        }
        if (!array && p->type != PARAM_SPECTRUM && p->count != tuple_size(p->type)) {
            diag_set(err, WEDGE_EXIT_INPUT, p->loc, "parameter \"%s %s\" expects %d value%s, got %d",
                     param_type_name(p->type), p->name, tuple_size(p->type), tuple_size(p->type) == 1 ? "" : "s",
                     p->count);
            return false;
        }
    }
    return true;
}
