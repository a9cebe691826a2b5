/* The mu that spends a --spp budget: a search over the plans' average (pipeline.c's
 * mu_for_budget; docs/algorithms.md 2.6).
 *
 * The average number of samples a plan asks for, A(mu), grows with mu and is close to a power
 * law, so log A against log mu is nearly a line. The search evaluates the ends first (a budget
 * at or below A(mu_lo) gives mu_lo, at or above A(mu_hi) gives mu_hi), then takes false-position
 * steps on that line (the Illinois variant: an end that stays put twice in a row has its value
 * halved, so the steps cannot stall on one side) and stops at the first mu whose plan lies within
 * `tolerance` under the budget, or after `max_steps` steps. The answer is always a mu whose plan
 * fits the budget (A <= budget) unless mu_lo's plan already exceeds it, as bisection's was. */
#ifndef WEDGE_RECON_BUDGET_SEARCH_H
#define WEDGE_RECON_BUDGET_SEARCH_H

#include <stdbool.h>

/* One plan at mu: its average samples per pixel into *avg; false on failure (the search stops). */
typedef bool (*BudgetPlanFn)(void *ctx, float mu, double *avg);

typedef struct {
    float mu_lo, mu_hi; /* the range searched, 0 < mu_lo < mu_hi */
    double tolerance;   /* relative: stop at a plan in [budget / (1 + tolerance), budget] */
    int max_steps;      /* plans between the ends at most */
} BudgetSearch;

/* The mu for `budget` into *mu; false when a plan failed. *plans (may be NULL) counts the plans made. */
bool budget_search_mu(const BudgetSearch *s, double budget, BudgetPlanFn plan, void *ctx, float *mu, int *plans);

#endif
