#include "recon/filter_select.h"

#include <stdio.h>
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

/* The --filter values; a new filter adds its name here (and its policy to recon_filter_for). */
static const char *const FILTER_NAMES[] = {"auto", "aaf", "none"};
enum { FILTER_NAME_COUNT = sizeof FILTER_NAMES / sizeof FILTER_NAMES[0] };

bool recon_filter_known(const char *requested)
{
    for (int i = 0; i < FILTER_NAME_COUNT; ++i)
        if (!strcmp(requested, FILTER_NAMES[i])) return true;
    return false;
}

const char *recon_filter_choices(char *buf, size_t size)
{
    size_t len = 0;
    if (size) buf[0] = 0;
    for (int i = 0; i < FILTER_NAME_COUNT && len < size; ++i) {
        const char *sep = i == 0 ? "" : i == FILTER_NAME_COUNT - 1 ? " or " : ", ";
        int w = snprintf(buf + len, size - len, "%s%s", sep, FILTER_NAMES[i]);
        if (w < 0) break;
        len += (size_t)w;
    }
    return buf;
}

const char *recon_filter_for(const char *requested, const Effects *fx, int effect)
{
    if (!recon_effect_present(fx, effect) || !strcmp(requested, "none")) return "none";
    return effect == RECON_MOTION ? "none" : "aaf"; /* AAF has no motion filter */
}
