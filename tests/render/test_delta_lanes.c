/* The delta lights lit at every vertex are computed for a whole wave in vectorised loops
 * over every path's lane (integrator.c: WaveReceivers, WaveDeltaSamples, point_lambert_lanes,
 * distant_lambert_lanes, delta_lanes_sum), and for glossy receivers path by path. With
 * WEDGE_DELTA_BY_PATH=1 every receiver takes the path-by-path route (light_prepare_sampled
 * and light_prepare_at, the code the lanes replaced for Lambert receivers): the two renders
 * must give the same frames bit for bit and the same ray and guard counts, for whole records
 * and for the radiance alone.
 *
 * The scenes give the lanes what they must get right: a point, a spot and a distant light
 * together (the order of their values in each path's sum), receivers facing towards and away
 * from each light (a distant light from below the floor's horizon lights only the spheres'
 * lower sides), one-sided panels seen and lit from either side of their geometric
 * normal, a light with a zero channel, Lambert and
 * glossy receivers at the first and second vertex (maxdepth 2: lanes of paths that died or
 * that moved to a new vertex), a checkerboard albedo, and camera rays that miss. */
#include "check.h"
#include "render_test_util.h"

#include "render/render_reads.h"

static const char *SCENE =
    "LookAt 0 2.2 -5  0 0.4 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 50 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ %d ]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [ 6 5 0 ] \"point3 from\" [ 1.2 2.5 -1 ]\n"
    "LightSource \"spot\" \"rgb I\" [ 9 9 9 ] \"point3 from\" [ -1.5 3 -1.5 ] \"point3 to\" [ 0 0 0 ]\n"
    "  \"float coneangle\" [ 25 ] \"float conedelta\" [ 8 ]\n"
    "LightSource \"distant\" \"rgb L\" [ 0.7 0.6 0.5 ] \"point3 from\" [ -1 3 -2 ] \"point3 to\" [ 0 0 0 ]\n"
    "LightSource \"distant\" \"rgb L\" [ 0.3 0.3 0.4 ] \"point3 from\" [ 1 -2 -1 ] \"point3 to\" [ 0 0 0 ]\n"
    "AttributeBegin\n"
    "  Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 8 ] \"float vscale\" [ 8 ]\n"
    "          \"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.1 0.2 0.1 ]\n"
    "  Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] \"integer indices\" [ 0 2 1  0 3 2 ]\n"
    "        \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]\n"
    "AttributeEnd\n"
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.3 0.2 ]\n"
    "  Translate -0.8 0.6 0 Shape \"sphere\" \"float radius\" [ 0.6 ] AttributeEnd\n"
    "AttributeBegin Material \"conductor\" \"float roughness\" [ 0.3 ]\n"
    "  Translate 0.8 0.5 0.3 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n"
    "AttributeBegin Material \"coateddiffuse\" \"rgb reflectance\" [ 0.2 0.5 0.7 ] \"float roughness\" [ 0.2 ]\n"
    "  Translate 0 0.3 1.2 Shape \"sphere\" \"float radius\" [ 0.3 ] AttributeEnd\n"
    /* one-sided panels, wound either way, seen and lit from the camera's side */
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ 1.4 0 -0.4  2.4 0 0.4  2.4 1.5 0.4  1.4 1.5 -0.4 ]\n"
    "        \"integer indices\" [ 0 1 2  0 2 3 ] AttributeEnd\n"
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -2.4 0 0.4  -1.4 0 -0.4  -1.4 1.5 -0.4  -2.4 1.5 0.4 ]\n"
    "        \"integer indices\" [ 0 2 1  0 3 2 ] AttributeEnd\n"
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "  Translate 0 1.6 0.8 Scale 1.5 0.05 0.4\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 ]\n"
    "        \"integer indices\" [ 0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  3 7 6  3 6 2  0 4 7  0 7 3  1 2 6  1 6 5 ]\n"
    "AttributeEnd\n";

static bool same_floats(const float *a, const float *b, size_t n) { return memcmp(a, b, n * sizeof *a) == 0; }

/* The scene at maxdepth depth rendered by the lanes and by paths (reads: what the frame
 * asks of the records); every frame buffer the renders fill and every counter equal. */
static void check_depth(int depth, unsigned reads)
{
    char text[8192];
    snprintf(text, sizeof text, SCENE, depth);
    RenderOptions o = {0};
    o.width = 40, o.height = 30, o.threads = 2, o.seed = 11, o.reads = reads;
    TestRender lanes, paths;
    unsetenv("WEDGE_DELTA_BY_PATH");
    bool ok = test_render(text, &o, &lanes);
    setenv("WEDGE_DELTA_BY_PATH", "1", 1);
    ok = test_render(text, &o, &paths) && ok;
    unsetenv("WEDGE_DELTA_BY_PATH");
    CHECK(ok);
    if (!ok) return;
    CHECK(renderer_integrator_scene(lanes.r)->lights->delta_every_count == 4);
    size_t n = (size_t)o.width * (size_t)o.height;
    const Frame *a = &lanes.frame, *b = &paths.frame;
    CHECK(same_floats(a->color, b->color, 3 * n));
    CHECK(same_floats(a->direct, b->direct, 3 * n) && same_floats(a->indirect, b->indirect, 3 * n));
    CHECK(same_floats(a->emission, b->emission, 3 * n) && same_floats(a->spp, b->spp, n));
    RenderStats x = lanes.stats, y = paths.stats;
    CHECK(x.rays_primary == y.rays_primary && x.rays_shadow == y.rays_shadow && x.rays_indirect == y.rays_indirect &&
          x.rays_bsdf == y.rays_bsdf && x.guarded_events == y.guarded_events && x.samples == y.samples);
    /* the scene exercises what it claims: light everywhere lit, misses, shadow rays */
    double sum = 0.0;
    for (size_t i = 0; i < 3 * n; ++i) sum += a->color[i];
    int dark = 0;
    for (size_t i = 0; i < n; ++i) dark += a->color[3 * i] == 0.0f && a->color[3 * i + 1] == 0.0f;
    CHECK(sum > 0.0 && test_frame_finite(a) && dark > 0);
    CHECK(x.rays_shadow > x.rays_primary);
    fprintf(stderr, "maxdepth %d, reads %d: shadow rays %lld, guarded %lld, mean %.5f, dark pixels %d\n", depth,
            (int)reads, x.rays_shadow, x.guarded_events, sum / (3.0 * (double)n), dark);
    test_render_free(&lanes), test_render_free(&paths);
}

int main(void)
{
    check_depth(1, RENDER_READS_RADIANCE);
    check_depth(2, RENDER_READS_RADIANCE);
    check_depth(2, RENDER_READS_ALL);
    CHECK_DONE();
}
