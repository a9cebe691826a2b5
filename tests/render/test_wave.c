/* Batched tracing (issue 22): Embree's stream and packet-of-16 interfaces find what single
 * rays find.
 *  - Exact spheres, a partial sphere and a partial disk are user geometry whose callbacks
 *    Embree calls with N rays and a valid mask: every ray of a batch gets the same
 *    hit/miss, the same distance to the bit (the callback's double arithmetic sees the same
 *    floats) and the same geometry as rtcIntersect1, and the same occlusion answer, for
 *    batch sizes that leave packets partly filled. An instanced sphere (its rays moved into
 *    instance space by Embree, in SIMD for packets) agrees to float rounding.
 *  - The wave integrator gives the same image in every batch mode (single rays exactly as
 *    before; streams and packets to rounding), with the same ray counts. */
#include <stdint.h>

#include "check.h"
#include "core/rng.h"
#include "render/tracer.h"
#include "render_test_util.h"

static const char *QUADRICS =
    "LookAt 0 0 -6  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "WorldBegin\n"
    "AttributeBegin Translate -1.2 0.3 0 Shape \"sphere\" \"float radius\" [ 0.8 ] AttributeEnd\n"
    "AttributeBegin Translate 1.1 -0.2 0.5 Rotate 30 1 0 0\n"
    "  Shape \"sphere\" \"float radius\" [ 0.9 ] \"float zmin\" [ -0.5 ] \"float zmax\" [ 0.6 ] \"float phimax\" [ 270 ]\n"
    "AttributeEnd\n"
    "AttributeBegin Translate 0 -1.3 0.2 Rotate 80 1 0 0\n"
    "  Shape \"disk\" \"float radius\" [ 1.5 ] \"float innerradius\" [ 0.3 ] \"float phimax\" [ 300 ]\n"
    "AttributeEnd\n"
    "ObjectBegin \"ball\" Shape \"sphere\" \"float radius\" [ 0.5 ] ObjectEnd\n"
    "AttributeBegin Translate 0.2 1.4 1 ObjectInstance \"ball\" AttributeEnd\n";

enum { RAYS = 203 }; /* not a multiple of 16 or of the 64-ray chunks */

/* Rays from around the camera towards the shapes, some short (tmax) to test occlusion.
 * Their directions' x and y signs vary, so every chunk mixes octants and the stream's
 * occlusion rays take tracer_occluded_batch's regrouping by octant. */
static void make_rays(TracerRay *rays, int n)
{
    Pcg32 rng;
    pcg32_seed(&rng, 7, 3);
    for (int i = 0; i < n; ++i) {
        vec3 o = v3(0.4f * (pcg32_float(&rng) - 0.5f), 0.4f * (pcg32_float(&rng) - 0.5f), -6.0f);
        vec3 target = v3(4.0f * (pcg32_float(&rng) - 0.5f), 4.0f * (pcg32_float(&rng) - 0.5f), 2.0f * pcg32_float(&rng) - 0.5f);
        vec3 d = v3_normalize(v3_sub(target, o));
        float tmax = (i % 3 == 0) ? 4.0f + 4.0f * pcg32_float(&rng) : INFINITY;
        rays[i] = (TracerRay){o, d, tmax, 0.0f, 0u};
    }
}

/* Parses scene text and builds its tracer; on failure reports it, frees the scene and
 * returns false. */
static bool build_scene(const char *text, SceneDesc *scene, Tracer *tr)
{
    Diag err = {0};
    CHECK(scene_parse_string(text, strlen(text), "<test>", NULL, scene, &err));
    bool built = tracer_build(tr, scene, 1, &err);
    CHECK(built);
    if (!built) {
        fprintf(stderr, "%s\n", err.message);
        scene_desc_free(scene);
    }
    return built;
}

/* tracer_occluded_arrays (rays as arrays, traced where active) answers each active lane as a
 * single ray does, and leaves the inactive lanes' entries alone: active lanes one in three
 * and then a run of inactive ones longer than a 64-ray chunk, so chunks fill from lanes far
 * apart and the last chunk is partly filled. */
static void check_occluded_arrays(const Tracer *tr, const TracerRay *rays, const bool *ref_occ, bool coherent)
{
    float o[3][RAYS], d[3][RAYS], tmax[RAYS], time01[RAYS];
    int active[RAYS], n_active = 0;
    for (int i = 0; i < RAYS; ++i) {
        o[0][i] = rays[i].o.x, o[1][i] = rays[i].o.y, o[2][i] = rays[i].o.z;
        d[0][i] = rays[i].d.x, d[1][i] = rays[i].d.y, d[2][i] = rays[i].d.z;
        tmax[i] = rays[i].tmax, time01[i] = rays[i].time01;
        active[i] = i % 3 != 1 && !(i >= 60 && i < 130);
        n_active += active[i];
    }
    TracerRayArrays a = {{o[0], o[1], o[2]}, {d[0], d[1], d[2]}, tmax, time01, active, 0u};
    bool occ[RAYS], untouched[RAYS];
    for (int i = 0; i < RAYS; ++i) occ[i] = untouched[i] = i % 2 == 0; /* markers an inactive lane keeps */
    tracer_occluded_arrays(tr, &a, RAYS, coherent, occ);
    int bad = 0, occluded = 0;
    for (int i = 0; i < RAYS; ++i) {
        bad += active[i] ? occ[i] != ref_occ[i] : occ[i] != untouched[i];
        occluded += active[i] && ref_occ[i];
    }
    CHECK(n_active > 64 && occluded > 0); /* more than one chunk */
    CHECK(2 * n_active < RAYS);           /* lanes mostly inactive: Embree's packets, coherent or not */
    if (bad) fprintf(stderr, "tracer_occluded_arrays (coherent %d): %d lanes differ\n", coherent, bad);
    CHECK(bad == 0);
}

/* tracer_occluded_arrays in the stream mode hands coherent lanes whose active rays use at
 * most two direction octants to Embree as the arrays themselves (rtcOccludedNp, inactive
 * lanes as rays Embree skips) where the arrays are 16-byte aligned, other coherent lanes as
 * rays sorted by octant, and incoherent lanes as packets of 16 filled from the arrays: each
 * way each active lane's answer is a single ray's and inactive lanes keep their entries.
 * Rays in one octant, in two (x's sign alternating) and as make_rays makes them (four), in
 * a scene scaled by s (s = 1e-5: the tracer's scale is not 1, so the origins are scaled into
 * a copy or into the packets), from arrays 16-byte aligned and from arrays one float off,
 * coherent and not. */
static void test_occluded_octants(double s)
{
    char text[2048];
    const char *world = strstr(QUADRICS, "WorldBegin\n") + strlen("WorldBegin\n");
    snprintf(text, sizeof text, "%.*sScale %g %g %g\n%s", (int)(world - QUADRICS), QUADRICS, s, s, s, world);
    SceneDesc scene;
    Tracer tr;
    if (!build_scene(text, &scene, &tr)) return;
    CHECK((tr.tracer_from_world != 1.0f) == (s < 1e-3));
    tr.batch_mode = TRACER_BATCH_STREAM;
    for (int octants = 1; octants <= 4; octants *= 2) {
        TracerRay rays[RAYS];
        make_rays(rays, RAYS);
        bool ref[RAYS];
        int occluded = 0, clear = 0;
        for (int i = 0; i < RAYS; ++i) {
            vec3 d = rays[i].d;
            if (octants == 1) rays[i].d = v3(fabsf(d.x), fabsf(d.y), fabsf(d.z));
            if (octants == 2) rays[i].d = v3(i % 2 ? -fabsf(d.x) : fabsf(d.x), fabsf(d.y), fabsf(d.z));
            rays[i].o = v3_scale(rays[i].o, (float)s);
            rays[i].tmax *= (float)s;
            ref[i] = tracer_occluded(&tr, rays[i].o, rays[i].d, rays[i].tmax, 0.0f);
            occluded += ref[i], clear += !ref[i];
        }
        CHECK(occluded > 4 && clear > 4);
        for (int offset = 0; offset < 4; ++offset) {
            bool coherent = offset < 2;
            _Alignas(64) float o[3][RAYS + 1], d[3][RAYS + 1], tmax[RAYS + 1], time01[RAYS + 1];
            int active[RAYS];
            for (int i = 0; i < RAYS; ++i) {
                int q = i + offset % 2;
                o[0][q] = rays[i].o.x, o[1][q] = rays[i].o.y, o[2][q] = rays[i].o.z;
                d[0][q] = rays[i].d.x, d[1][q] = rays[i].d.y, d[2][q] = rays[i].d.z;
                tmax[q] = rays[i].tmax, time01[q] = rays[i].time01;
                active[i] = i % 5 != 2;
            }
            int off = offset % 2;
            TracerRayArrays a = {{o[0] + off, o[1] + off, o[2] + off},
                                 {d[0] + off, d[1] + off, d[2] + off},
                                 tmax + off,
                                 time01 + off,
                                 active,
                                 0u};
            bool occ[RAYS], untouched[RAYS];
            for (int i = 0; i < RAYS; ++i) occ[i] = untouched[i] = i % 2 == 0;
            tracer_occluded_arrays(&tr, &a, RAYS, coherent, occ);
            int bad = 0;
            for (int i = 0; i < RAYS; ++i) bad += active[i] ? occ[i] != ref[i] : occ[i] != untouched[i];
            if (bad)
                fprintf(stderr, "%d octants, scale %g, offset %d, coherent %d: %d lanes differ\n", octants, s, off,
                        coherent, bad);
            CHECK(bad == 0);
        }
    }
    tracer_free(&tr);
    scene_desc_free(&scene);
}

static void test_quadric_batches(void)
{
    SceneDesc scene;
    Tracer tr;
    if (!build_scene(QUADRICS, &scene, &tr)) return;
    TracerRay rays[RAYS];
    make_rays(rays, RAYS);
    SurfaceHit ref[RAYS];
    bool ref_found[RAYS], ref_occ[RAYS];
    int hits = 0, instanced_hits = 0, occluded = 0;
    for (int i = 0; i < RAYS; ++i) {
        ref_found[i] = tracer_intersect_ex(&tr, rays[i].o, rays[i].d, rays[i].tmax, 0.0f, true, &ref[i]);
        ref_occ[i] = tracer_occluded(&tr, rays[i].o, rays[i].d, rays[i].tmax, 0.0f);
        hits += ref_found[i];
        instanced_hits += ref_found[i] && ref[i].instance >= 0;
        occluded += ref_occ[i];
        CHECK(ref_occ[i] == ref_found[i]);
    }
    /* the rays see every shape and miss some: the comparison below means something */
    CHECK(hits > RAYS / 4 && hits < RAYS);
    CHECK(instanced_hits > 3);
    CHECK(occluded > 0);

    for (int m = 0; m < TRACER_BATCH_MODE_COUNT; ++m) {
        tr.batch_mode = (TracerBatchMode)m;
        for (int coherent = 0; coherent < 2; ++coherent) {
            SurfaceHit got[RAYS];
            bool found[RAYS], occ[RAYS];
            tracer_intersect_batch(&tr, rays, RAYS, true, coherent, got, found);
            tracer_occluded_batch(&tr, rays, RAYS, coherent, occ);
            int bad_found = 0, bad_t = 0, bad_geom = 0, bad_occ = 0;
            for (int i = 0; i < RAYS; ++i) {
                bad_found += found[i] != ref_found[i];
                bad_occ += occ[i] != ref_occ[i];
                if (!found[i] || !ref_found[i]) continue;
                bad_geom += got[i].geom != ref[i].geom || got[i].instance != ref[i].instance;
                if (ref[i].instance < 0)
                    bad_t += memcmp(&got[i].t, &ref[i].t, sizeof(float)) != 0 || v3_length(v3_sub(got[i].p, ref[i].p)) != 0.0f;
                else
                    bad_t += !(fabsf(got[i].t - ref[i].t) <= 1e-5f * ref[i].t);
            }
            if (bad_found + bad_t + bad_geom + bad_occ)
                fprintf(stderr, "mode %s coherent %d: %d hit/miss, %d t, %d geometry, %d occlusion differ\n",
                        tracer_batch_mode_name((TracerBatchMode)m), coherent, bad_found, bad_t, bad_geom, bad_occ);
            CHECK(bad_found == 0 && bad_t == 0 && bad_geom == 0 && bad_occ == 0);
            /* lanes mostly inactive go to Embree as packets of 16 whatever the flag
             * (tracer.c, packets_of_16), never as the coherent stream of compacted chunks
             * that stalls inside Embree in the sanitizer build with this scene's instanced
             * sphere (docs/design.md 12.31) */
            check_occluded_arrays(&tr, rays, ref_occ, coherent);
        }
    }
    /* an empty batch traces nothing */
    tracer_intersect_batch(&tr, rays, 0, true, true, ref, ref_found);
    tracer_occluded_batch(&tr, rays, 0, true, ref_occ);
    tracer_free(&tr);
    scene_desc_free(&scene);
}

/* Triangles at the top level and in an instance, no top-level sphere: the camera stream's
 * common case (tracer_intersect_arrays without sphere lanes). */
static const char *TRIANGLES =
    "LookAt 0 0 -6  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "WorldBegin\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point3 P\" [ -2 -2 1  2 -2 1  2 2 1.5  -2 2 1.5 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"
    "ObjectBegin \"tri\" Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point3 P\" [ -0.5 0 0  0.5 0 0  0 0.8 0 ] ObjectEnd\n"
    "AttributeBegin Translate -0.6 -0.4 -0.5 Rotate 20 0 1 0 ObjectInstance \"tri\" AttributeEnd\n";

static bool same_hit(const SurfaceHit *a, const SurfaceHit *b)
{
    return memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(&a->p, &b->p, sizeof a->p) == 0 &&
           memcmp(&a->ng, &b->ng, sizeof a->ng) == 0 && memcmp(&a->ns, &b->ns, sizeof a->ns) == 0 &&
           memcmp(&a->uv, &b->uv, sizeof a->uv) == 0 && memcmp(&a->err, &b->err, sizeof a->err) == 0 &&
           a->geom == b->geom && a->prim == b->prim && a->instance == b->instance && a->object_id == b->object_id &&
           a->light == b->light;
}

/* tracer_intersect_arrays (the camera rays: the stream mode hands Embree the arrays
 * themselves, rtcIntersectNp) finds what tracer_intersect_batch finds for the same rays in
 * the same mode, bit for bit, with lengths given and with none (tmax NULL: INFINITY), in
 * every batch mode, coherent or not; RAYS lanes fill three chunks and part of a fourth. */
static void test_intersect_arrays(const char *text, bool top_sphere)
{
    SceneDesc scene;
    Tracer tr;
    if (!build_scene(text, &scene, &tr)) return;
    CHECK(tr.top_spheres == top_sphere);
    TracerRay rays[RAYS], rays_inf[RAYS];
    make_rays(rays, RAYS);
    float o[3][RAYS], d[3][RAYS], tmax[RAYS], time01[RAYS];
    for (int i = 0; i < RAYS; ++i) {
        o[0][i] = rays[i].o.x, o[1][i] = rays[i].o.y, o[2][i] = rays[i].o.z;
        d[0][i] = rays[i].d.x, d[1][i] = rays[i].d.y, d[2][i] = rays[i].d.z;
        tmax[i] = rays[i].tmax, time01[i] = rays[i].time01;
        rays_inf[i] = rays[i], rays_inf[i].tmax = INFINITY;
    }
    for (int m = 0; m < TRACER_BATCH_MODE_COUNT; ++m) {
        tr.batch_mode = (TracerBatchMode)m;
        for (int coherent = 0; coherent < 2; ++coherent)
            for (int lengths = 0; lengths < 2; ++lengths) {
                SurfaceHit ref[RAYS], got[RAYS];
                bool ref_found[RAYS], found[RAYS];
                tracer_intersect_batch(&tr, lengths ? rays : rays_inf, RAYS, true, coherent, ref, ref_found);
                TracerRayArrays a = {{o[0], o[1], o[2]}, {d[0], d[1], d[2]}, lengths ? tmax : NULL, time01, NULL, 0u};
                tracer_intersect_arrays(&tr, &a, RAYS, true, coherent, got, found);
                int bad = 0, hits = 0, instanced = 0;
                for (int i = 0; i < RAYS; ++i) {
                    bad += found[i] != ref_found[i] || (found[i] && !same_hit(&got[i], &ref[i]));
                    hits += ref_found[i];
                    instanced += ref_found[i] && ref[i].instance >= 0;
                }
                if (bad)
                    fprintf(stderr, "tracer_intersect_arrays, mode %s coherent %d lengths %d: %d lanes differ\n",
                            tracer_batch_mode_name((TracerBatchMode)m), coherent, lengths, bad);
                CHECK(bad == 0);
                CHECK(hits > RAYS / 4 && hits < RAYS && instanced > 0);
            }
    }
    tracer_free(&tr);
    scene_desc_free(&scene);
}

/* A layer's only sphere has a second, empty Embree primitive at the centre of its box (so
 * that Embree tests rays against the box before calling back; tracer.c,
 * QUADRIC_PRIM_ANCHOR): rays through that point, from outside and from inside, find the
 * sphere where it is and nothing else, in every batch mode; rays beside it find nothing. */
static void test_lone_sphere(void)
{
    static const char *LONE = "LookAt 0 0 -6  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                              "AttributeBegin Translate 0.25 0.5 0.75 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n";
    SceneDesc scene;
    Tracer tr;
    if (!build_scene(LONE, &scene, &tr)) return;
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    TracerRay rays[4] = {
        {v3(0.25f, 0.5f, -3.0f), z, INFINITY, 0.0f, 0u}, /* through the centre from outside: t 3.25 */
        {v3(0.25f, 0.5f, 0.5f), z, INFINITY, 0.0f, 0u},  /* from inside, through the centre: t 0.75 */
        {v3(0.25f, 1.1f, -3.0f), z, INFINITY, 0.0f, 0u}, /* beside the sphere, through its box's corner region */
        {v3(0.25f, 0.5f, -3.0f), z, 3.0f, 0.0f, 0u},     /* stops short of it */
    };
    const float t_expect[4] = {3.25f, 0.75f, -1.0f, -1.0f};
    for (int m = 0; m < TRACER_BATCH_MODE_COUNT; ++m) {
        tr.batch_mode = (TracerBatchMode)m;
        SurfaceHit hit[4];
        bool found[4], occ[4];
        tracer_intersect_batch(&tr, rays, 4, true, false, hit, found);
        tracer_occluded_batch(&tr, rays, 4, false, occ);
        for (int i = 0; i < 4; ++i) {
            bool expect = t_expect[i] > 0.0f;
            CHECK(found[i] == expect && occ[i] == expect);
            if (found[i] && expect) CHECK_NEAR(hit[i].t, t_expect[i], 1e-5);
        }
    }
    tracer_free(&tr);
    scene_desc_free(&scene);
}

/* Shadow rays aimed at a sphere or disk emitter skip it (Geom.mask_bit): two sphere lights
 * and a plain sphere in a row along z; rays along z through all three. A ray skipping light
 * A's bit is not stopped by A, but still by B and by the plain sphere; with no skip mask A
 * stops it, in every batch mode. */
static const char *TWO_LIGHTS =
    "LookAt 0 0 -6  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "WorldBegin\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] Translate 0 0 0 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] Translate 0 0 2 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n"
    "AttributeBegin Translate 0 0 4 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n";

static void test_shadow_rays_skip_their_light(void)
{
    SceneDesc scene;
    Tracer tr;
    if (!build_scene(TWO_LIGHTS, &scene, &tr)) return;
    const Layer *l = &tr.layers[0];
    unsigned bit[3] = {0, 0, 0};
    int spheres = 0;
    for (int i = 0; i < l->geom_count && spheres < 3; ++i)
        if (l->geoms[i].kind == GEOM_SPHERE) bit[spheres++] = l->geoms[i].mask_bit;
    CHECK(spheres == 3);
    if (!rtcGetDeviceProperty(tr.device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED)) {
        fprintf(stderr, "this Embree has no ray masks: emitters keep no bit, shadow rays test them\n");
        CHECK(bit[0] == 0 && bit[1] == 0 && bit[2] == 0);
        tracer_free(&tr);
        scene_desc_free(&scene);
        return;
    }
    CHECK(bit[0] != 0 && bit[1] != 0 && bit[0] != bit[1] && bit[2] == 0); /* the plain sphere has none */
    const vec3 z = v3(0.0f, 0.0f, 1.0f), o = v3(0.0f, 0.0f, -3.0f);
    TracerRay rays[6] = {
        {o, z, 3.0f, 0.0f, 0u},     /* into light A (front at t 2.5): stopped by A */
        {o, z, 3.0f, 0.0f, bit[0]}, /* the same, skipping A: free */
        {o, z, 5.0f, 0.0f, bit[0]}, /* through A into light B (t 4.5), skipping A: stopped by B */
        {o, z, 5.0f, 0.0f, bit[1]}, /* skipping B: stopped by A */
        {v3(0.0f, 0.0f, 3.0f), z, 1.0f, 0.0f, bit[0] | bit[1]}, /* into the plain sphere: stopped */
        {v3(0.0f, 0.0f, 1.0f), z, 1.0f, 0.0f, bit[1]},          /* between the lights into B, skipping B */
    };
    const bool expect[6] = {true, false, true, true, true, false};
    for (int m = 0; m < TRACER_BATCH_MODE_COUNT; ++m) {
        tr.batch_mode = (TracerBatchMode)m;
        bool occ[6];
        tracer_occluded_batch(&tr, rays, 6, false, occ);
        for (int i = 0; i < 6; ++i) {
            CHECK(occ[i] == expect[i]);
            if (occ[i] != expect[i]) fprintf(stderr, "mode %d ray %d: occluded %d\n", m, i, occ[i]);
        }
        /* the closest hit of a recorded shadow ray (the occluder's distance) skips the same */
        SurfaceHit hit[4];
        bool found[4];
        tracer_intersect_batch(&tr, rays, 4, false, false, hit, found);
        const float t_expect[4] = {2.5f, -1.0f, 4.5f, 2.5f};
        for (int i = 0; i < 4; ++i) {
            CHECK(found[i] == (t_expect[i] > 0.0f));
            if (found[i] && t_expect[i] > 0.0f) CHECK_NEAR(hit[i].t, t_expect[i], 1e-5);
        }
    }
    tracer_free(&tr);
    scene_desc_free(&scene);
}

/* An area light over spheres, a disk and triangles, one bounce (shadow, bounce and MIS
 * rays, user geometry in every batch). */
static const char *LIT =
    "LookAt 0 2 -5  0 0.3 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ]\n"
    "Sampler \"stratified\"\n"
    "Integrator \"path\" \"integer maxdepth\" [ 2 ]\n"
    "WorldBegin\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 6 6 6 ]\n"
    "  Translate 0 3 0 Rotate 90 1 0 0 Shape \"disk\" \"float radius\" [ 0.8 ] AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1  0 3 2 ]\n"
    "AttributeBegin Translate -0.7 0.6 0 Shape \"sphere\" \"float radius\" [ 0.6 ] AttributeEnd\n"
    "AttributeBegin Material \"conductor\" Translate 0.8 0.5 0.3 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n";

static void test_wave_images(void)
{
    static const TracerBatchMode modes[] = {TRACER_BATCH_SINGLE, TRACER_BATCH_STREAM, TRACER_BATCH_PACKET16};
    TestRender t[3];
    RenderOptions o = {0};
    o.width = 24, o.height = 18, o.threads = 2, o.seed = 5, o.spp = 8;
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
        setenv("WEDGE_TRACE_BATCH", tracer_batch_mode_name(modes[k]), 1);
        ok = test_render(LIT, &o, &t[k]) && ok;
    }
    unsetenv("WEDGE_TRACE_BATCH");
    CHECK(ok);
    if (!ok) return;
    size_t n = (size_t)o.width * (size_t)o.height;
    double sum = 0.0;
    for (size_t i = 0; i < 3 * n; ++i) sum += t[0].frame.color[i];
    CHECK(sum > 0.0 && test_frame_finite(&t[0].frame));
    for (int k = 1; k < 3; ++k) {
        int bad = 0;
        for (size_t i = 0; i < 3 * n; ++i) {
            float a = t[0].frame.color[i], b = t[k].frame.color[i];
            bad += !(fabsf(a - b) <= 1e-5f * (1.0f + fabsf(a)));
        }
        for (size_t i = 0; i < n; ++i) bad += t[0].frame.spp[i] != t[k].frame.spp[i];
        CHECK(bad == 0);
        CHECK(t[k].stats.rays_primary == t[0].stats.rays_primary && t[k].stats.rays_shadow == t[0].stats.rays_shadow &&
              t[k].stats.rays_indirect == t[0].stats.rays_indirect && t[k].stats.rays_bsdf == t[0].stats.rays_bsdf);
    }
    CHECK(t[0].stats.rays_primary == (long long)n * 8);
    for (int k = 0; k < 3; ++k) test_render_free(&t[k]);
}

int main(void)
{
    test_quadric_batches();
    test_occluded_octants(1.0);
    test_occluded_octants(1e-5);
    test_intersect_arrays(QUADRICS, true);
    test_intersect_arrays(TRIANGLES, false);
    test_lone_sphere();
    test_shadow_rays_skip_their_light();
    test_wave_images();
    CHECK_DONE();
}
