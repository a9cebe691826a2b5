/* The policy (see select.h). */
#include "recon/select.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* --filter auto: per effect, the method with the best equal-error time against Monte Carlo
 * on the bench scene of that effect: tools/bench-policy at 256x256, --spp 4-64, on a quiet
 * machine (docs/benchmarks.md, "The choice per effect after the faster MAAF and FSF"): soft
 * shadows aaf 1.85x (fsf 1.01x, maaf 0.94x; thin_occluders aaf 1.64x, fsf 0.96x, maaf
 * 0.76x), defocus aaf 1.56x (maaf 1.43x, lr 1.24x, fsf 1.13x), indirect aaf 8.85x. At AAF's
 * own default budget the same scenes give 9.9x, 3.2x and 13.8x ("AAF against Monte Carlo").
 * A method that lands adds its row to bench-policy's table and wins an effect only where its
 * measured speedup is higher. Re-run on every bench scene with two seeds (2026-11-28, a shared
 * machine; "The choice per effect on every bench scene, two seeds"): soft shadows aaf 1.53x
 * (maaf 0.67x, fsf 0.55x), defocus aaf 1.26x against maaf 1.30x and lr 1.30x (a tie within
 * that run's noise; paired by budget auto, i.e. aaf, is 1.26x maaf), indirect aaf ~7.3x: the
 * choices hold. Soft shadows after MAAF's shadow fix (2026-11-29, every bench scene with soft
 * shadows, two seeds; "MAAF for soft shadows in --filter auto"): maaf 2.55x against aaf 2.23x
 * on soft_shadows (thin_occluders 1.67x / 1.47x, tilted_stack 1.21x / 1.12x) but 0.96-1.03x
 * paired by budget (ahead at 16-32 spp, behind at 8 and at the default budget), and beside
 * another method's filters a frame with maaf's shadows runs two filters and plans its samples
 * by the larger of two plans: 1-36% more CPU at equal spp for equal or more error. aaf stays
 * there; where soft shadows are the frame's only effect maaf wins at every budget (the row
 * "soft shadows alone" below, measured after the later AAF and MAAF changes).
 * The defocus row (2026-11-29, "The defocus row of --filter auto to maaf"): maaf over the
 * whole frame gives 1.3-4x less error than aaf at equal spp on defocus, combined,
 * focal_crossing and bokeh_bright (1.16-1.80x the equal-error speed, paired by budget), so in
 * frames without motion the lens goes to maaf and the shading with it (follow_maaf_lens);
 * issue 18's check then passes on those four and envlight (0.95-1.05). */
/* The measurement behind lr for motion alone (docs/benchmarks.md, issue 18). */
#define LR_MOTION_ONLY_EVIDENCE "motion_shading 128x128: 29%/18% less error than unfiltered at 8/16 spp"

static const struct {
    Effect effect;
    bool without_motion; /* the row applies only to a frame without motion */
    bool alone;          /* the row applies only when the effect is the frame's only one */
    const char *method;
    const char *reason;
} AUTO_POLICY[] = {
    /* Soft shadows alone (2026-11-29, docs/benchmarks.md, "soft shadows as the frame's only
     * effect"): on the six bench scenes whose only effect is soft shadows, maaf / aaf at equal
     * error through Monte Carlo's curve, CPU time, seeds 1-2: 1.97x at 8 spp, 1.32x at 16, 1.29x
     * at 32, 1.12x at the default budget; worst scene spot_area_mm 0.89x (16 spp), tilted_stack
     * 0.91x (default). Beside another effect's filter maaf's shadows lose (0.71-0.93x). */
    {EFFECT_SOFT_SHADOWS, false, true, "maaf", "maaf, soft shadows alone: 1.97x/1.32x/1.29x/1.12x aaf's speed at equal "
                                               "error at 8/16/32 spp/default budget (six shadow-only bench scenes, 256x256)"},
    {EFFECT_SOFT_SHADOWS, false, false, "aaf", "aaf: 2.23x Monte Carlo's speed at equal error, maaf 2.55x but even paired by budget and "
                                 "slower beside other effects' filters (soft-shadow bench, 256x256, tools/bench-policy)"},
    /* maaf over the whole frame (issue 18, 2026-11-29): the four bench scenes with defocus and
     * no motion, paired by budget, maaf / aaf 1.20x (defocus), 1.34-1.47x (combined), 1.80x
     * (focal_crossing), 1.16x (bokeh_bright). With motion the lens is lr's above the blur
     * threshold (select_camera_by_blur) and aaf's below it: maaf was not measured there. */
    {EFFECT_DEFOCUS, true, false, "maaf", "maaf: 1.84x Monte Carlo's speed at equal error, aaf 1.46x; paired by budget 1.20x aaf's "
                                   "(combined 1.34x, focal_crossing 1.80x) (defocus bench, 256x256, tools/bench-policy)"},
    {EFFECT_DEFOCUS, false, false, "aaf", "aaf beside motion: maaf not measured beside lr's motion filter (without motion aaf "
                                   "1.46x Monte Carlo's speed at equal error, maaf 1.84x; tools/bench-policy)"},
    /* fsf indirect (issue 15): 1.14-1.60x aaf's relMSE at equal spp 8-64 and 1.48x its frame
     * time (indirect bench, 256x256; docs/benchmarks.md, 2026-11-28) */
    {EFFECT_INDIRECT, false, false, "aaf", "aaf: 8.85x Monte Carlo's speed at equal error (indirect bench, 256x256, tools/bench-policy)"},
    /* below the blur threshold, or without the probe (select_camera_by_blur decides above it) */
    {EFFECT_MOTION, false, false, "lr", "lr, motion only: moving objects get their own layers' motion filter (" LR_MOTION_ONLY_EVIDENCE ")"},
};

static const char *const NO_METHOD_REASON[EFFECT_COUNT] = {
    [EFFECT_SOFT_SHADOWS] = "no registered method filters soft shadows",
    [EFFECT_DEFOCUS] = "no registered method filters defocus",
    [EFFECT_MOTION] = "no registered method filters motion",
    [EFFECT_INDIRECT] = "no registered method filters indirect light",
};

/* A per-effect request, "EFFECT=METHOD[,EFFECT=METHOD...]" (METHOD: a method's name, "auto"
 * or "none"), into one word per effect (NULL: not named, auto decides). False when it is not
 * one, with why set: an unknown effect or method, a method that cannot filter the effect, an
 * effect named twice. The words point into buf (a copy of the request). */
static bool parse_per_effect(const char *request, char *buf, size_t size, const char *word[EFFECT_COUNT], char *why,
                             size_t why_size)
{
    for (int e = 0; e < EFFECT_COUNT; ++e) word[e] = NULL;
    if (!strchr(request, '=') || strlen(request) >= size) {
        snprintf(why, why_size, "not EFFECT=METHOD pairs");
        return false;
    }
    strcpy(buf, request);
    for (char *save = NULL, *pair = strtok_r(buf, ",", &save); pair; pair = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(pair, '=');
        Effect e;
        if (!eq) {
            snprintf(why, why_size, "'%s' is not EFFECT=METHOD", pair);
            return false;
        }
        *eq = 0;
        const char *method = eq + 1;
        if (!effect_from_name(pair, &e)) {
            snprintf(why, why_size, "unknown effect '%s' (soft_shadows, defocus, motion or indirect)", pair);
            return false;
        }
        if (word[e]) {
            snprintf(why, why_size, "%s is named twice", pair);
            return false;
        }
        const ReconMethodClass *m = recon_method_find(method);
        if (strcmp(method, "auto") && strcmp(method, "none") && !m) {
            snprintf(why, why_size, "unknown method '%s' for %s", method, pair);
            return false;
        }
        if (m && !effect_in(m->effects, e)) {
            snprintf(why, why_size, "%s cannot filter %s", method, pair);
            return false;
        }
        word[e] = method;
    }
    return true;
}

static void set_reason(ReconChoice *out, Effect e, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(out->reason[e], sizeof out->reason[e], fmt, ap);
    va_end(ap);
}

int recon_lr_max_budget_spp(EffectMask present)
{
    return effect_in(present, EFFECT_INDIRECT) ? RECON_LR_MAX_BUDGET_SPP_INDIRECT : RECON_LR_MAX_BUDGET_SPP;
}

/* The camera effects with motion (docs/benchmarks.md, "The choice per effect (issue 18)"):
 * layered reconstruction gathers, for a pixel, the samples of every pixel whose blur reaches
 * it (docs/algorithms.md section 8), so for defocus it has more samples than a per-pixel
 * filter only where the blur spans several pixels. On the bench at 128x128 it beats aaf-only
 * by 2-3x where the probe's median blur is 6.2 px (motion_defocus_hard, _soft) and loses up
 * to 2x where it is 1.8-2.0 px (all_effects, motion_defocus); RECON_LR_MIN_BLUR_PX = 3 px
 * sits between (a blur of 3 px reaches at least the 8 neighbours). Below the threshold the
 * motion is left to Monte Carlo (the lens to aaf): lr for the motion alone lowered the error
 * at equal samples (motion_shading, 9-60%) but added 0.3-0.8 s of CPU a 256 x 256 frame, and
 * at equal CPU it lost on moving_shadow at every budget, on motion_shading at three of four
 * and on all five random scenes where auto kept it (docs/benchmarks.md, "lr for the motion
 * alone at equal CPU"). A --spp budget of recon_lr_max_budget_spp or more leaves lr the motion
 * alone at any blur above the threshold: there its bias costs more than its gain for the lens
 * (docs/benchmarks.md, "LR's floor and the budget"). True when the effect is decided (a
 * method or Monte Carlo). */
static bool select_camera_by_blur(Effect e, EffectMask present, float blur_px, int budget_spp, ReconChoice *out)
{
    const ReconMethodClass *lr = recon_method_find("lr");
    if (!lr || !effect_in(lr->effects, e)) return false;
    int max_budget = recon_lr_max_budget_spp(present);
    if (blur_px >= RECON_LR_MIN_BLUR_PX && budget_spp >= max_budget) {
        if (e != EFFECT_MOTION) return false; /* defocus: the per-pixel filter's choice, below */
        out->method[e] = lr;
        set_reason(out, e, "lr, motion only: a budget of %d spp >= %d, where lr's bias outweighs its gain for the lens "
                   "(docs/benchmarks.md, issue 18)", budget_spp, max_budget);
    } else if (blur_px >= RECON_LR_MIN_BLUR_PX) {
        out->method[e] = lr;
        set_reason(out, e, "lr: median blur %.1f px >= %.0f px, layered reconstruction shares samples across pixels "
                   "(docs/benchmarks.md, issue 18)", (double)blur_px, (double)RECON_LR_MIN_BLUR_PX);
    } else if (e == EFFECT_MOTION) {
        out->method[e] = NULL;
        set_reason(out, e, "none, auto fell back to Monte Carlo: median blur %.1f px < %.0f px, where lr's motion filter "
                   "alone costs more CPU than it saves (docs/benchmarks.md, \"lr for the motion alone at equal CPU\")",
                   (double)blur_px, (double)RECON_LR_MIN_BLUR_PX);
    }
    return out->method[e] != NULL || e == EFFECT_MOTION;
}

/* auto's choice for effect e of the effects present; blur_px and budget_spp as for
 * recon_select_budget. */
static void select_auto(Effect e, EffectMask present, float blur_px, int budget_spp, ReconChoice *out)
{
    bool measured = effect_in(present, EFFECT_MOTION) && blur_px >= 0.0f && isfinite(blur_px);
    bool camera = e == EFFECT_MOTION || e == EFFECT_DEFOCUS;
    if (measured && camera) {
        out->blur_px = blur_px;
        if (select_camera_by_blur(e, present, blur_px, budget_spp, out)) return;
    }
    const char *why = NO_METHOD_REASON[e];
    for (size_t k = 0; k < sizeof AUTO_POLICY / sizeof AUTO_POLICY[0]; ++k) {
        const ReconMethodClass *m = recon_method_find(AUTO_POLICY[k].method);
        bool applies = (!AUTO_POLICY[k].without_motion || !effect_in(present, EFFECT_MOTION)) &&
                       (!AUTO_POLICY[k].alone || present == EFFECT_BIT(e));
        if (AUTO_POLICY[k].effect == e && applies && m && effect_in(m->effects, e)) {
            out->method[e] = m;
            why = AUTO_POLICY[k].reason;
            break;
        }
    }
    if (measured && camera && blur_px >= RECON_LR_MIN_BLUR_PX)
        set_reason(out, e, "%s: a budget of %d spp >= %d, where lr's bias outweighs its gain (docs/benchmarks.md, issue 18)",
                   out->method[e] ? out->method[e]->name : "none", budget_spp, recon_lr_max_budget_spp(present));
    else if (measured && camera)
        set_reason(out, e, "%s: median blur %.1f px < %.0f px, too little for lr to pay (docs/benchmarks.md, issue 18)",
                   out->method[e] ? out->method[e]->name : "none", (double)blur_px, (double)RECON_LR_MIN_BLUR_PX);
    else
        set_reason(out, e, "%s", why);
}

/* One adaptive filter per frame: where the lens is MAAF's, the effects auto decides that MAAF
 * also filters (soft shadows, indirect light) go to it too. A frame with two adaptive filters
 * runs both and traces pass 1 and the extra samples by the larger of their two plans
 * (pipeline.c, plan_at): at equal spp, MAAF's shadows beside AAF's lens and bounce cost 1-36%
 * more CPU for about the same error (combined, focal_crossing, all_effects and four more,
 * 8-32 spp), while MAAF over the whole frame gave 0.24-0.77x AAF's error on the scenes with
 * defocus (docs/benchmarks.md, "MAAF for soft shadows in --filter auto", sections 1 and 3). */
static void follow_maaf_lens(const bool by_auto[EFFECT_COUNT], ReconChoice *out)
{
    const ReconMethodClass *lens = out->method[EFFECT_DEFOCUS];
    if (!lens || strcmp(lens->name, "maaf")) return;
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (!by_auto[e] || e == EFFECT_DEFOCUS || !out->method[e] || out->method[e] == lens) continue;
        if (!effect_in(lens->effects, (Effect)e)) continue;
        out->method[e] = lens;
        set_reason(out, (Effect)e, "maaf, with the lens: one adaptive filter per frame (beside another method's "
                   "filters, 1-36%% more CPU at equal spp; docs/benchmarks.md, issue 18)");
    }
}

bool recon_select_wants_blur(EffectMask present, const char *request)
{
    if (!effect_in(present, EFFECT_MOTION)) return false;
    if (!strcmp(request, "auto")) return true;
    char buf[256], why[160];
    const char *w[EFFECT_COUNT];
    if (!parse_per_effect(request, buf, sizeof buf, w, why, sizeof why)) return false;
    bool motion_auto = !w[EFFECT_MOTION] || !strcmp(w[EFFECT_MOTION], "auto");
    bool defocus_auto = effect_in(present, EFFECT_DEFOCUS) && (!w[EFFECT_DEFOCUS] || !strcmp(w[EFFECT_DEFOCUS], "auto"));
    return motion_auto || defocus_auto;
}

void recon_select(EffectMask present, const char *request, float blur_px, ReconChoice *out)
{
    recon_select_budget(present, request, blur_px, 0, out);
}

void recon_select_budget(EffectMask present, const char *request, float blur_px, int budget_spp, ReconChoice *out)
{
    memset(out, 0, sizeof *out);
    out->blur_px = -1.0f;
    char buf[256], why[160];
    const char *per_effect[EFFECT_COUNT];
    bool mapped = parse_per_effect(request, buf, sizeof buf, per_effect, why, sizeof why);
    bool none = !strcmp(request, "none"), autom = !strcmp(request, "auto");
    const ReconMethodClass *asked = (none || autom) ? NULL : recon_method_find(request);
    bool by_auto[EFFECT_COUNT] = {false};
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (!effect_in(present, (Effect)e)) continue;
        if (mapped) {
            const char *w = per_effect[e];
            if (!w || !strcmp(w, "auto")) {
                by_auto[e] = true;
                select_auto((Effect)e, present, blur_px, budget_spp, out);
            } else if (!strcmp(w, "none")) {
                set_reason(out, (Effect)e, "--filter EFFECT=none: plain Monte Carlo");
            } else {
                out->method[e] = recon_method_find(w);
                set_reason(out, (Effect)e, "asked for with --filter EFFECT=METHOD");
            }
        } else if (none) {
            set_reason(out, (Effect)e, "--filter none: plain Monte Carlo");
        } else if (asked) {
            bool can = effect_in(asked->effects, (Effect)e);
            out->method[e] = can ? asked : NULL;
            set_reason(out, (Effect)e, "%s", can ? "asked for with --filter" : "the method asked for with --filter cannot filter it");
        } else if (autom) {
            by_auto[e] = true;
            select_auto((Effect)e, present, blur_px, budget_spp, out);
        } else {
            set_reason(out, (Effect)e, "unknown --filter");
        }
    }
    follow_maaf_lens(by_auto, out);
    memcpy(out->by_auto, by_auto, sizeof out->by_auto);
}

/* The shadow filters that take a moving area light's poses over the shutter (its time-mean r(x),
 * MAAF's swept light: docs/algorithms.md 1.9, 9.29; FSF's swept light with its samples' density
 * since fsf13: docs/algorithms.md 10, below Monte Carlo's error at 16-256 spp on
 * moving_light_defocus); a filter not listed is taken to see the area the light sweeps as a
 * uniform light, and is warned about. */
static bool follows_moving_light(const ReconMethodClass *m)
{
    return !strcmp(m->name, "aaf") || !strcmp(m->name, "maaf") || !strcmp(m->name, "fsf");
}

void recon_select_moving_light(ReconChoice *c, bool area_light_moves)
{
    if (!area_light_moves || !c->method[EFFECT_SOFT_SHADOWS]) return;
    const ReconMethodClass *m = c->method[EFFECT_SOFT_SHADOWS];
    bool follows = follows_moving_light(m);
    c->shadow_light_moves = !follows;
    if (!c->by_auto[EFFECT_SOFT_SHADOWS]) return; /* asked for by name: kept (warned about unless it follows) */
    /* auto leaves them to Monte Carlo even when the filter follows the light: the probe's camera
     * model misses there (on moving_light_defocus auto's aaf + lr measured 0.58x Monte Carlo's
     * equal-error speed at 16 spp, 0.94x with the shadows left to Monte Carlo; mlight1) */
    c->method[EFFECT_SOFT_SHADOWS] = NULL;
    if (follows)
        set_reason(c, EFFECT_SOFT_SHADOWS,
                   "none, auto fell back to Monte Carlo: an area light moves during the shutter; %s's shadow filter "
                   "follows it, but auto's probe misjudges such frames (docs/benchmarks.md, mlight1)",
                   m->name);
    else
        set_reason(c, EFFECT_SOFT_SHADOWS,
                   "none, auto fell back to Monte Carlo: an area light moves during the shutter, and %s's shadow "
                   "filter takes it as a uniform light over the area it sweeps (biased; docs/benchmarks.md, mlight1)",
                   m->name);
}

bool recon_choice_moving_light_warning(const ReconChoice *c, char *buf, size_t size)
{
    if (size) buf[0] = '\0';
    if (!c->shadow_light_moves || !c->method[EFFECT_SOFT_SHADOWS] || c->by_auto[EFFECT_SOFT_SHADOWS]) return false;
    snprintf(buf, size,
             "an area light moves during the shutter, and %s's shadow filter takes it as a uniform light over the area it "
             "sweeps: "
             "the soft shadows are biased (--filter auto leaves them to Monte Carlo)",
             c->method[EFFECT_SOFT_SHADOWS]->name);
    return true;
}

/* The shading effects auto's fallback decides (auto_fallback.h): the filters whose gain the
 * probe measures per effect. */
static bool fallback_candidate(const ReconChoice *c, Effect e)
{
    return (e == EFFECT_SOFT_SHADOWS || e == EFFECT_INDIRECT) && c->by_auto[e] && c->method[e];
}

static bool is_camera(Effect e)
{
    return e == EFFECT_DEFOCUS || e == EFFECT_MOTION;
}

/* The camera effects auto filters, judged together (kept or left to Monte Carlo as one): only
 * when no camera filter was named explicitly (that one would run whatever auto decides, and
 * the probe cannot tell its gain from theirs). */
static EffectMask camera_candidates(const ReconChoice *c)
{
    EffectMask m = 0;
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (!is_camera((Effect)e) || !c->method[e]) continue;
        if (!c->by_auto[e]) return 0;
        m |= EFFECT_BIT(e);
    }
    return m;
}

bool recon_select_wants_fallback(const ReconChoice *c)
{
    return fallback_candidate(c, EFFECT_SOFT_SHADOWS) || fallback_candidate(c, EFFECT_INDIRECT) || camera_candidates(c);
}

AutoFallbackFrame recon_select_fallback_frame(const ReconChoice *c, int spp)
{
    EffectMask cameras = camera_candidates(c);
    AutoFallbackFrame f = {.direct = fallback_candidate(c, EFFECT_SOFT_SHADOWS), .indirect = fallback_candidate(c, EFFECT_INDIRECT), .spp = spp};
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (effect_in(cameras, (Effect)e)) {
            f.cameras++;
            continue;
        }
        bool other = c->method[e] && !fallback_candidate(c, (Effect)e);
        f.others += other;
        f.camera = f.camera || (other && is_camera((Effect)e));
    }
    return f;
}

CameraBlurKinds recon_select_fallback_blur(const ReconChoice *c)
{
    EffectMask cameras = camera_candidates(c);
    /* sharpest_lens: set by recon_gain_probe_judge (gain_probe.c) from the defocus method */
    return (CameraBlurKinds){effect_in(cameras, EFFECT_DEFOCUS), effect_in(cameras, EFFECT_MOTION), false, false};
}

void recon_select_fallback(ReconChoice *c, const AutoFallback *fb)
{
    c->fallback = *fb;
    c->fallback_decided = true;
    c->fell_back = 0;
    if (fb->camera_fell_back) {
        EffectMask cameras = camera_candidates(c);
        for (int e = 0; e < EFFECT_COUNT; ++e) {
            if (!effect_in(cameras, (Effect)e)) continue;
            set_reason(c, (Effect)e, "none, auto fell back to Monte Carlo: %s predicted %.2fx its equal-error speed, %.2fx "
                       "without (error %.2fx at equal spp, footprint %.1f pixels, alpha %.2f, gain probe)", c->method[e]->name, fb->camera_speedup, fb->camera_speedup_without, fb->camera_error,
                       fb->camera_footprint, fb->alpha);
            c->method[e] = NULL;
            c->fell_back |= EFFECT_BIT(e);
        }
    }
    static const struct {
        Effect effect;
        FilterGainConfig bit;
    } SHADING[] = {{EFFECT_SOFT_SHADOWS, FILTER_GAIN_DIRECT}, {EFFECT_INDIRECT, FILTER_GAIN_INDIRECT}};
    for (size_t k = 0; k < sizeof SHADING / sizeof SHADING[0]; ++k) {
        Effect e = SHADING[k].effect;
        if (!(fb->asked & SHADING[k].bit)) continue;
        /* the prediction for this effect: the configuration with it against the one without */
        FilterGainConfig with = fb->chosen | SHADING[k].bit, without = fb->chosen & ~SHADING[k].bit;
        if (fb->chosen & SHADING[k].bit) {
            set_reason(c, e, "%s, kept: predicted %.2fx Monte Carlo's equal-error speed (%.2fx without it; error share "
                       "%.0f%%, alpha %.2f, gain probe)", c->method[e]->name, fb->speedup[with], fb->speedup[without],
                       100.0 * fb->share[with], fb->alpha);
        } else {
            set_reason(c, e, "none, auto fell back to Monte Carlo: %s predicted %.2fx its equal-error speed, %.2fx "
                       "without (error share %.0f%%, alpha %.2f, gain probe)", c->method[e]->name, fb->speedup[with],
                       fb->speedup[without], 100.0 * fb->share[with], fb->alpha);
            c->method[e] = NULL;
            c->fell_back |= EFFECT_BIT(e);
        }
    }
}

const char *recon_choice_name(const ReconChoice *c, Effect e)
{
    return (unsigned)e < EFFECT_COUNT && c->method[e] ? c->method[e]->name : "none";
}

bool recon_choice_any(const ReconChoice *c)
{
    for (int e = 0; e < EFFECT_COUNT; ++e)
        if (c->method[e]) return true;
    return false;
}

bool recon_choice_splits_pixels(const ReconChoice *c, Effect e)
{
    if (!c->method[e] || !c->method[e]->filters_split_pixels) return false;
    for (int k = EFFECT_DEFOCUS; k <= EFFECT_MOTION; ++k)
        if (c->method[k] && !c->method[k]->filters_split_pixels) return false;
    return true;
}

bool recon_filter_known(const char *request)
{
    return recon_filter_problem(request, NULL, 0);
}

bool recon_filter_problem(const char *request, char *why, size_t why_size)
{
    if (!strcmp(request, "auto") || !strcmp(request, "none") || recon_method_find(request)) return true;
    char buf[256], scratch[160];
    const char *per_effect[EFFECT_COUNT];
    return parse_per_effect(request, buf, sizeof buf, per_effect, why ? why : scratch, why ? why_size : sizeof scratch);
}

const char *recon_filter_choices(char *buf, size_t size)
{
    const char *names[16];
    int count = 0;
    names[count++] = "auto";
    for (int i = 0; recon_methods[i] && count < 15; ++i) names[count++] = recon_methods[i]->name;
    names[count++] = "none";
    size_t len = 0;
    if (size) buf[0] = 0;
    for (int i = 0; i < count && len < size; ++i) {
        const char *sep = i == 0 ? "" : i == count - 1 ? " or " : ", ";
        int w = snprintf(buf + len, size - len, "%s%s", sep, names[i]);
        if (w < 0) break;
        len += (size_t)w;
    }
    if (len < size) snprintf(buf + len, size - len, " (or a method per effect, e.g. motion=lr,defocus=lr)");
    return buf;
}
