/* How much of LR's value a pixel takes when LR shares the frame with an adaptive method
 * (docs/algorithms.md 8.16).
 *
 * LR reads a fixed count of samples per pixel, the count every pixel has (pass 1's when an
 * adaptive shading filter plans more): lr_spp. A pixel the plan gave pixel_spp > lr_spp
 * samples has its own estimate (the shading filter's value from all of them), while LR's
 * carries the deviations of only lr_spp samples, and the per-pixel shading corrections it
 * moves across pixels belong to the mixture of layers in the pixel they came from, an error
 * that does not fall with samples. The pixel takes LR_SHARE_WORTH * lr_spp / pixel_spp of LR's
 * value (at most all of it) and the rest from its own: all of LR where LR saw every sample (or
 * half of them), and its own estimate as its count grows, so the frame converges to the
 * shading filter's image of the pixel (measured: the motion bench scenes at 32 spp, 24-55%
 * less error than LR's value alone). */
#ifndef WEDGE_RECON_LR_SHARE_H
#define WEDGE_RECON_LR_SHARE_H

/* What LR's value is worth in samples, per sample it read. LR's screen filter averages each
 * pixel's samples with its neighbours', so its value is less noisy than the mean of the
 * lr_spp samples it read (> 1), but it keeps a bias that does not fall with samples (LR's
 * value alone did not converge, docs/algorithms.md 8.16), so not much more. Measured under
 * `--filter auto` at 256 x 256, seeds 1-2 (docs/benchmarks.md, "moving_shadow under --filter
 * auto: the overscan band's pass 2 and LR's share"): 1 (the rule before) -> 2 lowered relMSE
 * 0-11% on the six motion scenes from 16 spp to their default budgets (one point +0.9%:
 * moving_shadow, 64 spp, one seed); 3 was better still on five of them but 8% worse than 2 on
 * moving_shadow at 16 spp; LR alone (a very large worth) 1.1-3x worse there. */
#define LR_SHARE_WORTH 2.0f

/* LR's weight in [0, 1]: 1 when pixel_spp <= LR_SHARE_WORTH * lr_spp (or lr_spp or
 * pixel_spp is not a positive count), else LR_SHARE_WORTH * lr_spp / pixel_spp. */
static inline float lr_share_weight(int lr_spp, float pixel_spp)
{
    float worth = LR_SHARE_WORTH * (float)lr_spp;
    if (!(pixel_spp > worth) || lr_spp <= 0) return 1.0f;
    return worth / pixel_spp;
}

#endif
