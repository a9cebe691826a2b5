/* A packet of rays against a whole, translated sphere in single precision, for the lanes a
 * rounding-error bound can decide (issue 22); the rest go to sphere_packet_hits. */
#ifndef WEDGE_RENDER_SPHERE_PACKET_FLOAT_H
#define WEDGE_RENDER_SPHERE_PACKET_FLOAT_H

enum { SPHERE_PACKET_FLOAT_MAX = 16 }; /* lanes: Embree 3's largest packet */

/* The rays and sphere of sphere_packet_hits (sphere_packet.h), n <= SPHERE_PACKET_FLOAT_MAX.
 * decided[i] = 1 for a dead lane and for a live lane the rounding bound settles: then hit[i]
 * is the exact test's (so sphere_packet_hits') and, where hit, t[i] is within t_err[i] of its
 * t. decided[i] = 0 where a live lane lies within the bound of a decision (the discriminant's
 * sign, near tangency, a root against tnear or tfar) or its arithmetic overflowed: its hit
 * and t are not to be used. Returns 1 when every lane was decided. */
int sphere_packet_hits_float(const float *rays, const int *valid, unsigned n, double w, const double translation[3],
                             double r, int *hit, double *t, float *t_err, int *decided);

/* The float test, with sphere_packet_hits' results for the lanes it leaves undecided: each
 * lane's hit and t depend on its own ray alone. */
void sphere_packet_hits_fast(const float *rays, const int *valid, unsigned n, double w, const double translation[3],
                             double r, int *hit, double *t);

#endif
