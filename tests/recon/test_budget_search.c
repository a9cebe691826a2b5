/* budget_search_mu (src/recon/budget_search.h): the mu whose plan spends a --spp budget.
 * Synthetic plan averages stand in for the pipeline's plans: power laws (the shape the search
 * assumes), a power law with an offset, a staircase and a curve that is flat over part of the
 * range (shapes it does not assume). For every budget the answer must keep the contract: the
 * ends when the budget lies outside the range, else a plan that fits the budget and lies within
 * the tolerance under it whenever the function reaches that window, with few plans on a power
 * law; and a failing plan must stop the search. */
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "recon/budget_search.h"

typedef struct {
    int shape;  /* 0 power law, 1 offset power law, 2 staircase, 3 flat then steep, 4 saturating */
    double k;   /* exponent */
    int calls;
    int fail_at; /* the call that fails (0: none) */
} Fn;

static double avg_of(const Fn *f, double mu)
{
    switch (f->shape) {
    case 0: return 4.0 * pow(mu, f->k);
    case 1: return 9.0 + 2.0 * pow(mu, f->k);
    case 2: return 4.0 * pow(2.0, floor(log2(mu)));    /* jumps: no mu lands between steps */
    case 3: return mu < 30.0 ? 8.0 : 8.0 * pow(mu / 30.0, 2.0); /* a plateau at 8 */
    default: return 2.0 + 3000.0 * (1.0 - exp(-mu / 400.0));  /* concave in log-log */
    }
}

static bool plan(void *ctx, float mu, double *avg)
{
    Fn *f = ctx;
    if (++f->calls == f->fail_at) return false;
    *avg = avg_of(f, mu);
    return true;
}

int main(void)
{
    const BudgetSearch s = {1.0f, 1.0e4f, 0.02, 16}; /* pipeline.c's settings */
    const double budgets[] = {2, 4, 5, 9, 12, 16, 23.5, 64, 100, 333, 1024, 5000, 1e6};
    const Fn shapes[] = {{0, 0.5, 0, 0}, {0, 1.0, 0, 0}, {0, 3.0, 0, 0}, {1, 0.7, 0, 0},
                          {2, 1, 0, 0}, {3, 1, 0, 0}, {4, 1, 0, 0}};
    for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; ++k)
        for (size_t b = 0; b < sizeof budgets / sizeof budgets[0]; ++b) {
            Fn f = shapes[k];
            float mu = -1.0f;
            int plans = 0;
            CHECK(budget_search_mu(&s, budgets[b], plan, &f, &mu, &plans));
            CHECK(plans == f.calls);
            CHECK(mu >= s.mu_lo && mu <= s.mu_hi);
            double a_lo = avg_of(&f, s.mu_lo), a_hi = avg_of(&f, s.mu_hi), a = avg_of(&f, mu);
            if (a_lo >= budgets[b]) {
                CHECK(mu == s.mu_lo && plans == 1);
            } else if (a_hi <= budgets[b]) {
                CHECK(mu == s.mu_hi && plans == 2);
            } else {
                CHECK(a <= budgets[b] * (1.0 + 1e-6)); /* the plan fits the budget */
                CHECK(plans <= s.max_steps + 2);
                /* continuous shapes, the plateau too, reach the tolerance window before the
                 * steps run out */
                if (f.shape != 2) CHECK(a >= budgets[b] / (1.0 + s.tolerance) * (1.0 - 1e-6));
                /* on a power law log A is a line: false position lands on the budget in one step,
                 * but mu's rounding to float can put that plan a hair above it; the steps after
                 * stay few (bisection took 12 between the ends) */
                if (f.shape == 0) CHECK(plans <= 2 + 4);
                /* where one end's value goes stale (a curve bending away from the line) the
                 * Illinois halving keeps the steps few: with it at most 6 and 8 plans, without
                 * the halving of the high end the offset power law took 8, without that of the
                 * low end the saturating curve took 14 */
                if (f.shape == 1) CHECK(plans <= 6);
                if (f.shape == 4) CHECK(plans <= 8);
                if (!(a <= budgets[b] * (1.0 + 1e-6)) || plans > s.max_steps + 2)
                    fprintf(stderr, "shape %d k %g budget %g: mu %g avg %g plans %d\n", f.shape, f.k, budgets[b],
                            (double)mu, a, plans);
            }
        }
    /* A failing plan stops the search and leaves *mu alone, at the first end, the second end
     * and inside the loop. */
    for (int fail = 1; fail <= 3; ++fail) {
        Fn f = {0, 1.0, 0, fail};
        float mu = -1.0f;
        int plans = -1;
        CHECK(!budget_search_mu(&s, 100.0, plan, &f, &mu, &plans));
        CHECK(mu == -1.0f);
        CHECK(plans == fail - 1);
    }
    CHECK_DONE();
}
