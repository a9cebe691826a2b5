/* --filter auto's fallback to Monte Carlo (see auto_fallback.h). */
#include "recon/auto_fallback.h"

#include <math.h>
#include <string.h>

static int filters_in(FilterGainConfig c)
{
    return ((c & FILTER_GAIN_DIRECT) != 0) + ((c & FILTER_GAIN_INDIRECT) != 0);
}

/* The sinks c's shading filters add beside a camera filter (the frame's first sink being the
 * camera filter's): one per method of theirs the camera filters do not run. */
static int own_sinks_in(FilterGainConfig c, const AutoFallbackFrame *f)
{
    if (!f->camera && f->cameras == 0) return 0;
    bool direct = (c & FILTER_GAIN_DIRECT) != 0 && f->direct_own_sink, indirect = (c & FILTER_GAIN_INDIRECT) != 0 && f->indirect_own_sink;
    return direct && indirect && f->shading_one_method ? 1 : direct + indirect;
}

double auto_fallback_time_us(FilterGainConfig c, const AutoFallbackFrame *f, double sample_us)
{
    double n = (double)f->spp;
    double t = n * sample_us;
    int filters = filters_in(c) + f->others + f->cameras;
    if (filters > 0) t += n * AUTO_SINK_US_PER_SAMPLE * (1 + own_sinks_in(c, f)) + AUTO_FILTER_US_PER_PIXEL * filters;
    return t;
}

double auto_fallback_neighbour_error(int spp, double alpha)
{
    /* Monte Carlo's error falls as N^-alpha, a borrowed sample's as N^-1: their ratio grows as
     * N^(alpha - 1) past the counts the footprints were measured at (within and below them the
     * footprints stand as measured) */
    return spp > AUTO_FOOTPRINT_FIT_SPP ? pow((double)spp / AUTO_FOOTPRINT_FIT_SPP, alpha - 1.0) : 1.0;
}

double auto_fallback_camera_margin(int spp)
{
    /* the margin covers the camera model's spread where it was measured; past those counts its
     * misses all erred towards the filters (their bias is not in it), and the faster
     * prediction wins */
    return spp > AUTO_FOOTPRINT_FIT_SPP ? 1.0 : AUTO_CAMERA_MIN_ADVANTAGE;
}

/* The shading filters' decision for frame f (camera filters among f->others, none judged).
 * beside_candidates: those camera filters are candidates whose footprint the probe measured, and
 * each configuration is judged by the error the camera filters leave with it (E_cam) in its time. */
static void decide_shading(const FilterGainTotals *t, const AutoFallbackFrame *f, bool beside_candidates, AutoFallback *out)
{
    double t_mc = (double)f->spp * out->sample_us;
    /* the asked configuration first: it stays unless another is predicted faster by more than
     * the model's error */
    out->chosen = out->asked;
    double best = -1.0, asked_speed = 0.0;
    for (int k = 0; k < FILTER_GAIN_CONFIGS; ++k) out->share[k] = 0.0, out->speedup[k] = 0.0;
    for (int k = 0; k < FILTER_GAIN_CONFIGS; ++k) {
        FilterGainConfig c = (FilterGainConfig)(out->asked & ~k); /* asked, then its subsets */
        if (out->speedup[c] > 0.0) continue;                   /* seen */
        double share = filter_gain_share(t, c), error_ratio;
        if (beside_candidates) {
            /* what the camera filters leave with c's shading filter, and the share of what they
             * leave without one that it removes */
            double left_by_camera = filter_gain_camera_error_ratio_at(t, FILTER_GAIN_NONE, AUTO_FILTER_FOOTPRINT, out->neighbour_error);
            error_ratio = filter_gain_camera_error_ratio_at(t, c, AUTO_FILTER_FOOTPRINT, out->neighbour_error);
            share = left_by_camera > 0.0 ? 1.0 - error_ratio / left_by_camera : 0.0;
        } else {
            if (f->camera) { /* the lens's variance is the camera filter's: see the header */
                double asked_share = filter_gain_share(t, out->asked);
                share = asked_share > 0.0 ? filter_gain_filterable_share(t) * share / asked_share : 0.0;
            }
            error_ratio = (1.0 - share) + share * out->neighbour_error / AUTO_FILTER_FOOTPRINT;
        }
        out->share[c] = share;
        double time_us = auto_fallback_time_us(c, f, out->sample_us);
        out->speedup[c] = time_us > 0.0 && error_ratio > 0.0 ? pow(error_ratio, -1.0 / out->alpha) * t_mc / time_us : 1.0;
        if (c == out->asked) asked_speed = out->speedup[c];
        if (out->speedup[c] > best) best = out->speedup[c], out->chosen = c;
    }
    double margin = AUTO_FALLBACK_MIN_ADVANTAGE;
    if (beside_candidates && own_sinks_in(out->asked, f) > 0) margin = AUTO_OWN_SINK_MIN_ADVANTAGE;
    if (best < margin * asked_speed) out->chosen = out->asked;
}

void auto_fallback_decide(const FilterGainTotals *t, double rays_per_sample, const AutoFallbackFrame *f, AutoFallback *out)
{
    memset(out, 0, sizeof *out);
    out->asked = (f->direct ? FILTER_GAIN_DIRECT : 0) | (f->indirect ? FILTER_GAIN_INDIRECT : 0);
    out->alpha = filter_gain_alpha(t);
    out->sample_us = AUTO_RAY_US * rays_per_sample;
    out->spp = f->spp;
    out->neighbour_error = auto_fallback_neighbour_error(f->spp, out->alpha);
    /* the camera filters kept: the shading judged beside them, by what they leave (E_cam) when
     * they are candidates, else as before the camera judgement existed (speeds relative, the
     * named camera filter's gain not in them) */
    AutoFallbackFrame kept = *f;
    kept.others += f->cameras, kept.camera = f->camera || f->cameras > 0, kept.cameras = 0;
    decide_shading(t, &kept, f->cameras > 0, out);
    if (f->cameras == 0) return;
    /* the camera filters judged: kept with the shading chosen beside them, against left to
     * Monte Carlo with the shading judged alone (docs/algorithms.md, "the camera effects") */
    double t_mc = (double)f->spp * out->sample_us;
    out->camera_asked = true;
    out->camera_footprint = t->pixels ? t->camera_footprint_sum / t->pixels : 1.0;
    out->camera_error = filter_gain_camera_error_ratio_at(t, out->chosen, AUTO_FILTER_FOOTPRINT, out->neighbour_error);
    double time_kept = auto_fallback_time_us(out->chosen, &kept, out->sample_us);
    out->camera_speedup = time_kept > 0.0 && out->camera_error > 0.0
                              ? pow(out->camera_error, -1.0 / out->alpha) * t_mc / time_kept : 1.0;
    AutoFallbackFrame without = *f;
    without.cameras = 0;
    AutoFallback alone = *out;
    decide_shading(t, &without, false, &alone);
    out->camera_speedup_without = alone.speedup[alone.chosen];
    if (out->camera_speedup_without >= auto_fallback_camera_margin(f->spp) * out->camera_speedup) {
        memcpy(out->share, alone.share, sizeof out->share);
        memcpy(out->speedup, alone.speedup, sizeof out->speedup);
        out->chosen = alone.chosen;
        out->camera_fell_back = true;
    }
}
