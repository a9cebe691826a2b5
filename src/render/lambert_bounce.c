/* Lambert bounces in lanes (see lambert_bounce.h). */
#include "render/lambert_bounce.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/vectorise.h"

static inline int32_t float_bits(float x)
{
    int32_t bits;
    memcpy(&bits, &x, sizeof bits);
    return bits;
}

/* One loop over the lanes with every array a restrict parameter (GCC vectorises it then).
 * Everything is computed in every lane and kept by selects: an operation in one arm of a
 * branch that could trap where the scalar code never runs it stops the vectoriser. */
static WEDGE_VECTORISED void bounce_loop(int count, const float *restrict px, const float *restrict py,
                                         const float *restrict pz, const float *restrict gx_, const float *restrict gy_,
                                         const float *restrict gz_, const float *restrict err,
                                         const float *restrict nx_, const float *restrict ny_,
                                         const float *restrict nz_, const float *restrict cos_o_,
                                         const float *restrict ax, const float *restrict ay, const float *restrict az,
                                         const float *restrict bx, const float *restrict by, const float *restrict bz,
                                         const float *restrict lx_, const float *restrict ly_,
                                         const float *restrict lz_, const int *restrict lambert,
                                         float *restrict wx_, float *restrict wy_, float *restrict wz_,
                                         float *restrict pdf_, float *restrict nbx, float *restrict nby,
                                         float *restrict nbz, float *restrict ox, float *restrict oy,
                                         float *restrict oz, int *restrict sampled_, int *restrict guarded_,
                                         int *restrict bounce_)
{
    for (int k = 0; k < count; ++k) {
        float nx = nx_[k], ny = ny_[k], nz = nz_[k];
        /* the tangents of v3_basis (Duff et al. 2017, "Building an orthonormal basis,
         * revisited", listing 3) */
        float sign = copysignf(1.0f, nz);
        float a = -1.0f / (sign + nz);
        float c = nx * ny * a;
        float t1x = 1.0f + sign * nx * nx * a, t1y = sign * c, t1z = -sign * nx;
        float t2x = c, t2y = sign + ny * ny * a, t2z = -ny;
        /* the local direction in world space, unnormalised (unit to rounding) */
        float lx = lx_[k], ly = ly_[k], lz = lz_[k];
        float wx = t1x * lx + t2x * ly + nx * lz;
        float wy = t1y * lx + t2y * ly + ny * lz;
        float wz = t1z * lx + t2z * ly + nz * lz;
        /* bsdf_diffuse_pdf: |cos_i| / pi on wo's side, else 0 */
        float cos_i = nx * wx + ny * wy + nz * wz;
        int same_side = !(cos_o_[k] * cos_i <= 0.0f);
        float pdf_lit = fabsf(cos_i) * 0.318309886f; /* in every lane, then selected */
        float pdf = same_side ? pdf_lit : 0.0f;
        int sampled = lambert[k] & same_side & (pdf_lit > 0.0f); /* pdf > 0 */
        /* f |cos| / pdf = albedo / pi * cos_i / pdf where sampled, times the throughput */
        float q = cos_i / pdf;
        float vx = bx[k] * (ax[k] * 0.318309886f * q), vy = by[k] * (ay[k] * 0.318309886f * q),
              vz = bz[k] * (az[k] * 0.318309886f * q);
        /* guard3: finite3 (x * 0 is 0 for a finite x, NaN otherwise) */
        float z = vx * 0.0f + vy * 0.0f + vz * 0.0f;
        int finite = z == z;
        vx = finite ? vx : 0.0f, vy = finite ? vy : 0.0f, vz = finite ? vz : 0.0f;
        /* !max_component_nonpositive: the guarded throughput is finite, and a finite float
         * is > 0 exactly when its bits, read as a signed integer, are (+0 is all zeros, a
         * negative value or -0 has the sign bit set); integer compares, which GCC does not
         * take for a trap that keeps the loop from vectorising */
        int positive = (float_bits(vx) > 0) | (float_bits(vy) > 0) | (float_bits(vz) > 0);
        /* surface_offset */
        float gx = gx_[k], gy = gy_[k], gz = gz_[k];
        float side = gx * wx + gy * wy + gz * wz >= 0.0f ? err[k] : -err[k];
        ox[k] = px[k] + gx * side, oy[k] = py[k] + gy * side, oz[k] = pz[k] + gz * side;
        wx_[k] = wx, wy_[k] = wy, wz_[k] = wz;
        pdf_[k] = pdf;
        nbx[k] = vx, nby[k] = vy, nbz[k] = vz;
        sampled_[k] = sampled;
        guarded_[k] = sampled & !finite;
        bounce_[k] = sampled & positive;
    }
}

void lambert_bounce_lanes(int count, const LambertBounceIn *in, const LambertBounceOut *out)
{
    bounce_loop(count, in->p[0], in->p[1], in->p[2], in->ng[0], in->ng[1], in->ng[2], in->err, in->n[0], in->n[1],
                in->n[2], in->cos_o, in->albedo[0], in->albedo[1], in->albedo[2], in->beta[0], in->beta[1], in->beta[2],
                in->local[0], in->local[1], in->local[2], in->lambert, out->wi[0], out->wi[1], out->wi[2], out->pdf,
                out->beta_next[0], out->beta_next[1], out->beta_next[2], out->o[0], out->o[1], out->o[2], out->sampled,
                out->guarded, out->bounce);
}
