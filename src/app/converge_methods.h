/* The methods `wedge converge` can sweep. A method is a name, the extra `wedge render`
 * arguments that select it, and whether it takes the mu knob (DESIGN.md section 4: larger
 * mu, more samples and smaller filters). A filter registers itself with the harness by
 * adding one row to the table in converge_methods.c. */
#ifndef WEDGE_APP_CONVERGE_METHODS_H
#define WEDGE_APP_CONVERGE_METHODS_H

#include <stdbool.h>

#define CONVERGE_MAX_METHOD_ARGS 8

typedef struct {
    const char *name;
    const char *render_args[CONVERGE_MAX_METHOD_ARGS]; /* NULL-terminated */
    bool takes_mu;          /* swept over --mu LIST, passed to render as "--mu X" */
    const char *summary;
} ConvergeMethod;

/* The Monte Carlo methods that equal-error speedups are measured against, each on its own
 * (speedup.csv has a row per run and baseline). */
extern const char *const converge_baseline_methods[];
extern const int converge_baseline_method_count;

/* NULL when unknown. */
const ConvergeMethod *converge_method_find(const char *name);
int converge_method_count(void);
const ConvergeMethod *converge_method_at(int i);
/* The render arguments of references: the low-discrepancy sampler converges fastest, and
 * it is unbiased, so it is as good a reference for a stratified sweep as for itself (the
 * reference seed differs from every run's seed, so the errors are independent). */
extern const char *const converge_reference_args[];
extern const int converge_reference_arg_count;

#endif
