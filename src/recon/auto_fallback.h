/* --filter auto's fallback to Monte Carlo: from the gain probe's measurements (gain_probe.h),
 * whether the frame's shading filters are predicted to reach a lower error than plain Monte
 * Carlo in the same time, per configuration of the effects auto chose to filter
 * (docs/algorithms.md, "auto's fallback to Monte Carlo", for the model and its derivation).
 *
 *   time per pixel   T(c) = N t_s + [a filter runs] N t_sink + t_px k(c)
 *   error ratio      E(c) = (1 - s(c)) + s(c) g(N) / F   (filter_gain_error_ratio_at)
 *   growth with N    g(N) = max(1, N / N_fit)^(alpha - 1)  (auto_fallback_neighbour_error)
 *   equal-error speed against Monte Carlo at N samples:
 *                    S(c) = E(c)^(-1/alpha) * N t_s / T(c)
 *
 * with N the frame's samples per pixel, t_s Monte Carlo's CPU time per sample (the probe's
 * rays per sample times AUTO_RAY_US),
 * k(c) the filters that run, s(c) the probe's share of the error an ideal filter of c
 * removes, alpha Monte Carlo's convergence exponent (filter_gain_alpha) and F the filters'
 * footprint, measured at N_fit samples (AUTO_FOOTPRINT_FIT_SPP). g: a filter replaces a
 * pixel's stratified samples by its neighbours' (F samples' worth, one its own), whose error
 * relative to the pixel falls as 1/N where Monte Carlo's falls as N^-alpha; so the error it
 * leaves, relative to Monte Carlo's, grows as N^(alpha - 1) past the counts F was measured at
 * (docs/algorithms.md, "the error ratio's growth with N"). The configuration of the highest
 * S is kept when it beats the one auto chose by AUTO_FALLBACK_MIN_ADVANTAGE; otherwise auto's
 * choice stands (at every count: this model errs towards Monte Carlo, the adaptive plans
 * not in it).
 *
 * Beside a camera filter named explicitly, the per-sample variance the probe sees is mostly the
 * lens's or the shutter's, which that filter removes in every configuration; the shading
 * filters' share is then taken as the variance in the pixels they may touch
 * (filter_gain_filterable_share), split between the configurations as their ideal shares are:
 * s(c) = q s_ideal(c) / s_ideal(asked).
 *
 * Beside camera candidates (whose footprint the probe measured), each shading configuration is
 * judged by the error the camera filters leave with it, S(c) = E_cam(c)^(-1/alpha) N t_s / T(c),
 * and T(c) charges a shading filter whose method no camera filter runs its own sink (N t_sink:
 * AAF beside LR records its own samples; one sink per method), a filter sharing their method its
 * pass alone; a configuration with its own sink gives way to a subset AUTO_OWN_SINK_MIN_ADVANTAGE
 * faster, one without to a subset AUTO_FALLBACK_MIN_ADVANTAGE faster (docs/algorithms.md, "a
 * shading filter beside a kept camera filter").
 *
 * The camera filters auto chose (defocus, motion) are judged as one candidate: kept, with the
 * shading configuration c_k chosen beside them as above (so S_keep = S(c_k)),
 *   S_keep = E_cam(c_k)^(-1/alpha) * N t_s / T(c_k)     (filter_gain_camera_error_ratio_at: each
 *            pixel's variance over its camera footprint, camera_gain.h)
 * against S_drop, the best S of the shading judged as in a frame without a camera filter; they
 * are left to Monte Carlo when S_drop >= AUTO_CAMERA_MIN_ADVANTAGE S_keep, past N_fit when
 * S_drop >= S_keep (auto_fallback_camera_margin: the margin is the camera model's spread at
 * 8-16 spp; past them its misses all erred towards the filters, whose bias is not in it). */
#ifndef WEDGE_RECON_AUTO_FALLBACK_H
#define WEDGE_RECON_AUTO_FALLBACK_H

#include <stdbool.h>

#include "recon/filter_gain.h"

/* The model's constants, measured on a subset of the bench scenes (soft_shadows, indirect,
 * thin_occluders; 256x256 and 64x64, 8 and 16 spp, --threads 1, CPU time of --filter auto
 * against --filter none; docs/benchmarks.md, "auto's fallback to Monte Carlo"): */
/* CPU microseconds per ray of plain Monte Carlo (its frame's time over its rays, shading
 * included): 0.044 (soft_shadows), 0.059 (thin_occluders), 0.084 (indirect) */
#define AUTO_RAY_US 0.06
/* CPU microseconds a filtered frame spends per sample beyond plain Monte Carlo's (the
 * pipeline's sink, the guides, the methods' statistics, recorded ray geometry): 0.07-0.15 */
#define AUTO_SINK_US_PER_SAMPLE 0.10
/* ... per pixel and filtered effect (plans, filter passes, composite): 0.8-1.6 */
#define AUTO_FILTER_US_PER_PIXEL 1.1
/* Left out: the filtered frame's fixed CPU time (the OpenCL driver, context and kernels,
 * 0.031-0.036 s here), so that the decision does not depend on the image's size
 * (docs/algorithms.md, "what the model ignores"). */
/* A configuration replaces the one auto chose only when its predicted speed is at least this
 * many times the chosen one's: the model's error. On the three scenes the constants come from,
 * predicted over measured equal-error speed ran 0.83-1.26x; 4/3 covers it. (On the check set
 * it ran 0.34-1.6x: it underestimates the filters where the unfilterable part sits in glossy
 * or textured pixels that the adaptive plans give more samples, wire_screen 0.77x predicted
 * against 1.56x measured at 8 spp; docs/benchmarks.md, "auto's fallback to Monte Carlo".) */
#define AUTO_FALLBACK_MIN_ADVANTAGE (4.0 / 3.0)
/* Beside camera candidates, a configuration with a shading filter of another method than
 * theirs (its own sink) is replaced by a subset predicted this many times faster: there the
 * model's E_cam(c) / E_cam(none) ran 0.97-1.17x the measured ratio (AAF's shadows or bounce
 * beside LR, six bench scenes, 256x256, 16 spp: 0.98-1.11x in speed), and its time of the
 * camera filters is low (LR's frame measured 4.1-6.3 us a pixel over Monte Carlo's at 16 spp,
 * 2.7-3.8 in the model), which makes the shading filter's share of the time look ~10% larger
 * than it is (docs/benchmarks.md, auto6). Beside MAAF's lens, whose shading filters share its
 * method, E_cam's ratio ran 0.26-1.38x the measured one and AUTO_FALLBACK_MIN_ADVANTAGE stays. */
#define AUTO_OWN_SINK_MIN_ADVANTAGE 1.15
/* The independent samples a shading filter's kernel averages, relative to one pixel's: the
 * factor by which it lowers the error it can remove. */
#define AUTO_FILTER_FOOTPRINT 50.0
/* N_fit: the highest sample count at which AUTO_FILTER_FOOTPRINT and the camera footprint
 * below were measured (8 and 16 spp): g(N) = 1 up to it */
#define AUTO_FOOTPRINT_FIT_SPP 16
/* The camera filters' footprint (camera_gain.h), F = 1 + efficiency (A - 1) at most a cap,
 * A a sample's blur area in pixels: fitted on defocus, motion and motion_defocus_hard only
 * (256x256, 8 and 16 spp; efficiency 0.05-0.5 and caps 10-100 tried; docs/benchmarks.md, "auto
 * judges its camera filters"). */
#define AUTO_CAMERA_EFFICIENCY 0.2
#define AUTO_CAMERA_FOOTPRINT_MAX 50.0
/* The camera filters are left to Monte Carlo only when that is predicted this many times
 * faster than keeping them (the model's error on the camera side). */
#define AUTO_CAMERA_MIN_ADVANTAGE (4.0 / 3.0)

typedef struct {
    bool direct, indirect;   /* auto chose to filter soft shadows / indirect light (candidates) */
    int others;              /* other effects a filter takes whatever this decides (camera
                              * effects, effects named explicitly) */
    bool camera;             /* among them a camera effect (defocus, motion) */
    int spp;                 /* N: the frame's samples per pixel */
    int cameras;             /* camera effects auto chose to filter (candidates as one: kept or
                              * left to Monte Carlo together); 0 when a camera filter was named
                              * explicitly (then it is among others) */
    /* Beside camera candidates: the soft-shadow / indirect filter's method is none of theirs, so
     * it records its own per-sample data where theirs is all the frame had (AAF's shadows beside
     * LR), and costs AUTO_SINK_US_PER_SAMPLE a sample more than a filter sharing a camera
     * filter's method (MAAF's shadows beside MAAF's lens), which pays its pass alone. */
    bool direct_own_sink, indirect_own_sink;
    /* both shading filters run one method (AAF's shadows and bounce): one sink between them (the
     * second costs its pass alone: 0.7-0.8 us a pixel beside LR, 16 spp) */
    bool shading_one_method;
} AutoFallbackFrame;

typedef struct {
    FilterGainConfig asked;  /* the candidates' configuration */
    FilterGainConfig chosen; /* the one kept (a subset of asked) */
    double share[FILTER_GAIN_CONFIGS];   /* s(c) */
    double speedup[FILTER_GAIN_CONFIGS]; /* S(c); 0 for configurations not open to the frame */
    double alpha;
    double sample_us;        /* t_s, microseconds */
    int spp;
    double neighbour_error;  /* g(N): a borrowed sample's error relative to Monte Carlo's, against
                              * that at N_fit (auto_fallback_neighbour_error) */
    /* the camera filters' judgement (cameras > 0 in the frame) */
    bool camera_asked;       /* the frame had camera candidates */
    bool camera_fell_back;   /* they were left to Monte Carlo */
    double camera_error;     /* their configuration's error over Monte Carlo's at N, E_cam */
    double camera_footprint; /* F, the probe pixels' mean */
    double camera_speedup;   /* S with the camera filters (and the shading kept beside them) */
    double camera_speedup_without; /* S without them (the best shading configuration alone) */
    int samples_nonfinite;   /* probe samples left out (non-finite) */
} AutoFallback;

/* The decision for a frame from the probe's totals and rays per sample. */
void auto_fallback_decide(const FilterGainTotals *t, double rays_per_sample, const AutoFallbackFrame *f, AutoFallback *out);

/* g(N) = (N / AUTO_FOOTPRINT_FIT_SPP)^(alpha - 1) above AUTO_FOOTPRINT_FIT_SPP, 1 up to it. */
double auto_fallback_neighbour_error(int spp, double alpha);

/* The advantage Monte Carlo needs over auto's camera filters at spp samples:
 * AUTO_CAMERA_MIN_ADVANTAGE up to AUTO_FOOTPRINT_FIT_SPP, 1 past it. */
double auto_fallback_camera_margin(int spp);

/* T(c), microseconds per pixel (the frame's camera candidates count as filters that run). */
double auto_fallback_time_us(FilterGainConfig c, const AutoFallbackFrame *f, double sample_us);

#endif
