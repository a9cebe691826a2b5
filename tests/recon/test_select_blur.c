/* The issue-18 rule in recon/select: under --filter auto, a scene with motion sends its camera
 * effects (motion, defocus) to lr when the blur probe's median blur is at least
 * RECON_LR_MIN_BLUR_PX, else defocus keeps aaf and the motion is left to Monte Carlo; the measured value
 * is in the reason line; scenes without motion and explicit requests ignore the value. With a
 * --spp budget of recon_lr_max_budget_spp or more (higher with indirect light), lr keeps only
 * the motion. */
#include <string.h>

#include "../check.h"
#include "recon/select.h"

/* auto's camera choice at a blur of 9.4 px (above RECON_LR_MIN_BLUR_PX) under a budget: motion
 * always lr, defocus the method named. */
static void check_camera(EffectMask present, int budget_spp, const char *defocus, ReconChoice *c)
{
    recon_select_budget(present, "auto", 9.4f, budget_spp, c);
    CHECK_STR(recon_choice_name(c, EFFECT_DEFOCUS), defocus);
    CHECK_STR(recon_choice_name(c, EFFECT_MOTION), "lr");
}

int main(void)
{
    EffectMask all = EFFECT_BIT(EFFECT_SOFT_SHADOWS) | EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_MOTION) |
                     EFFECT_BIT(EFFECT_INDIRECT);
    EffectMask motion_defocus = EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_MOTION);
    ReconChoice c;

    /* above the threshold (and exactly at it): lr for both camera effects, shading keeps aaf */
    float above[] = {RECON_LR_MIN_BLUR_PX, 9.4f};
    for (int k = 0; k < 2; ++k) {
        recon_select(all, "auto", above[k], &c);
        CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "lr");
        CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "lr");
        CHECK_STR(recon_choice_name(&c, EFFECT_SOFT_SHADOWS), "aaf");
        CHECK_STR(recon_choice_name(&c, EFFECT_INDIRECT), "aaf");
        CHECK(c.blur_px == above[k]);
    }
    recon_select(motion_defocus, "auto", 9.44f, &c);
    CHECK_STR(c.reason[EFFECT_MOTION], "lr: median blur 9.4 px >= 3 px, layered reconstruction shares samples "
                                       "across pixels (docs/benchmarks.md, issue 18)");

    /* a large --spp budget: lr keeps the motion alone, defocus goes to aaf; just under it, or
     * without a budget, lr takes both; below the blur threshold the budget changes nothing.
     * Without indirect light the threshold is RECON_LR_MAX_BUDGET_SPP, with it
     * RECON_LR_MAX_BUDGET_SPP_INDIRECT (aaf's lens filter then sees the bounce's noise too). */
    EffectMask direct_only = all & ~EFFECT_BIT(EFFECT_INDIRECT);
    CHECK(recon_lr_max_budget_spp(direct_only) == RECON_LR_MAX_BUDGET_SPP);
    CHECK(recon_lr_max_budget_spp(motion_defocus) == RECON_LR_MAX_BUDGET_SPP);
    CHECK(recon_lr_max_budget_spp(all) == RECON_LR_MAX_BUDGET_SPP_INDIRECT);
    CHECK(RECON_LR_MAX_BUDGET_SPP_INDIRECT > RECON_LR_MAX_BUDGET_SPP);
    check_camera(direct_only, RECON_LR_MAX_BUDGET_SPP, "aaf", &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_SOFT_SHADOWS), "aaf");
    CHECK_STR(c.reason[EFFECT_DEFOCUS], "aaf: a budget of 48 spp >= 48, where lr's bias outweighs its gain "
                                        "(docs/benchmarks.md, issue 18)");
    CHECK_STR(c.reason[EFFECT_MOTION], "lr, motion only: a budget of 48 spp >= 48, where lr's bias outweighs its gain "
                                       "for the lens (docs/benchmarks.md, issue 18)");
    /* with indirect light the same budget keeps lr for both, up to the higher threshold */
    int under_indirect[] = {RECON_LR_MAX_BUDGET_SPP, RECON_LR_MAX_BUDGET_SPP_INDIRECT - 1};
    for (int k = 0; k < 2; ++k) check_camera(all, under_indirect[k], "lr", &c);
    check_camera(all, RECON_LR_MAX_BUDGET_SPP_INDIRECT, "aaf", &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_INDIRECT), "aaf");
    CHECK_STR(c.reason[EFFECT_DEFOCUS], "aaf: a budget of 96 spp >= 96, where lr's bias outweighs its gain "
                                        "(docs/benchmarks.md, issue 18)");
    int under[] = {0, RECON_LR_MAX_BUDGET_SPP - 1};
    for (int k = 0; k < 2; ++k) check_camera(direct_only, under[k], "lr", &c);
    recon_select_budget(motion_defocus, "auto", 1.76f, 4096, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "aaf");
    CHECK_STR(c.reason[EFFECT_DEFOCUS], "aaf: median blur 1.8 px < 3 px, too little for lr to pay (docs/benchmarks.md, issue 18)");
    recon_select_budget(motion_defocus, "lr", 9.4f, 4096, &c); /* asked for: the budget does not matter */
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "lr");

    /* below: defocus aaf, the motion left to Monte Carlo (lr for it alone costs more CPU than
     * it saves), the value in the reasons */
    recon_select(motion_defocus, "auto", 1.76f, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "aaf");
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "none");
    CHECK_STR(c.reason[EFFECT_DEFOCUS], "aaf: median blur 1.8 px < 3 px, too little for lr to pay (docs/benchmarks.md, issue 18)");
    CHECK_STR(c.reason[EFFECT_MOTION], "none, auto fell back to Monte Carlo: median blur 1.8 px < 3 px, where lr's motion filter "
                                       "alone costs more CPU than it saves (docs/benchmarks.md, \"lr for the motion alone at "
                                       "equal CPU\")");
    recon_select(EFFECT_BIT(EFFECT_MOTION), "auto", 0.0f, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "none");
    recon_select(EFFECT_BIT(EFFECT_MOTION), "auto", RECON_LR_MIN_BLUR_PX, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "lr");
    recon_select(motion_defocus, "auto", nextafterf(RECON_LR_MIN_BLUR_PX, 0.0f), &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "aaf");

    /* not measured (negative, NaN): exactly the choice without the probe */
    ReconChoice before;
    recon_select(motion_defocus, "auto", -1.0f, &before);
    recon_select(motion_defocus, "auto", NAN, &c);
    CHECK_STR(recon_choice_name(&before, EFFECT_DEFOCUS), "aaf");
    CHECK_STR(recon_choice_name(&before, EFFECT_MOTION), "lr");
    CHECK(before.blur_px == -1.0f && c.blur_px == -1.0f);
    CHECK(!memcmp(before.reason, c.reason, sizeof c.reason));

    /* no motion: the value is ignored, the choice is the policy's row (maaf, test_select_lens.c) */
    EffectMask defocus = EFFECT_BIT(EFFECT_DEFOCUS);
    recon_select(defocus, "auto", 50.0f, &c);
    recon_select(defocus, "auto", -1.0f, &before);
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "maaf");
    CHECK(!memcmp(before.reason, c.reason, sizeof c.reason) && c.blur_px == -1.0f);
    CHECK(!recon_select_wants_blur(defocus, "auto"));

    /* explicit requests ignore it; a per-effect request lets auto decide the rest */
    recon_select(motion_defocus, "aaf", 50.0f, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "aaf");
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "none");
    recon_select(motion_defocus, "defocus=aaf", 50.0f, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "aaf");
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "lr");
    CHECK(recon_select_wants_blur(motion_defocus, "auto"));
    CHECK(recon_select_wants_blur(motion_defocus, "defocus=aaf"));
    CHECK(!recon_select_wants_blur(motion_defocus, "motion=lr,defocus=lr"));
    CHECK(!recon_select_wants_blur(motion_defocus, "lr"));
    CHECK(!recon_select_wants_blur(motion_defocus, "none"));
    return check_failures ? 1 : 0;
}
