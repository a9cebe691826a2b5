/* The light a shadow-ray record names is the light its sample point lies on.
 *
 * Filters read ShadowRayRecord.light_index to look up the light's geometry
 * (renderer_light_info): a record that names a neighbouring triangle of the same mesh gives
 * them a light point off that light and an image wrong only by a little, which no closed-form
 * radiance test sees. Here every record of a render is checked against the geometry of the
 * light it names: on that triangle (inside its edges, on its plane) or on that sphere's
 * surface, at the record's shutter time for a moving light. The scene has each kind of light
 * sampling path: a large emitting mesh (its triangles batched as one group, each lane its own
 * triangle), a quad (a group a triangle), a sphere light, a moving mesh, and both a Lambert
 * floor (the batched next-event estimation) and a rough conductor patch (the per-path light
 * sample). */
#include "check.h"
#include "render_test_util.h"

enum { GRID = 6, MOVING_GRID = 3 };

typedef struct {
    const Renderer *r;
    int lights;
    int *per_light;      /* records naming each light */
    int checked, off_light, bad_index;
    float worst_off;     /* largest distance off the named light, in units of its size */
} RecordCheck;

/* Distance of p from triangle t (outside its edges or off its plane), over the triangle's
 * longest edge; 0 inside. */
static float off_triangle(const vec3 t[3], vec3 p)
{
    vec3 n = v3_cross(v3_sub(t[1], t[0]), v3_sub(t[2], t[0]));
    float area2 = v3_length(n);
    float size = fmaxf(fmaxf(v3_length(v3_sub(t[1], t[0])), v3_length(v3_sub(t[2], t[1]))), v3_length(v3_sub(t[0], t[2])));
    vec3 u = v3_scale(n, 1.0f / area2);
    float off = fabsf(v3_dot(u, v3_sub(p, t[0])));
    for (int e = 0; e < 3; ++e) {
        vec3 a = t[e], b = t[(e + 1) % 3];
        /* signed distance of p inside edge ab, in the triangle's plane */
        float inside = v3_dot(v3_cross(v3_sub(b, a), v3_sub(p, a)), u) / v3_length(v3_sub(b, a));
        if (inside < 0.0f) off = fmaxf(off, -inside);
    }
    return off / size;
}

static void record_add(void *ctx, int px, int py, const SampleRecord *rec)
{
    (void)px, (void)py;
    RecordCheck *c = ctx;
    for (int k = 0; k < rec->shadow_count; ++k) {
        const ShadowRayRecord *s = &rec->shadow[k];
        RenderLightInfo info;
        if (s->light_index < 0 || s->light_index >= c->lights || !renderer_light_info_at(c->r, s->light_index, rec->time, &info) ||
            info.kind != RENDER_LIGHT_AREA) {
            __atomic_add_fetch(&c->bad_index, 1, __ATOMIC_RELAXED);
            continue;
        }
        float off;
        if (info.is_triangle) {
            off = off_triangle(info.tri_world, s->light_p_world);
        } else {
            float radius = sqrtf(info.area_world / (4.0f * (float)M_PI));
            off = fabsf(v3_length(v3_sub(s->light_p_world, info.center_world)) - radius) / radius;
        }
        __atomic_add_fetch(&c->per_light[s->light_index], 1, __ATOMIC_RELAXED);
        __atomic_add_fetch(&c->checked, 1, __ATOMIC_RELAXED);
        if (off > 1e-4f) __atomic_add_fetch(&c->off_light, 1, __ATOMIC_RELAXED);
        /* the worst case, for the log (a race here only loses a maximum) */
        if (off > c->worst_off) c->worst_off = off;
    }
}

/* An n x n quad grid at height y over [x0, x0 + w] x [z0, z0 + w] (test_grid_mesh's winding
 * faces down). */
typedef struct {
    int n;
    double x0, z0, w, y;
} Grid;

static void grid_at(void *ctx, int c, int r, double p[3])
{
    const Grid *g = ctx;
    p[0] = g->x0 + g->w * c / g->n, p[1] = g->y, p[2] = g->z0 + g->w * r / g->n;
}

static void append_grid(char *text, size_t cap, Grid g)
{
    size_t len = strlen(text);
    bool ok = test_appendf(text, cap, &len, " Shape \"trianglemesh\" ") && test_grid_mesh(text, cap, g.n, g.n, grid_at, &g);
    len = strlen(text);
    CHECK(ok && test_appendf(text, cap, &len, "\n"));
}

int main(void)
{
    static char text[65536];
    snprintf(text, sizeof text,
             "LookAt 0 4 -3  0 0 0.3  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 50 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 40 ]\n"
             "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\n"
             "Material \"diffuse\"\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
             "AttributeBegin\n Material \"conductor\" \"float roughness\" [ 0.3 ]\n"
             " Shape \"trianglemesh\" \"point3 P\" [ 0.2 0.01 -1.5  1.5 0.01 -1.5  1.5 0.01 -0.2  0.2 0.01 -0.2 ]"
             " \"integer indices\" [ 0 2 1 0 3 2 ]\nAttributeEnd\n"
             "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\n");
    append_grid(text, sizeof text, (Grid){GRID, -1.4, -0.6, 1.2, 2.0});
    size_t len = strlen(text);
    snprintf(text + len, sizeof text - len,
             "AttributeEnd\n"
             "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"
             " Shape \"trianglemesh\" \"point3 P\" [ 0.3 2.2 0.3  0.9 2.2 0.3  0.9 2.2 0.9  0.3 2.2 0.9 ]"
             " \"integer indices\" [ 0 1 2 0 2 3 ]\nAttributeEnd\n"
             "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n Translate 0.6 1.6 -0.9\n"
             " Shape \"sphere\" \"float radius\" [ 0.15 ]\nAttributeEnd\n"
             "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
             " TransformTimes 0 1\n ActiveTransform EndTime\n Translate 0.5 0 0\n ActiveTransform All\n");
    append_grid(text, sizeof text, (Grid){MOVING_GRID, -0.5, 1.0, 0.6, 1.8});
    len = strlen(text);
    snprintf(text + len, sizeof text - len, "AttributeEnd\n");

    RenderOptions o = {0};
    o.seed = 3, o.threads = 2, o.record_ray_geometry = true;
    TestRender t;
    CHECK(test_render(text, &o, &t));
    int lights = renderer_light_count(t.r);
    int triangles = 2 * GRID * GRID + 2 + 2 * MOVING_GRID * MOVING_GRID;
    CHECK(lights == triangles + 1);
    RecordCheck c = {.r = t.r, .lights = lights, .per_light = calloc((size_t)lights, sizeof(int))};
    SampleSink sink = {record_add, &c};
    frame_clear(&t.frame);
    CHECK(render_pass(t.r, 1, NULL, renderer_spp(t.r), &t.frame, &sink));

    /* which lights the records named: most of the large mesh's triangles, the quad, the
     * sphere and the moving mesh, each shape by its own entries */
    int mesh_named = 0, quad_named = 0, sphere_named = 0, moving_named = 0, moving = 0;
    for (int i = 0; i < lights; ++i) {
        RenderLightInfo info;
        CHECK(renderer_light_info(t.r, i, &info));
        moving += info.moving;
        if (!c.per_light[i]) continue;
        if (info.moving) moving_named++;
        else if (!info.is_triangle) sphere_named++;
        else if (info.center_world.y > 2.1f) quad_named++;
        else mesh_named++;
    }
    fprintf(stderr, "%d records checked: %d off the light they name (worst %.2g of its size), %d bad indices; "
                    "named: %d of the mesh's %d triangles, %d of the quad's 2, sphere %d, %d of the moving mesh's %d\n",
            c.checked, c.off_light, (double)c.worst_off, c.bad_index, mesh_named, 2 * GRID * GRID, quad_named, sphere_named,
            moving_named, 2 * MOVING_GRID * MOVING_GRID);
    CHECK(c.checked > 48 * 40 * 16 / 2);
    CHECK(c.bad_index == 0);
    CHECK(c.off_light == 0);
    CHECK(mesh_named > GRID * GRID);
    CHECK(quad_named == 2);
    CHECK(sphere_named == 1);
    CHECK(moving_named > MOVING_GRID * MOVING_GRID);
    CHECK(moving == 2 * MOVING_GRID * MOVING_GRID);
    free(c.per_light);
    test_render_free(&t);
    CHECK_DONE();
}
