/* The light each stored sample carries into LR when a shading filter (soft shadows, indirect
 * light) ran before it (docs/algorithms.md 8.17).
 *
 * A sample's radiance holds the light its first hit received along one light sample and one
 * bounce: the noise the shading filter averaged out of the pixel mean. LR moves samples
 * across pixels by their lens and time coordinates, so whatever light a sample carries comes
 * along. Each sample therefore carries the filtered light instead of its own, times its own
 * albedo: its deviation from its pixel's mean keeps the texture and geometry the camera
 * dimensions move, and loses the light sample's noise. The filtered light is taken from the
 * pixel that sees the sample's point through the lens centre at mid-shutter (LR's reprojection
 * to u = v = 0, t = 1/2), when that pixel is on the same surface, else from the sample's own
 * pixel. A pixel's samples still average to its value, whatever they carry. */
#ifndef WEDGE_RECON_LR_SHADING_H
#define WEDGE_RECON_LR_SHADING_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/gbuffer.h"
#include "recon/method.h"
#include "recon/sample_store.h"

/* The store's shading fields as LR reads them, per sample: SAMPLE_FIELD_SHADING's albedo rgb,
 * object id and delta lights' direct rgb (base); _SHADING_DIRECT's filterable direct rgb and
 * diffuse albedo rgb (direct: the filterable direct light is the diffuse lobe's, the glossy
 * lobes' passes through, gbuffer.h, so it takes the diffuse albedo); _SHADING_INDIRECT's
 * filterable indirect rgb (indirect). The indirect and delta lights take the albedo. direct
 * and indirect are NULL where the frame does not filter that light, base where it filters
 * neither (all three then). */
enum { LR_SHADING_BASE_FLOATS = 7, LR_SHADING_DIRECT_FLOATS = 6, LR_SHADING_INDIRECT_FLOATS = 3 };
typedef struct {
    const float *base, *direct, *indirect;
} LrShading;

/* The store's shading fields (all NULL without SAMPLE_FIELD_SHADING). */
LrShading lr_shading_of(const SampleStore *st);
/* The same rows from stored sample `first` on (the first of a pixel's: pixel * capacity). */
LrShading lr_shading_from(const LrShading *s, size_t first);

/* Pixel i's filtered light per unit albedo for one shading effect (value4 as
 * ReconShadingLight gives it, times factor[i] when factor is not NULL) into out; false where
 * that effect was not filtered there (value4 NULL, the pixel passed through, non-finite). */
bool lr_filtered_light(const float *value4, const float *factor, size_t i, float out[3]);

/* The pixel whose filtered light a sample takes: the one containing its reprojected centre
 * position (x0_px, y0_px) when that pixel shows the sample's object (gbuffer object id) at a
 * mean depth within 5% of the sample's, else `own`. */
size_t lr_light_pixel(const GBuffer *g, float x0_px, float y0_px, float depth, float object_id, size_t own);

/* Per pixel, the mean direct light of the point, spot and distant lights per unit albedo
 * over its stored samples (base: SAMPLE_FIELD_SHADING, LrShading's base), into
 * delta4 (r, g, b, usable): usable where the pixel is one surface (not mixed) with non-black
 * albedo. A sample picks one light, so a delta light's share of one sample is 0 or its
 * light over the pick's probability: this mean is its light without that noise. */
void lr_delta_light(const GBuffer *g, const SampleStore *st, const float *base, float *delta4);

/* Half-width of the centre-light box, pixels. */
#define LR_CENTRE_RADIUS_PX 2

/* Where no shading filter's light is there to take (the pixel a sample's point is seen from
 * through the lens centre at mid-shutter passed through: motion or defocus mixed it, e.g. every
 * pixel a moving object sweeps over), the light of the sample's own object around that point:
 * every stored sample is put at its lens-centre, mid-shutter position (centre_xy, 2 floats per
 * stored sample, capacity layout), each pixel-sized bin keeps up to LR_CENTRE_SLOTS objects'
 * sums of direct, indirect and delta light and of albedo, and a box of
 * (2 LR_CENTRE_RADIUS_PX + 1)^2 bins of the same object gives the light per unit albedo. In
 * that frame a moving object's points stand still, so the box averages light over the
 * object's surface, as the shading filters do over a static one. docs/algorithms.md 8.19. */
typedef struct {
    int width, height;
    float *id;    /* per bin and slot: the object, NaN when empty */
    float *light; /* per bin and slot: direct, indirect, delta rgb per unit albedo (NaN: none) */
} LrCentreLight;

/* Builds the map (24 floats per pixel); false when out of memory (cl then holds nothing). */
bool lr_centre_light_build(LrCentreLight *cl, const GBuffer *g, const SampleStore *st, const LrShading *shading,
                           const float *centre_xy);

/* The 9 floats of the bin at (x_px, y_px) for that object, or NULL (outside, or no slot). */
const float *lr_centre_light_at(const LrCentreLight *cl, float x_px, float y_px, float object_id);

void lr_centre_light_free(LrCentreLight *cl);

/* The light of n samples of one pixel (radiance: n x 3; shading: their rows (lr_shading_from),
 * or NULL when no shading filter ran; src: the pixel each sample takes its light from, or NULL;
 * delta4: lr_delta_light's, or NULL; centre9: the centre light of these samples (n x 9 floats,
 * lr_centre_light_at's, NaN where none), or NULL, used where src's pixel has no filtered light) into out (n x 3), shifted by one
 * per-pixel constant so that they average to value (rgb). */
void lr_pixel_light(int n, const float *radiance, const LrShading *shading, const size_t *src,
                    const ReconShadingLight *light, const float *delta4, const float *centre9, const float value[3],
                    float *out);

#endif
