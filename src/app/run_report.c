/* JSON run report. */
#include "app/run_report.h"

#include "io/atomic_file.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; ++p) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

/* JSON has no NaN/Inf: write 0 for them (they never occur unless a clock misbehaves). */
static double finite_or_zero(double v) { return isfinite(v) ? v : 0.0; }

/* "pixels_filtered": {"METHOD": {"EFFECT": pixels, ...}, ...}: which method filtered how
 * many pixels of each effect (methods in the order they first appear among the effects). */
static void write_pixels_filtered(FILE *f, const RunReport *r)
{
    fprintf(f, ",\n  \"pixels_filtered\": {");
    int methods_written = 0;
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        const char *m = r->filters[e];
        if (!effect_in(r->effects, (Effect)e) || !m || !strcmp(m, "none")) continue;
        bool seen = false;
        for (int k = 0; k < e && !seen; ++k)
            seen = effect_in(r->effects, (Effect)k) && r->filters[k] && !strcmp(r->filters[k], m);
        if (seen) continue;
        fprintf(f, "%s", methods_written++ ? ", " : "");
        json_string(f, m);
        fprintf(f, ": {");
        for (int k = e, first = 1; k < EFFECT_COUNT; ++k) {
            if (!effect_in(r->effects, (Effect)k) || !r->filters[k] || strcmp(r->filters[k], m)) continue;
            fprintf(f, "%s\"%s\": %lld", first ? "" : ", ", effect_name((Effect)k), r->pixels_filtered[k]);
            first = 0;
        }
        fprintf(f, "}");
    }
    fprintf(f, "}");
}

/* "auto_fallback": auto's decision from the gain probe (recon/auto_fallback.h): the effects it
 * left to Monte Carlo, per configuration of the shading filters (none, direct, indirect,
 * both) the predicted share of the error removed and equal-error speed against Monte Carlo,
 * the camera filters' judgement when auto chose one ("camera") and the probe samples left out
 * as non-finite. */
static void write_auto_fallback(FILE *f, const RunReport *r)
{
    const AutoFallback *a = r->auto_fallback;
    if (!a) return;
    static const char *const CONFIG[FILTER_GAIN_CONFIGS] = {"none", "soft_shadows", "indirect", "both"};
    fprintf(f, ",\n  \"auto_fallback\": {\"fell_back\": [");
    for (int e = 0, first = 1; e < EFFECT_COUNT; ++e)
        if (effect_in(r->auto_fell_back, (Effect)e)) fprintf(f, "%s\"%s\"", first ? "" : ", ", effect_name((Effect)e)), first = 0;
    fprintf(f, "], \"asked\": \"%s\", \"chosen\": \"%s\", \"spp\": %d, \"alpha\": %.4f, \"sample_us\": %.5f, "
            "\"neighbour_error\": %.4f",
            CONFIG[a->asked], CONFIG[a->chosen], a->spp, finite_or_zero(a->alpha), finite_or_zero(a->sample_us),
            finite_or_zero(a->neighbour_error));
    const char *what[2] = {"share", "speedup"};
    for (int k = 0; k < 2; ++k) {
        fprintf(f, ", \"%s\": {", what[k]);
        for (int c = 0, first = 1; c < FILTER_GAIN_CONFIGS; ++c) {
            if ((c & ~(int)a->asked) != 0) continue; /* not open to this frame */
            fprintf(f, "%s\"%s\": %.4f", first ? "" : ", ", CONFIG[c], finite_or_zero(k ? a->speedup[c] : a->share[c]));
            first = 0;
        }
        fprintf(f, "}");
    }
    if (a->camera_asked)
        fprintf(f, ", \"camera\": {\"fell_back\": %s, \"error\": %.4f, \"footprint\": %.3f, \"speedup\": %.4f, "
                "\"speedup_without\": %.4f}", a->camera_fell_back ? "true" : "false", finite_or_zero(a->camera_error),
                finite_or_zero(a->camera_footprint), finite_or_zero(a->camera_speedup), finite_or_zero(a->camera_speedup_without));
    fprintf(f, ", \"probe_nonfinite_samples\": %d", a->samples_nonfinite);
    fprintf(f, "}");
}

bool run_report_write(const char *path, const RunReport *r, Diag *err)
{
    /* Composed in memory, then written atomically like every output file. */
    char *text = NULL;
    size_t text_len = 0;
    FILE *f = open_memstream(&text, &text_len);
    if (!f) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot write report '%s': %s", path, strerror(errno));
        return false;
    }
    fprintf(f, "{\n");
    fprintf(f, "  \"width\": %d,\n  \"height\": %d,\n", r->width, r->height);
    fprintf(f, "  \"spp_avg\": %.6g,\n", finite_or_zero(r->spp_avg));
    fprintf(f, "  \"overscan_px\": %d,\n", r->overscan_px);
    fprintf(f, "  \"seconds_total\": %.6f,\n", finite_or_zero(r->seconds_total));
    fprintf(f, "  \"seconds_trace\": %.6f,\n", finite_or_zero(r->seconds_trace));
    fprintf(f, "  \"seconds_filter\": %.6f,\n", finite_or_zero(r->seconds_filter));
    fprintf(f, "  \"seconds_build\": %.6f,\n", finite_or_zero(r->seconds_build));
    fprintf(f, "  \"cpu_seconds_total\": %.6f,\n", finite_or_zero(r->cpu_seconds_total));
    fprintf(f, "  \"rays_primary\": %lld,\n  \"rays_shadow\": %lld,\n  \"rays_indirect\": %lld,\n  \"rays_bsdf\": %lld,\n",
            r->rays_primary, r->rays_shadow, r->rays_indirect, r->rays_bsdf);
    fprintf(f, "  \"effects\": {");
    for (int e = 0; e < EFFECT_COUNT; ++e)
        fprintf(f, "%s\"%s\": %s", e ? ", " : "", effect_name((Effect)e), effect_in(r->effects, (Effect)e) ? "true" : "false");
    fprintf(f, "},\n");
    fprintf(f, "  \"threads\": %d,\n  \"seed\": %" PRIu64 ",\n", r->threads, r->seed);
    fprintf(f, "  \"guarded_events\": %lld,\n", r->guarded_events);
    fprintf(f, "  \"nonfinite_pixels\": %lld,\n", r->nonfinite_pixels);
    fprintf(f, "  \"sampler\": ");
    json_string(f, r->sampler);
    fprintf(f, ",\n  \"filter\": ");
    json_string(f, r->filter);
    fprintf(f, ",\n  \"filters\": {");
    for (int e = 0, first = 1; e < EFFECT_COUNT; ++e) {
        if (!effect_in(r->effects, (Effect)e)) continue;
        fprintf(f, "%s\"%s\": ", first ? "" : ", ", effect_name((Effect)e));
        json_string(f, r->filters[e] ? r->filters[e] : "none");
        first = 0;
    }
    fprintf(f, "}");
    if (r->blur_probe_px >= 0.0f)
        fprintf(f, ",\n  \"blur_probe_px\": %.3f,\n  \"blur_probe_unbounded\": %d", (double)r->blur_probe_px,
                r->blur_probe_unbounded);
    write_auto_fallback(f, r);
    write_pixels_filtered(f, r);
    fprintf(f, ",\n  \"mu\": %.6g", finite_or_zero(r->mu));
    if (r->cl_device && r->cl_device[0]) {
        fprintf(f, ",\n  \"cl_device\": ");
        json_string(f, r->cl_device);
    }
    fprintf(f, ",\n  \"scene\": ");
    json_string(f, r->scene);
    fprintf(f, ",\n  \"output\": ");
    json_string(f, r->output);
    fprintf(f, ",\n  \"steps\": %d", r->steps);
    fprintf(f, ",\n  \"ranks\": %d,\n  \"bytes_communicated\": [%lld, %lld, %lld, %lld]", r->ranks > 0 ? r->ranks : 1,
            r->bytes_pass[0], r->bytes_pass[1], r->bytes_pass[2], r->bytes_pass[3]);
    fprintf(f, ",\n  \"triangles\": %ld,\n  \"interrupted\": %s\n}\n", r->triangles, r->interrupted ? "true" : "false");
    bool ok = !ferror(f);
    if (fclose(f) != 0) ok = false;
    if (!ok) {
        free(text);
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot write report '%s'", path);
        return false;
    }
    AtomicFile af;
    ok = atomic_file_open(&af, path, err);
    if (ok && !atomic_file_pwrite(&af, text, text_len, 0)) {
        atomic_file_abort(&af);
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot write report '%s': %s", path, strerror(errno));
        ok = false;
    } else if (ok) {
        ok = atomic_file_commit(&af, err);
    }
    free(text);
    return ok;
}
