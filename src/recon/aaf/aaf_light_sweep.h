/* A moving area light as the shadow filters' unoccluded irradiance r(x) sees it
 * (docs/algorithms.md 1.9).
 *
 * A pixel's direct light is the average over the shutter of what each sample sees at its own
 * time, so the r(x) AAF-shadow eq. 1 divides out must be the same average: the time mean of
 * the projected solid angle of the light's pose at each time, not of its pose at shutter open.
 * The mean is a Gauss-Legendre quadrature over the shutter coordinate (uniform, as the
 * sampler draws it): each moving emitter becomes AAF_SWEEP_NODES copies, one per node at that
 * node's pose, with its radiance times the node's weight, so r(x)'s sum over emitters is the
 * quadrature and its normaliser (sum of radiance times area) is unchanged. */
#ifndef WEDGE_RECON_AAF_LIGHT_SWEEP_H
#define WEDGE_RECON_AAF_LIGHT_SWEEP_H

#include "recon/aaf/aaf_stats.h"
#include "render/renderer.h"

enum { AAF_SWEEP_NODES = 8 };

/* The shutter coordinate of quadrature node k in [0, AAF_SWEEP_NODES) and its weight (the
 * weights sum to 1). */
double aaf_sweep_node(int k, double *weight);

/* r(x)'s emitters for the lights[0..count) of r (aaf_lights_from_renderer's): each static
 * light as it is, each moving area light as its poses at the nodes. Returns how many and
 * stores the malloc'ed list in *out; 0 and NULL when no area light moves (or out of memory:
 * r(x) then takes the poses at shutter open, as before). */
int aaf_light_sweep(const Renderer *r, const AafLightGeom *lights, int count, AafLightGeom **out);

#endif
