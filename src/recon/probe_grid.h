/* The pixels the probes trace before a frame (the blur probe, the gain probe): the centre pixel
 * of each of nx x ny equal cells of a w x h image, in row order, as a wave's pixel list. */
#ifndef WEDGE_RECON_PROBE_GRID_H
#define WEDGE_RECON_PROBE_GRID_H

#include "render/integrator.h"

/* Fills pix[0 .. count) with grid cells first .. first + count - 1, each with spp samples
 * (sample indices 0 .. spp - 1 of a set of spp). */
void probe_grid_pixels(WavePixel *pix, int first, int count, int nx, int ny, int w, int h, int spp);

#endif
