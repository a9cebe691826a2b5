/* The defocus row of --filter auto (recon/select.c, AUTO_POLICY and follow_maaf_lens): in a
 * frame without motion the lens goes to maaf, and the effects auto decides that maaf also
 * filters (soft shadows, indirect light) go with it, one adaptive filter per frame. With
 * motion the lens keeps aaf below lr's blur threshold, and so does the frame's shading (the
 * motion, measured below it, is left to Monte Carlo; without the probe it is lr's). An
 * effect named in the request keeps what was asked; a lens asked of maaf takes auto's shading
 * along, a lens asked of aaf does not. Every subset of the four effects is checked against
 * the rule written out here. Soft shadows as the frame's only effect go to maaf; beside any
 * other effect they stay aaf's unless the lens is maaf's. */
#include <string.h>

#include "../check.h"
#include "recon/select.h"

/* What the rule says auto gives effect e (present) when the request leaves it to auto; lens:
 * the frame's defocus method ("" when the frame has no lens); blur_px: the blur probe's median
 * (negative: no probe). */
static const char *expected(Effect e, EffectMask present, const char *lens, float blur_px)
{
    bool motion = effect_in(present, EFFECT_MOTION);
    switch (e) {
    case EFFECT_MOTION: /* measured below lr's threshold: left to Monte Carlo */
        return blur_px >= 0.0f && blur_px < RECON_LR_MIN_BLUR_PX ? "none" : "lr";
    case EFFECT_DEFOCUS:
        return motion ? "aaf" : "maaf";
    default: /* soft shadows, indirect light; soft shadows alone go to maaf too */
        return !strcmp(lens, "maaf") || present == EFFECT_BIT(EFFECT_SOFT_SHADOWS) ? "maaf" : "aaf";
    }
}

int main(void)
{
    ReconChoice c;
    for (EffectMask present = 0; present < (EffectMask)1 << EFFECT_COUNT; ++present) {
        bool lens = effect_in(present, EFFECT_DEFOCUS), motion = effect_in(present, EFFECT_MOTION);
        /* without a blur probe (wedge info) and with one below lr's threshold */
        float blur[] = {-1.0f, 1.8f};
        for (int b = 0; b < 2; ++b) {
            recon_select(present, "auto", blur[b], &c);
            const char *auto_lens = lens ? (motion ? "aaf" : "maaf") : "";
            for (int e = 0; e < EFFECT_COUNT; ++e) {
                if (!effect_in(present, (Effect)e)) {
                    CHECK(c.method[e] == NULL);
                    continue;
                }
                CHECK_STR(recon_choice_name(&c, (Effect)e), expected((Effect)e, present, auto_lens, blur[b]));
            }
        }
        if (!lens) continue;
        /* the lens asked for: maaf takes auto's shading along, aaf leaves it to aaf */
        const char *asked[] = {"maaf", "aaf"};
        for (int k = 0; k < 2; ++k) {
            char request[32];
            snprintf(request, sizeof request, "defocus=%s", asked[k]);
            recon_select(present, request, -1.0f, &c);
            CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), asked[k]);
            for (int e = 0; e < EFFECT_COUNT; ++e)
                if (effect_in(present, (Effect)e) && e != EFFECT_DEFOCUS)
                    CHECK_STR(recon_choice_name(&c, (Effect)e), expected((Effect)e, present, asked[k], -1.0f));
        }
        /* an effect named in the request keeps what was asked beside auto's maaf lens */
        if (!motion && effect_in(present, EFFECT_SOFT_SHADOWS)) {
            recon_select(present, "soft_shadows=aaf", -1.0f, &c);
            CHECK_STR(recon_choice_name(&c, EFFECT_SOFT_SHADOWS), "aaf");
            CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "maaf");
            CHECK(!strncmp(c.reason[EFFECT_SOFT_SHADOWS], "asked for", 9));
        }
    }
    /* the reasons name the measurement */
    EffectMask combined = EFFECT_BIT(EFFECT_SOFT_SHADOWS) | EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_INDIRECT);
    recon_select(combined, "auto", -1.0f, &c);
    CHECK(!strncmp(c.reason[EFFECT_DEFOCUS], "maaf: 1.84x Monte Carlo's speed", 31));
    CHECK(!strncmp(c.reason[EFFECT_INDIRECT], "maaf, with the lens: one adaptive filter per frame", 50));
    recon_select(EFFECT_BIT(EFFECT_SOFT_SHADOWS), "auto", -1.0f, &c);
    CHECK(!strncmp(c.reason[EFFECT_SOFT_SHADOWS], "maaf, soft shadows alone: 1.97x", 31));
    recon_select(EFFECT_BIT(EFFECT_SOFT_SHADOWS) | EFFECT_BIT(EFFECT_INDIRECT), "auto", -1.0f, &c);
    CHECK(!strncmp(c.reason[EFFECT_SOFT_SHADOWS], "aaf: 2.23x", 10));
    CHECK_DONE();
}
