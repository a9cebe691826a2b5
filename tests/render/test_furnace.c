/* The emission / direct / indirect split, by a furnace: the camera sits inside a closed
 * sphere whose inner surface emits L (ReverseOrientation makes the sphere emit inwards) and
 * reflects with albedo rho. Every point sees the emitting surface in every direction, so
 * the light after k reflections is rho^k L exactly:
 *   emission = L, direct = rho L, indirect = rho^2 L + ... + rho^(maxdepth) L.
 * This exercises sphere-light sampling from inside (uniform area) and MIS of BSDF rays that
 * hit the light. Each part must match within 1%. */
#include "check.h"
#include "render_test_util.h"

static void furnace(int max_depth, double L, double rho)
{
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0.3 -0.2 0.1  1 0.5 -0.3  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 1 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 1 ] \"integer yresolution\" [ 1 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 16384 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ %d ]\n"
             "WorldBegin\n"
             "AttributeBegin\n ReverseOrientation\n Material \"diffuse\" \"rgb reflectance\" [ %g %g %g ]\n"
             " AreaLightSource \"diffuse\" \"rgb L\" [ %g %g %g ]\n Shape \"sphere\" \"float radius\" [ 2 ]\nAttributeEnd\n",
             max_depth, rho, rho, rho, L, L, L);
    TestRender t;
    RenderOptions o = {0};
    o.seed = 13;
    o.sampler_set = true;
    o.sampler = SAMPLER_STRATIFIED;
    if (!test_render(text, &o, &t)) {
        CHECK(false);
        return;
    }
    double n = t.frame.spp[0];
    double em = t.frame.emission[0] / n, di = t.frame.direct[0] / n, in = t.frame.indirect[0] / n;
    double want_in = 0.0;
    for (int k = 2; k <= max_depth; ++k) want_in += pow(rho, k) * L;
    fprintf(stderr, "maxdepth %d: emission %.5f (%.5f) direct %.5f (%.5f) indirect %.5f (%.5f)\n", max_depth, em, L, di,
            rho * L, in, want_in);
    CHECK_NEAR(em / L, 1.0, 1e-6);
    CHECK_NEAR(di / (rho * L), 1.0, 0.01);
    if (max_depth >= 2)
        CHECK_NEAR(in / want_in, 1.0, 0.01);
    else
        CHECK(in == 0.0);
    CHECK(test_frame_finite(&t.frame));
    test_render_free(&t);
}

int main(void)
{
    furnace(1, 1.5, 0.5);
    furnace(2, 1.5, 0.5);
    furnace(3, 1.0, 0.7);
    CHECK_DONE();
}
