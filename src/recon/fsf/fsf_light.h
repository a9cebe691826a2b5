/* The light FSF filters over: its two axes, extents, and the unoccluded irradiance it gives.
 *
 * FSF parameterises the area light with orthogonal axes u, v (section 4.1) and shears along
 * the receiver's image of each. We take the brightest planar emitter made of triangles (an
 * emitter shape, e.g. the two triangles of a quad light): its centre, its normal, u along the
 * shortest edge of its first triangle (for a quad split on a diagonal, a side of the quad) and
 * v = n x u; the half extents are the largest projections of its vertices. A sample's light
 * coordinates are (p - centre) . u and (p - centre) . v. */
#ifndef WEDGE_RECON_FSF_LIGHT_H
#define WEDGE_RECON_FSF_LIGHT_H

#include <stdbool.h>

#include "core/diag.h"
#include "core/vec.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/gbuffer.h"
#include "render/renderer.h"

typedef struct {
    vec3 centre_world, normal_world, axis_world[2]; /* axis 0: u, axis 1: v (unit) */
    float half_m[2];                                /* half extents along u, v */
    float ramp_m[2];                                /* a moving light: its samples' density ramps
                                                     * along u, v (FsfGrid.ramp_m); 0: uniform */
    float pose_m[2], motion_m[2];                   /* a moving light: its pose's extent at shutter
                                                     * open and its centroid's motion over the
                                                     * shutter along u, v (FsfGeoTerm's); 0: static */
    int shape;                                      /* the emitter's SceneDesc shape */
    float fill;                                     /* its triangles' area over the rectangle's,
                                                     * 4 half_m[0] half_m[1] (FSF_MIN_LIGHT_FILL);
                                                     * a moving light's over its pose's at shutter
                                                     * open, pose_m[0] pose_m[1] */
} FsfLight;

/* The shadow filter's box profile and its density correction take the light's samples to be
 * uniform over the rectangle of half extents half_m: a light that fills less of it (a triangle,
 * a trapezoid) has them on part of it only, and the filter's mean is biased (a generated scene
 * with a 2.8 m x 0.43 m triangle light: 5x Monte Carlo's relMSE at 16 spp, the same light as a
 * rectangle 0.74x, a trapezoid filling 80% of its bounding box 1.8x). Below this fill the
 * light's shadows are left to Monte Carlo (every pixel's share of filterable light is 0), with
 * a warning. */
#define FSF_MIN_LIGHT_FILL 0.95f

/* The shadows' grid over the light's half extents, its taps to FSF_REACH_SIGMAS_NARROW, and
 * 13 shift nodes (12 y2 bins), not the paper's 17: pass 1a's nodes per sample, passes 1b and
 * 2b's bins go down by a quarter (the kernels 0.87x on soft_shadows at 16 spp) and the error
 * over seeds 1-3 at 8-32 spp moves 0.97x on soft_shadows, 1.00-1.02x on thin_occluders,
 * 1.01-1.06x on tilted_stack, each within its seeds' spread; 9 nodes cost tilted_stack 1.28x
 * at 32 spp (docs/algorithms.md section 10, "Coarser shift grids, shorter taps"). */
#define FSF_LIGHT_SHIFT_NODES 13
FsfGrid fsf_light_grid(const FsfLight *l);

/* A moving light's ramp below this share of its half extent is left out (the box): the motion
 * along that axis is below what the samples can tell. */
#define FSF_RAMP_MIN_REL 1e-3f

/* false with d set when the scene has no planar area light made of triangles. */
bool fsf_light_from_renderer(const Renderer *r, FsfLight *out, Diag *d);

/* FSF's shear is the geometry of its one light (the light coordinates of a sample aimed at
 * another emitter mean nothing on this light's plane): a pixel is filtered only where at
 * least this share of its unoccluded irradiance comes from FSF's light. Below it the pixel
 * keeps its Monte Carlo mean and is nobody's neighbour. */
#define FSF_MIN_LIGHT_SHARE 0.9f

/* Whether pixel i's samples saw a crease of one object (its mean shading normal, the sum of
 * its samples' unit normals over their count, shorter than FSF_CREASE_MEAN_NORMAL): the
 * filter divides the pixel's light by r(x) at its unit mean normal, but the light of a pixel
 * across a crease is the mean of each face's own, which r(x) does not give (a polygon's
 * irradiance is linear in the normal while the whole light is above both faces: the mean
 * normal's length is then the ratio; a face that sees the light below its horizon adds zeros
 * r(x) knows nothing of). Its demodulated value is off its neighbours' lit fraction (9% above
 * it in the one-pixel column where scale_range's block turns from its lit front to its unlit
 * side), and the filter's average of the two is biased. Such a pixel keeps its Monte Carlo
 * mean and is nobody's neighbour, as a mixed one (docs/algorithms.md 10, "FSF's biases on
 * held-out scenes"). */
#define FSF_CREASE_MEAN_NORMAL FSF_NEIGHBOUR_COS_MIN /* the guides' neighbour angle */
bool fsf_pixel_creased(const GBuffer *g, size_t i);

/* The share of the scene's emitted power (luminance times area) that FSF's light (the
 * brightest triangle emitter) has among the area lights; 0 when the scene also has a light of
 * another kind (point, spot, distant, infinite), whose light FSF's shadow filter leaves to
 * Monte Carlo wherever it dominates. Known before any sample: fsf_budget_plan.h uses it. */
float fsf_light_power_share(const Renderer *r);

/* Per pixel, the share of the unoccluded irradiance from every area light (triangles exactly;
 * spheres and disks, which FSF cannot shear along but which light the pixel all the same, as
 * small sources: a sphere's cap above the horizon, a disk as a point of its area) that the
 * emitter shape `shape` (FsfLight.shape) gives; 0 where none reaches the pixel. */
void fsf_light_share(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                     const float *nrm4, float *share);

/* Per pixel (hit pixels of pos4 / nrm4): `irradiance`, a quantity proportional to the
 * unoccluded direct irradiance from every triangle area light (sum of luminance(L) times the
 * projected solid angle, polygon_irradiance.h; 0 where no surface), and `share`, as
 * fsf_light_share, in one pass (each triangle's projected solid angle found once for both,
 * each sum in the emitters' order, a planar mesh emitter's triangles summed through its boundary:
 * emitter_boundary.h); either output may be NULL. */
void fsf_irradiance_and_share(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                              const float *nrm4, float *irradiance, float *share);

/* The inputs of an earlier fsf_irradiance_and_share (copies, n pixels). */
typedef struct {
    unsigned char *hit;
    float *pos4, *nrm4;
} FsfShadeInputs;

/* Copies the inputs (false: out of memory, nothing kept); fsf_shade_inputs_free releases them. */
bool fsf_shade_inputs_keep(FsfShadeInputs *k, int n, const unsigned char *hit, const float *pos4, const float *nrm4);
void fsf_shade_inputs_free(FsfShadeInputs *k);

/* fsf_irradiance_and_share (both outputs) where a pixel's hit flag, mean position or mean
 * normal differ by a bit from `before`'s; elsewhere irradiance and share keep the values the
 * call with `before`'s inputs gave them: a pixel's sums depend on its own inputs only, so the
 * result is the full call's, bit for bit. The plan's guides (after pass 1) and the filter's
 * (after pass 2) differ only where pass 2 added samples. */
void fsf_irradiance_and_share_since(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                                    const float *nrm4, const FsfShadeInputs *before, float *irradiance, float *share);

#endif
