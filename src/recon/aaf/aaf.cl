/* Axis-aligned filtering: one 1D pass of the separable, spatially varying Gaussian of
 * AAF-shadow eqs. 10-12 (and AAF-GI eq. 16), run twice: along x, then along y.
 * OpenCL C 1.2, float only, no extensions.
 *
 * Layout: every per-pixel quantity is its own float plane (structure of arrays) of `pitch`
 * floats per row, with `pad` rows/columns of padding around the image; pixel (x, y) is at
 * (y + pad) * pitch + x + pad. Padding holds zeros, i.e. "unusable, radius 0", so no tap
 * ever needs a bounds check as long as radius <= pad. One work-item filters 8 consecutive
 * pixels of a row with float8 arithmetic: its neighbours along x and along y are 8
 * consecutive floats too (vload8), which vectorises on CPUs (PoCL) and is coalesced on GPUs.
 *
 * Planes:
 *   in_r/g/b  the quantity to filter (irradiance with albedo divided out, or radiance)
 *   in_w      1 if the pixel may contribute to its neighbours, 0 if not (no surface, zero
 *             albedo, padding); such a centre pixel keeps its own value
 *   p[xyz], depth   world position of the receiver, its camera depth (world units)
 *   n[xyz], id      unit shading normal, object id (-1: no surface)
 *   inv2b2    1/(2 beta^2) of the centre pixel (world^-2, or px^-2 in pixel mode)
 *   radius    filter radius in pixels (0: leave the pixel as it is), <= pad
 *
 * Distances are measured in a plane (eq. 12): plane_mode 1 uses the centre pixel's entry of
 * the planes l[xyz] (the unit normal of its light, for shadows: a rectangle light's normal, or
 * for a sphere light the receiver -> light direction), plane_mode 0 the centre pixel's own
 * normal (its tangent plane, for indirect light); a zero normal gives plain 3D distance.
 *
 * Neighbours are rejected (AAF-shadow Sec. 6, DESIGN.md section 4) when they belong to
 * another object, their normal is more than acos(cos_normal_min) away, or they lie further
 * than depth_tol_rel * depth from the centre's tangent plane (a depth discontinuity).
 * With sharp_inv_factor > 0 a neighbour is also rejected when its own width is less than
 * 1/sqrt(sharp_inv_factor) of the centre's (its inv2b2 is larger than sharp_inv_factor times
 * the centre's) or it is not filtered at all: its signal holds detail (a sharper shadow) that
 * the centre's wider filter would smear into the centre.
 * Pixel mode (defocus): the distance is the tap offset in pixels; blurring across objects is
 * the effect being reconstructed, so objects are not compared, but with plane_mode 1 the
 * plane lx holds each pixel's mean signed CoC slope and a neighbour is rejected unless its
 * slope has the centre's sign and at least half its magnitude. */

#define AAF_MODE_WORLD 0
#define AAF_MODE_PIXEL 1

__kernel void aaf_filter_pass(int width, int height, int pitch, int pad, int axis, int mode,
                              float cos_normal_min, float depth_tol_rel,
                              float sharp_inv_factor, int plane_mode,
                              __global const float *in_r, __global const float *in_g,
                              __global const float *in_b, __global const float *in_w,
                              __global const float *px, __global const float *py,
                              __global const float *pz, __global const float *depth,
                              __global const float *nx, __global const float *ny,
                              __global const float *nz, __global const float *id,
                              __global const float *inv2b2, __global const float *radius,
                              __global const float *lx, __global const float *ly,
                              __global const float *lz,
                              __global float *out_r, __global float *out_g,
                              __global float *out_b, __global float *out_w)
{
    int x0 = (int)get_global_id(0) * 8;
    int y = (int)get_global_id(1);
    if (x0 >= width || y >= height) return;
    int base = (y + pad) * pitch + x0 + pad;

    float8 c_r = vload8(0, in_r + base), c_g = vload8(0, in_g + base), c_b = vload8(0, in_b + base);
    float8 c_w = vload8(0, in_w + base);
    float8 rad = vload8(0, radius + base);
    float8 inv = vload8(0, inv2b2 + base);
    /* The loop runs to the largest radius of the 8 lanes; lanes with smaller radii mask
     * their extra taps. Lanes past the image's right edge lie in the padding (radius 0). */
    float4 m4 = fmax(rad.lo, rad.hi);
    float2 m2 = fmax(m4.lo, m4.hi);
    int reach = min((int)fmax(m2.x, m2.y), pad);
    int stride = axis == 0 ? 1 : pitch;
    bool world = mode == AAF_MODE_WORLD;

    float8 c_px = 0.0f, c_py = 0.0f, c_pz = 0.0f, c_nx = 0.0f, c_ny = 0.0f, c_nz = 0.0f, c_id = 0.0f;
    float8 c_lx = 0.0f, c_ly = 0.0f, c_lz = 0.0f, tol = 0.0f;
    if (world) {
        c_px = vload8(0, px + base);
        c_py = vload8(0, py + base);
        c_pz = vload8(0, pz + base);
        c_nx = vload8(0, nx + base);
        c_ny = vload8(0, ny + base);
        c_nz = vload8(0, nz + base);
        c_id = vload8(0, id + base);
        c_lx = plane_mode ? vload8(0, lx + base) : c_nx;
        c_ly = plane_mode ? vload8(0, ly + base) : c_ny;
        c_lz = plane_mode ? vload8(0, lz + base) : c_nz;
        tol = depth_tol_rel * vload8(0, depth + base);
    }

    float8 s_r = 0.0f, s_g = 0.0f, s_b = 0.0f, s_w = 0.0f;
    for (int k = -reach; k <= reach; ++k) {
        int o = base + k * stride;
        float fk = (float)k;
        float8 n_w = vload8(0, in_w + o);
        int8 ok = (fabs((float8)fk) <= rad) & (n_w != 0.0f); /* within radius, usable */
        float8 dist2;
        if (world) {
            float8 dx = vload8(0, px + o) - c_px;
            float8 dy = vload8(0, py + o) - c_py;
            float8 dz = vload8(0, pz + o) - c_pz;
            float8 cosn = c_nx * vload8(0, nx + o) + c_ny * vload8(0, ny + o) + c_nz * vload8(0, nz + o);
            float8 off = fabs(c_nx * dx + c_ny * dy + c_nz * dz);
            ok = ok & (vload8(0, id + o) == c_id)   /* same object */
                    & (cosn >= cos_normal_min)      /* no normal discontinuity */
                    & (off <= tol);                 /* no depth discontinuity */
            if (sharp_inv_factor > 0.0f)            /* no sharper neighbour */
                ok = ok & (vload8(0, radius + o) > 0.0f) & (vload8(0, inv2b2 + o) <= sharp_inv_factor * inv);
            float8 along = c_lx * dx + c_ly * dy + c_lz * dz;                  /* eq. 12 */
            dist2 = fmax(dx * dx + dy * dy + dz * dz - along * along, 0.0f);
        } else {
            /* defocus: a neighbour contributes when its CoC slope has the centre's sign and
             * at least half its size; a sharper neighbour (an in-focus object, or the other
             * side of the focal plane) would bleed into the blur */
            if (plane_mode) {
                float8 c_s = vload8(0, lx + base);
                ok = ok & (vload8(0, lx + o) * c_s >= 0.5f * c_s * c_s);
            }
            dist2 = (float8)(fk * fk);
        }
        float8 wt = select((float8)0.0f, exp(-dist2 * inv), ok);                 /* eq. 11 */
        /* a rejected neighbour's value is not read at all: 0 * NaN would be NaN, and a pixel
         * passed through (usable 0) may hold anything */
        s_r += wt * select((float8)0.0f, vload8(0, in_r + o), ok);
        s_g += wt * select((float8)0.0f, vload8(0, in_g + o), ok);
        s_b += wt * select((float8)0.0f, vload8(0, in_b + o), ok);
        s_w += wt;
    }
    /* Normalise (eq. 11's constant cancels). The centre passes its own tests with weight 1,
     * so s_w >= 1 whenever the pixel is filtered, unless its normal is zero. */
    int8 filt = (rad > 0.0f) & (c_w != 0.0f) & (s_w > 0.0f);
    float8 inv_w = 1.0f / select((float8)1.0f, s_w, filt);
    vstore8(select(c_r, s_r * inv_w, filt), 0, out_r + base);
    vstore8(select(c_g, s_g * inv_w, filt), 0, out_g + base);
    vstore8(select(c_b, s_b * inv_w, filt), 0, out_b + base);
    vstore8(select(c_w, (float8)1.0f, filt), 0, out_w + base);
}

/* Layout conversion between the host's interleaved float4 pixels (row-major, no padding)
 * and four padded planes. One work-item per pixel. */
__kernel void aaf_unpack4(int width, int height, int pitch, int pad, __global const float4 *src,
                          __global float *p0, __global float *p1, __global float *p2, __global float *p3)
{
    int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    float4 v = src[y * width + x];
    int o = (y + pad) * pitch + x + pad;
    p0[o] = v.x;
    p1[o] = v.y;
    p2[o] = v.z;
    p3[o] = v.w;
}

/* Filter parameters (1/(2 beta^2), radius): the radius is clamped to [0, pad], the padding
 * every tap relies on. */
__kernel void aaf_unpack_params(int width, int height, int pitch, int pad, __global const float2 *src,
                                __global float *inv2b2, __global float *radius)
{
    int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    float2 v = src[y * width + x];
    int o = (y + pad) * pitch + x + pad;
    inv2b2[o] = v.x;
    radius[o] = clamp(v.y, 0.0f, (float)pad);
}

__kernel void aaf_pack4(int width, int height, int pitch, int pad,
                        __global const float *p0, __global const float *p1,
                        __global const float *p2, __global const float *p3, __global float4 *dst)
{
    int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    int o = (y + pad) * pitch + x + pad;
    dst[y * width + x] = (float4)(p0[o], p1[o], p2[o], p3[o]);
}
