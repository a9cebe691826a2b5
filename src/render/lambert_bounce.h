/* The bounce of a Lambert path vertex, sampled for a whole stage in one vectorised loop over
 * every path's lane (issue 22): the direction of a cosine-weighted sample in the local
 * frame, turned into world space about the lobe's axis, its density and weight, the path's
 * throughput after it (guarded) and the bounce ray's origin pushed off the surface. */
#ifndef WEDGE_RENDER_LAMBERT_BOUNCE_H
#define WEDGE_RENDER_LAMBERT_BOUNCE_H

/* Lane k of each array. In: the receiver (position p, geometric normal ng, offset err, the
 * Lambert lobe's axis n: the shading normal on the side of wo, cos_o = n . wo, albedo), the
 * path's throughput beta, the direction local (warp_cosine_hemisphere of the lane's BSDF
 * dimensions, in the frame (t1, t2, n) that v3_basis(n) completes) and whether the lane is a
 * live Lambert vertex (lambert; other lanes are computed and their outputs mean nothing).
 * Out, per lane:
 *   wi      the world direction t1 x + t2 y + n z (unit to rounding; not normalised)
 *   pdf     bsdf_diffuse_pdf(cos_o, n . wi)
 *   sampled pdf > 0 (a sample was taken: the path may bounce)
 *   beta_next beta * albedo / pi * (n . wi) / pdf, or 0 where that is not finite
 *   guarded sampled and beta_next was not finite (a guarded event)
 *   bounce  sampled and some channel of beta_next > 0 (the bounce ray is traced)
 *   o       the bounce ray's origin: p pushed by err along ng towards wi (surface_offset)
 * Each lane does the operations of v3_basis, bsdf_diffuse_pdf, the weight f |cos| / pdf, the
 * guard and surface_offset in their order, so every copy gives the scalar values bit for bit
 * (tests/render/test_lambert_bounce.c). */
typedef struct {
    const float *p[3], *ng[3], *err, *n[3], *cos_o, *albedo[3], *beta[3], *local[3];
    const int *lambert;
} LambertBounceIn;

typedef struct {
    float *wi[3], *pdf, *beta_next[3], *o[3];
    int *sampled, *guarded, *bounce;
} LambertBounceOut;

void lambert_bounce_lanes(int count, const LambertBounceIn *in, const LambertBounceOut *out);

#endif
