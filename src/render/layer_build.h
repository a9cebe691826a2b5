/* Which of Embree's two builds a layer's scene gets (issue 22, thirty-fourth round). */
#ifndef WEDGE_RENDER_LAYER_BUILD_H
#define WEDGE_RENDER_LAYER_BUILD_H

#include <stdbool.h>

#include "render/tracer.h"

/* The box-area share past which a layer's triangle meshes are built two-level: see
 * layer_build_two_level. */
#define LAYER_TWO_LEVEL_SHARE 0.2

/* Whether the layer whose geometries are geoms[0 .. count) should be built two-level (Embree's
 * RTC_BUILD_QUALITY_LOW: one tree per mesh under a tree of the meshes) rather than as one tree
 * over all its triangles (RTC_BUILD_QUALITY_MEDIUM). True when the triangle meshes' bounding
 * boxes, the largest left out, have a surface area summing to at least LAYER_TWO_LEVEL_SHARE
 * times that of the box around them all: large meshes (walls) beside the largest (a floor).
 * Why, and what it costs elsewhere: docs/design.md 12.27. Only the tree changes: the same
 * triangles, the same intersection test and traversal, so the same hits but for the order in
 * which hits at one distance (a ray through a shared edge) are met. */
bool layer_build_two_level(const Geom *geoms, int count);

#endif
