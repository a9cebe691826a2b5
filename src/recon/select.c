/* The policy (see select.h). */
#include "recon/select.h"

#include <stdio.h>
#include <string.h>

/* --filter auto: per effect, the method with the best equal-error time against Monte Carlo
 * on the bench scene of that effect (docs/benchmarks.md, "AAF against Monte Carlo": at
 * 256x256, 9.9x for soft shadows, 3.2x for defocus, 13.8x for indirect light, the lower of
 * the stratified and Sobol' baselines). A method that lands adds its measured row here and
 * wins an effect only where its measured speedup is higher. */
static const struct {
    Effect effect;
    const char *method;
    const char *reason;
} AUTO_POLICY[] = {
    {EFFECT_SOFT_SHADOWS, "aaf", "aaf: 9.9x less time than Monte Carlo at equal error (soft-shadow bench, 256x256)"},
    {EFFECT_DEFOCUS, "aaf", "aaf: 3.2x less time than Monte Carlo at equal error (defocus bench, 256x256)"},
    {EFFECT_INDIRECT, "aaf", "aaf: 13.8x less time than Monte Carlo at equal error (indirect bench, 256x256)"},
};

static const char *const NO_METHOD_REASON[EFFECT_COUNT] = {
    [EFFECT_SOFT_SHADOWS] = "no registered method filters soft shadows",
    [EFFECT_DEFOCUS] = "no registered method filters defocus",
    [EFFECT_MOTION] = "lr filters it with --filter lr; auto leaves it: lr is 0.7x Monte Carlo's speed at equal error on the mild motion+defocus bench, 2.1x on the hard one (256x192, 8 spp)",
    [EFFECT_INDIRECT] = "no registered method filters indirect light",
};

void recon_select(EffectMask present, const char *request, ReconChoice *out)
{
    memset(out, 0, sizeof *out);
    bool none = !strcmp(request, "none"), autom = !strcmp(request, "auto");
    const ReconMethodClass *asked = (none || autom) ? NULL : recon_method_find(request);
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (!effect_in(present, (Effect)e)) continue;
        if (none) {
            out->reason[e] = "--filter none: plain Monte Carlo";
        } else if (asked) {
            bool can = effect_in(asked->effects, (Effect)e);
            out->method[e] = can ? asked : NULL;
            out->reason[e] = can ? "asked for with --filter" : "the method asked for with --filter cannot filter it";
        } else if (autom) {
            out->reason[e] = NO_METHOD_REASON[e];
            for (size_t k = 0; k < sizeof AUTO_POLICY / sizeof AUTO_POLICY[0]; ++k) {
                const ReconMethodClass *m = recon_method_find(AUTO_POLICY[k].method);
                if (AUTO_POLICY[k].effect == (Effect)e && m && effect_in(m->effects, (Effect)e)) {
                    out->method[e] = m;
                    out->reason[e] = AUTO_POLICY[k].reason;
                    break;
                }
            }
        } else {
            out->reason[e] = "unknown --filter";
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

bool recon_filter_known(const char *request)
{
    return !strcmp(request, "auto") || !strcmp(request, "none") || recon_method_find(request) != NULL;
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
    return buf;
}
