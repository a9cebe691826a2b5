#include "recon/filter_select.h"

#include <string.h>

const char *recon_effect_name(int effect)
{
    static const char *const names[RECON_EFFECT_COUNT] = {"soft_shadows", "defocus", "motion", "indirect"};
    return effect >= 0 && effect < RECON_EFFECT_COUNT ? names[effect] : "?";
}

bool recon_effect_present(const Effects *fx, int effect)
{
    switch (effect) {
    case RECON_SOFT_SHADOWS: return fx->soft_shadows;
    case RECON_DEFOCUS: return fx->defocus;
    case RECON_MOTION: return fx->motion;
    case RECON_INDIRECT: return fx->indirect;
    default: return false;
    }
}

bool recon_filter_known(const char *requested)
{
    return !strcmp(requested, "auto") || !strcmp(requested, "aaf") || !strcmp(requested, "none");
}

const char *recon_filter_choices(void) { return "auto, aaf or none"; }

const char *recon_filter_for(const char *requested, const Effects *fx, int effect)
{
    if (!recon_effect_present(fx, effect) || !strcmp(requested, "none")) return "none";
    return effect == RECON_MOTION ? "none" : "aaf"; /* AAF has no motion filter */
}
