/* FSF's OpenCL passes (fsf.cl) against the C passes on indirect-light samples (fsf_bounce.h's
 * grid: v over [-5, 5]^2, samples clamped inside it, fsf_synth_bounce_disk), with shears and
 * widths varying over the image as fsf_bounce_params makes them (both signs, some pixels left
 * out). Skipped (77) without an OpenCL device. */
#include "check.h"
#include "fsf_synth.h"
#include "recon/fsf/fsf_cl.h"

int main(void)
{
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    if (!rt) {
        fprintf(stderr, "skipped: %s\n", d.message);
        return 77;
    }
    FsfCl *cl = fsf_cl_create(rt, &d);
    CHECK(cl != NULL);
    const int W = 45, H = 38, l = 4;
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    fsf_synth_bounce_disk(&f, l, 0.2f, 1.0f, 0.2f, 0.15f, true, 3);
    for (int i = 0; i < W * H; ++i) {
        float x = (float)(i % W) / W, y = (float)(i / W) / H;
        if (i % 9 == 4) f.count[i] = 7;         /* fewer samples than slots */
        if (i % 29 == 3) f.usable[i] = 0;       /* passed through, never a source */
        float ang = 0.4f * y;                   /* gather directions turning over the image */
        f.px[i].dir[0][0] = cosf(ang), f.px[i].dir[0][1] = sinf(ang);
        f.px[i].dir[1][0] = -sinf(ang), f.px[i].dir[1][1] = cosf(ang);
        /* v units per step: up to the parallax bound's 1 v over the taps */
        f.px[i].eta_m[0] = 0.02f + 0.05f * x, f.px[i].eta_m[1] = (i % 3 == 0 ? -1.0f : 1.0f) * 0.04f * y;
        f.px[i].sigma_px[0] = i % 13 == 0 ? 0.0f : 0.5f + 7.5f * y;
        f.px[i].sigma_px[1] = 1.0f + 6.0f * x;
    }
    FsfGrid g = fsf_bounce_grid();
    FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
    size_t n = (size_t)W * H;
    float *c_out = malloc(4 * n * sizeof(float)), *cl_out = malloc(4 * n * sizeof(float));
    CHECK(fsf_filter_factored(&f.s, &g, f.px, &gd, c_out));
    double secs = 0.0, worst = 0.0;
    if (cl) CHECK(fsf_cl_run(cl, &f.s, &g, f.px, &gd, cl_out, &secs, &d));
    for (size_t i = 0; cl && i < n; ++i)
        for (int c = 0; c < 4; ++c)
            worst = fmax(worst, fabs((double)c_out[4 * i + c] - cl_out[4 * i + c]) / fmax(fabs(c_out[4 * i + 3]), 1e-3));
    printf("indirect samples: OpenCL against C: largest difference %.3g of the pixel's weight (kernels %.4f s)\n", worst,
           secs);
    /* rounding only, as test_fsf_cl (a lost tap or node would be ~1e-2) */
    CHECK(worst < 1e-5);
    free(c_out), free(cl_out);
    fsf_synth_free(&f);
    fsf_cl_destroy(cl);
    cl_runtime_destroy(rt);
    CHECK_DONE();
}
