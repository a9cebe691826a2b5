/* The probes' grid of pixels (see probe_grid.h). */
#include "recon/probe_grid.h"

void probe_grid_pixels(WavePixel *pix, int first, int count, int nx, int ny, int w, int h, int spp)
{
    for (int k = 0; k < count; ++k) {
        int i = first + k, gx = i % nx, gy = i / nx;
        int px = (int)(((double)gx + 0.5) * w / nx), py = (int)(((double)gy + 0.5) * h / ny);
        pix[k] = (WavePixel){px, py, 0, spp, 0, spp};
    }
}
