/* Cost of the pixel sampler alone (issue 22, "The sampler, second round" in
 * docs/benchmarks.md): draws the dimensions one camera sample of a depth-1 path takes (film
 * 2D, lens 2D, light pick 1D, light 2D, a skipped lobe dimension, BSDF 2D), pixel by pixel
 * in the renderer's rounds of sample indices ([0,4) [4,8) [8,16) ... [64,128) [128,192)
 * ...), setting the sampler up again per pixel and round as a wave does. Prints
 * nanoseconds per camera sample (best of the repeats) and a checksum of the values, which
 * must agree between builds whose samplers give the same values.
 * With `run` (a sampler that has sampler_run_*), the same values are drawn as the wave
 * draws them: per pixel and round, dimension by dimension for all the round's samples, and
 * summed in the same order (the checksum must not change).
 * usage: bench_sampler SPP [stratified|sobol] [PIXELS] [REPEATS] [run] */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/sampler.h"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); /* CPU time: the machine is shared */
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The renderer's next round end after `begin` (renderer.c: at least 4 samples of a pixel per
 * round, doubling up to 64, then 64 at a time). */
static int round_end(int begin)
{
    if (begin < 4) return 4;
    if (begin < 64) return 2 * begin;
    return begin + 64;
}

int main(int argc, char **argv)
{
    int spp = argc > 1 ? atoi(argv[1]) : 64;
    SamplerKind kind = argc > 2 && strcmp(argv[2], "sobol") == 0 ? SAMPLER_SOBOL : SAMPLER_STRATIFIED;
    int pixels = argc > 3 ? atoi(argv[3]) : 4096;
    int repeats = argc > 4 ? atoi(argv[4]) : 3;
    if (spp < 1 || pixels < 1 || repeats < 1) {
        fprintf(stderr, "usage: bench_sampler SPP [stratified|sobol] [PIXELS] [REPEATS]\n");
        return 2;
    }
    bool runs = argc > 5 && strcmp(argv[5], "run") == 0;
#ifndef SAMPLER_RUN_MAX
    if (runs) {
        fprintf(stderr, "bench_sampler: this sampler has no runs\n");
        return 2;
    }
#endif
    static PixelSampler s;
    double best_s = 1e30, checksum = 0.0;
    for (int rep = 0; rep < repeats; ++rep) {
        double sum = 0.0, t0 = now_s();
        for (int begin = 0; begin < spp; begin = round_end(begin)) {
            int end = round_end(begin) < spp ? round_end(begin) : spp;
            for (int p = 0; p < pixels; ++p) {
                sampler_start_pixel(&s, kind, 1, p % 256, p / 256, 0, spp);
#ifdef SAMPLER_RUN_MAX
                if (runs) {
                    /* dimensions 0-1 film, 2-3 lens, 4 pick, 5-6 light, 7 lobe (skipped), 8-9 BSDF */
                    static SamplerRun run;
                    static vec2 film[SAMPLER_RUN_MAX], lens[SAMPLER_RUN_MAX], light[SAMPLER_RUN_MAX], bsdf[SAMPLER_RUN_MAX];
                    static float pick[SAMPLER_RUN_MAX];
                    for (int i0 = begin; i0 < end; i0 += SAMPLER_RUN_MAX) {
                        sampler_run_begin(&s, &run, i0, end - i0);
                        sampler_run_2d(&s, &run, 0, film);
                        sampler_run_2d(&s, &run, 2, lens);
                        sampler_run_1d(&s, &run, 4, pick);
                        sampler_run_2d(&s, &run, 5, light);
                        sampler_run_2d(&s, &run, 8, bsdf);
                        for (int k = 0; k < run.count; ++k)
                            sum += film[k].x + film[k].y + lens[k].x + lens[k].y + pick[k] + light[k].x + light[k].y +
                                   bsdf[k].x + bsdf[k].y;
                    }
                    continue;
                }
#endif
                for (int i = begin; i < end; ++i) {
                    sampler_start_sample(&s, i);
                    vec2 film = sampler_2d(&s), lens = sampler_2d(&s);
                    float pick = sampler_1d(&s);
                    vec2 light = sampler_2d(&s);
                    sampler_skip(&s, 1);
                    vec2 bsdf = sampler_2d(&s);
                    sum += film.x + film.y + lens.x + lens.y + pick + light.x + light.y + bsdf.x + bsdf.y;
                }
            }
        }
        double dt = now_s() - t0;
        if (dt < best_s) best_s = dt;
        checksum = sum;
    }
    printf("%s%s spp %d: %.2f ns per sample, checksum %.17g\n", sampler_kind_name(kind), runs ? " runs" : "", spp,
           best_s / ((double)pixels * spp) * 1e9, checksum);
    return 0;
}
