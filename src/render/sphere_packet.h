/* A packet of rays against a whole sphere that is only translated (issue 22): the common
 * case of the sphere callback, in a loop over the packet that GCC vectorises. */
#ifndef WEDGE_RENDER_SPHERE_PACKET_H
#define WEDGE_RENDER_SPHERE_PACKET_H

/* Rays i < n of an Embree RTCRayN packet (structure of arrays: field k of ray i is
 * rays[k n + i]), with valid[i] == -1 for live rays, against the full sphere of radius r
 * whose object space is geometry space moved by translation[3]; w is the geometry's
 * geom_from_tracer. hit[i] (0 or 1) and t[i] (when hit) are what tracer_quadric_hit finds
 * for each live ray, bit for bit. */
void sphere_packet_hits(const float *rays, const int *valid, unsigned n, double w, const double translation[3], double r,
                        int *hit, double *t);

#endif
