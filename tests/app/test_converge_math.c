/* The reference-cache hash and the equal-error speedup arithmetic of `wedge converge`. */
#include <math.h>
#include <string.h>

#include "app/converge_speedup.h"
#include "app/ref_cache.h"
#include "check.h"

int main(void)
{
    /* FNV-1a 64 published test vectors (Fowler/Noll/Vo reference test suite). */
    CHECK(fnv1a64("", 0, FNV1A64_OFFSET) == 0xcbf29ce484222325ull);
    CHECK(fnv1a64("a", 1, FNV1A64_OFFSET) == 0xaf63dc4c8601ec8cull);
    CHECK(fnv1a64("foobar", 6, FNV1A64_OFFSET) == 0x85944171f73967e8ull);

    /* Keys: tagged, length-prefixed fields; field boundaries matter. */
    RefKeyHash a, b;
    char ha[33], hb[33];
    ref_key_init(&a);
    ref_key_add_string(&a, "s", "ab");
    ref_key_add_string(&a, "s", "c");
    ref_key_init(&b);
    ref_key_add_string(&b, "s", "a");
    ref_key_add_string(&b, "s", "bc");
    ref_key_hex(&a, ha);
    ref_key_hex(&b, hb);
    CHECK(strlen(ha) == 32);
    CHECK(strcmp(ha, hb) != 0);
    ref_key_init(&b);
    ref_key_add_string(&b, "s", "ab");
    ref_key_add_string(&b, "s", "c");
    ref_key_hex(&b, hb);
    CHECK_STR(ha, hb);
    ref_key_init(&b);
    ref_key_add_int(&b, "spp", 64);
    ref_key_hex(&b, hb);
    ref_key_init(&a);
    ref_key_add_int(&a, "spp", 65);
    ref_key_hex(&a, ha);
    CHECK(strcmp(ha, hb) != 0);

    /* Log-log slope of an exact power law y = 3 x^-1.25. */
    double x[4] = {4, 16, 64, 256}, y[4];
    for (int i = 0; i < 4; ++i) y[i] = 3.0 * pow(x[i], -1.25);
    CHECK_NEAR(loglog_slope(x, y, 4), -1.25, 1e-12);
    CHECK(isnan(loglog_slope(x, y, 1)));

    /* Equal-error cost on an exact baseline error = 0.5 / spp, seconds = 0.01 spp:
     * log-log interpolation is exact on a power law, so the cost at error e is spp = 0.5/e. */
    CurvePoint mc[4] = {{64, 0.64, 0.5 / 64}, {4, 0.04, 0.5 / 4}, {256, 2.56, 0.5 / 256}, {16, 0.16, 0.5 / 16}};
    EqualErrorCost c = equal_error_cost(mc, 4, 0.5 / 40.0);
    CHECK(c.valid && !c.extrapolated);
    CHECK_NEAR(c.spp, 40.0, 1e-9);
    CHECK_NEAR(c.seconds, 0.4, 1e-11);
    /* A method at 10 spp reaching the error of 40 baseline spp: 4x fewer samples. */
    CHECK_NEAR(c.spp / 10.0, 4.0, 1e-9);
    /* Beyond the measured range the end segment is extended and flagged. */
    c = equal_error_cost(mc, 4, 0.5 / 1024.0);
    CHECK(c.valid && c.extrapolated);
    CHECK_NEAR(c.spp, 1024.0, 1e-6);
    c = equal_error_cost(mc, 4, 0.5 / 2.0);
    CHECK(c.valid && c.extrapolated);
    CHECK_NEAR(c.spp, 2.0, 1e-9);
    /* Unusable inputs. */
    CHECK(!equal_error_cost(mc, 1, 0.01).valid);
    CHECK(!equal_error_cost(mc, 4, 0.0).valid);
    CHECK(!equal_error_cost(mc, 4, NAN).valid);
    CurvePoint flat[2] = {{4, 1, 0.1}, {16, 4, 0.1}};
    CHECK(!equal_error_cost(flat, 2, 0.05).valid);
    CHECK_DONE();
}
