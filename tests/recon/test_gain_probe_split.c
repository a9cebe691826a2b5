/* The gain probe with split pixels (gain_probe.h; docs/algorithms.md 4.6 and "auto's fallback
 * to Monte Carlo"): where the frame's filters take a mixed pixel's first surface, the probe
 * must count that surface's light as filterable, as the G-buffer will, and nothing more.
 *
 * On foreground_bars at 64 x 64 (a defocused fence over most of the frame) the same probe
 * samples are read both ways:
 *   - Monte Carlo's own variance and the samples are the same (the split changes what is
 *     read, not what is traced);
 *   - with the split, no configuration leaves more variance than without it (a split pixel
 *     never adds variance; an unsplit mixed pixel keeps all of its);
 *   - with the split, most mixed pixels become filterable and the share of variance the
 *     shadow filter can remove rises;
 * and on soft_shadows (no lens: mixed pixels only along silhouettes) the first two hold too. */
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "recon/gain_probe.h"
#include "recon_test_util.h"

enum { RES = 64 };

static bool probe_both(const char *name, GainProbe *whole, GainProbe *split)
{
    char *text = recon_test_bench_scene_at(name, RES);
    CHECK(text != NULL);
    if (!text) return false;
    SceneDesc scene;
    Renderer *r = NULL;
    bool ok = recon_test_renderer(text, 1, 16, false, &scene, &r);
    CHECK(ok);
    if (ok) {
        CHECK(recon_gain_probe(r, false, false, (CameraBlurKinds){false, false, false, false}, whole));
        CHECK(recon_gain_probe(r, true, true, (CameraBlurKinds){false, false, false, false}, split));
        /* the same samples read two ways */
        CHECK(whole->samples == split->samples && whole->samples > 0);
        CHECK(whole->totals.left[FILTER_GAIN_NONE] == split->totals.left[FILTER_GAIN_NONE]);
        for (int c = 0; c < FILTER_GAIN_CONFIGS; ++c) CHECK(split->totals.left[c] <= whole->totals.left[c]);
        renderer_destroy(r);
        scene_desc_free(&scene);
    }
    free(text);
    return ok;
}

int main(void)
{
    GainProbe whole, split;
    if (probe_both("foreground_bars", &whole, &split)) {
        const FilterGainTotals *a = &whole.totals, *b = &split.totals;
        double sa = filter_gain_share(a, FILTER_GAIN_DIRECT), sb = filter_gain_share(b, FILTER_GAIN_DIRECT);
        printf("foreground_bars: filterable pixels %d -> %d of %d, direct share %.3f -> %.3f\n", a->pixels_filterable,
               b->pixels_filterable, a->pixels, sa, sb);
        /* the fence mixes most pixels (test_split_pipeline: 60% and more get split) */
        CHECK(a->pixels_filterable < a->pixels / 2);
        CHECK(b->pixels_filterable >= 2 * a->pixels_filterable);
        CHECK(sb > 1.5 * sa);
    }
    if (probe_both("soft_shadows", &whole, &split)) {
        double sa = filter_gain_share(&whole.totals, FILTER_GAIN_DIRECT);
        double sb = filter_gain_share(&split.totals, FILTER_GAIN_DIRECT);
        printf("soft_shadows: filterable pixels %d -> %d of %d, direct share %.3f -> %.3f\n",
               whole.totals.pixels_filterable, split.totals.pixels_filterable, whole.totals.pixels, sa, sb);
    }
    CHECK_DONE();
}
