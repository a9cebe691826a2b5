/* The sphere test of tracer_quadric_hit for a whole packet (issue 22).
 *
 * Embree calls user geometry with packets of up to 16 rays; on defocus.pbrt nearly full
 * ones (camera and shadow rays of a wave: 14-16 live lanes of 16). tracer_quadric_hit
 * solves each ray on its own, a chain of dependent double divisions and square roots with
 * early exits. For the usual sphere (whole, placed by a translation) this does the same
 * operations, in the same order, for all lanes at once: the exits become masks, so GCC
 * vectorises the loop (WEDGE_VECTORISED), and every lane's results equal
 * tracer_quadric_hit's bit for bit (IEEE + - * / and sqrt round the same in every width; no
 * contraction, docs/design.md 12.4). The discriminant is pbrt-v4's accurate form (section
 * 6.8.1), as there. */
#include "render/sphere_packet.h"

#include <math.h>

#include "core/vectorise.h"

enum { RAYN_ORG_X, RAYN_ORG_Y, RAYN_ORG_Z, RAYN_TNEAR, RAYN_DIR_X, RAYN_DIR_Y, RAYN_DIR_Z, RAYN_TIME, RAYN_TFAR };

WEDGE_VECTORISED void sphere_packet_hits(const float *rays, const int *valid, unsigned n, double w,
                                         const double translation[3], double r, int *restrict hit, double *restrict t)
{
    const float *ox = rays + RAYN_ORG_X * n, *oy = rays + RAYN_ORG_Y * n, *oz = rays + RAYN_ORG_Z * n;
    const float *dx = rays + RAYN_DIR_X * n, *dy = rays + RAYN_DIR_Y * n, *dz = rays + RAYN_DIR_Z * n;
    const float *tn = rays + RAYN_TNEAR * n, *tf = rays + RAYN_TFAR * n;
    double tx = translation[0], ty = translation[1], tz = translation[2];
    for (unsigned i = 0; i < n; ++i) {
        /* quadric_hit_rayn's scaling, then tracer_quadric_hit's translation-only object space */
        double o0 = w * ox[i] + tx, o1 = w * oy[i] + ty, o2 = w * oz[i] + tz;
        double d0 = w * dx[i], d1 = w * dy[i], d2 = w * dz[i];
        double tnear = tn[i], tfar = tf[i];
        double a = d0 * d0 + d1 * d1 + d2 * d2;
        double b = 2.0 * (d0 * o0 + d1 * o1 + d2 * o2);
        double c = o0 * o0 + o1 * o1 + o2 * o2 - r * r;
        double f = b / (2.0 * a);
        double v0 = o0 - f * d0, v1 = o1 - f * d1, v2 = o2 - f * d2;
        double len2 = v0 * v0 + v1 * v1 + v2 * v2;
        double len = sqrt(len2);
        double disc = 4.0 * a * (r + len) * (r - len);
        double root = sqrt(disc);
        double q = b < 0.0 ? -0.5 * (b - root) : -0.5 * (b + root);
        /* both quotients for every lane, then the selections (so no branch is left) */
        double t0 = q / a, c_q = c / q, t1 = q != 0.0 ? c_q : t0;
        double lo = t0 > t1 ? t1 : t0, hi = t0 > t1 ? t0 : t1;
        int in_lo = (lo > tnear) & (lo < tfar), in_hi = (hi > tnear) & (hi < tfar);
        /* tracer_quadric_hit's exits: no direction, a sure miss before the square root, a negative
         * discriminant (a NaN from the masked lanes' arithmetic goes nowhere) */
        int ok = (valid[i] == -1) & (a > 0.0) & !(len2 > r * r * (1.0 + 1e-9)) & !(disc < 0.0);
        hit[i] = ok & (in_lo | in_hi);
        t[i] = in_lo ? lo : hi;
    }
}
