/* The mu that spends a --spp budget (see budget_search.h). */
#include "recon/budget_search.h"

#include <math.h>

/* log(avg / budget): the signed distance of a plan from the budget on the log scale */
static double log_gap(double avg, double budget) { return log(fmax(avg, 1e-9)) - log(budget); }

bool budget_search_mu(const BudgetSearch *s, double budget, BudgetPlanFn plan, void *ctx, float *mu, int *plans)
{
    int made = 0;
    double avg;
    bool ok = true;
    float answer = s->mu_lo;
    if (!(ok = plan(ctx, s->mu_lo, &avg))) goto done;
    ++made;
    if (avg >= budget) goto done; /* most budgets of a fast render: no search */
    double x_lo = log(s->mu_lo), f_lo = log_gap(avg, budget);
    if (!(ok = plan(ctx, s->mu_hi, &avg))) goto done;
    ++made;
    if (avg <= budget) {
        answer = s->mu_hi;
        goto done;
    }
    double x_hi = log(s->mu_hi), f_hi = log_gap(avg, budget);
    int last_side = 0;
    for (int it = 0; it < s->max_steps; ++it) {
        double x = (x_lo * f_hi - x_hi * f_lo) / (f_hi - f_lo);
        if (!(x > x_lo && x < x_hi)) x = 0.5 * (x_lo + x_hi); /* rounding at a flat end */
        if (!(ok = plan(ctx, (float)exp(x), &avg))) goto done;
        ++made;
        double f = log_gap(avg, budget);
        int side = f > 0.0 ? 1 : -1;
        if (side > 0) {
            x_hi = x, f_hi = f;
            if (last_side > 0) f_lo *= 0.5;
        } else {
            x_lo = x, f_lo = f;
            if (f >= -log1p(s->tolerance)) break;
            if (last_side < 0) f_hi *= 0.5;
        }
        last_side = side;
    }
    answer = (float)exp(x_lo);
done:
    if (ok) *mu = answer;
    if (plans) *plans = made;
    return ok;
}
