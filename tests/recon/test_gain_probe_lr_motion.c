/* The gain probe under LR's motion rule (gain_probe.h, probe_motion_rule.h; branch held4): where
 * LR would give a layer no motion filter, the probe's camera footprint leaves the motion out.
 * The same probe samples are read both ways (CameraBlurKinds.lr_motion_rule off and on):
 *  - on spin_defocus (a ball and a square spinning about their own axes: speeds that differ
 *    across each object, LR keeps no motion filter there) the rule lowers the frame's mean
 *    footprint and raises the predicted camera error: the filter is judged on the blur it
 *    really averages;
 *  - on motion_defocus_hard (objects translating: one speed a layer, LR shears them) it
 *    changes the predicted error by less than it does on spin_defocus;
 *  - Monte Carlo's own variance is the same either way (the rule changes what is read);
 *  - the probe asks for the rule exactly when auto's motion filter is LR's (above the blur
 *    threshold; below it auto leaves the motion to Monte Carlo). */
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "recon/gain_probe.h"
#include "recon/select.h"
#include "recon_test_util.h"

/* relative rise of the predicted camera error under the rule; -1 on failure */
static double probe_rise(const char *name)
{
    SceneDesc scene;
    Renderer *r = NULL;
    double rise = -1.0;
    if (recon_test_bench_renderer(name, 1, 8, &scene, &r)) { /* its own film: 160 x 120, 256 x 192 */
        GainProbe plain, ruled;
        CHECK(recon_gain_probe(r, false, false, (CameraBlurKinds){true, true, false, false}, &plain));
        CHECK(recon_gain_probe(r, false, false, (CameraBlurKinds){true, true, false, true}, &ruled));
        CHECK(plain.samples == ruled.samples && plain.samples > 0);
        CHECK(plain.totals.left[FILTER_GAIN_NONE] == ruled.totals.left[FILTER_GAIN_NONE]);
        /* the rule only takes motion out of a blur: no pixel's footprint grows */
        CHECK(ruled.totals.camera_footprint_sum <= plain.totals.camera_footprint_sum);
        double e_plain = filter_gain_camera_error_ratio(&plain.totals, FILTER_GAIN_NONE, 1.0);
        double e_ruled = filter_gain_camera_error_ratio(&ruled.totals, FILTER_GAIN_NONE, 1.0);
        printf("%s: mean footprint %.2f -> %.2f, camera error %.4f -> %.4f\n", name,
               plain.totals.camera_footprint_sum / plain.totals.pixels, ruled.totals.camera_footprint_sum / ruled.totals.pixels,
               e_plain, e_ruled);
        CHECK(e_ruled >= e_plain);
        rise = e_plain > 0.0 ? e_ruled / e_plain - 1.0 : -1.0;
        renderer_destroy(r);
        scene_desc_free(&scene);
    } else {
        CHECK(false);
    }
    return rise;
}

int main(void)
{
    /* the rule is asked for when auto's motion filter is LR's, with or without its lens */
    ReconChoice c;
    recon_select_budget(EFFECT_BIT(EFFECT_MOTION) | EFFECT_BIT(EFFECT_DEFOCUS), "auto", 8.0f, 8, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "lr");
    CHECK(recon_gain_probe_blur(&c).lr_motion_rule);
    /* below the blur threshold auto leaves the motion to Monte Carlo: nothing to judge it by */
    recon_select_budget(EFFECT_BIT(EFFECT_MOTION) | EFFECT_BIT(EFFECT_DEFOCUS), "auto", 1.0f, 8, &c);
    CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "none");
    CHECK(!recon_gain_probe_blur(&c).lr_motion_rule);
    recon_select_budget(EFFECT_BIT(EFFECT_DEFOCUS), "auto", -1.0f, 8, &c);
    CHECK(!recon_gain_probe_blur(&c).lr_motion_rule); /* no motion */

    double spin = probe_rise("spin_defocus"), hard = probe_rise("motion_defocus_hard");
    printf("rise of the predicted camera error: spin_defocus %.3f, motion_defocus_hard %.3f\n", spin, hard);
    CHECK(spin > 0.5);      /* the spinning objects' motion was most of their blur */
    CHECK(hard < spin / 4); /* translations: LR shears them, the rule leaves them */
    return check_failures ? 1 : 0;
}
