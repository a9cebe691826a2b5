/* lights_pick_in_mesh (src/render/light_mesh_pick.c): choosing the triangle of an emitting
 * mesh from the position sample keeps every triangle's probability, maps u.x monotonically
 * and invertibly (so a stratum of u.x lands in one run of the mesh), and leaves other
 * lights alone. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "render/light_choose.h"
#include "render/tracer.h"
#include "scene/scene_desc.h"

/* Every scene's camera and film, up to WorldBegin. */
#define SCENE_HEAD                                                                                                    \
    "LookAt 0 0 -5  0 0 0  0 1 0\n"                                                                                   \
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"                                                                 \
    "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"                                   \
    "WorldBegin\n"

/* A sphere light of radius 0.5 below the origin. */
#define SPHERE_LIGHT                                                                                                  \
    "AttributeBegin\n"                                                                                                \
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 1 2 3 ]\n"                                                            \
    "  Translate 0 -2 0\n"                                                                                            \
    "  Shape \"sphere\" \"float radius\" [ 0.5 ]\n"                                                                  \
    "AttributeEnd\n"

/* An emitting mesh of three triangles of areas 0.5, 1 and 2 (so unequal powers) and a point
 * light. */
static const char *scene_text =
    SCENE_HEAD
    "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 4 0 ]\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ 0 3 0  1 3 0  0 3 1   2 3 0  4 3 0  2 3 1   5 3 0  7 3 0  5 3 2 ]\n"
    "        \"integer indices\" [ 0 2 1  3 5 4  6 8 7 ]\n"
    "AttributeEnd\n";

/* An infinite light, a sphere light, a point light (lit at every vertex, never picked), a mesh of four triangles whose second has no area (no
 * power: the pick skips it) and a moving quad (triangles, not static). */
static const char *mixed_text =
    SCENE_HEAD
    "LightSource \"infinite\" \"rgb L\" [ 0.1 0.1 0.1 ]\n"
    "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 4 0 ]\n"
    SPHERE_LIGHT
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ 0 3 0  1 3 0  0 3 1   2 3 0  3 3 0  4 3 0   5 3 0  7 3 0  5 3 2"
    "                                        8 3 0  9 3 0  8 3 3 ]\n"
    "        \"integer indices\" [ 0 2 1  3 5 4  6 8 7  9 11 10 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  ActiveTransform EndTime\n"
    "  Translate 0.5 0 0\n"
    "  ActiveTransform All\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
    "  Shape \"bilinearmesh\" \"point3 P\" [ -1 -3 0  1 -3 0  -1 -3 1  1 -3 1 ] \"integer indices\" [ 0 1 2 3 ]\n"
    "AttributeEnd\n";

/* The mesh of scene_text declared before the point light: the lights without power (the
 * point light, lit at every vertex) then come after the mesh's run. */
static const char *mesh_first_text =
    SCENE_HEAD
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ 0 3 0  1 3 0  0 3 1   2 3 0  4 3 0  2 3 1   5 3 0  7 3 0  5 3 2 ]\n"
    "        \"integer indices\" [ 0 2 1  3 5 4  6 8 7 ]\n"
    "AttributeEnd\n"
    "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 4 0 ]\n";

/* A constant sky beside a distant sun (envlight's lights): the sky is the one light the pick
 * can land on (the sun is lit at every vertex, never picked), first in the table. */
static const char *sky_sun_text =
    SCENE_HEAD
    "LightSource \"infinite\" \"rgb L\" [ 0.55 0.65 0.85 ]\n"
    "LightSource \"distant\" \"point3 from\" [ 2 2.2 3 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 2.6 2.4 2.1 ]\n"
    "Shape \"sphere\" \"float radius\" [ 1 ]\n";

/* A sphere light beside two lights without power (a point light and a distant one): the
 * sphere is the one light the pick can land on. */
static const char *sphere_one_text =
    SCENE_HEAD
    "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 4 0 ]\n"
    SPHERE_LIGHT
    "LightSource \"distant\" \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 1 1 1 ]\n";

/* A constant sky between a point light and a distant light (neither is picked): the one light
 * the pick can land on is neither first nor last in the table. */
static const char *sky_between_text =
    SCENE_HEAD
    "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 4 0 ]\n"
    "LightSource \"infinite\" \"rgb L\" [ 0.5 0.5 0.5 ]\n"
    "LightSource \"distant\" \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 1 1 1 ]\n"
    "Shape \"sphere\" \"float radius\" [ 1 ]\n";

/* The scene of text with its tracer and lights; false (and a failed check) when one fails. */
static bool build(const char *text, SceneDesc *scene, Tracer *tr, LightSet *set)
{
    Diag err = {0};
    CHECK(scene_parse_string(text, strlen(text), "<test>", NULL, scene, &err));
    memset(tr, 0, sizeof *tr);
    CHECK(check_failures == 0 && tracer_build(tr, scene, 1, &err));
    CHECK(check_failures == 0 && lights_build(set, scene, tr, &err));
    return check_failures == 0;
}

/* lights_choose against the chain it replaces, on a grid of u_pick x u.x with both ends
 * (and u_pick past them: 1, which can put the target on the total, a negative one and NaN):
 * the same light, the same bits of *pmf and u->x, and static_triangle as
 * light_is_static_triangle. Returns how many lights of each kind were chosen; *sole says
 * whether the set has one emitting mesh, *one whether it has one light the pick can land on
 * (lights_choose's shortcuts). */
static int choose_mismatches(const LightSet *set, const Tracer *tr, int chosen[3])
{
    enum { NP = 301, NX = 97 };
    int bad = 0;
    for (int a = 0; a <= NP + 3; ++a) {
        float u_pick = a == NP ? 0x1.fffffep-1f : a == NP + 1 ? 1.0f : a == NP + 2 ? -0.25f : a == NP + 3 ? NAN : (float)a / NP;
        for (int b = 0; b <= NX; ++b) {
            float ux = b == NX ? 0x1.fffffep-1f : (float)b / NX;
            float pmf_ref = -1.0f, pmf = -1.0f;
            vec2 u_ref = {ux, 0.25f}, u = u_ref;
            int ref = lights_pick(set, u_pick, &pmf_ref);
            if (ref >= 0) ref = lights_pick_in_mesh(set, tr, ref, &u_ref, &pmf_ref);
            bool tri = true;
            int got = lights_choose(set, u_pick, &u, &pmf, &tri);
            if (got != ref || memcmp(&pmf, &pmf_ref, sizeof pmf) != 0 || memcmp(&u, &u_ref, sizeof u) != 0) ++bad;
            if (got >= 0 && tri != light_is_static_triangle(set, tr, got)) ++bad;
            if (got >= 0) ++chosen[set->lights[got].kind == LIGHT_AREA ? (tri ? 1 : 2) : 0];
        }
    }
    return bad;
}

static void check_choose(const char *text, int chosen[3], bool *sole, bool *one)
{
    SceneDesc scene;
    Tracer tr;
    LightSet set;
    if (!build(text, &scene, &tr, &set)) return;
    *sole = set.sole_mesh_end > 0;
    *one = set.sole_light >= 0;
    CHECK(choose_mismatches(&set, &tr, chosen) == 0);
    lights_free(&set);
    tracer_free(&tr);
    scene_desc_free(&scene);
}

/* Table entries edited by hand, each light's pmf taken again from the cdf and
 * lights_find_sole_mesh run again, as lights_build leaves them. */
static void edit_cdf(LightSet *set, int i, float value)
{
    set->cdf[i] = value;
    for (int k = 0; k < set->count; ++k) set->choice[k].pmf = lights_pmf(set, k);
    lights_find_sole_mesh(set);
}

/* Tables edited by hand, where lights_choose must still answer as the search does: a
 * negative entry before the one light with power (the pick still lands on it for targets in
 * [0, total), not for a negative one), an entry after it below the total (two lights with
 * power: no shortcut), and a first entry above the next (the search's skip of lights
 * without width then passes the first light: no shortcut). */
static void check_edited_tables(void)
{
    SceneDesc scene[2];
    Tracer tr[2];
    LightSet set[2];
    if (!build(sky_between_text, &scene[0], &tr[0], &set[0]) || !build(sky_sun_text, &scene[1], &tr[1], &set[1])) return;
    LightSet *a = &set[0], *b = &set[1];
    CHECK(a->count == 3 && a->lights[1].kind == LIGHT_INFINITE && a->sole_light == 1);
    CHECK(b->count == 2 && b->lights[0].kind == LIGHT_INFINITE && b->sole_light == 0);
    int chosen[3] = {0, 0, 0};
    float total = a->power_total;
    edit_cdf(a, 0, -0.5f * total);
    CHECK(a->sole_light == 1);
    CHECK(choose_mismatches(a, &tr[0], chosen) == 0);
    edit_cdf(a, 0, 0.0f);
    edit_cdf(a, 2, 0.5f * total);
    CHECK(a->sole_light < 0);
    CHECK(choose_mismatches(a, &tr[0], chosen) == 0);
    edit_cdf(a, 2, total);
    CHECK(a->sole_light == 1);
    edit_cdf(b, 0, 2.0f * b->power_total);
    CHECK(b->sole_light < 0);
    CHECK(choose_mismatches(b, &tr[1], chosen) == 0);
    for (int k = 0; k < 2; ++k) {
        lights_free(&set[k]);
        tracer_free(&tr[k]);
        scene_desc_free(&scene[k]);
    }
}

int main(void)
{
    int chosen[3] = {0, 0, 0}; /* other lights, static triangles, other area lights */
    bool sole[5] = {false, false, true, true, true}, one[5] = {true, true, true, false, false};
    check_choose(scene_text, chosen, &sole[0], &one[0]);
    check_choose(mesh_first_text, chosen, &sole[1], &one[1]);
    check_choose(mixed_text, chosen, &sole[2], &one[2]);
    int before_one[3] = {chosen[0], chosen[1], chosen[2]};
    check_choose(sky_sun_text, chosen, &sole[3], &one[3]);
    check_choose(sphere_one_text, chosen, &sole[4], &one[4]);
    CHECK(chosen[0] > 0 && chosen[1] > 0 && chosen[2] > 0);
    /* the shortcut is taken where one mesh holds every light with power, wherever the others are */
    CHECK(sole[0] && sole[1] && !sole[2]);
    /* the one-light shortcut: a sky beside a sun, a sphere light beside two delta lights
     * (both chosen there); not where several lights or triangles can be picked */
    CHECK(!one[0] && !one[1] && !one[2] && one[3] && one[4]);
    CHECK(!sole[3] && !sole[4] && chosen[0] > before_one[0] && chosen[2] > before_one[2]);
    check_edited_tables();

    SceneDesc scene;
    Tracer tr;
    LightSet set;
    if (!build(scene_text, &scene, &tr, &set)) return 1;

    int first = -1, n_tri = 0, point = -1;
    for (int i = 0; i < set.count; ++i) {
        if (set.lights[i].kind == LIGHT_AREA) {
            if (first < 0) first = i;
            ++n_tri;
        } else {
            point = i;
        }
    }
    CHECK(n_tri == 3 && point >= 0);
    if (check_failures) return 1;
    double mesh_pmf = 0.0;
    for (int k = 0; k < 3; ++k) mesh_pmf += lights_pmf(&set, first + k);

    /* Probabilities: u_pick and u.x on independent midpoint grids. The pick lands in the
     * mesh with probability mesh_pmf; the final triangle k must then come up with
     * probability lights_pmf(k) (exact up to the grid's resolution), and *pmf must say so. */
    enum { NP = 400, NX = 2000 };
    double count[3] = {0, 0, 0}, total = 0.0;
    int bad_pmf = 0, bad_range = 0, outside = 0;
    for (int a = 0; a < NP; ++a) {
        float u_pick = (a + 0.5f) / NP, pmf = 0.0f;
        int li = lights_pick(&set, u_pick, &pmf);
        for (int b = 0; b < NX; ++b) {
            vec2 u = {(b + 0.5f) / NX, 0.3f};
            float p = pmf;
            int k = lights_pick_in_mesh(&set, &tr, li, &u, &p);
            total += 1.0;
            if (li == point) {
                /* not a mesh: nothing changes */
                if (k != li || u.x != (b + 0.5f) / NX || p != pmf) ++bad_pmf;
                continue;
            }
            if (k < first || k >= first + 3) {
                ++outside;
                continue;
            }
            count[k - first] += 1.0;
            if (p != lights_pmf(&set, k)) ++bad_pmf;
            if (!(u.x >= 0.0f && u.x < 1.0f) || u.y != 0.3f) ++bad_range;
        }
    }
    CHECK(bad_pmf == 0);
    CHECK(bad_range == 0);
    CHECK(outside == 0);
    for (int k = 0; k < 3; ++k) CHECK_NEAR(count[k] / total, lights_pmf(&set, first + k), 2.0 / NP + 2.0 / NX);
    /* the areas are 0.5 : 1 : 2, so are the powers */
    CHECK_NEAR(lights_pmf(&set, first + 1) / lights_pmf(&set, first), 2.0, 1e-5);
    CHECK_NEAR(lights_pmf(&set, first + 2) / lights_pmf(&set, first), 4.0, 1e-5);

    /* Stratification: for a fixed pick inside the mesh, u.x -> (k, u'.x) is the inverse CDF
     * of the mesh's triangles: position = (cdf[k] - cdf[first] + u'.x w_k) / (mesh power)
     * gives u.x back, so it is monotone and a stratum of u.x maps to one contiguous run. */
    float pmf0 = 0.0f;
    int li0 = lights_pick(&set, 0.0f, &pmf0); /* area lights come first: the mesh's first */
    CHECK(li0 == first);
    for (float x = 0.0f; x < 1.0f && li0 == first; x += 1.0f / 997.0f) {
        vec2 u = {x, 0.5f};
        float p = pmf0;
        int k = lights_pick_in_mesh(&set, &tr, li0, &u, &p);
        double lo = set.cdf[first], hi = set.cdf[first + 3];
        double back = (set.cdf[k] - lo + u.x * (set.cdf[k + 1] - set.cdf[k])) / (hi - lo);
        CHECK_NEAR(back, x, 2e-6);
    }

    lights_free(&set);
    tracer_free(&tr);
    scene_desc_free(&scene);
    return check_failures ? 1 : 0;
}
