/* The reconstruction pipeline (see pipeline.h). */
#include "recon/pipeline.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "core/clock.h"
#include "core/env_knob.h"
#include "recon/blur_probe.h"
#include "recon/budget_search.h"
#include "recon/composite.h"
#include "recon/gain_probe.h"
#include "recon/moving_lights.h"
#include "recon/overscan.h"

/* A --spp budget is met by searching mu on a log scale over this range. Not below 1: mu = 1
 * is the critical band (001 eq. 8, 002 eq. 15); a smaller mu widens the filter past it and
 * blurs the signal itself (on combined.pbrt at --spp 16, mu 0.16 had 3.5x the error of plain
 * Monte Carlo). A budget below the plan at mu = 1 scales the extra samples down instead. */
#define BUDGET_MU_MIN 1.0f
#define BUDGET_MU_MAX 1.0e4f
/* The search for mu (mu_for_budget) stops at a plan within BUDGET_PLAN_TOLERANCE under the
 * budget, or after BUDGET_SEARCH_STEPS plans between the ends; the extras are then scaled to
 * the budget exactly (scale_extras), so a closer mu buys nothing. Each step is one plan of the
 * whole frame (about 4 ms at 256x256 on soft_shadows, 20 ms on all_effects): 24 bisection steps
 * and no test of the ends cost 0.35-0.8 s of a 2-12 s frame (all_effects, --spp 16 and 64). */
#define BUDGET_SEARCH_STEPS 16
#define BUDGET_PLAN_TOLERANCE 0.02
/* ... and progressive steps double mu from this start when none was given. */
#define STEP_MU_START 2.0f
/* MPI ranks time the tracing of each tile; a gap longer than this between two pixels'
 * samples is counted as this long (see time_sample). */
#define WAVE_GAP_MAX_S 2.0e-3
/* Stages of a frame timed for WEDGE_DIST_LOG. */
#define DIST_MARKS 16

typedef struct {
    const ReconMethodClass *cls;
    ReconMethod *m;
    EffectMask effects;
} MethodSlot;

struct ReconPipeline {
    Renderer *r;
    ReconOptions opt;
    ReconChoice choice;
    MethodSlot slots[EFFECT_COUNT];
    int slot_count;
    bool filtering;              /* some effect has a method */
    bool fixed_only;             /* no method plans: one pass at a fixed count */
    GBuffer g;
    bool g_ready;
    SampleStore *store;
    bool store_full;             /* pass 1 filled every pixel's store: later samples skip it */
    bool guides_unread;          /* no method reads the guides: the sink sums the unfiltered
                                  * light alone (gbuffer_add_unfiltered) */
    ClRuntime *rt;
    ReconResult res;
    float *value_direct4, *value_indirect4, *radiance4; /* 4 floats per pixel each */
    int *spp_total, *spp_extra;
    int *spp_mine;               /* MPI ranks: a pass's counts with 0 for the pixels of others */
    float *trace_s;              /* MPI ranks: tracing seconds measured per pixel this pass */
    int pass;                    /* sampler passes started */
    int traced;                  /* passes begun (begin_pass), for time_sample */
    double mark_s[DIST_MARKS];   /* WEDGE_DIST_LOG: when each stage ended (wall, CPU) */
    double mark_cpu_s[DIST_MARKS];
    long mark_faults[DIST_MARKS]; /* the process's minor page faults: the pages it touched first */
    double mark_main_cpu_s[DIST_MARKS]; /* the calling (main) thread's CPU: what cannot spread
                                         * over the node's cores */
    const char *mark_name[DIST_MARKS];
    int mark_count;
    /* overscan (overscan.h): the band traced around the image, and what the caller sees
     * when there is one (the visible window of res and g); without one, res and g */
    int margin_px;
    ReconResult out;
    GBuffer g_out;
    bool g_out_ready;
    float *aov_out[RECON_AOV_MAX];
};

static size_t pixel_count(const ReconPipeline *p)
{
    return (size_t)renderer_width(p->r) * (size_t)renderer_height(p->r);
}

/* The pixels the caller sees: the frame without the overscan band. */
static size_t visible_count(const ReconPipeline *p)
{
    return (size_t)(renderer_width(p->r) - 2 * p->margin_px) * (size_t)(renderer_height(p->r) - 2 * p->margin_px);
}

static MethodSlot *slot_for(ReconPipeline *p, Effect e)
{
    for (int s = 0; s < p->slot_count; ++s)
        if (effect_in(p->slots[s].effects, e)) return &p->slots[s];
    return NULL;
}

/* The band a frame is traced with: the widest reach beyond a pixel among the chosen methods
 * (LR: its window margin), none with ReconOptions.no_overscan. Set on the renderer after the
 * choice (the blur probe, like `wedge info`'s, sees the plain image) and before any pass. */
static bool overscan_begin(ReconPipeline *p, Diag *d)
{
    int margin = 0;
    for (int s = 0; s < p->slot_count && !p->opt.no_overscan; ++s) {
        int reach = p->slots[s].cls->overscan_px ? p->slots[s].cls->overscan_px() : 0;
        if (reach > margin) margin = reach;
    }
    if (margin != renderer_overscan_px(p->r) && !renderer_set_overscan(p->r, margin, d)) return false;
    p->margin_px = margin;
    return true;
}

static bool distributed(const ReconPipeline *p) { return p->opt.dist && p->opt.dist->ranks > 1; }
static bool is_root(const ReconPipeline *p) { return !distributed(p) || p->opt.dist->rank == 0; }

bool recon_pipeline_create(Renderer *r, const ReconOptions *o, ReconPipeline **out, Diag *d)
{
    *out = NULL;
    if (!o->filter || !recon_filter_known(o->filter)) {
        char choices[256];
        diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0}, "--filter wants %s, got '%s'",
                 recon_filter_choices(choices, sizeof choices), o->filter ? o->filter : "");
        return false;
    }
    ReconPipeline *p = calloc(1, sizeof *p);
    if (!p) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    p->r = r;
    p->opt = *o;
    /* The blur probe decides the camera effects under auto when something moves; wedge info
     * runs the same probe (fixed samples and seed), so the two name the same methods, and so
     * does every MPI rank without communicating. */
    BlurProbe blur = {.median_blur_px = -1.0f};
    /* a renderer that served a pipeline with a band probes (and is chosen for) the plain image */
    if (renderer_overscan_px(r) && !renderer_set_overscan(r, 0, d)) {
        free(p);
        return false;
    }
    if (recon_select_wants_blur(renderer_effects(r), o->filter) && !recon_blur_probe(r, &blur)) {
        free(p);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    recon_select_budget(renderer_effects(r), o->filter, blur.median_blur_px, o->spp, &p->choice);
    recon_select_moving_light(&p->choice, recon_area_light_moves(r));
    p->choice.blur_unbounded = blur.samples_unbounded;
    /* auto's shading filters, judged on what this frame shows before any of their cost is
     * paid (the sink, the guides, the driver): where the gain probe predicts that Monte Carlo
     * reaches a lower error in the same time, the effect is left to it, and with no filter
     * left the frame is plain Monte Carlo at the same samples (auto_fallback.h). Without
     * --spp the frame is judged at the scene's sample count, what --filter none traces.
     * WEDGE_AUTO_FALLBACK=0 keeps auto's static choice (tests of the filters' pipeline on tiny
     * frames, measurements of what the fallback changes). */
    if (!recon_gain_probe_judge(r, o->spp > 0 ? o->spp : renderer_spp(r), &p->choice)) {
        free(p);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    /* one slot per distinct method, holding every effect it filters */
    p->fixed_only = true;
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        const ReconMethodClass *c = p->choice.method[e];
        if (!c) continue;
        p->filtering = true;
        int s = 0;
        while (s < p->slot_count && p->slots[s].cls != c) ++s;
        if (s == p->slot_count) {
            p->slots[p->slot_count++].cls = c;
            if (c->adaptive) p->fixed_only = false;
        }
        p->slots[s].effects |= EFFECT_BIT(e);
    }
    /* What the passes' users read (render_reads.h): when a method runs, the G-buffer sink, the
     * sample store and the methods' sinks read every first-hit field and the composite the
     * frame's albedo; without one the pipeline reads the radiance alone, and the caller's
     * declaration says the rest. A caller that declares nothing (0) keeps everything. */
    renderer_set_reads(r, p->filtering ? RENDER_READS_ALL : (o->reads ? o->reads | RENDER_READS_RADIANCE : 0));
    /* On the main thread, before anything is traced, although loading the driver takes 30-40
     * ms here (PoCL with LLVM): moved beside pass 1 (measured: pass 1 began 29 ms sooner), the
     * first load installed LLVM's alternate signal stack on the helper thread, and
     * AddressSanitizer aborted when that thread exited ("unable to unmap"). Only rank 0
     * reconstructs, so only it loads the driver: the other ranks would spend the same 30-40
     * ms of CPU before their first sample, which rank 0's first gather then waits for (a bad
     * --cl-device still stops every rank: the caller's dist_max_int). */
    if (p->filtering && is_root(p)) {
        /* the driver starts its worker threads here (PoCL: one per core of the machine), and
         * they inherit this thread's cores: with several ranks, every core of the node's
         * ranks, which wait while rank 0 reconstructs (dist_node_cpus) */
        int before[256], before_count = getenv("WEDGE_DIST_LOG") ? dist_thread_ids(before, 256) : 0;
        dist_node_cpus(o->dist, true);
        bool ok = cl_runtime_check_device(o->cl_device, d);
        dist_node_cpus(o->dist, false);
        if (before_count > 0 && distributed(p)) dist_log_new_threads(o->dist, before, before_count, "driver");
        if (!ok) {
            free(p);
            return false;
        }
    }
    if (!overscan_begin(p, d)) {
        free(p);
        return false;
    }
    p->res.width = renderer_width(r);
    p->res.height = renderer_height(r);
    p->res.choice = p->choice;
    /* what the caller sees before the first frame: the visible size */
    p->out = p->res;
    p->out.width = renderer_width(r) - 2 * p->margin_px, p->out.height = renderer_height(r) - 2 * p->margin_px;
    p->out.overscan_px = p->margin_px;
    *out = p;
    return true;
}

void recon_pipeline_destroy(ReconPipeline *p)
{
    if (!p) return;
    for (int s = 0; s < p->slot_count; ++s)
        if (p->slots[s].m) p->slots[s].cls->destroy(p->slots[s].m);
    cl_runtime_destroy(p->rt);
    sample_store_destroy(p->store);
    if (p->g_ready) gbuffer_free(&p->g);
    if (p->g_out_ready) gbuffer_free(&p->g_out);
    free(p->out.rgb);
    for (int k = 0; k < RECON_AOV_MAX; ++k) free(p->aov_out[k]);
    free(p->res.rgb);
    free(p->value_direct4);
    free(p->value_indirect4);
    free(p->radiance4);
    free(p->spp_total);
    free(p->spp_extra);
    free(p->spp_mine);
    free(p->trace_s);
    free(p);
}

const ReconResult *recon_pipeline_result(const ReconPipeline *p) { return p->margin_px ? &p->out : &p->res; }
const GBuffer *recon_pipeline_gbuffer(const ReconPipeline *p) { return p->margin_px ? &p->g_out : &p->g; }

/* ---- sampling ---- */

/* WEDGE_DIST_LOG=1: each rank prints when each stage of a filtered frame ended
 * (CLOCK_MONOTONIC, the same clock for every rank of one machine, then its CPU time, its
 * minor page faults so far and its main thread's CPU time), to see where the time of several
 * ranks goes and what memory each touches first (tools/bench-mpi --breakdown) */
static void dist_mark(ReconPipeline *p, const char *what)
{
    if (p->mark_count >= DIST_MARKS) return;
    /* and the process's CPU time, which other jobs on the machine inflate less than the wall
     * time (they still slow it through shared caches; MPI polling counts while it waits) */
    struct rusage use;
    getrusage(RUSAGE_SELF, &use);
    p->mark_faults[p->mark_count] = use.ru_minflt;
    p->mark_name[p->mark_count] = what;
    p->mark_cpu_s[p->mark_count] = clock_cpu_seconds();
    struct timespec cpu;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu);
    p->mark_main_cpu_s[p->mark_count] = timespec_seconds(cpu);
    p->mark_s[p->mark_count++] = clock_wall_seconds();
}

static void dist_marks_print(ReconPipeline *p)
{
    if (getenv("WEDGE_DIST_LOG") && p->opt.dist) { /* one write: mpirun interleaves the ranks' writes */
        char line[80 * DIST_MARKS];
        int at = snprintf(line, sizeof line, "dist-times rank %d:", p->opt.dist->rank);
        for (int k = 0; k < p->mark_count && at > 0 && (size_t)at < sizeof line; ++k)
            at += snprintf(line + at, sizeof line - (size_t)at, " %s %.4f %.4f %ld %.4f", p->mark_name[k], p->mark_s[k],
                           p->mark_cpu_s[k], p->mark_faults[k], p->mark_main_cpu_s[k]);
        fprintf(stderr, "%s\n", line);
    }
    p->mark_count = 0;
}

/* The counts this rank traces: counts (or uniform where counts is NULL) for the pixels it
 * owns, 0 for the others; without ranks, counts itself (NULL: uniform). */
static const int *counts_mine(ReconPipeline *p, const int *counts, int uniform)
{
    if (!distributed(p)) return counts;
    int w = renderer_width(p->r), h = renderer_height(p->r);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            bool mine = dist_owner(p->opt.dist, x, y) == p->opt.dist->rank;
            p->spp_mine[i] = mine ? (counts ? counts[i] : uniform) : 0;
        }
    return p->spp_mine;
}

enum { MAX_STATE_ARRAYS = 64 };

/* Every per-pixel array samples accumulate into: the frame, the guides' sums, the store, the
 * methods' statistics. */
static int state_arrays(ReconPipeline *p, DistArray *a)
{
    int n = 0;
    Frame *f = &p->g.frame;
    /* the sums the frame holds (every rank's frame holds the same: frame_init_planes) */
    FrameSum sums[FRAME_SUM_COUNT];
    frame_sums(f, sums);
    for (int k = 0; k < FRAME_SUM_COUNT; ++k)
        if (sums[k].sum) a[n++] = (DistArray){sums[k].sum, (size_t)sums[k].floats_per_pixel * sizeof(float)};
    if (p->filtering) a[n++] = (DistArray){p->g.sums, sizeof(GBufferSums)};
    if (p->g.others) a[n++] = (DistArray){p->g.others, sizeof(GBufferOtherSums)};
    if (p->store) n += sample_store_arrays(p->store, a + n, MAX_STATE_ARRAYS - n);
    for (int s = 0; s < p->slot_count; ++s)
        if (p->slots[s].cls->shared) n += p->slots[s].cls->shared(p->slots[s].m, a + n, MAX_STATE_ARRAYS - n);
    return n;
}

/* After a pass traced with counts (NULL: uniform): every rank finished it (or all treat it
 * as cancelled), rank 0 holds every pixel's state (state_arrays), and every rank knows the
 * tracing seconds measured in each tile (dist_measure). */
static bool gather_pass(ReconPipeline *p, int pass, const int *counts, int uniform, bool *complete, Diag *d)
{
    if (!distributed(p)) return true;
    *complete = dist_all_ok(p->opt.dist, *complete);
    DistArray a[MAX_STATE_ARRAYS];
    int n = state_arrays(p, a);
    if (!dist_gather(p->opt.dist, a, n, pass, d)) return false;
    return !p->trace_s || dist_measure(p->opt.dist, p->trace_s, counts, uniform, d);
}

/* Where a tracing thread's samples last arrived (MPI ranks): the time until its next pixel's
 * samples arrive is the tracing of the wave that holds them (the renderer traces a few pixels'
 * samples at once, then hands them over), charged to that next pixel; summed over an 8x8 tile
 * it is the tile's tracing time to within a wave. */
static _Thread_local const ReconPipeline *clock_pipe;
static _Thread_local int clock_traced, clock_px = -1, clock_py = -1;
static _Thread_local double clock_s;

static void time_sample(ReconPipeline *p, int px, int py)
{
    if (clock_pipe == p && clock_traced == p->traced && clock_px == px && clock_py == py) return;
    double now = clock_wall_seconds();
    /* a wave of 256 samples takes 0.05-1 ms here; a longer gap is the thread descheduled
     * (other jobs on the cores), not the pixel's cost */
    if (clock_pipe == p && clock_traced == p->traced)
        p->trace_s[(size_t)py * (size_t)p->g.width + (size_t)px] += (float)fmin(now - clock_s, WAVE_GAP_MAX_S);
    clock_pipe = p, clock_traced = p->traced, clock_px = px, clock_py = py, clock_s = now;
}

/* Before a pass after the first: ownership balanced by the pass's counts (the same on every
 * rank), and the state of each tile that changed owner handed from rank 0 (which holds every
 * pixel after the gather) to its new owner, whose sums then continue from the values a
 * single process has. */
static bool rebalance(ReconPipeline *p, const int *counts, int pass, Diag *d)
{
    if (!distributed(p)) return true;
    ReconDist *dist = p->opt.dist;
    long long moved = dist->tiles_moved;
    if (!dist_reassign(dist, counts, d)) return false;
    DistArray a[MAX_STATE_ARRAYS];
    int n = state_arrays(p, a);
    if (getenv("WEDGE_DIST_LOG") && dist->rank == 0)
        fprintf(stderr, "dist: pass %d: %lld of %d tiles changed owner\n", p->pass + 1, dist->tiles_moved - moved,
                dist->tile_count);
    return dist_handover(dist, a, n, pass, d);
}

/* Rank 0's cores: its own while it traces (the other ranks trace on theirs), the node's
 * otherwise (they wait for its plan and reconstruction, whose threads it starts; see
 * dist_node_cpus). Its render threads, started by the pass, inherit the calling thread's. */
static void rank0_tracing(ReconPipeline *p, bool tracing)
{
    if (distributed(p) && is_root(p)) dist_node_cpus(p->opt.dist, !tracing);
}

/* Every sample goes to the guides, the store and each method, in that order. */
static void fan_out(void *ctx, int px, int py, const SampleRecord *rec)
{
    ReconPipeline *p = ctx;
    if (p->trace_s) time_sample(p, px, py);
    if (p->guides_unread) gbuffer_add_unfiltered(&p->g, px, py, rec);
    else gbuffer_add(&p->g, px, py, rec);
    if (p->store && !p->store_full) sample_store_add(p->store, px, py, rec);
    for (int s = 0; s < p->slot_count; ++s)
        if (p->slots[s].cls->add_sample) p->slots[s].cls->add_sample(p->slots[s].m, px, py, rec);
}

/* The ray geometry pass 1 records: what the frame's methods declared they read for the
 * effects they filter (ReconMethodClass.shadow_geometry, .bounce_geometry). */
typedef struct {
    bool shadow, bounce;
} RayGeometry;
static const RayGeometry NO_RAY_GEOMETRY = {false, false};

static RayGeometry frame_ray_geometry(const ReconPipeline *p)
{
    RayGeometry g = NO_RAY_GEOMETRY;
    for (int s = 0; s < p->slot_count; ++s) {
        g.shadow = g.shadow || (p->slots[s].cls->shadow_geometry & p->slots[s].effects);
        g.bounce = g.bounce || (p->slots[s].cls->bounce_geometry & p->slots[s].effects);
    }
    return g;
}

static void begin_pass(ReconPipeline *p, int pass, RayGeometry geometry)
{
    p->traced++; /* the time between passes is no tile's */
    for (int s = 0; s < p->slot_count; ++s)
        if (p->slots[s].cls->begin_pass) p->slots[s].cls->begin_pass(p->slots[s].m, pass);
    /* ray geometry only when a method reads it: otherwise shadow rays stay any-hit
     * occlusion queries, cheaper than closest-hit traces */
    renderer_set_record_ray_geometry(p->r, geometry.shadow || geometry.bounce);
    renderer_set_record_bounce_geometry(p->r, geometry.bounce);
}

/* Whether the scene has an `infinite` light that emits (constant, or an image's mean). */
static bool scene_has_environment_light(const Renderer *r)
{
    for (int i = 0, n = renderer_light_count(r); i < n; ++i) {
        RenderLightInfo info;
        if (renderer_light_info(r, i, &info) && info.kind == RENDER_LIGHT_INFINITE &&
            (info.radiance.x > 0.0f || info.radiance.y > 0.0f || info.radiance.z > 0.0f))
            return true;
    }
    return false;
}

/* Whether some method plans the frame and every one that does is named in names (NULL-ended). */
static bool planned_only_by(const ReconPipeline *p, const char *const *names)
{
    bool planned = false;
    for (int s = 0; s < p->slot_count; ++s) {
        if (!p->slots[s].cls->adaptive) continue;
        bool named = false;
        for (const char *const *n = names; *n && !named; ++n) named = !strcmp(p->slots[s].cls->name, *n);
        if (!named) return false;
        planned = true;
    }
    return planned;
}

/* Pass 1 traced pass1 samples in every pixel; when that fills the store (its capacity is
 * pass 1's count: LR beside an adaptive method), every later sample would be dropped, after
 * an atomic count and, per sample, the first hit's two projections that only the store reads
 * (SampleRecord.motion_px): pass 2 then leaves the store out and the integrator skips them
 * (auto on moving_shadow, 256x256: 0.94x / 0.91x the CPU at 16 / 32 spp, images bit for bit;
 * docs/benchmarks.md, "LR's CPU beside the shading filters"). */
static void store_skip_when_full(ReconPipeline *p, int pass1)
{
    if (!p->store || pass1 < sample_store_capacity(p->store)) return;
    p->store_full = true;
    renderer_set_record_motion(p->r, false);
}


/* Buffers, guides, store and methods for a filtered frame. */
static bool setup_filtered(ReconPipeline *p, Diag *d)
{
    /* Without --spp the plans' own counts set the frame's samples. Under an environment light
     * MAAF's plan is blind to the sky's unfiltered noise (below) and left it: envlight.pbrt,
     * seeds 1-2, 3.3x AAF's default error for 0.48x its CPU time. Such a frame takes the
     * scene file's sample count as its budget instead (what --filter none traces), and with it
     * the sky's rule below: traced uniformly, MAAF's design and mu set for that budget
     * (docs/benchmarks.md, "MAAF's default budget under a sky"). AAF's default frame keeps its
     * plan (its error there was 0.30x MAAF's). */
    if (p->opt.spp <= 0 && planned_only_by(p, (const char *const[]){"maaf", NULL}) && scene_has_environment_light(p->r))
        p->opt.spp = renderer_spp(p->r);
    int w = renderer_width(p->r), h = renderer_height(p->r);
    size_t n = pixel_count(p);
    if (!gbuffer_init(&p->g, w, h, recon_camera_from(renderer_camera(p->r)))) goto oom;
    p->g_ready = true;
    if (!dist_tiles_reset(p->opt.dist, w, h, d)) return false;
    p->res.rgb = calloc(3 * n, sizeof(float));
    p->value_direct4 = malloc(4 * n * sizeof(float));
    p->value_indirect4 = malloc(4 * n * sizeof(float));
    p->radiance4 = malloc(4 * n * sizeof(float));
    p->spp_total = malloc(n * sizeof(int));
    p->spp_extra = calloc(n, sizeof(int));
    if (distributed(p)) p->spp_mine = malloc(n * sizeof(int)), p->trace_s = calloc(n, sizeof(float));
    if (!p->res.rgb || !p->value_direct4 || !p->value_indirect4 || !p->radiance4 || !p->spp_total || !p->spp_extra ||
        (distributed(p) && (!p->spp_mine || !p->trace_s)))
        goto oom;
    int pass1 = 0, fixed_max = 0;
    unsigned fields = 0;
    bool direct_filtered = false, indirect_filtered = false;
    for (int s = 0; s < p->slot_count; ++s) {
        const ReconMethodClass *c = p->slots[s].cls;
        int k = c->pass1_spp(p->slots[s].effects);
        /* a method that sizes pass 1 from the budget (FSF: the share its store keeps) */
        if (p->opt.spp > 0 && c->adaptive && c->budget_pass1_share) {
            k = (int)lroundf(c->budget_pass1_share(p->r, p->slots[s].effects) * (float)p->opt.spp);
            if (k < 1) k = 1;
        }
        if (k > pass1) pass1 = k;
        if (!c->adaptive && k > fixed_max) fixed_max = k;
        fields |= c->sample_fields_for ? c->sample_fields_for(p->slots[s].effects) : c->sample_fields;
        direct_filtered |= effect_in(p->slots[s].effects, EFFECT_SOFT_SHADOWS);
        indirect_filtered |= effect_in(p->slots[s].effects, EFFECT_INDIRECT);
    }
    /* the shading fields only for the lights filtered in this frame: nothing else replaces them */
    bool shading_filtered = direct_filtered || indirect_filtered;
    if (!shading_filtered) fields &= ~(unsigned)SAMPLE_FIELD_SHADING;
    if (!direct_filtered) fields &= ~(unsigned)SAMPLE_FIELD_SHADING_DIRECT;
    if (!indirect_filtered) fields &= ~(unsigned)SAMPLE_FIELD_SHADING_INDIRECT;
    p->guides_unread = !shading_filtered;
    for (int s = 0; s < p->slot_count; ++s) p->guides_unread = p->guides_unread && p->slots[s].cls->guides_unread;
    if (!gbuffer_track_split(&p->g, recon_choice_splits_pixels(&p->choice, EFFECT_SOFT_SHADOWS),
                             recon_choice_splits_pixels(&p->choice, EFFECT_INDIRECT))) goto oom;
    /* a fixed-count frame takes the --spp budget in one pass */
    if (p->fixed_only && p->opt.spp > 0) pass1 = p->opt.spp;
    /* A fixed-count method (LR) reads the first samples of every pixel, as many as the pixel
     * with the fewest has: beside an adaptive method it would see pass 1 only, and the plan's
     * extra samples would reach the image through the pixel means alone. Where it reconstructs
     * defocus, every pixel's value is its reconstruction, so under a budget the frame is traced
     * uniformly in pass 1 (all_effects at 32 spp: relMSE 5.1e-4 -> 4.1e-4; with a wider lens
     * 6.0e-4 -> 4.3e-4); the adaptive methods' plans still set their filters (mu from the
     * budget) and find the budget spent: no pass 2. Where it takes motion alone (moving objects
     * over a static frame the adaptive filters serve) the plan keeps the budget: traced
     * uniformly, motion_shading at 32 spp lost 30% (4.4e-4 -> 5.8e-4). */
    bool budget_in_pass1 = false;
    for (int s = 0; s < p->slot_count && !p->fixed_only && p->opt.spp > 0; ++s)
        if (!p->slots[s].cls->adaptive && (p->slots[s].effects & EFFECT_BIT(EFFECT_DEFOCUS)))
            budget_in_pass1 = true;
    /* An environment light's direct light reaches the image unfiltered (no shading filter
     * takes it: the soft-shadow filters are built around area lights), with Monte Carlo's
     * noise on every surface that sees the sky. The plans set each pixel's count from the
     * noise their filters leave (001 eqs. 14-21), blind to that part: they give the open, easily
     * filtered surfaces few samples, where the sky's noise then stays, and spend the rest
     * where each sample costs more rays. Traced uniformly instead (the filters still at the
     * budget's mu), envlight.pbrt at 64 spp went from 6.2e-4 to 5.3e-4 relMSE for 27% less
     * CPU time (docs/benchmarks.md, "auto on an environment light"). Measured for AAF's and
     * MAAF's plans: MAAF's frame on envlight.pbrt, seeds 1-4, at 8 / 16 / 32 spp 0.72x /
     * 0.90x / 1.31x the error for 0.83x / 0.80x / 0.79x the CPU time (at 64 spp 1.58x / 0.73x;
     * docs/benchmarks.md, "The defocus row to maaf"). A frame planned by another method (FSF)
     * keeps its plans, not measured here. */
    bool plans_measured = planned_only_by(p, (const char *const[]){"aaf", "maaf", NULL});
    if (p->opt.spp > 0 && plans_measured && scene_has_environment_light(p->r)) budget_in_pass1 = true;
    if (budget_in_pass1) pass1 = p->opt.spp;
    /* an adaptive budget below the methods' pass 1 lowers pass 1 (and leaves nothing to plan) */
    if (!p->fixed_only && !budget_in_pass1 && p->opt.spp > 0 && p->opt.spp < pass1) pass1 = p->opt.spp;
    p->res.pass1_spp = pass1;
    if (fields) {
        /* the store keeps what the fixed-count methods take (or pass 1 of adaptive ones) */
        int capacity = fixed_max > pass1 ? fixed_max : pass1;
        size_t limit = p->opt.mem_limit_bytes ? p->opt.mem_limit_bytes : sample_store_default_limit();
        if (!sample_store_create(fields, w, h, capacity, limit, &p->store, d)) return false;
        p->store_full = false;
    }
    /* screen motion only when a method stores it (LR): the integrator skips its projections */
    renderer_set_record_motion(p->r, (fields & (SAMPLE_FIELD_MOTION | SAMPLE_FIELD_LR_KEY)) != 0);
    for (int s = 0; s < p->slot_count; ++s) {
        ReconSetup setup = {p->r, &p->g, p->slots[s].cls->sample_fields ? p->store : NULL, p->slots[s].effects,
                            p->opt.mu, p->opt.spp, {0}, p->margin_px};
        memcpy(setup.method_options, p->opt.method_options, sizeof setup.method_options);
        if (!p->slots[s].cls->create(&setup, &p->slots[s].m, d)) return false;
    }
    return true;
oom:
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the reconstruction buffers (%dx%d)", w, h);
    return false;
}

/* The per-pixel total the methods' plans ask for at mu (the maximum over methods), in
 * p->spp_total; returns the image's average. */
static bool plan_at(ReconPipeline *p, float mu, double *avg, Diag *d)
{
    size_t n = pixel_count(p);
    const float *spp_now = p->g.frame.spp;
    for (size_t i = 0; i < n; ++i) p->spp_total[i] = (int)spp_now[i];
    int *one = malloc(n * sizeof(int));
    if (!one) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the sample plan");
        return false;
    }
    for (int s = 0; s < p->slot_count; ++s) {
        const ReconMethodClass *c = p->slots[s].cls;
        if (!c->plan || !c->adaptive) continue;
        if (!c->plan(p->slots[s].m, mu, spp_now, one, d)) {
            free(one);
            return false;
        }
        for (size_t i = 0; i < n; ++i)
            if (one[i] > p->spp_total[i]) p->spp_total[i] = one[i];
    }
    free(one);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) sum += p->spp_total[i];
    *avg = n ? sum / (double)n : 0.0;
    return true;
}

/* Whether pixel i lies in the overscan band (none without one). */
static bool in_band(const ReconPipeline *p, size_t i)
{
    int w = renderer_width(p->r), h = renderer_height(p->r), m = p->margin_px;
    int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
    return x < m || y < m || x >= w - m || y >= h - m;
}

/* Scales the extra samples per pixel to `room` samples in all, by error diffusion in scan
 * order (deterministic, each pixel within one sample of its share); with no extras at all,
 * the room is spread evenly over the visible pixels (the band's are cropped: band_extras_zero). */
static void scale_extras(ReconPipeline *p, double room)
{
    size_t n = pixel_count(p);
    double want = 0.0;
    for (size_t i = 0; i < n; ++i) want += p->spp_extra[i];
    if (room <= 0.0) {
        memset(p->spp_extra, 0, n * sizeof(int));
        return;
    }
    size_t visible = n;
    if (want <= 0.0 && p->margin_px) {
        int m2 = 2 * p->margin_px;
        visible = (size_t)(renderer_width(p->r) - m2) * (size_t)(renderer_height(p->r) - m2);
    }
    double scale = want > 0.0 ? room / want : 0.0, carry = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double share = want > 0.0 ? scale * p->spp_extra[i] : in_band(p, i) ? 0.0 : room / (double)visible;
        double v = share + carry;
        int k = (int)floor(v + 0.5);
        if (k < 0) k = 0;
        carry = v - k;
        p->spp_extra[i] = k;
    }
}

/* The samples the frame has so far. */
static double frame_samples(const ReconPipeline *p)
{
    double have = 0.0;
    for (size_t i = 0; i < pixel_count(p); ++i) have += p->g.frame.spp[i];
    return have;
}

/* The overscan band gets no extra samples: its pixels are cropped, and they reach the image
 * only through LR's windows (which read the store, filled by pass 1) and the shading filters'
 * taps of the border pixels. Under a --spp budget the room they leave goes to the visible
 * pixels (scale_extras), so the frame still traces the budget. Dropping them with the visible
 * counts kept changed moving_shadow's relMSE by under 0.1% (docs/benchmarks.md,
 * "moving_shadow under --filter auto: the overscan band's pass 2 and LR's share"). */
static void band_extras_zero(ReconPipeline *p)
{
    for (size_t i = 0; i < pixel_count(p); ++i)
        if (in_band(p, i)) p->spp_extra[i] = 0;
}

/* The extra samples per pixel: the plan's total minus what each pixel has (none in the
 * overscan band). With a --spp budget the extras are scaled to make the frame's average
 * exactly the budget. */
static void extras_from_plan(ReconPipeline *p, int budget)
{
    size_t n = pixel_count(p);
    const float *now = p->g.frame.spp;
    for (size_t i = 0; i < n; ++i) {
        int e = p->spp_total[i] - (int)now[i];
        p->spp_extra[i] = e > 0 ? e : 0;
    }
    if (p->margin_px) band_extras_zero(p);
    if (budget > 0) scale_extras(p, (double)budget * (double)n - frame_samples(p));
}

/* mu for a --spp budget without --mu (budget_search.h). */
typedef struct {
    ReconPipeline *p;
    Diag *d;
} BudgetPlanCtx;

static bool budget_plan(void *ctx, float mu, double *avg)
{
    BudgetPlanCtx *c = ctx;
    return plan_at(c->p, mu, avg, c->d);
}

static bool mu_for_budget(ReconPipeline *p, int budget, float *mu, Diag *d)
{
    BudgetSearch s = {BUDGET_MU_MIN, BUDGET_MU_MAX, BUDGET_PLAN_TOLERANCE, BUDGET_SEARCH_STEPS};
    BudgetPlanCtx c = {p, d};
    return budget_search_mu(&s, (double)budget, budget_plan, &c, mu, NULL);
}

/* ---- the OpenCL device, opened on a helper thread while pass 1 traces ---- */

typedef struct {
    pthread_t thread;
    bool started;
    ReconPipeline *p;
    ClRuntime *rt;
    Diag diag;
} DeviceOpener;

static void *opener_main(void *arg)
{
    DeviceOpener *op = arg;
    ReconPipeline *p = op->p;
    /* on any core of the node's ranks: after rank 0's pass-1 tiles (several ranks and a pass
     * 2), those of the ranks that wait for rank 0's gather and plan; beside pass 1 (a
     * fixed-count frame), whichever the system finds free rather than only rank 0's, whose
     * tiles would finish last (its 10-60 ms of CPU) */
    dist_node_cpus(p->opt.dist, true);
    double t0 = clock_wall_seconds();
    op->rt = cl_runtime_create(p->opt.cl_device, &op->diag);
    for (int s = 0; op->rt && s < p->slot_count; ++s)
        if (p->slots[s].cls->open_device && !p->slots[s].cls->open_device(p->slots[s].m, op->rt, &op->diag)) {
            cl_runtime_destroy(op->rt);
            op->rt = NULL;
        }
    if (getenv("WEDGE_DIST_LOG")) { /* the CPU it takes from the tracing on this rank's cores */
        struct timespec cpu;
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu);
        fprintf(stderr, "dist-opener: wall %.4f cpu %.4f\n", clock_wall_seconds() - t0, timespec_seconds(cpu));
    }
    return NULL;
}

static void opener_start(DeviceOpener *op, ReconPipeline *p)
{
    memset(op, 0, sizeof *op);
    op->p = p;
    /* Creating the context and building the kernels takes 50-150 ms on PoCL: do it on a
     * helper thread while the pass traces. */
    op->started = pthread_create(&op->thread, NULL, opener_main, op) == 0;
    if (!op->started) opener_main(op);
}

static bool opener_join(DeviceOpener *op, ReconPipeline *p, Diag *d)
{
    if (op->started) pthread_join(op->thread, NULL);
    op->started = false;
    if (!op->rt) {
        if (d) *d = op->diag;
        return false;
    }
    p->rt = op->rt;
    return true;
}

/* Visible pixels of a demodulated light (4 floats per pixel, NULL: none) flagged usable. */
static long long usable_pixels(const ReconPipeline *p, const float *value4)
{
    long long n = 0;
    int w = renderer_width(p->r), h = renderer_height(p->r), m = p->margin_px;
    for (int y = m; value4 && y < h - m; ++y)
        for (int x = m; x < w - m; ++x) n += value4[4 * ((size_t)y * (size_t)w + (size_t)x) + 3] > 0.0f;
    return n;
}

/* Filters and composites the frame's samples into res.rgb. */
static bool reconstruct(ReconPipeline *p, Diag *d)
{
    MethodSlot *sh = slot_for(p, EFFECT_SOFT_SHADOWS), *in = slot_for(p, EFFECT_INDIRECT);
    const float *factor = NULL;
    float factor_min = 0.0f;
    if (sh && sh->cls->light_factor && !sh->cls->light_factor(sh->m, EFFECT_SOFT_SHADOWS, &factor, &factor_min, d))
        return false;
    float *direct4 = sh ? p->value_direct4 : NULL, *indirect4 = in ? p->value_indirect4 : NULL;
    CompositeCounts inputs = composite_prepare(&p->g, factor, factor_min, direct4, indirect4);
    p->res.guarded_events += inputs.guarded;

    double kernel_s = 0.0;
    memset(p->res.pixels_filtered, 0, sizeof p->res.pixels_filtered);
    p->res.pixels_filtered[EFFECT_SOFT_SHADOWS] = usable_pixels(p, direct4);
    p->res.pixels_filtered[EFFECT_INDIRECT] = usable_pixels(p, indirect4);
    if (direct4) {
        if (!sh->cls->filter_light(sh->m, EFFECT_SOFT_SHADOWS, direct4, &kernel_s, d)) return false;
        p->res.seconds_kernels += kernel_s;
    }
    if (indirect4) {
        if (!in->cls->filter_light(in->m, EFFECT_INDIRECT, indirect4, &kernel_s, d)) return false;
        p->res.seconds_kernels += kernel_s;
    }
    EffectMask camera = 0;
    MethodSlot *cam = NULL;
    for (int e = EFFECT_DEFOCUS; e <= EFFECT_MOTION; ++e) {
        MethodSlot *s = slot_for(p, (Effect)e);
        if (!s) continue;
        camera |= EFFECT_BIT(e);
        cam = s;
        p->res.pixels_filtered[e] = (long long)visible_count(p);
    }
    composite_image(&p->g, factor, direct4, indirect4, p->res.rgb, cam ? p->radiance4 : NULL);
    /* one method filters the camera effects together (a second one, if the policy ever
     * splits them, filters the first one's output) */
    ReconShadingLight shading = {direct4, factor, indirect4};
    for (int s = 0; s < p->slot_count && camera; ++s) {
        EffectMask mine = p->slots[s].effects & camera;
        if (!mine) continue;
        if (p->slots[s].cls->shading_light) p->slots[s].cls->shading_light(p->slots[s].m, &shading);
        if (!p->slots[s].cls->filter_radiance(p->slots[s].m, mine, p->radiance4, &kernel_s, d)) return false;
        p->res.seconds_kernels += kernel_s;
    }
    CompositeCounts out = composite_finish(p->res.rgb, cam ? p->radiance4 : NULL, pixel_count(p));
    /* pixels whose means or whose filtered result were not finite (each set to 0) */
    p->res.guarded_events += out.guarded;
    p->res.nonfinite_pixels = inputs.bad_pixels + out.bad_pixels;
    p->res.aov_count = 0;
    for (int s = 0; s < p->slot_count; ++s)
        if (p->slots[s].cls->aovs)
            p->res.aov_count += p->slots[s].cls->aovs(p->slots[s].m, p->res.aovs + p->res.aov_count,
                                                      RECON_AOV_MAX - p->res.aov_count);
    return true;
}

/* The plain mean of the samples taken (Monte Carlo, or a cancelled render). */
static bool plain_mean(ReconPipeline *p, Diag *d)
{
    size_t n = pixel_count(p);
    if (!p->res.rgb && !(p->res.rgb = calloc(3 * n, sizeof(float)))) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for a %dx%d image", p->res.width, p->res.height);
        return false;
    }
    /* pixels whose mean is not finite (frame_resolve3 sets them to 0): counted, reported */
    const Frame *f = &p->g.frame;
    p->res.nonfinite_pixels = 0;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            if (f->spp[i] > 0.0f && !isfinite(f->color[3 * i + (size_t)k] / f->spp[i])) {
                p->res.nonfinite_pixels++;
                break;
            }
    p->res.guarded_events += frame_resolve3(f, f->color, p->res.rgb);
    p->res.aov_count = 0;
    memset(p->res.pixels_filtered, 0, sizeof p->res.pixels_filtered);
    memset(&p->res.choice, 0, sizeof p->res.choice);
    memcpy(p->res.choice.reason, p->choice.reason, sizeof p->res.choice.reason);
    p->res.choice.blur_px = p->choice.blur_px;
    p->res.choice.blur_unbounded = p->choice.blur_unbounded;
    return true;
}

/* --filter none (or nothing to filter): one pass, no sink, the frame's sums alone (no guides:
 * nothing reads them), and of those only the ones the caller reads (render_reads.h). */
static bool render_plain(ReconPipeline *p, Diag *d)
{
    int w = renderer_width(p->r), h = renderer_height(p->r);
    unsigned planes = render_reads_frame_planes(renderer_reads(p->r));
    if (!gbuffer_init_frame(&p->g, w, h, recon_camera_from(renderer_camera(p->r)), planes)) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for a %dx%d frame", w, h);
        return false;
    }
    p->g_ready = true;
    if (!dist_tiles_reset(p->opt.dist, w, h, d)) return false;
    int spp = p->opt.spp > 0 ? p->opt.spp : renderer_spp(p->r);
    p->res.pass1_spp = spp;
    renderer_set_record_ray_geometry(p->r, false);
    p->spp_extra = calloc((size_t)w * (size_t)h, sizeof(int)); /* progressive steps' counts */
    if (!p->spp_extra || (distributed(p) && !(p->spp_mine = malloc((size_t)w * (size_t)h * sizeof(int))))) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for a %dx%d frame", w, h);
        return false;
    }
    rank0_tracing(p, true);
    bool complete = render_pass(p->r, p->pass++, counts_mine(p, NULL, spp), spp, &p->g.frame, NULL);
    rank0_tracing(p, false);
    if (!gather_pass(p, 0, NULL, spp, &complete, d)) return false;
    p->res.cancelled = !complete;
    p->res.spp_avg = frame_spp_avg(&p->g.frame);
    if (!plain_mean(p, d)) return false;
    p->res.choice = p->choice;
    p->res.steps = 1;
    return true;
}

static bool step_frame(ReconPipeline *p, double spp_cap, Diag *d);

static bool render_frame(ReconPipeline *p, Diag *d)
{
    if (p->res.steps > 0) return step_frame(p, 0.0, d);
    if (!p->filtering) return render_plain(p, d);
    double t0 = clock_wall_seconds(), t_trace = 0.0;
    dist_mark(p, "start");
    if (!setup_filtered(p, d)) return false;
    dist_mark(p, "setup");
    SampleSink sink = {fan_out, p};
    RayGeometry geometry = frame_ray_geometry(p);

    /* The device opens on rank 0 while pass 1 traces: a fixed-count frame (LR) has no pass 2
     * to hide its 50-150 ms behind, and it needs nothing pass 1 computes. With several ranks
     * and a pass 2, once rank 0's pass-1 tiles are traced instead: beside its tracing it made
     * rank 0 the last to reach the first gather (the opening's CPU on top of an equal share
     * of tiles, 0.02-0.06 s), whereas after it the opening overlaps rank 0's gather and plan
     * on the node's other cores, where the other ranks wait (dist_node_cpus).
     * WEDGE_DIST_OPEN=pass1 (for measuring against it): beside pass 1 on every frame. */
    DeviceOpener opener;
    bool opened = false;
    bool open_late = distributed(p) && !p->fixed_only &&
                     !(getenv("WEDGE_DIST_OPEN") && strcmp(getenv("WEDGE_DIST_OPEN"), "pass1") == 0);
    if (is_root(p) && !open_late) {
        opener_start(&opener, p);
        opened = true;
    }

    /* ---- pass 1 ---- */
    begin_pass(p, 0, geometry);
    double t = clock_wall_seconds();
    int pass1 = p->res.pass1_spp;
    rank0_tracing(p, true);
    bool complete = render_pass(p->r, p->pass++, counts_mine(p, NULL, pass1), pass1, &p->g.frame, &sink);
    rank0_tracing(p, false);
    t_trace += clock_wall_seconds() - t;
    dist_mark(p, "pass1");
    if (is_root(p) && open_late) {
        opener_start(&opener, p);
        opened = true;
    }
    if (!gather_pass(p, 0, NULL, pass1, &complete, d)) {
        if (opened) opener_join(&opener, p, NULL);
        return false;
    }
    dist_mark(p, "gather1");
    if (complete) {
        /* ---- plans (rank 0) and pass 2 (adaptive methods) ---- */
        float mu = p->opt.mu;
        if (is_root(p)) {
            if (!p->fixed_only) {
                /* the plans read the guides of pass 1 (a fixed-count frame resolves them once,
                 * below, from the same sums) */
                gbuffer_resolve_guides(&p->g);
                double avg;
                if ((p->opt.spp > 0 && !(mu > 0.0f) && !mu_for_budget(p, p->opt.spp, &mu, d)) || !plan_at(p, mu, &avg, d)) {
                    opener_join(&opener, p, NULL);
                    return false;
                }
                extras_from_plan(p, p->opt.spp);
            }
            dist_mark(p, "plan");
        }
        p->res.mu = mu > 0.0f ? mu : 0.0f;
        if (!p->fixed_only) {
            if (!dist_broadcast_ints(p->opt.dist, p->spp_extra, pixel_count(p), d) ||
                !rebalance(p, p->spp_extra, 1, d)) {
                if (opened) opener_join(&opener, p, NULL);
                return false;
            }
            dist_mark(p, "bcast");
            /* plans come from pass 1; pass 2 only refines the guides, without ray geometry,
             * continuing each pixel's pass-1 sampler set (with Sobol', the first n points of
             * each dimension's sequence: docs/sampling.md, "Continuing a pixel's samples") */
            begin_pass(p, 1, NO_RAY_GEOMETRY);
            store_skip_when_full(p, pass1);
            t = clock_wall_seconds();
            rank0_tracing(p, true);
            complete = render_pass_more(p->r, 0, pass1, counts_mine(p, p->spp_extra, 0), &p->g.frame, &sink);
            rank0_tracing(p, false);
            t_trace += clock_wall_seconds() - t;
            dist_mark(p, "pass2");
            if (!gather_pass(p, 1, p->spp_extra, 0, &complete, d)) {
                if (opened) opener_join(&opener, p, NULL);
                return false;
            }
            dist_mark(p, "gather2");
        }
    }
    p->res.spp_avg = frame_spp_avg(&p->g.frame);
    bool ok;
    if (!is_root(p)) { /* another rank: its samples are on rank 0 now */
        ok = true;
        p->res.cancelled = !complete;
        p->res.steps = complete ? 1 : 0;
    } else if (!complete) { /* cancelled: the plain mean of what was taken */
        p->res.cancelled = true;
        if (opened) opener_join(&opener, p, NULL);
        ok = plain_mean(p, d);
    } else {
        gbuffer_resolve_guides(&p->g);
        ok = opener_join(&opener, p, d);
        if (ok) {
            snprintf(p->res.device, sizeof p->res.device, "%s", cl_runtime_device_label(p->rt));
            ok = reconstruct(p, d);
        }
        if (ok) p->res.steps = 1;
        dist_mark(p, "recon");
    }
    dist_marks_print(p);
    p->res.seconds_filter = clock_wall_seconds() - t0 - t_trace;
    return ok;
}

static bool step_frame(ReconPipeline *p, double spp_cap, Diag *d)
{
    if (p->res.steps == 0) return render_frame(p, d);
    if (p->res.cancelled) return true;
    size_t n = pixel_count(p);
    /* at the cap (less than one sample of room left): nothing to add */
    if (spp_cap > 0.0 && frame_samples(p) + 1.0 > spp_cap * (double)n) return true;
    double t0 = clock_wall_seconds(), t_trace = 0.0;
    int pass_slot = p->pass < 3 ? p->pass : 3; /* the byte counter of this pass */
    if (!p->filtering) { /* Monte Carlo: double the samples (up to the cap) */
        /* pass 1's count times 2^(steps - 1), bounded like any sample count */
        int doublings = p->res.steps - 1 < 24 ? p->res.steps - 1 : 24;
        double want = ldexp((double)p->res.pass1_spp, doublings);
        int spp = want < (double)SCENE_SPP_MAX ? (int)want : SCENE_SPP_MAX;
        if (is_root(p)) { /* rank 0 holds every pixel's count: the others follow its plan */
            for (size_t i = 0; i < n; ++i) p->spp_extra[i] = spp;
            double room = spp_cap > 0.0 ? floor(spp_cap * (double)n - frame_samples(p)) : INFINITY;
            if (room < (double)spp * (double)n) scale_extras(p, room); /* the cap, spread evenly */
        }
        if (!dist_broadcast_ints(p->opt.dist, p->spp_extra, n, d) || !rebalance(p, p->spp_extra, pass_slot, d))
            return false;
        double t = clock_wall_seconds();
        rank0_tracing(p, true);
        bool complete = render_pass(p->r, p->pass++, counts_mine(p, p->spp_extra, 0), 0, &p->g.frame, NULL);
        rank0_tracing(p, false);
        t_trace += clock_wall_seconds() - t;
        if (!gather_pass(p, pass_slot, p->spp_extra, 0, &complete, d)) return false;
        p->res.cancelled = !complete;
        p->res.spp_avg = frame_spp_avg(&p->g.frame);
        bool ok = plain_mean(p, d);
        p->res.choice = p->choice;
        p->res.steps += !p->res.cancelled;
        p->res.seconds_filter += clock_wall_seconds() - t0 - t_trace;
        return ok;
    }
    /* each step doubles mu: the filters narrow and the plans (rank 0's) ask for more samples */
    float mu = (p->res.mu > 0.0f ? p->res.mu : STEP_MU_START) * 2.0f;
    if (is_root(p)) {
        if (!p->fixed_only) {
            double avg;
            if (!plan_at(p, mu, &avg, d)) return false;
            extras_from_plan(p, 0);
        }
        /* every pixel gets at least pass 1's count more, so that the step always adds samples */
        double want = 0.0;
        for (size_t i = 0; i < n; ++i) {
            if (p->fixed_only) p->spp_extra[i] = 0;
            if (p->spp_extra[i] < p->res.pass1_spp) p->spp_extra[i] = p->res.pass1_spp;
            want += p->spp_extra[i];
        }
        /* ... but not past the cap: the plan scaled down to what is left. Without a cap a step
         * at most doubles the frame's samples: where a plan's count grows faster than mu (AAF's
         * indirect cap and far pixels grow as mu^3 past mu 2, docs/algorithms.md 2.6), doubling
         * mu would ask 8x the samples, and a preview's steps would lengthen 8-fold each */
        double room = spp_cap > 0.0 ? floor(spp_cap * (double)n - frame_samples(p)) : frame_samples(p);
        if (room < want) scale_extras(p, room);
    }
    if (!dist_broadcast_ints(p->opt.dist, p->spp_extra, n, d) || !rebalance(p, p->spp_extra, pass_slot, d))
        return false;
    p->res.mu = mu;
    SampleSink sink = {fan_out, p};
    begin_pass(p, p->pass, NO_RAY_GEOMETRY);
    double t = clock_wall_seconds();
    rank0_tracing(p, true);
    bool complete = render_pass(p->r, p->pass++, counts_mine(p, p->spp_extra, 0), 0, &p->g.frame, &sink);
    rank0_tracing(p, false);
    t_trace += clock_wall_seconds() - t;
    if (!gather_pass(p, pass_slot, p->spp_extra, 0, &complete, d)) return false;
    p->res.spp_avg = frame_spp_avg(&p->g.frame);
    bool ok;
    if (!is_root(p)) {
        ok = true;
        p->res.steps += complete;
        p->res.cancelled = !complete;
    } else if (!complete) {
        p->res.cancelled = true;
        ok = plain_mean(p, d);
    } else {
        gbuffer_resolve_guides(&p->g);
        ok = reconstruct(p, d);
        if (ok) p->res.steps++;
    }
    p->res.seconds_filter += clock_wall_seconds() - t0 - t_trace;
    return ok;
}

/* With overscan, what the caller sees: the visible window of the image, the AOV layers and the
 * guides, and spp_avg as the samples traced (the band's too) per visible pixel. */
static bool overscan_publish(ReconPipeline *p, Diag *d)
{
    if (!p->margin_px) return true;
    int w = renderer_width(p->r), h = renderer_height(p->r), m = p->margin_px;
    size_t n = visible_count(p);
    float *rgb = p->out.rgb;
    p->out = p->res;
    p->out.width = w - 2 * m, p->out.height = h - 2 * m;
    p->out.rgb = rgb ? rgb : malloc(3 * n * sizeof(float));
    if (!p->g_out_ready && gbuffer_init(&p->g_out, p->out.width, p->out.height, p->g.cam)) p->g_out_ready = true;
    for (int k = 0; k < p->res.aov_count; ++k)
        if (!p->aov_out[k]) p->aov_out[k] = malloc(n * sizeof(float));
    bool oom = !p->out.rgb || !p->g_out_ready;
    for (int k = 0; k < p->res.aov_count; ++k) oom = oom || !p->aov_out[k];
    if (oom) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the visible %dx%d image", p->out.width, p->out.height);
        return false;
    }
    if (p->res.rgb) overscan_crop(p->out.rgb, p->res.rgb, w, h, m, 3 * sizeof(float));
    for (int k = 0; k < p->res.aov_count; ++k) {
        overscan_crop(p->aov_out[k], p->res.aovs[k].data, w, h, m, sizeof(float));
        p->out.aovs[k].data = p->aov_out[k];
    }
    if (p->g_ready) overscan_crop_gbuffer(&p->g_out, &p->g, m);
    p->out.spp_avg = frame_samples(p) / (double)n;
    p->out.overscan_px = m;
    return true;
}

bool recon_pipeline_render(ReconPipeline *p, Diag *d) { return render_frame(p, d) && overscan_publish(p, d); }

bool recon_pipeline_step(ReconPipeline *p, double spp_cap, Diag *d)
{
    /* the cap counts samples per visible pixel (the caller's spp_avg); the steps count per
     * traced pixel */
    if (p->margin_px && spp_cap > 0.0) spp_cap *= (double)visible_count(p) / (double)pixel_count(p);
    return step_frame(p, spp_cap, d) && overscan_publish(p, d);
}
