/* Image-based environment light (pbrt-v4 "infinite" light with "filename"), importance
 * sampled by a piecewise-constant 2D distribution over the image.
 *
 * Two image layouts, chosen by the aspect ratio:
 * - square images: pbrt-v4's parameterisation, the equal-area octahedral map of Clarberg
 *   2008 ("Fast equal-area mapping of the (hemi)sphere using SIMD", JGT 13(3)); pbrt-v4's
 *   ImageInfiniteLight accepts nothing else. Every pixel covers the same solid angle
 *   (4 pi / pixel count), so the solid-angle pdf is the image-space pdf over 4 pi.
 * - 2:1 images: a wedge extension for the common latitude-longitude (equirectangular)
 *   maps, in pbrt-v3's convention: u = phi / (2 pi) with phi = atan2(y, x) in [0, 2 pi),
 *   v = theta / pi with theta measured from +z (row 0 is the +z pole). A pixel's solid
 *   angle shrinks as sin(theta), so the sampling weights carry sin(theta) and the pdf
 *   converts with 1 / (2 pi^2 sin(theta)).
 * Any other aspect ratio is an error.
 *
 * Directions: w points from the scene towards the environment (the direction of an
 * escaping ray), in world space; world_from_light rotates the map like pbrt-v4's light
 * transform (the CTM at the light's definition). Radiance is looked up per pixel (nearest
 * texel, as pbrt-v4's ImageLe), which makes the sampling density exactly proportional to
 * the pixel's mean rgb for the equal-area layout. pbrt-v4's "compensated" MIS
 * distribution (average subtracted) is not used: the plain one is unbiased with any
 * strategy combination. */
#ifndef WEDGE_RENDER_ENVMAP_H
#define WEDGE_RENDER_ENVMAP_H

#include <stdbool.h>

#include "core/diag.h"
#include "core/transform.h"
#include "core/vec.h"

typedef enum { ENVMAP_EQUAL_AREA, ENVMAP_LATLONG } EnvmapLayout;

typedef struct {
    EnvmapLayout layout;
    int width, height;
    float *rgb;             /* linear radiance times scale, row 0 first, owned */
    float *row_cdf;         /* height + 1: marginal CDF over rows */
    float *col_cdf;         /* height * (width + 1): conditional CDFs within each row */
    float *pixel_weight;    /* width * height: sampling weight of each pixel */
    double weight_total;    /* sum of pixel weights (the domain is [0,1]^2) */
    Mat4 world_from_light, light_from_world;
} Envmap;

/* From interleaved linear rgb (3 floats a pixel, row 0 first); radiance = rgb * scale.
 * Non-finite and negative values become 0. err: exit 2 (bad aspect ratio / size) or 3. */
bool envmap_init(Envmap *e, int width, int height, const float *rgb, float scale, Diag *err);
/* Reads an EXR (linear) or PNG (sRGB-decoded) through image_read_linear_rgb. */
bool envmap_load(Envmap *e, const char *path, float scale, Diag *err);
void envmap_free(Envmap *e);
/* Sets the light's placement (a rotation; any scale is normalised away). */
void envmap_set_transform(Envmap *e, const Mat4 *world_from_light);

/* Radiance arriving from world direction w (unit). */
vec3 envmap_Le(const Envmap *e, vec3 w_world);
/* Draws a direction with density envmap_pdf. False when the map has no sampleable pixel. */
bool envmap_sample(const Envmap *e, vec2 u, vec3 *w_world, vec3 *Le, float *pdf);
/* Solid-angle density of envmap_sample producing w. */
float envmap_pdf(const Envmap *e, vec3 w_world);
/* Mean radiance over the sphere (for the light-selection power 4 pi^2 r^2 mean). */
vec3 envmap_mean_radiance(const Envmap *e);

/* The parameterisations, in light space. uv in [0,1]^2; directions unit. */
vec3 envmap_equal_area_to_dir(vec2 uv);
vec2 envmap_dir_to_equal_area(vec3 w);
vec3 envmap_latlong_to_dir(vec2 uv);
vec2 envmap_dir_to_latlong(vec3 w);

#endif
