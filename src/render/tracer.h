/* The Embree scene: every shape of a SceneDesc as Embree geometry, plus what shading needs
 * to interpret a hit (which shape, its material and emitter, normals, uv).
 *
 * Layout: layer 0 is the top-level scene. Static shapes live there in world space
 * (triangles pre-transformed; spheres/disks as exact user geometry with their object
 * transform). A shape whose transform moves during the shutter becomes a one-shape layer
 * instanced with Embree motion (quaternion decomposition per time step), so it moves
 * rigidly as pbrt-v4's AnimatedTransform. Each ObjectBegin/End becomes a layer instanced by
 * every ObjectInstance. Scenes without motion build no motion data.
 *
 * Units: callers give and get world units. Embree itself sees each layer scaled by a power
 * of two that brings it near unit size (tracer_from_world, Layer.tracer_from_geom; 1 for
 * ordinary scenes), which keeps its float triangle test accurate at any scene scale. */
#ifndef WEDGE_RENDER_TRACER_H
#define WEDGE_RENDER_TRACER_H

#include <embree3/rtcore.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/animated_xform.h"
#include "core/diag.h"
#include "core/vec.h"
#include "scene/scene_desc.h"

/* The largest coordinate magnitude the ray tracer takes: Embree rejects rays whose origin
 * exceeds about 1.84e18 in any coordinate (an assertion, not an error), so geometry and the
 * camera must stay inside this, with room for the hit points' offsets. */
#define TRACER_COORD_MAX 1.0e18f
/* The smallest scene extent (world units) the scale tests cover: smaller scenes get a warning. */
#define TRACER_EXTENT_TESTED_MIN 1.0e-12f

typedef enum { GEOM_TRIANGLES, GEOM_SPHERE, GEOM_DISK, GEOM_INSTANCE } GeomKind;

/* What shading a hit on a triangle needs that does not depend on where the triangle was
 * hit, found once per triangle (shade_triangle). */
typedef struct {
    vec3 n;    /* unit geometric normal, (p1 - p0) x (p2 - p0) normalised */
    float mag; /* largest |coordinate| of its vertices (the hit point's error bound) */
} TriangleShading;

/* One Embree geometry. "Geometry space" is world space for layer 0 and instance space for
 * the other layers. */
typedef struct {
    GeomKind kind;
    int shape;               /* index into SceneDesc.shapes (-1 for instances) */
    int material;            /* SceneDesc material index, -1 = default */
    int area_light;          /* SceneDesc area light index, -1 = none (always -1 inside ObjectBegin) */
    unsigned mask_bit;       /* a static sphere or disk emitter: its own Embree geometry mask bit,
                              * which shadow rays aimed at it skip (commit_layer); 0: none */
    int light_first;         /* first Light of this geometry (+ primID for triangles), -1 = none;
                              * set by lights_build */
    bool flip_normal;        /* pbrt-v4: reverse_orientation XOR transform swaps handedness */
    bool uv_unread;          /* nothing reads a hit's uv (its material has no texture): spheres
                              * and disks leave SurfaceHit.uv 0 instead of computing it (an
                              * atan2 and an acos); set by the renderer, false after tracer_build */
    /* triangles, positions in geometry space */
    int vertex_count, triangle_count;
    const float *p;          /* world-unit positions, 3 floats per vertex (what shading and lights read) */
    const float *p_tracer;   /* Embree's vertex buffer: p times tracer_from_geom (= p when that is 1) */
    const uint32_t *index;   /* Embree index buffer, 3 per triangle */
    vec3 *n;                 /* shading normals in geometry space (NULL = none) */
    vec2 *uv;                /* per-vertex uv (NULL = pbrt default (0,0) (1,0) (1,1)) */
    TriangleShading *tri_shading; /* per triangle */
    double geom_from_tracer; /* 1 / its Layer's tracer_from_geom, for the sphere/disk callbacks */
    /* spheres and disks: object-space quadric, placed by geom_from_object */
    double radius, zmin, zmax, phimax_rad, height, inner_radius;
    Mat4 geom_from_object, object_from_geom;
    bool object_translation_only; /* object_from_geom's 3x3 part is the identity (tracer_quadric_hit) */
    /* spheres: the polar angles of zmin and zmax (acos(z / radius)), which shading's v
     * coordinate is measured between: per shape, so not recomputed at every hit */
    double theta_zmin_rad, theta_zmax_rad;
    /* spheres and disks: radius times the largest stretch of geom_from_object, the shape's
     * share of a hit point's error bound (per shape: found once, not at every hit) */
    double quadric_reach;
    /* instances */
    int instance;            /* index into Tracer.instances (GEOM_INSTANCE), else -1 */
    int owner_instance;      /* for a moving shape's own layer: the instance that moves it */
} Geom;

typedef struct {
    RTCScene scene;
    float tracer_from_geom;  /* Embree sees this layer's geometry space times this power of two
                              * (layer 0: Tracer.tracer_from_world) */
    Geom *geoms;
    int geom_count, geom_cap;
} Layer;

typedef struct {
    int layer;               /* the instanced layer */
    bool moving;
    AnimXform motion;        /* world-from-instance over the shutter (when moving) */
    RTCGeometry geometry;    /* for rtcGetGeometryTransform at a ray's time */
    Mat4 world_from_inst;    /* static instances (and shutter-open pose of moving ones) */
    Mat4 inst_from_world;
    /* moving: tracer_world_from_instance's poses at time01 = 0 and 1 (the shutter's ends in
     * most scenes), kept once the build is done (pose_kept): LR's motion vectors ask for
     * both at every hit, and Embree's interpolation of a quaternion decomposition is not free */
    Mat4 pose_at_end[2];
    bool pose_kept;
} Instance;

/* How batches of rays go to Embree (tracer_*_batch): one rtcIntersect1 / rtcOccluded1 per
 * ray, Embree's stream interface (rtcIntersect1M / rtcOccluded1M), or packets of 16
 * (rtcIntersect16 / rtcOccluded16). The modes find the same surfaces, but not always the same
 * hit bit for bit: in stream mode a ray's answer can depend on the rays traced beside it (one
 * pixel of 4096 differed at relMSE 2.7e-11 when rounds changed which pixels share a wave,
 * docs/benchmarks.md, "Cost per sample against resolution: ..."), so a change of a wave's make-up
 * is not bit for bit by construction. docs/benchmarks.md compares the modes' speed. */
typedef enum { TRACER_BATCH_SINGLE, TRACER_BATCH_STREAM, TRACER_BATCH_PACKET16, TRACER_BATCH_MODE_COUNT } TracerBatchMode;
#define TRACER_BATCH_DEFAULT TRACER_BATCH_STREAM

enum { TRACER_TWO_LEVEL_AUTO, TRACER_TWO_LEVEL_NEVER, TRACER_TWO_LEVEL_ALWAYS, TRACER_TWO_LEVEL_CHOICES };

typedef struct {
    RTCDevice device;
    TracerBatchMode batch_mode; /* TRACER_BATCH_DEFAULT, or WEDGE_TRACE_BATCH=single|stream|packet16 */
    bool robust;             /* RTC_SCENE_FLAG_ROBUST on every layer (WEDGE_EMBREE_ROBUST=0: off) */
    Layer *layers;
    int layer_count;
    Instance *instances;
    int instance_count;
    bool has_motion;         /* some geometry moves: rays carry time */
    bool top_spheres;        /* the top level holds a sphere (whose hits a batch may shade together) */
    bool shadow_coherent_ok; /* no ObjectBegin prototype: occlusion streams may be coherent (design.md 12.31) */
    float bounds_min[3], bounds_max[3]; /* world bounds (shutter open and close) */
    /* Scale normalisation: Embree sees the world multiplied by tracer_from_world, a power of
     * two chosen from the bounds (1 for scenes of ordinary size), so that its float
     * triangle test neither underflows nor overflows (each instanced layer has its own
     * factor, Layer.tracer_from_geom); every tracer_* function takes and returns world
     * units. world_from_tracer is its exact inverse. */
    float tracer_from_world, world_from_tracer;
    double seconds_build;
    long triangle_count;
    long long embree_bytes, embree_bytes_peak; /* from Embree's memory monitor */
    /* each layer's build (commit_layer): TRACER_TWO_LEVEL_AUTO (layer_build_two_level), or
     * WEDGE_EMBREE_TWO_LEVEL=0|1 for measurements and tests (never / always two-level); last,
     * so that the fields the rays read keep their places */
    int two_level;
} Tracer;

/* Where a ray hit, in world space, ready for shading. */
typedef struct {
    float t;                 /* ray parameter (world units when the direction is unit) */
    vec3 p;                  /* world position */
    vec3 ng;                 /* unit geometric normal, pbrt-v4 orientation */
    vec3 ns;                 /* unit shading normal, on ng's side */
    vec2 uv;
    float err;               /* offset along ng that keeps new rays off this surface */
    const Geom *geom;
    int prim;
    int instance;            /* -1 when not instanced */
    int object_id;           /* top-level geometry id: one per static shape / instance */
    int light;               /* Light index when the surface emits, else -1 */
} SurfaceHit;

/* Builds the Embree scene. Errors: exit 2 for bad shapes (mesh loading), exit 3 for Embree
 * failures. Area lights inside object instances are not supported (pbrt-v4 neither): a
 * warning is added to the scene and they do not emit. */
bool tracer_build(Tracer *tr, SceneDesc *scene, int threads, Diag *err);
void tracer_free(Tracer *tr);

/* Closest hit along o + t d, t in (0, tmax). Returns false on a miss. */
bool tracer_intersect(const Tracer *tr, vec3 o, vec3 d, float tmax, float time01, SurfaceHit *hit);
/* As tracer_intersect; with shade_all false, a hit on a surface that does not emit fills
 * only t, geom, prim, instance, object_id and light (= -1): for rays whose hit point is
 * not shaded (the last ray of a path, occluder distances). */
bool tracer_intersect_ex(const Tracer *tr, vec3 o, vec3 d, float tmax, float time01, bool shade_all, SurfaceHit *hit);
/* Any hit along o + t d, t in (0, tmax). */
bool tracer_occluded(const Tracer *tr, vec3 o, vec3 d, float tmax, float time01);

/* One ray of a batch: o + t d for t in (0, tmax), at pose fraction time01. */
typedef struct {
    vec3 o, d;
    float tmax, time01;
    unsigned skip_mask;      /* geometry mask bits the ray ignores (Geom.mask_bit); 0: none */
} TracerRay;

/* tracer_intersect_ex / tracer_occluded for n rays at once, through tr->batch_mode.
 * coherent: the rays start close together and point the same way (camera rays of a few
 * pixels, shadow rays to one light), a hint to Embree. In the stream mode, incoherent rays
 * (bounce rays, a sky's shadow rays) go to Embree as packets of 16 (docs/design.md 12.34). */
void tracer_intersect_batch(const Tracer *tr, const TracerRay *rays, int n, bool shade_all, bool coherent,
                            SurfaceHit *hits, bool *found);
void tracer_occluded_batch(const Tracer *tr, const TracerRay *rays, int n, bool coherent, bool *occluded);

/* Rays as arrays, lane i: origin o[.][i], unit direction d[.][i], length tmax[i] (tmax NULL:
 * INFINITY in every lane), time01[i], every lane the same skip_mask; for occlusion, lanes with
 * active[i] == 0 are not traced. */
typedef struct {
    const float *o[3], *d[3], *tmax, *time01;
    const int *active;
    unsigned skip_mask;
} TracerRayArrays;

/* tracer_intersect_batch for the n lanes of a (all traced: active is not read), in the
 * lanes' order. */
void tracer_intersect_arrays(const Tracer *tr, const TracerRayArrays *a, int n, bool shade_all, bool coherent,
                             SurfaceHit *hits, bool *found);

/* tracer_occluded_batch for the active lanes of a (n lanes), in the lanes' order: the answer
 * of active lane i in occluded[i] (inactive lanes' entries are left as they are). In the
 * stream mode, coherent lanes whose rays use few direction octants go to Embree as these
 * arrays themselves, read in place, where they are 16-byte aligned; incoherent lanes, and
 * lanes of which fewer than half are active whatever the flag, as packets of 16 of the
 * active lanes. */
void tracer_occluded_arrays(const Tracer *tr, const TracerRayArrays *a, int n, bool coherent, bool *occluded);
const char *tracer_batch_mode_name(TracerBatchMode mode);

/* The nearest hit in (tnear, tfar) of the ray o + t d (geometry space, double) on sphere or
 * disk g, solved in its object space (pbrt-v4's Sphere and Disk): the callbacks' test, and
 * the oracle of sphere_packet_hits (test_sphere_packet). */
bool tracer_quadric_hit(const Geom *g, const double o_geom[3], const double d_geom[3], double tnear, double tfar,
                        double *t_out);

/* World-from-geometry transform of a layer geometry at a time (identity for layer 0). */
Mat4 tracer_world_from_instance(const Tracer *tr, int instance, float time01);

/* A ray origin on the surface, pushed off it to the side of direction w. (Inline: two or
 * three per camera sample, each on the way to a traversal.) */
static inline vec3 surface_offset(const SurfaceHit *h, vec3 w)
{
    float s = v3_dot(h->ng, w) >= 0.0f ? h->err : -h->err;
    return v3_madd(h->p, h->ng, s);
}

#endif
