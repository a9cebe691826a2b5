/* MAAF's per-light table for the soft-shadow filter (maaf_shadow.h): each area light's emitter
 * centre (the area-weighted centroid of every triangle of its shape), its axes (along the shape's
 * first triangle's first edge: a quad light's edges) and extent along them, a moving light's
 * swept extent (maaf_light_sweep.h), and its y-design (eq. 6, docs/algorithms.md 9.3). Disks and
 * spheres are boxes of their (silhouette) area. Linear in the lights for a planar mesh light. */
#ifndef WEDGE_RECON_MAAF_LIGHTS_H
#define WEDGE_RECON_MAAF_LIGHTS_H

#include "recon/aaf/aaf_stats.h"
#include "recon/maaf/maaf_shadow.h"
#include "render/renderer.h"

/* lights[0..count) from r's lights and their AAF geometry geoms (aaf_lights_from_renderer), the
 * design's pairs and knob kappa (Omega_y_max = kappa 2 / sigma_light). A light that is not an
 * area light, or has no extent, is left zero (omega_y_max 0: its samples are not filtered). A
 * moving light's poses are read for its means and not kept (sweep NULL, sweep_nodes set): the
 * table owns no memory. False when out of memory (every entry zeroed): a table missing a shape's
 * vertices or a moving light's poses would filter with a narrower light than the scene's. */
bool maaf_lights_from_renderer(const Renderer *r, const AafLightGeom *geoms, int count, int pairs, float kappa,
                               MaafLight *lights);

#endif
