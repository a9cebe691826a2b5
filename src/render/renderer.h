/* The render loop: a scene built for tracing, rendered in passes over tiles on all cores.
 *
 *   Renderer *r; renderer_create(scene, &opts, &r, &err);
 *   Frame f; frame_init(&f, renderer_width(r), renderer_height(r));
 *   render_pass(r, 0, NULL, renderer_spp(r), &f, NULL);      // uniform spp
 *   render_pass(r, 1, per_pixel_spp, 0, &f, &sink);            // an independent second pass
 *   render_pass_more(r, 0, 16, per_pixel_more, &f, &sink);     // or: continue pass 0's 16
 *
 * Each pixel's sampler is seeded from (seed, pixel, pass). A pass runs in rounds, each
 * taking the next slice of every pixel's sample indices ([0,64) [64,128) ..., a remainder
 * of fewer than 64 joined to the round before it: [0,65), [0,64) [64,158); a pass
 * cancelled in its first round then gives the pixels it did not reach samples [0,4)), so
 * an interrupted pass leaves a complete image; the rounds depend only on the sample counts and
 * a pixel's samples of a round are summed by one thread in order (in the frame's fixed
 * slices [0,4) [4,8) [8,16) [16,32) [32,64) [64,128) ...), so images are bit-identical for
 * any thread count. */
#ifndef WEDGE_RENDER_RENDERER_H
#define WEDGE_RENDER_RENDERER_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/diag.h"
#include "core/sampler.h"
#include "render/camera.h"
#include "render/frame.h"
#include "render/integrator.h"
#include "render/render_reads.h"
#include "render/sample_record.h"
#include "scene/scene_desc.h"

typedef struct {
    long long samples_done, samples_total;
    long long rays_done;
    double seconds;
} RenderProgress;

typedef void (*RenderProgressFn)(void *ctx, const RenderProgress *p);

typedef struct {
    int width, height;        /* 0: the film's resolution */
    int spp;                  /* 0: the scene's pixelsamples */
    uint64_t seed;
    int threads;              /* 0: all online cores */
    bool sampler_set;         /* false: map the scene's sampler name */
    SamplerKind sampler;
    const char *pixel_filter;  /* NULL: the scene's PixelFilter statement, else the box */
    bool record_ray_geometry; /* fill SampleRecord shadow/bounce arrays (filters that need them) */
    bool record_motion;       /* fill SampleRecord.motion_px (filters that need it) */
    unsigned reads;           /* what the render's users read (render_reads.h); 0: not declared,
                               * everything is filled */
    volatile sig_atomic_t *cancel; /* when it becomes non-zero, passes stop after the current rows */
    RenderProgressFn progress;     /* called about 10 times a second from the calling thread */
    void *progress_ctx;
} RenderOptions;

typedef struct {
    long long rays_primary, rays_shadow;
    long long rays_indirect;  /* bounce rays that continue a path */
    long long rays_bsdf;      /* a path's last, BSDF-sampled ray: emitters found for MIS of direct light */
    long long rays_bsdf_skipped; /* such rays not traced: they miss the emitters' box (light_bounds.c) */
    long long guarded_events;
    long long samples;
    double seconds_trace;     /* wall time inside render_pass */
    double seconds_build;     /* Embree scene build */
} RenderStats;

typedef struct Renderer Renderer;

/* Builds camera, materials, Embree scene and lights. Scene warnings raised while building
 * are added to scene->warnings. Errors: exit 2 bad input, exit 3 runtime. */
bool renderer_create(SceneDesc *scene, const RenderOptions *opt, Renderer **out, Diag *err);
void renderer_destroy(Renderer *r);

int renderer_width(const Renderer *r);
int renderer_height(const Renderer *r);
int renderer_spp(const Renderer *r);
int renderer_threads(const Renderer *r);
int renderer_max_depth(const Renderer *r);
SamplerKind renderer_sampler(const Renderer *r);
/* The scene's effects (scene_analyze_effects), which the renderer samples (DESIGN.md section 2). */
EffectMask renderer_effects(const Renderer *r);
const Camera *renderer_camera(const Renderer *r);
/* What the integrator traces with (camera, tracer, lights, materials, which dimensions are
 * sampled), for probes that trace a few samples of their own (recon/blur_probe.h). */
const IntegratorScene *renderer_integrator_scene(const Renderer *r);
RenderStats renderer_stats(const Renderer *r);
/* Triangles in the Embree scene and Embree's peak memory (bytes). */
long renderer_triangle_count(const Renderer *r);
long long renderer_embree_peak_bytes(const Renderer *r);

/* What a filter may want to know about a light (index = ShadowRayRecord.light_index).
 * Area lights are one entry per emitting triangle, sphere or disk; `shape` (the SceneDesc
 * shape index) groups the triangles of one emitter. Geometry at shutter open
 * (renderer_light_info) or at a shutter time (renderer_light_info_at). */
typedef enum { RENDER_LIGHT_AREA, RENDER_LIGHT_POINT, RENDER_LIGHT_SPOT, RENDER_LIGHT_DISTANT, RENDER_LIGHT_INFINITE } RenderLightKind;
typedef struct {
    RenderLightKind kind;
    int shape;               /* area lights: SceneDesc shape index; else -1 */
    vec3 center_world;       /* area: centroid (sphere: centre); point/spot: position */
    vec3 normal_world;       /* triangles/disks: emitting-side unit normal; spot: axis; distant: towards the light */
    float area_world;        /* area lights (sphere: full surface) */
    vec3 radiance;           /* L (area, distant, infinite) or intensity I (point, spot), times scale */
    bool two_sided;
    bool moving;             /* area light on an instance that moves during the shutter */
    bool is_triangle;        /* area light on a triangle: its vertices follow */
    vec3 tri_world[3];       /*   in the order whose (p1 - p0) x (p2 - p0) is normal_world */
} RenderLightInfo;
int renderer_light_count(const Renderer *r);
bool renderer_light_info(const Renderer *r, int light, RenderLightInfo *info);
/* The same with a moving area light at shutter fraction shutter_u in [0, 1] (the time a sample
 * with that shutter coordinate traces at); other lights as renderer_light_info. */
bool renderer_light_info_at(const Renderer *r, int light, float shutter_u, RenderLightInfo *info);

/* Turns the recording of shadow/bounce ray geometry in SampleRecords on or off for the
 * following passes (initially RenderOptions.record_ray_geometry). A filter that needs the
 * geometry only in its first pass can turn it off for the second. Not during a pass. */
void renderer_set_record_ray_geometry(Renderer *r, bool on);
/* With the ray geometry on, whether its bounce array is filled too (on after the call
 * above). Off, only the shadow rays are recorded, and the first hit's last BSDF rays that
 * cannot reach an emitter are not traced (a maxdepth-1 frame: the emitter-box test). */
void renderer_set_record_bounce_geometry(Renderer *r, bool on);
/* The same for SampleRecord.motion_px (initially RenderOptions.record_motion). */
void renderer_set_record_motion(Renderer *r, bool on);
/* The users' declaration of what they read of the following passes (render_reads.h; initially
 * RenderOptions.reads, 0: everything). Without RENDER_READS_FIRST_HIT the records' first-hit
 * fields are left unset; without RENDER_READS_FRAME_GUIDES the frame's albedo, normal, depth
 * and hits sums are not added (and the frame says so: Frame.guides_skipped). A frame made for
 * the declaration (render_reads_frame_planes) holds only the sums it reads: a pass adds to the
 * sums its frame holds. Not during a pass. */
void renderer_set_reads(Renderer *r, unsigned reads);
unsigned renderer_reads(const Renderer *r);

/* Overscan: traces a band of margin_px pixels around the image, for filters that read
 * samples beyond a pixel (LR reprojects from up to its window margin; at the image border
 * those sources would be missing). Afterwards the raster is (W + 2M) x (H + 2M)
 * (renderer_width/height) and pixel (x + M, y + M) shoots the rays pixel (x, y) shot before:
 * the screen window grows by M pixels' worth on each side, the camera is rebuilt from a copy
 * of the scene's CameraDesc. Samplers are seeded from the enlarged pixel index, so a pixel's
 * samples change (statistically the same). Call before any pass; margin_px 0 restores the
 * plain raster. False (err) when the camera cannot be rebuilt or margin_px < 0. */
bool renderer_set_overscan(Renderer *r, int margin_px, Diag *err);
/* The band traced around the visible image (0: none). The visible image is
 * renderer_width - 2M by renderer_height - 2M pixels. */
int renderer_overscan_px(const Renderer *r);

/* Renders pass `pass` into frame (sums are added): spp_per_pixel[y * width + x] samples per
 * pixel, or spp_uniform everywhere when spp_per_pixel is NULL. sink (may be NULL) gets
 * every SampleRecord. Returns false when cancelled (the frame holds what was done) or when
 * the frame's size is not the renderer's. */
bool render_pass(Renderer *r, int pass, const int *spp_per_pixel, int spp_uniform, Frame *frame, const SampleSink *sink);

/* Adds spp_more[y * width + x] samples to each pixel after the spp_before that
 * render_pass(r, pass, NULL, spp_before, ...) took, as the same pass: each pixel's samples
 * of both calls together are one sampler set continued (sampler_continue_pixel); with the
 * Sobol' sampler, the first spp_before + spp_more points of each dimension's sequence. An
 * adaptive second pass made this way integrates better than an independent one (pass-1
 * and pass-2 points stratified together). Same return values as render_pass. */
bool render_pass_more(Renderer *r, int pass, int spp_before, const int *spp_more, Frame *frame,
                      const SampleSink *sink);

#endif
