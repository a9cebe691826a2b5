/* The camera filters' footprint (see camera_gain.h). */
#include "recon/camera_gain.h"

#include <math.h>

double camera_blur_area_px(double coc_diameter_px, double motion_px)
{
    double c = isfinite(coc_diameter_px) && coc_diameter_px > 0.0 ? coc_diameter_px : 0.0;
    double m = isfinite(motion_px) && motion_px > 0.0 ? motion_px : 0.0;
    /* pixel + disk + disk around the pixel's perimeter + pixel along the segment + disk along it */
    return 1.0 + M_PI * c * c / 4.0 + 2.0 * c + m + m * c;
}

double camera_footprint(double area_px, double efficiency, double cap)
{
    double f = 1.0 + efficiency * (area_px - 1.0);
    return f < 1.0 ? 1.0 : f > cap ? cap : f;
}

double camera_pixel_footprint(const float *footprints, int n)
{
    double inverse_sum = 0.0;
    for (int k = 0; k < n; ++k) inverse_sum += 1.0 / footprints[k];
    return n > 0 && inverse_sum > 0.0 ? n / inverse_sum : 1.0;
}

double camera_sample_area_px(const ReconCamera *cam, const SampleRecord *rec, CameraBlurKinds kinds)
{
    if (!rec->hit) return 1.0;
    double c = kinds.defocus ? 2.0 * fabs((double)recon_coc_slope_px(cam, rec->depth_cam)) : 0.0;
    double m = kinds.motion ? hypot((double)rec->motion_px[0], (double)rec->motion_px[1]) : 0.0;
    return camera_blur_area_px(c, m);
}

double camera_lens_sharpest_diameter_px(const float *coc_slope_px, int n)
{
    double least = INFINITY;
    bool positive = false, negative = false;
    for (int k = 0; k < n; ++k) {
        double s = (double)coc_slope_px[k];
        if (!isfinite(s)) continue; /* a miss */
        positive |= s > 0.0, negative |= s < 0.0;
        least = fmin(least, fabs(s));
    }
    return !isfinite(least) || (positive && negative) ? 0.0 : 2.0 * least;
}

double camera_pixel_footprint_sharpest_lens(const float *coc_slope_px, const float *motion_px, int n, double efficiency,
                                            double cap)
{
    double coc_px = camera_lens_sharpest_diameter_px(coc_slope_px, n);
    double inverse_sum = 0.0;
    for (int k = 0; k < n; ++k) {
        /* each sample's footprint rounded to float as the probe stores per-sample ones */
        float footprint = (float)camera_footprint(camera_blur_area_px(coc_px, motion_px[k]), efficiency, cap);
        inverse_sum += 1.0 / footprint;
    }
    return n > 0 && inverse_sum > 0.0 ? n / inverse_sum : 1.0;
}
