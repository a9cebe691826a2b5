/* How much of LR's value a pixel takes when LR shares the frame with an adaptive method
 * (docs/algorithms.md 8.16).
 *
 * LR reads a fixed count of samples per pixel, the count every pixel has (pass 1's when an
 * adaptive shading filter plans more): lr_spp. A pixel the plan gave pixel_spp > lr_spp
 * samples has its own estimate (the shading filter's value from all of them), while LR's
 * carries the deviations of only lr_spp samples, and the per-pixel shading corrections it
 * moves across pixels belong to the mixture of layers in the pixel they came from, an error
 * that does not fall with samples. The pixel takes lr_spp / pixel_spp of LR's value and the
 * rest from its own: all of LR where LR saw every sample, and its own estimate as its count
 * grows, so the frame converges to the shading filter's image of the pixel (measured: the
 * motion bench scenes at 32 spp, 24-55% less error than LR's value alone). */
#ifndef WEDGE_RECON_LR_SHARE_H
#define WEDGE_RECON_LR_SHARE_H

/* LR's weight in [0, 1]: 1 when pixel_spp <= lr_spp (or not a positive count), else
 * lr_spp / pixel_spp. */
static inline float lr_share_weight(int lr_spp, float pixel_spp)
{
    if (!(pixel_spp > (float)lr_spp) || lr_spp <= 0) return 1.0f;
    return (float)lr_spp / pixel_spp;
}

#endif
