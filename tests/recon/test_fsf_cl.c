/* FSF's OpenCL kernels (fsf.cl) against the C passes (fsf_filter.c) on the same synthetic
 * samples: a varying shear, width and gather direction field and some rejected pixels, so
 * that every branch of the kernels runs. Skipped (77) without an OpenCL device. */
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
    const int W = 53, H = 37, l = 4;
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    FsfGrid g = fsf_grid_default(0.7f, 0.5f);
    fsf_synth_light(&f, &g, l, false, 11);
    unsigned st = 5;
    for (int i = 0; i < W * H; ++i) {
        float x = (float)(i % W) / W, y = (float)(i / W) / H;
        for (int k = 0; k < f.cap; ++k) {
            size_t slot = (size_t)i * f.cap + (size_t)k;
            float lit = f.y[2 * slot] - 0.2f * f.y[2 * slot + 1] > 0.4f * (x - 0.5f) ? 1.0f : 0.0f;
            f.v[3 * slot] = lit, f.v[3 * slot + 1] = 0.3f + lit, f.v[3 * slot + 2] = fsf_rand01(&st);
        }
        if (i % 7 == 3) f.count[i] = 9;         /* fewer samples than slots */
        if (i % 31 == 5) f.usable[i] = 0;       /* passed through, never a source */
        if (i % 17 == 2) f.nrm4[4 * i + 2] = -1; /* another orientation: rejected */
        float ang = 0.3f * x;
        f.px[i].dir[0][0] = cosf(ang), f.px[i].dir[0][1] = sinf(ang);
        f.px[i].dir[1][0] = -sinf(ang), f.px[i].dir[1][1] = cosf(ang);
        f.px[i].eta_m[0] = 0.01f + 0.05f * y, f.px[i].eta_m[1] = 0.03f * x;
        /* pass 1a's densities without a shear and with the opposite one (fsf.cl has its own
         * branch for eta 0 and orders the interval ends of a negative eta) */
        if (i % 13 == 4) f.px[i].eta_m[0] = 0.0f;
        if (i % 5 == 1) f.px[i].eta_m[0] = -f.px[i].eta_m[0], f.px[i].eta_m[1] = -f.px[i].eta_m[1];
        f.px[i].sigma_px[0] = i % 11 == 0 ? 0.0f : 1.0f + 7.0f * x;
        f.px[i].sigma_px[1] = 2.0f + 5.0f * y;
    }
    FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
    size_t n = (size_t)W * H;
    float *c_out = malloc(4 * n * sizeof(float)), *cl_out = malloc(4 * n * sizeof(float));
    /* the default grid (16 bins: pass 1a fills 4 slices per launch here), one whose bins do
     * not divide into those launches (10: 4 + 4 + 2) and one whose samples reach 17 nodes
     * (three float8 chunks in 1a, 96 densities in 2a) */
    const int nodes[3] = {17, 11, 33};
    for (int gi = 0; gi < 3; ++gi) {
        g.shift_nodes = nodes[gi], g.y2_bins = nodes[gi] - 1;
        CHECK(fsf_filter_factored(&f.s, &g, f.px, &gd, c_out));
        double secs = 0.0;
        if (cl) CHECK(fsf_cl_run(cl, &f.s, &g, f.px, &gd, cl_out, &secs, &d));
        double worst = 0.0;
        for (size_t i = 0; cl && i < n; ++i)
            for (int c = 0; c < 4; ++c) {
                double e = fabs((double)c_out[4 * i + c] - cl_out[4 * i + c]) / fmax(fabs(c_out[4 * i + 3]), 1e-3);
                if (e > worst) worst = e;
            }
        printf("%d shift nodes: OpenCL against C: largest difference %.3g of the pixel's weight (kernels %.4f s)\n",
               nodes[gi], worst, secs);
        /* the same float arithmetic in another order and exp vs expf: rounding only (3e-7
         * measured; a node or tap lost or shifted would show as a whole sample's weight, ~1e-2) */
        CHECK(worst < 1e-5);
    }
    free(c_out), free(cl_out);
    fsf_synth_free(&f);
    fsf_cl_destroy(cl);
    cl_runtime_destroy(rt);
    return check_failures ? 1 : 0;
}
