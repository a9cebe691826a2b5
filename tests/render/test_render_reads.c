/* The users' declaration of what they read (render/render_reads.h, issue 22): a render whose
 * users read the radiance alone skips the first-hit record fields, the records' unfiltered
 * parts and the frame's albedo, normal, depth and hits sums, and nothing else. Checked here on a scene with a lens, glossy, diffuse and dielectric surfaces,
 * an area light beside a point light, and bounces:
 *  - declared radiance only: colour, direct, indirect, emission and spp bit for bit those of
 *    an undeclared render (which keeps everything; the split adds up to the colour), and the
 *    frame says its guides were skipped (albedo, normal, depth and hits left at 0: the work
 *    was really skipped);
 *  - declared frame guides: every sum bit for bit the undeclared render's;
 *  - declared first hit: a sink sees every record field the undeclared render gives it
 *    (the first-hit fields, the unfiltered parts, nonzero here, and the radiance split);
 *  - the same renderer declared everything again after a skipped pass (renderer_set_reads,
 *    frame_clear) gives the full frame: a later user that needs the AOVs gets them;
 *  - a frame made with fewer planes (frame_init_planes: the colour and the counts, with or
 *    without the parts and the guides) gets every sum it holds bit for bit the full frame's,
 *    under every declaration; the planes it lacks stay NULL. */
#include "check.h"
#include "render/render_reads.h"
#include "render_test_util.h"

static const char *SCENE_TEXT =
    "LookAt 0 1.5 -5  0 0.3 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.08 ] \"float focaldistance\" [ 4 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 16 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 8 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 3 ]\n"
    "WorldBegin\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 6 6 6 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5 ]\n"
    "  \"integer indices\" [ 0 2 1 0 3 2 ] AttributeEnd\n"
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.5 0.4 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin Material \"conductor\" \"float roughness\" [ 0.15 ]\n"
    "  Translate -0.8 0.6 0 Shape \"sphere\" \"float radius\" [ 0.6 ] AttributeEnd\n"
    "AttributeBegin Material \"coateddiffuse\" \"rgb reflectance\" [ 0.2 0.5 0.7 ] \"float roughness\" [ 0.3 ]\n"
    "  Translate 0.9 0.5 0.5 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd\n"
    /* a dielectric first hit's light and a point light's beside the area light's are the
     * records' unfiltered parts (sample_record.h) */
    "AttributeBegin Material \"dielectric\" \"float eta\" [ 1.5 ]\n"
    "  Translate 0 0.35 -1.2 Shape \"sphere\" \"float radius\" [ 0.35 ] AttributeEnd\n"
    "LightSource \"point\" \"point3 from\" [ 1.5 2 -1.5 ] \"rgb I\" [ 2 2 2 ]\n";

static bool same_floats(const float *a, const float *b, size_t n) { return memcmp(a, b, n * sizeof(float)) == 0; }

static bool same_radiance(const Frame *a, const Frame *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return same_floats(a->color, b->color, 3 * n) && same_floats(a->direct, b->direct, 3 * n) &&
           same_floats(a->indirect, b->indirect, 3 * n) && same_floats(a->emission, b->emission, 3 * n) &&
           same_floats(a->spp, b->spp, n);
}

static bool same_guides(const Frame *a, const Frame *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return same_floats(a->albedo, b->albedo, 3 * n) && same_floats(a->normal, b->normal, 3 * n) &&
           same_floats(a->depth, b->depth, n) && same_floats(a->hits, b->hits, n);
}

/* The sum of the absolute values of the frame's guide sums (0: nothing was added). */
static double guides_magnitude(const Frame *f)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    double s = 0.0;
    for (size_t i = 0; i < 3 * n; ++i) s += fabs(f->albedo[i]) + fabs(f->normal[i]);
    for (size_t i = 0; i < n; ++i) s += fabs(f->depth[i]) + fabs(f->hits[i]);
    return s;
}

/* Whether the frame's split adds up to its colour (L = emission + direct + indirect per
 * sample, sample_record.h; the sums round apart by a few float ulps) with direct and indirect
 * light somewhere: the split was summed, not left out. */
static bool split_adds_up(const Frame *f)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    double parts[2] = {0};
    for (size_t i = 0; i < 3 * n; ++i) {
        double split = (double)f->direct[i] + f->indirect[i] + f->emission[i];
        if (fabs(split - f->color[i]) > 1e-5 * fabs(f->color[i]) + 1e-30) return false;
        parts[0] += fabs(f->direct[i]), parts[1] += fabs(f->indirect[i]);
    }
    return parts[0] > 0.0 && parts[1] > 0.0; /* the camera sees no emitter here: emission is 0 */
}

/* A sink folding every first-hit field of the records it sees into a checksum (order
 * matters: the renders that feed it run on one thread, so the records come in one order). */
typedef struct {
    double sum, unfiltered; /* unfiltered: the records' unfiltered parts, summed */
    long records, hits;
} FirstHitSum;

static void fold(FirstHitSum *s, double v) { s->sum = s->sum * 1.000001 + v; }

static void first_hit_add(void *ctx, int px, int py, const SampleRecord *r)
{
    FirstHitSum *s = ctx;
    ++s->records;
    /* the parts a method reads on a hit and on a miss */
    const vec3 *u[] = {&r->direct, &r->indirect, &r->emission, &r->unfiltered, &r->unfiltered_direct};
    for (size_t k = 0; k < sizeof u / sizeof u[0]; ++k) fold(s, u[k]->x), fold(s, u[k]->y), fold(s, u[k]->z);
    s->unfiltered += fabs(r->unfiltered.x) + fabs(r->unfiltered_direct.x);
    fold(s, r->motion_px[0]), fold(s, r->motion_px[1]), fold(s, r->shadow_count), fold(s, r->bounce_count);
    fold(s, r->shadow[0].d_light_world), fold(s, r->bounce[0].d_hit_world);
    if (!r->hit) {
        fold(s, r->depth_cam), fold(s, r->object_id), fold(s, r->albedo.x), fold(s, r->n_shading.y);
        return;
    }
    ++s->hits;
    const vec3 *v[] = {&r->albedo, &r->albedo_diffuse, &r->albedo_glossy, &r->p_world, &r->n_shading};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) fold(s, v[k]->x), fold(s, v[k]->y), fold(s, v[k]->z);
    fold(s, r->phong_exponent), fold(s, r->unfilterable), fold(s, r->depth_cam), fold(s, r->object_id);
    fold(s, px + 1000 * py);
}

int main(void)
{
    TestRender all, radiance, guides;
    RenderOptions o_radiance = {.reads = RENDER_READS_RADIANCE};
    RenderOptions o_guides = {.reads = RENDER_READS_RADIANCE | RENDER_READS_FRAME_GUIDES};
    if (!test_render(SCENE_TEXT, NULL, &all) || !test_render(SCENE_TEXT, &o_radiance, &radiance) ||
        !test_render(SCENE_TEXT, &o_guides, &guides))
        return 1;
    /* the scene has guides to lose: most pixels see a surface */
    CHECK(guides_magnitude(&all.frame) > 100.0);
    CHECK(!all.frame.guides_skipped);
    CHECK(split_adds_up(&all.frame) && split_adds_up(&radiance.frame));

    /* radiance only: the same image, the guides skipped (and said to be) */
    CHECK(same_radiance(&all.frame, &radiance.frame));
    CHECK(radiance.frame.guides_skipped);
    CHECK(guides_magnitude(&radiance.frame) == 0.0);
    CHECK(radiance.stats.rays_shadow == all.stats.rays_shadow && radiance.stats.rays_indirect == all.stats.rays_indirect);

    /* the guides declared: everything as the undeclared render */
    CHECK(same_radiance(&all.frame, &guides.frame));
    CHECK(same_guides(&all.frame, &guides.frame));
    CHECK(!guides.frame.guides_skipped);

    /* a sink that reads the first-hit fields, declared: the records the undeclared render gives */
    FirstHitSum s_all = {0}, s_decl = {0};
    SampleSink k_all = {first_hit_add, &s_all}, k_decl = {first_hit_add, &s_decl};
    RenderOptions o_one = {.threads = 1}, o_first = {.threads = 1, .reads = RENDER_READS_RADIANCE | RENDER_READS_FIRST_HIT};
    TestRender a, b;
    if (!test_render_sink(SCENE_TEXT, &o_one, &k_all, &a) || !test_render_sink(SCENE_TEXT, &o_first, &k_decl, &b))
        return 1;
    CHECK(s_all.records == s_decl.records && s_all.hits == s_decl.hits && s_all.hits > 0);
    CHECK(s_all.hits < s_all.records); /* and misses, whose first-hit fields are set too */
    CHECK(s_all.sum == s_decl.sum);
    CHECK(s_all.unfiltered > 0.0 && s_all.unfiltered == s_decl.unfiltered); /* there are unfiltered parts to lose */
    /* the first hit alone does not make the frame's sums */
    CHECK(b.frame.guides_skipped && same_radiance(&all.frame, &b.frame));

    /* the skipping renderer, told that a user reads everything again: the full frame */
    renderer_set_reads(radiance.r, 0);
    CHECK(renderer_reads(radiance.r) == 0);
    frame_clear(&radiance.frame);
    CHECK(!radiance.frame.guides_skipped);
    render_pass(radiance.r, 0, NULL, renderer_spp(radiance.r), &radiance.frame, NULL);
    CHECK(same_radiance(&all.frame, &radiance.frame) && same_guides(&all.frame, &radiance.frame));
    CHECK(!radiance.frame.guides_skipped);
    /* ... and by declaring every read explicitly, not only by the 0 that declares nothing;
     * then back to the radiance alone, which skips again */
    renderer_set_reads(radiance.r, RENDER_READS_ALL);
    frame_clear(&radiance.frame);
    render_pass(radiance.r, 0, NULL, renderer_spp(radiance.r), &radiance.frame, NULL);
    CHECK(same_radiance(&all.frame, &radiance.frame) && same_guides(&all.frame, &radiance.frame));
    CHECK(!radiance.frame.guides_skipped);
    renderer_set_reads(radiance.r, RENDER_READS_RADIANCE);
    frame_clear(&radiance.frame);
    render_pass(radiance.r, 0, NULL, renderer_spp(radiance.r), &radiance.frame, NULL);
    CHECK(same_radiance(&all.frame, &radiance.frame) && radiance.frame.guides_skipped);

    /* frames with fewer planes, under each declaration: the sums they hold are the full frame's */
    const unsigned declared[] = {0, RENDER_READS_RADIANCE, RENDER_READS_RADIANCE | RENDER_READS_FRAME_GUIDES,
                                 RENDER_READS_ALL};
    const unsigned planes[] = {0, FRAME_PLANES_PARTS, FRAME_PLANES_GUIDES, FRAME_PLANES_ALL};
    size_t n = (size_t)all.frame.width * (size_t)all.frame.height;
    for (size_t d = 0; d < sizeof declared / sizeof declared[0]; ++d)
        for (size_t k = 0; k < sizeof planes / sizeof planes[0]; ++k) {
            Frame thin;
            CHECK(frame_init_planes(&thin, all.frame.width, all.frame.height, planes[k]));
            CHECK(frame_planes(&thin) == planes[k]);
            renderer_set_reads(radiance.r, declared[d]);
            for (int again = 0; again < 2; ++again) { /* and after frame_clear of a thin frame */
                if (again) frame_clear(&thin);
                render_pass(radiance.r, 0, NULL, renderer_spp(radiance.r), &thin, NULL);
                CHECK(same_floats(all.frame.color, thin.color, 3 * n) && same_floats(all.frame.spp, thin.spp, n));
                bool parts = planes[k] & FRAME_PLANES_PARTS, guides = planes[k] & FRAME_PLANES_GUIDES;
                CHECK(parts ? same_radiance(&all.frame, &thin) : !thin.direct && !thin.indirect && !thin.emission);
                if (!guides) CHECK(!thin.albedo && !thin.normal && !thin.depth && !thin.hits && thin.guides_skipped);
                else if (render_reads_frame_guides(declared[d]))
                    CHECK(same_guides(&all.frame, &thin) && !thin.guides_skipped);
                else CHECK(thin.guides_skipped && guides_magnitude(&thin) == 0.0);
            }
            frame_free(&thin);
        }
    /* the planes a declaration asks for */
    CHECK(render_reads_frame_planes(0) == FRAME_PLANES_ALL && render_reads_frame_planes(RENDER_READS_ALL) == FRAME_PLANES_ALL);
    CHECK(render_reads_frame_planes(RENDER_READS_RADIANCE) == 0);
    CHECK(render_reads_frame_planes(RENDER_READS_RADIANCE | RENDER_READS_FIRST_HIT) == 0);
    CHECK(render_reads_frame_planes(RENDER_READS_RADIANCE | RENDER_READS_FRAME_GUIDES) == FRAME_PLANES_GUIDES);
    CHECK(render_reads_frame_planes(RENDER_READS_RADIANCE | RENDER_READS_FRAME_PARTS) == FRAME_PLANES_PARTS);

    test_render_free(&all), test_render_free(&radiance), test_render_free(&guides);
    test_render_free(&a), test_render_free(&b);
    CHECK_DONE();
}
