/* Which reconstruction method each distribution effect gets (DESIGN.md section 1: the
 * renderer chooses per effect). The one policy, read by `wedge render` (through the
 * pipeline) and `wedge info`, so the two always agree. */
#ifndef WEDGE_RECON_SELECT_H
#define WEDGE_RECON_SELECT_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/auto_fallback.h"
#include "recon/camera_gain.h"
#include "recon/method.h"
#include "scene/effects.h"

enum { RECON_REASON_SIZE = 192 };

typedef struct {
    const ReconMethodClass *method[EFFECT_COUNT]; /* NULL: the effect is absent or not filtered */
    char reason[EFFECT_COUNT][RECON_REASON_SIZE]; /* one line: why ("" for absent effects); an
                                                   * array, not a pointer, so that a measured value
                                                   * can be part of it and the choice copies whole */
    float blur_px;                                /* the blur probe's value it read, -1: none */
    int blur_unbounded;                           /* the probe's samples_unbounded (set by the
                                                   * caller that ran it; 0 otherwise) */
    bool by_auto[EFFECT_COUNT];                   /* auto decided the effect (--filter auto, or
                                                   * EFFECT=auto / not named in the per-effect form) */
    bool fallback_decided;                        /* the gain probe ran and recon_select_fallback
                                                   * applied its decision (fallback below) */
    EffectMask fell_back;                         /* effects auto had chosen a filter for and then
                                                   * left to Monte Carlo */
    AutoFallback fallback;                        /* the decision's numbers */
    bool shadow_light_moves;                      /* an area light moves and the frame's shadow
                                                   * filter does not model its motion
                                                   * (recon_select_moving_light): an explicit
                                                   * one is then biased */
} ReconChoice;

/* --filter auto sends the camera effects (motion, and defocus with it) of a scene with motion
 * to layered reconstruction (lr) when the blur probe's median blur extent is at least this
 * many pixels, else defocus to aaf and motion alone to lr: docs/benchmarks.md, "The choice
 * per effect (issue 18)", for the measurement and the why. */
#define RECON_LR_MIN_BLUR_PX 3.0f
/* ... unless the frame's --spp budget is at least this: there layered reconstruction's bias
 * (its disk approximation, a floor near relMSE 2.5e-4 on the hard bench scenes) outweighs its
 * noise reduction, and defocus goes to aaf, motion alone to lr (docs/benchmarks.md, "LR's
 * floor and the budget"). */
#define RECON_LR_MAX_BUDGET_SPP 48
/* The same threshold in a frame that also has indirect light: the lens filter of aaf then runs
 * on a composite that still carries the bounce's residual noise, which lr's reprojection
 * averages further, so aaf needs about twice the samples to pass lr's floor (crossovers 59-150
 * spp with indirect light against 40-62 spp without, docs/benchmarks.md, "The budget rule
 * with indirect light"). */
#define RECON_LR_MAX_BUDGET_SPP_INDIRECT 96
/* Which of the two applies to the effects present. */
int recon_lr_max_budget_spp(EffectMask present);

/* The choice for the effects present and a --filter request: "auto" (the measured best per
 * effect), "none" (plain Monte Carlo), a method's name (that method for every effect it can
 * filter, nothing for the others), or a method per effect, "EFFECT=METHOD[,...]" with METHOD
 * a method's name, auto or none (effects not named: auto's choice), e.g. "motion=lr,defocus=lr"
 * for layered reconstruction of the camera effects beside auto's shading filters. An unknown
 * request chooses nothing. blur_px: the blur probe's median blur extent at the render's
 * resolution (recon/blur_probe.h) when motion is present, read by auto's choice for motion
 * and defocus; a negative value (or NaN) when it was not measured (scenes without motion: the
 * choice does not depend on it). */
void recon_select(EffectMask present, const char *request, float blur_px, ReconChoice *out);
/* The same for a frame with an average budget of budget_spp samples per pixel (--spp; 0: none,
 * the methods' own counts), which auto's choice of the camera effects reads. */
void recon_select_budget(EffectMask present, const char *request, float blur_px, int budget_spp, ReconChoice *out);
/* Whether recon_select's choice under this request reads blur_px: motion is present and auto
 * decides motion or defocus (motion's choice is lr either way; the value is in its reason).
 * Callers run the probe only then. */
bool recon_select_wants_blur(EffectMask present, const char *request);

/* A moving area light: the soft shadows auto chose a filter for are left to Monte Carlo, with the
 * reason: fsf takes the area the light sweeps as a uniform light (biased); aaf and maaf take its
 * poses over the shutter (docs/algorithms.md 1.9), but auto's probe misjudges such frames
 * (docs/benchmarks.md, mlight1). Explicit filters keep theirs, and shadow_light_moves tells the
 * caller to warn when the kept one is biased (fsf). Call after recon_select_budget and before the
 * fallback's probe. */
void recon_select_moving_light(ReconChoice *c, bool area_light_moves);
/* The warning for a shadow filter asked for by name under a moving area light, into buf (one
 * line, no prefix); false (and buf "") when there is nothing to warn about. */
bool recon_choice_moving_light_warning(const ReconChoice *c, char *buf, size_t size);

/* Whether auto chose a filter that its fallback to Monte Carlo may take back: a shading filter
 * (soft shadows, indirect light) or its camera filters (defocus, motion; judged together, and
 * only when no camera filter was named explicitly). The caller then runs the gain probe
 * (gain_probe.h) and applies the decision with recon_select_fallback. Explicit filters never
 * fall back. */
bool recon_select_wants_fallback(const ReconChoice *c);
/* The frame auto_fallback_decide judges: auto's shading filters and camera filters as
 * candidates, every other filtered effect counted, spp the frame's samples per pixel. */
AutoFallbackFrame recon_select_fallback_frame(const ReconChoice *c, int spp);
/* Which blur the gain probe measures the camera footprint of: the camera candidates'. */
CameraBlurKinds recon_select_fallback_blur(const ReconChoice *c);
/* Applies a decision: the candidates left out of fb->chosen (the camera candidates when
 * fb->camera_fell_back) get no method and a reason that gives the prediction; the shading
 * filters kept get the prediction as their reason. */
void recon_select_fallback(ReconChoice *c, const AutoFallback *fb);

/* "aaf", or "none" when the effect is not filtered. */
const char *recon_choice_name(const ReconChoice *c, Effect e);
/* Whether any effect is filtered. */
bool recon_choice_any(const ReconChoice *c);
/* Whether the choice filters shading light e (soft shadows or indirect) in mixed pixels'
 * first surfaces (method.h, filters_split_pixels; docs/algorithms.md 4.6): e's method and
 * every camera effect's method do. */
bool recon_choice_splits_pixels(const ReconChoice *c, Effect e);

/* True for the --filter values the renderer accepts: "auto", "none", every method's name and
 * the per-effect form. */
bool recon_filter_known(const char *request);
/* The same, and for a per-effect request that is not valid, what is wrong in why ("lr cannot
 * filter soft_shadows"); why may be NULL. */
bool recon_filter_problem(const char *request, char *why, size_t why_size);
/* Those values as a phrase for messages, "auto, aaf or none", written to buf (truncated to
 * size - 1 characters); returns buf. */
const char *recon_filter_choices(char *buf, size_t size);

#endif
