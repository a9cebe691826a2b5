/* The shadow rays of an emitting mesh's lanes (the wave's mesh group, mesh_shadow_rays) end
 * just off each lane's own triangle, not further: a sheet a little below a 32-triangle panel
 * light (0.05 under it, each triangle's area 0.125) hides the panel from the floor
 * completely, so with direct light only (maxdepth 1) the floor is black, exactly. A ray whose
 * far end were pushed by another length than the triangle's surface offset (its area, say)
 * or on the wrong side would end below the sheet and light the floor. Without the sheet the
 * floor is lit (the control), and shadow rays are traced in both renders. */
#include "check.h"
#include "render_test_util.h"

enum { COLS = 4, ROWS = 4 }; /* 4 x 4 quads of 0.5 x 0.5: 32 triangles of area 0.125 */

/* the panel's points: 0.5 apart at height 2; test_grid_mesh's winding faces down (-y), towards the floor */
static void panel_at(void *ctx, int c, int r, double p[3])
{
    (void)ctx;
    p[0] = -1.0 + 0.5 * c, p[1] = 2.0, p[2] = -1.0 + 0.5 * r;
}

static double render_floor(bool sheet, long long *rays_shadow)
{
    char text[8192] = "LookAt 0 1 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 20 ]\n"
                      "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
                      "Sampler \"independent\" \"integer pixelsamples\" [ 16 ]\n"
                      "Integrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
                      "AttributeBegin\n  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                      "  Shape \"trianglemesh\" \"point3 P\" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
                      "AttributeEnd\n"
                      "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n  Shape \"trianglemesh\" ";
    bool ok = test_grid_mesh(text, sizeof text, COLS, ROWS, panel_at, NULL);
    size_t len = strlen(text);
    ok = ok && test_appendf(text, sizeof text, &len, "\nAttributeEnd\n%s",
                           sheet ? "AttributeBegin\n  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                                   "  Shape \"trianglemesh\" \"point3 P\" [ -1.5 1.95 -1.5  1.5 1.95 -1.5  1.5 1.95 1.5  -1.5 1.95 1.5 ]"
                                   " \"integer indices\" [ 0 1 2 0 2 3 ]\nAttributeEnd\n"
                                 : "");
    CHECK(ok);
    TestRender t;
    RenderOptions o = {0};
    o.threads = 2;
    o.seed = 3;
    if (!test_render(text, &o, &t)) return -1.0;
    CHECK(test_frame_finite(&t.frame));
    double mean = test_mean(&t);
    *rays_shadow = t.stats.rays_shadow;
    test_render_free(&t);
    return mean;
}

int main(void)
{
    long long rays_open = 0, rays_sheet = 0;
    double open = render_floor(false, &rays_open), hidden = render_floor(true, &rays_sheet);
    fprintf(stderr, "floor without the sheet %g, under it %g (shadow rays %lld / %lld)\n", open, hidden, rays_open,
            rays_sheet);
    CHECK(open > 0.05);
    CHECK(hidden == 0.0);
    CHECK(rays_open > 1000 && rays_sheet > 1000);
    CHECK_DONE();
}
