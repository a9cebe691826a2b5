/* Host side of fsf_flat.cl (see fsf_flat_cl.h). */
#include "recon/fsf/fsf_flat_cl.h"

#include <stdlib.h>

#include "recon/fsf/fsf_cl_kept.h"

_Static_assert(sizeof(FsfPixel) == 8 * sizeof(float), "fsf_flat.cl reads FsfPixel as 8 floats");

/* fsf_flat.cl's FsfFlatArgs, passed by value */
typedef struct {
    cl_int width, height;
    cl_float reach, cos_normal_min, plane_tol_rel;
    cl_int guided;
} FsfFlatArgs;

/* G (pass A's output) and the result, 4 floats a pixel each: written before they are read in
 * every run, kept (fsf_cl_kept.h) */
enum { KEPT_G, KEPT_OUT, KEPT_N };

struct FsfFlatCl {
    ClRuntime *rt;
    cl_kernel pass_a, pass_b;
    FsfClKept kept[KEPT_N];
};

FsfFlatCl *fsf_flat_cl_create(ClRuntime *rt, Diag *d)
{
    FsfFlatCl *f = calloc(1, sizeof *f);
    if (!f) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's indirect-light kernels");
        return NULL;
    }
    f->rt = rt;
    if (!(f->pass_a = cl_runtime_kernel(rt, "fsf_flat_pass_a", d)) ||
        !(f->pass_b = cl_runtime_kernel(rt, "fsf_flat_pass_b", d))) {
        fsf_flat_cl_destroy(f);
        return NULL;
    }
    return f;
}

void fsf_flat_cl_destroy(FsfFlatCl *f)
{
    if (!f) return;
    for (int k = 0; k < KEPT_N; ++k) fsf_cl_kept_free(&f->kept[k]);
    if (f->pass_a) clReleaseKernel(f->pass_a);
    if (f->pass_b) clReleaseKernel(f->pass_b);
    free(f);
}

/* A 1D launch over n pixels in groups of a fixed size (a size PoCL picks itself is compiled
 * anew per global size: cl_launch_2d) */
static cl_int launch(FsfFlatCl *f, cl_kernel k, size_t n, cl_event *ev)
{
    size_t local = 64, global = (n + local - 1) / local * local;
    return clEnqueueNDRangeKernel(f->rt->queue, k, 1, NULL, &global, &local, 0, NULL, ev);
}

static cl_int set_args(cl_kernel k, const FsfFlatArgs *a, const cl_mem *mems, int nm)
{
    cl_int err = clSetKernelArg(k, 0, sizeof *a, a);
    for (int i = 0; i < nm; ++i) err |= clSetKernelArg(k, (cl_uint)(i + 1), sizeof(cl_mem), &mems[i]);
    return err;
}

bool fsf_flat_cl_run(FsfFlatCl *f, const float *value4, const int *count, int width, int height, const FsfGrid *g,
                     const FsfPixel *px, const FsfGuides *gd, float *out4, double *kernel_seconds, Diag *d)
{
    size_t n = (size_t)width * (size_t)height, n1 = n > 0 ? n : 1;
    cl_int guided = gd->pos4 && gd->nrm4;
    FsfFlatArgs a = {width, height, g->reach_sigmas, gd->cos_normal_min, gd->plane_tol_rel, guided};
    cl_context ctx = f->rt->context;
    const cl_mem_flags ro = CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR;
    enum { VAL, COUNT, PX, USE, POS, NRM, NBUF };
    cl_mem b[NBUF] = {0};
    cl_int err = CL_SUCCESS;
    b[VAL] = clCreateBuffer(ctx, ro, sizeof(float) * 4 * n1, (void *)value4, &err);
    if (!err) b[COUNT] = clCreateBuffer(ctx, ro, sizeof(int) * n1, (void *)count, &err);
    if (!err) b[PX] = clCreateBuffer(ctx, ro, sizeof(FsfPixel) * n1, (void *)px, &err);
    if (!err) b[USE] = clCreateBuffer(ctx, ro, n1, (void *)gd->usable, &err);
    /* without guides the kernels read neither: a float4 each */
    if (!err) b[POS] = guided ? clCreateBuffer(ctx, ro, sizeof(float) * 4 * n1, (void *)gd->pos4, &err)
                              : clCreateBuffer(ctx, CL_MEM_READ_ONLY, sizeof(float) * 4, NULL, &err);
    if (!err) b[NRM] = guided ? clCreateBuffer(ctx, ro, sizeof(float) * 4 * n1, (void *)gd->nrm4, &err)
                              : clCreateBuffer(ctx, CL_MEM_READ_ONLY, sizeof(float) * 4, NULL, &err);
    cl_mem G = err ? NULL : fsf_cl_kept_get(ctx, &f->kept[KEPT_G], sizeof(float) * 4 * n1, &err);
    cl_mem out = err ? NULL : fsf_cl_kept_get(ctx, &f->kept[KEPT_OUT], sizeof(float) * 4 * n1, &err);
    const char *what = "buffer allocation";
    cl_event ev[2] = {NULL, NULL};
    if (!err && n > 0) {
        cl_mem ma[7] = {b[VAL], b[COUNT], b[PX], b[USE], b[POS], b[NRM], G};
        cl_mem mb[6] = {G, b[PX], b[USE], b[POS], b[NRM], out};
        what = "arguments";
        err = set_args(f->pass_a, &a, ma, 7) | set_args(f->pass_b, &a, mb, 6);
        if (!err) what = "pass A", err = launch(f, f->pass_a, n, &ev[0]);
        if (!err) what = "pass B", err = launch(f, f->pass_b, n, &ev[1]);
        if (!err)
            what = "download",
            err = clEnqueueReadBuffer(f->rt->queue, out, CL_TRUE, 0, sizeof(float) * 4 * n, out4, 0, NULL, NULL);
    }
    clFinish(f->rt->queue);
    double secs = 0.0;
    for (int k = 0; k < 2; ++k)
        if (ev[k]) secs += cl_event_seconds(ev[k]), clReleaseEvent(ev[k]);
    if (kernel_seconds) *kernel_seconds = secs;
    for (int i = 0; i < NBUF; ++i)
        if (b[i]) clReleaseMemObject(b[i]);
    if (err != CL_SUCCESS) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s (FSF indirect light): %s", what, cl_error_name(err));
        return false;
    }
    return true;
}
