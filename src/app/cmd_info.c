/* wedge info SCENE [--json] [--filter NAME]: what the parser understood of a scene (film,
 * camera, counts, lights by type, effects, the method each effect gets and why, warnings), as
 * text or as one JSON object; wedge info --filters [--json]: the reconstruction methods. */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "core/diag.h"
#include "geometry/mesh.h"
#include "recon/blur_probe.h"
#include "recon/gain_probe.h"
#include "recon/moving_lights.h"
#include "recon/cl/cl_runtime.h"
#include "recon/select.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

enum { INFO_RES_MAX = 65536 }; /* as wedge render --res */
enum { INFO_SPP_MAX = SCENE_SPP_MAX }; /* as wedge render --spp */

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wedge info [SCENE] [--json] [--filter NAME] [--res WxH] [--spp N]\n"
            "       wedge info --filters [--json]\n"
            "       wedge info --cl\n\n"
            "Summarises a pbrt-v4 scene (without SCENE: the embedded default scene): film, camera, sampler, counts of shapes, triangles\n"
            "(after loading meshes), lights by type, materials, the distribution effects found\n"
            "(soft_shadows, defocus, motion, indirect) with the reconstruction method each gets\n"
            "and why, and the parser's warnings.\n\n"
            "  --json         print one JSON object instead of text\n"
            "  --filter NAME  the methods 'wedge render --filter NAME' would use (default auto)\n"
            "  --res WxH      ... at this resolution (default: the film's): with motion, auto's\n"
            "                 choice for the camera effects depends on the blur in pixels\n"
            "  --spp N        ... for a budget of N samples per pixel (as 'wedge render --spp N';\n"
            "                 default: none): with a large one auto leaves the lens to aaf\n"
            "  --filters      list the reconstruction methods: effects, sampling, storage\n"
            "  --cl           list the OpenCL platforms and devices\n");
}

/* Light counts by type; area lights are the emissive shapes outside object definitions. */
typedef struct {
    const char *type;
    int count;
} LightCount;

static int count_lights(const SceneDesc *s, LightCount *out, int max)
{
    int n = 0;
    int area = 0;
    for (int i = 0; i < s->shape_count; ++i) area += s->shapes[i].area_light >= 0 && s->shapes[i].object < 0;
    if (area) out[n++] = (LightCount){"area", area};
    for (int i = 0; i < s->light_count; ++i) {
        int k = 0;
        while (k < n && strcmp(out[k].type, s->lights[i].type)) ++k;
        if (k == n) {
            if (n == max) continue;
            out[n++] = (LightCount){s->lights[i].type, 0};
        }
        out[k].count++;
    }
    return n;
}

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c == '\n') fputs("\\n", f);
        else if (c == '\t') fputs("\\t", f);
        else if (c < 0x20 || c >= 0x7f) fprintf(f, "\\u%04x", c);
        else fputc(c, f);
    }
    fputc('"', f);
}

/* The effects a mask holds, as a JSON array of names. */
static void json_effects(FILE *f, EffectMask m)
{
    fprintf(f, "[");
    for (int e = 0, first = 1; e < EFFECT_COUNT; ++e)
        if (effect_in(m, (Effect)e)) {
            fprintf(f, "%s\"%s\"", first ? "" : ", ", effect_name((Effect)e));
            first = 0;
        }
    fprintf(f, "]");
}

/* "filters": {effect: method} and "reasons": {effect: why}, for the present effects. */
static void json_choice(FILE *f, const SceneDesc *s, const ReconChoice *c)
{
    fprintf(f, ", \"filters\": {");
    for (int e = 0, first = 1; e < EFFECT_COUNT; ++e)
        if (effect_in(s->effects, (Effect)e)) {
            fprintf(f, "%s\"%s\": \"%s\"", first ? "" : ", ", effect_name((Effect)e), recon_choice_name(c, (Effect)e));
            first = 0;
        }
    fprintf(f, "}, \"reasons\": {");
    for (int e = 0, first = 1; e < EFFECT_COUNT; ++e)
        if (effect_in(s->effects, (Effect)e)) {
            fprintf(f, "%s\"%s\": ", first ? "" : ", ", effect_name((Effect)e));
            json_string(f, c->reason[e]);
            first = 0;
        }
    fprintf(f, "}");
    /* the blur probe's median (px at the probed resolution), null when the choice did not read it */
    if (c->blur_px >= 0.0f) fprintf(f, ", \"blur_probe_px\": %.3f", (double)c->blur_px);
    else fprintf(f, ", \"blur_probe_px\": null");
    /* probe samples whose blur overflowed a float, counted at FLT_MAX px in the median */
    fprintf(f, ", \"blur_probe_unbounded\": %d", c->blur_unbounded);
}

static void print_json(const SceneDesc *s, const ReconChoice *c, long triangles, FILE *f)
{
    fprintf(f, "{\"scene\": ");
    json_string(f, s->path);
    fprintf(f, ", \"effects\": ");
    json_effects(f, s->effects);
    json_choice(f, s, c);
    fprintf(f, ", \"width\": %d, \"height\": %d, \"spp\": %d, \"triangles\": %ld", s->film.xres, s->film.yres,
            s->sampler.spp, triangles);
    LightCount lc[64];
    int nl = count_lights(s, lc, 64);
    fprintf(f, ", \"lights\": {");
    for (int i = 0; i < nl; ++i) {
        fprintf(f, "%s", i ? ", " : "");
        json_string(f, lc[i].type);
        fprintf(f, ": %d", lc[i].count);
    }
    fprintf(f, "}, \"shapes\": %d, \"instances\": %d, \"materials\": %d, \"textures\": %d, \"max_depth\": %d",
            s->shape_count, s->instance_count, s->material_count, s->texture_count, s->integrator.max_depth);
    fprintf(f, ", \"camera\": {\"fov\": %g, \"lensradius\": %g, \"focaldistance\": %g, \"shutteropen\": %g, "
               "\"shutterclose\": %g}",
            (double)s->camera.fov_deg, (double)s->camera.lens_radius, (double)s->camera.focal_distance,
            (double)s->camera.shutter_open, (double)s->camera.shutter_close);
    fprintf(f, ", \"warnings\": [");
    for (int i = 0; i < s->warning_count; ++i) {
        fprintf(f, "%s", i ? ", " : "");
        json_string(f, s->warnings[i]);
    }
    fprintf(f, "]}\n");
}

static void print_text(const SceneDesc *s, const ReconChoice *c, long triangles, FILE *f)
{
    fprintf(f, "scene       %s\n", s->path);
    fprintf(f, "film        %s %dx%d -> %s\n", s->film.type, s->film.xres, s->film.yres, s->film.filename);
    fprintf(f, "camera      %s fov %g lensradius %g focaldistance %g shutter [%g, %g]\n", s->camera.type,
            (double)s->camera.fov_deg, (double)s->camera.lens_radius, (double)s->camera.focal_distance,
            (double)s->camera.shutter_open, (double)s->camera.shutter_close);
    fprintf(f, "sampler     %s, %d spp\n", s->sampler.type, s->sampler.spp);
    fprintf(f, "integrator  %s, maxdepth %d\n", s->integrator.type, s->integrator.max_depth);
    fprintf(f, "shapes      %d (%d object definitions, %d instances)\n", s->shape_count, s->object_count,
            s->instance_count);
    fprintf(f, "triangles   %ld\n", triangles);
    LightCount lc[64];
    int nl = count_lights(s, lc, 64);
    fprintf(f, "lights     ");
    if (!nl) fprintf(f, " none");
    for (int i = 0; i < nl; ++i) fprintf(f, " %s %d", lc[i].type, lc[i].count);
    fprintf(f, "\nmaterials   %d, textures %d\n", s->material_count, s->texture_count);
    fprintf(f, "effects    ");
    for (int e = 0; e < EFFECT_COUNT; ++e)
        if (effect_in(s->effects, (Effect)e)) fprintf(f, " %s (filter: %s)", effect_name((Effect)e), recon_choice_name(c, (Effect)e));
    fprintf(f, "%s\n", s->effects ? "" : " none");
    for (int e = 0; e < EFFECT_COUNT; ++e)
        if (effect_in(s->effects, (Effect)e) && c->reason[e][0])
            fprintf(f, "  %-12s %s\n", effect_name((Effect)e), c->reason[e]);
    char biased[RECON_REASON_SIZE];
    if (recon_choice_moving_light_warning(c, biased, sizeof biased)) fprintf(f, "  %-12s warning: %s\n", "soft_shadows", biased);
    fprintf(f, "warnings    %d\n", s->warning_count);
    for (int i = 0; i < s->warning_count; ++i) fprintf(f, "  %s\n", s->warnings[i]);
}

/* wedge info --filters: the registered methods. */
static void print_methods(bool json, FILE *f)
{
    if (json) fprintf(f, "{\"methods\": [");
    for (int i = 0; recon_methods[i]; ++i) {
        const ReconMethodClass *m = recon_methods[i];
        const char *sampling = m->adaptive ? "adaptive" : "fixed";
        const char *storage = m->sample_fields ? "per-sample" : "per-pixel";
        if (json) {
            fprintf(f, "%s{\"name\": ", i ? ", " : "");
            json_string(f, m->name);
            fprintf(f, ", \"effects\": ");
            json_effects(f, m->effects);
            fprintf(f, ", \"sampling\": \"%s\", \"storage\": \"%s\", \"title\": ", sampling, storage);
            json_string(f, m->title);
            fprintf(f, "}");
            continue;
        }
        fprintf(f, "%-6s", m->name);
        for (int e = 0, first = 1; e < EFFECT_COUNT; ++e)
            if (effect_in(m->effects, (Effect)e)) {
                fprintf(f, "%s%s", first ? " " : ",", effect_name((Effect)e));
                first = 0;
            }
        fprintf(f, "; %s sampling, %s storage\n       %s\n", sampling, storage, m->title);
    }
    if (json) fprintf(f, "]}\n");
}

int cmd_info(int argc, char **argv)
{
    const char *path = NULL, *filter = "auto";
    bool json = false, cl = false, methods = false;
    int res_w = 0, res_h = 0; /* 0: the film's */
    int budget_spp = 0;       /* 0: no --spp budget */
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--json")) json = true;
        else if (!strcmp(argv[i], "--cl")) cl = true;
        else if (!strcmp(argv[i], "--filters")) methods = true;
        else if (!strcmp(argv[i], "--res")) {
            char tail;
            if (i + 1 >= argc || sscanf(argv[i + 1], "%dx%d%c", &res_w, &res_h, &tail) != 2 || res_w < 1 ||
                res_h < 1 || res_w > INFO_RES_MAX || res_h > INFO_RES_MAX) {
                fprintf(stderr, "wedge info: --res wants WxH with W and H in [1, %d], got '%s'\n", INFO_RES_MAX,
                        i + 1 < argc ? argv[i + 1] : "");
                return WEDGE_EXIT_USAGE;
            }
            ++i;
        }
        else if (!strcmp(argv[i], "--spp")) {
            char tail;
            if (i + 1 >= argc || sscanf(argv[i + 1], "%d%c", &budget_spp, &tail) != 1 || budget_spp < 1 ||
                budget_spp > INFO_SPP_MAX) {
                fprintf(stderr, "wedge info: --spp wants a whole number in [1, %d], got '%s'\n", INFO_SPP_MAX,
                        i + 1 < argc ? argv[i + 1] : "");
                return WEDGE_EXIT_USAGE;
            }
            ++i;
        }
        else if (!strcmp(argv[i], "--filter")) {
            char why[160];
            if (i + 1 < argc && strchr(argv[i + 1], '=') && !recon_filter_problem(argv[i + 1], why, sizeof why)) {
                fprintf(stderr, "wedge info: --filter %s: %s\n", argv[i + 1], why);
                return WEDGE_EXIT_USAGE;
            }
            if (i + 1 >= argc || !recon_filter_known(argv[i + 1])) {
                char choices[256];
                fprintf(stderr, "wedge info: --filter wants %s, got '%s'\n", recon_filter_choices(choices, sizeof choices),
                        i + 1 < argc ? argv[i + 1] : "");
                return WEDGE_EXIT_USAGE;
            }
            filter = argv[++i];
        }
        else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return WEDGE_EXIT_OK;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            fprintf(stderr, "wedge info: unknown option '%s'\n", argv[i]);
            usage(stderr);
            return WEDGE_EXIT_USAGE;
        } else if (path) {
            fprintf(stderr, "wedge info: more than one scene given\n");
            usage(stderr);
            return WEDGE_EXIT_USAGE;
        } else
            path = argv[i];
    }

    /* ---- wedge info --cl: owned by the OpenCL engineer (recon module) ---- */
    if (cl) return recon_print_devices(stdout) ? WEDGE_EXIT_OK : WEDGE_EXIT_RUNTIME;
    /* ---- end of the --cl part ---- */
    if (methods) {
        print_methods(json, stdout);
        return WEDGE_EXIT_OK;
    }

    /* Without SCENE: the scene embedded in the binary, as for wedge render. */
    SceneDesc scene;
    Diag err;
    bool parsed = path ? scene_parse_file(path, &scene, &err)
                       : scene_parse_string(wedge_default_scene, strlen(wedge_default_scene), "<default>", NULL,
                                            &scene, &err);
    if (!parsed) {
        fprintf(stderr, "%s\n", err.message);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    long triangles = 0;
    for (int i = 0; i < scene.shape_count; ++i) {
        const char *t = scene.shapes[i].type;
        if (!strcmp(t, "sphere") || !strcmp(t, "disk")) continue;
        long n = mesh_triangle_count(&scene.shapes[i], &err);
        if (n < 0) {
            fprintf(stderr, "%s\n", err.message);
            scene_desc_free(&scene);
            return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
        }
        triangles += n;
    }
    /* The scene built as wedge render builds it (materials, textures, lights, Embree
     * geometry; one pixel, one thread): the warnings only the build finds (an unknown
     * texture, a mix naming itself, a skipped light) are shown here too, and a scene that
     * cannot be built fails here as it would there. */
    /* With motion and auto deciding the camera effects, the blur probe at the render's
     * resolution (--res, else the film's), the one recon_pipeline_create runs: the choice
     * depends on it, and info must name the method render will use. */
    bool probe = recon_select_wants_blur(scene.effects, filter);
    RenderOptions ro = {0};
    ro.width = probe ? res_w : 1, ro.height = probe ? res_h : 1;
    ro.threads = 1;
    Renderer *r = NULL;
    if (!renderer_create(&scene, &ro, &r, &err)) {
        fprintf(stderr, "%s\n", err.message);
        scene_desc_free(&scene);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    BlurProbe blur = {.median_blur_px = -1.0f};
    if (probe && !recon_blur_probe(r, &blur)) {
        fprintf(stderr, "wedge info: out of memory\n");
        renderer_destroy(r);
        scene_desc_free(&scene);
        return WEDGE_EXIT_RUNTIME;
    }
    ReconChoice choice;
    recon_select_budget(scene.effects, filter, blur.median_blur_px, budget_spp, &choice);
    recon_select_moving_light(&choice, recon_area_light_moves(r));
    choice.blur_unbounded = blur.samples_unbounded;
    /* auto's fallback to Monte Carlo, judged as recon_pipeline_create judges it: the gain probe
     * at the render's resolution */
    bool judged = !recon_select_wants_fallback(&choice);
    if (!judged && !probe) {
        renderer_destroy(r);
        r = NULL;
        ro.width = res_w, ro.height = res_h;
        if (!renderer_create(&scene, &ro, &r, &err)) {
            fprintf(stderr, "%s\n", err.message);
            scene_desc_free(&scene);
            return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
        }
    }
    if (!judged && !recon_gain_probe_judge(r, budget_spp > 0 ? budget_spp : renderer_spp(r), &choice)) {
        fprintf(stderr, "wedge info: out of memory\n");
        renderer_destroy(r);
        scene_desc_free(&scene);
        return WEDGE_EXIT_RUNTIME;
    }
    renderer_destroy(r);
    if (json) print_json(&scene, &choice, triangles, stdout);
    else print_text(&scene, &choice, triangles, stdout);
    scene_desc_free(&scene);
    return WEDGE_EXIT_OK;
}
