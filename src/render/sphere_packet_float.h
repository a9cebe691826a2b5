/* A packet of rays against a whole, translated sphere in single precision, for the lanes a
 * rounding-error bound can decide (issue 22); the rest go to sphere_packet_hits. */
#ifndef WEDGE_RENDER_SPHERE_PACKET_FLOAT_H
#define WEDGE_RENDER_SPHERE_PACKET_FLOAT_H

/* The rays and sphere of sphere_packet_hits (sphere_packet.h). Returns 1 when every live
 * lane was decided: then hit[i] is the exact test's (so sphere_packet_hits') and, where
 * hit, t[i] is within t_err[i] of its t. Returns 0 when some live lane lies within the bound
 * of a decision (the discriminant's sign, near tangency, a root against tnear or tfar) or
 * its arithmetic overflowed: then hit and t are not to be used. */
int sphere_packet_hits_float(const float *rays, const int *valid, unsigned n, double w, const double translation[3],
                             double r, int *hit, double *t, float *t_err);

#endif
