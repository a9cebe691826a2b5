/* The method table of `wedge converge` (see converge_methods.h). */
#include "app/converge_methods.h"

#include <string.h>

static const ConvergeMethod methods[] = {
    {"mc", {"--sampler", "stratified", "--filter", "none", NULL}, false,
     "unfiltered Monte Carlo, stratified (jittered) samples"},
    {"mc-ld", {"--sampler", "sobol", "--filter", "none", NULL}, false,
     "unfiltered Monte Carlo, Owen-scrambled Sobol' samples"},
    /* The renderer's default: each effect gets the method select.c's policy gives it (issue
     * 18). Adaptive when that includes AAF, so it takes --mu like aaf. */
    {"auto", {"--sampler", "stratified", "--filter", "auto", NULL}, true,
     "each effect filtered by the method the policy picks (wedge info shows which)"},
    {"auto-ld", {"--sampler", "sobol", "--filter", "auto", NULL}, true,
     "the policy's methods with Owen-scrambled Sobol' samples"},
    /* Filters: the filter picks its own per-pixel sample counts from mu (--spp is then only a
     * label of the run; spp_avg in the results is what it really used). */
    {"aaf", {"--sampler", "stratified", "--filter", "aaf", NULL}, true,
     "axis-aligned filtering (papers 001, 002) of every effect the scene has"},
    {"aaf-ld", {"--sampler", "sobol", "--filter", "aaf", NULL}, true,
     "axis-aligned filtering with Owen-scrambled Sobol' samples"},
    /* fixed-count filters: --spp is the samples per pixel they take */
    {"lr", {"--sampler", "stratified", "--filter", "lr", NULL}, false,
     "layered reconstruction (paper 004) of defocus and motion blur"},
    {"lr-ld", {"--sampler", "sobol", "--filter", "lr", NULL}, false,
     "layered reconstruction with Owen-scrambled Sobol' samples"},
    {"maaf", {"--sampler", "stratified", "--filter", "maaf", NULL}, true,
     "multiple axis-aligned filters (paper 003) of soft shadows and defocus"},
    {"maaf-ld", {"--sampler", "sobol", "--filter", "maaf", NULL}, true,
     "multiple axis-aligned filters with Owen-scrambled Sobol' samples"},
    {"fsf", {"--sampler", "stratified", "--filter", "fsf", NULL}, false,
     "fast 4D sheared filtering (paper 000) of soft shadows, indirect light and defocus"},
    {"fsf-ld", {"--sampler", "sobol", "--filter", "fsf", NULL}, false,
     "fast 4D sheared filtering with Owen-scrambled Sobol' samples"},
};

/* Both Monte Carlo methods are baselines: at equal error the faster sampler differs with spp
 * and scene (docs/sampling.md), and a speedup is quoted against the stronger of the two. */
const char *const converge_baseline_methods[] = {"mc", "mc-ld"};
const int converge_baseline_method_count = 2;

const char *const converge_reference_args[] = {"--sampler", "sobol", "--filter", "none"};
const int converge_reference_arg_count = 4;

int converge_method_count(void) { return (int)(sizeof methods / sizeof methods[0]); }

const ConvergeMethod *converge_method_at(int i)
{
    return i >= 0 && i < converge_method_count() ? &methods[i] : NULL;
}

const ConvergeMethod *converge_method_find(const char *name)
{
    for (int i = 0; i < converge_method_count(); ++i)
        if (!strcmp(methods[i].name, name)) return &methods[i];
    return NULL;
}
