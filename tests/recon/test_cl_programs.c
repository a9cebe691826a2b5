/* One OpenCL program per embedded source (cl_runtime.h): kernel_declared finds exactly the
 * kernels the compiler reports for each source, and no other source claims them; a runtime
 * builds nothing until a kernel is asked for, then only the program that declares it, once;
 * each method's device set-up (AAF, FSF, LR, MAAF) builds its own program and no other,
 * and finds every kernel it needs there (a kernel moved to another method's file, or one
 * source's kernels asked for through another's program, fails here). */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/aaf/aaf_filter.h"
#include "recon/cl/cl_runtime_internal.h"
#include "recon/cl/kernel_decl.h"
#include "recon/cl/kernel_sources.h"
#include "recon/fsf/fsf_cl.h"
#include "recon/lr/lr_cl.h"
#include "recon/maaf/maaf_filter.h"

static void declarations(void)
{
    CHECK(kernel_declared("__kernel void a_b(int x) {}", "a_b"));
    CHECK(kernel_declared("kernel  void\n  a_b  (int x) {}", "a_b"));
    CHECK(kernel_declared("__kernel\nvoid\na_b\n(int x) {}", "a_b"));
    CHECK(!kernel_declared("static void a_b(int x) {}", "a_b"));                 /* a helper */
    CHECK(!kernel_declared("__kernel void maaf_unpack(int x) {}", "aaf_unpack")); /* a longer name */
    CHECK(!kernel_declared("__kernel void a_b2(int x) {}", "a_b"));
    CHECK(!kernel_declared("__kernel void k(int x) { a_b(x); }", "a_b"));        /* a call */
    CHECK(!kernel_declared("__kernel void a_b", "a_b"));
    CHECK(!kernel_declared("my__kernel void a_b(int x) {}", "a_b"));
    CHECK(kernel_declared("void a_b(int y);\n__kernel void a_b(int x) {}", "a_b")); /* the second */
}

/* The kernel names the compiler reports for source, built alone, into names (';'-separated). */
static bool compiler_kernel_names(const char *source, char *names, size_t n)
{
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create_with_sources(NULL, &source, 1, &d);
    if (!rt) {
        fprintf(stderr, "%s\n", d.message);
        return false;
    }
    bool ok = clGetProgramInfo(rt->programs[0].program, CL_PROGRAM_KERNEL_NAMES, n, names, NULL) == CL_SUCCESS;
    cl_runtime_destroy(rt);
    return ok && names[0];
}

static cl_program kernel_program(cl_kernel k)
{
    cl_program p = NULL;
    clGetKernelInfo(k, CL_KERNEL_PROGRAM, sizeof p, &p, NULL);
    return p;
}

/* Every kernel of every embedded source, asked for in a lazy runtime: the scan agrees with
 * the compiler, and each source's program is built at its first kernel and only then. */
static void embedded_sources(void)
{
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    CHECK(rt != NULL);
    if (!rt) {
        fprintf(stderr, "%s\n", d.message);
        return;
    }
    CHECK(cl_runtime_programs_built(rt) == 0);
    int sources = 0;
    for (const WedgeKernelSource *s = wedge_kernel_sources; s->name; ++s) ++sources;
    CHECK(sources == rt->program_count);
    CHECK(sources >= 4); /* aaf, fsf, lr, maaf */
    for (int i = 0; i < sources; ++i) {
        static char names[8192];
        CHECK(compiler_kernel_names(wedge_kernel_sources[i].source, names, sizeof names));
        int kernels = 0;
        for (char *save = NULL, *name = strtok_r(names, ";", &save); name; name = strtok_r(NULL, ";", &save)) {
            ++kernels;
            for (int j = 0; j < sources; ++j)
                if (kernel_declared(wedge_kernel_sources[j].source, name) != (i == j)) {
                    fprintf(stderr, "kernel %s of %s: declared by %s? scan says %d\n", name,
                            wedge_kernel_sources[i].name, wedge_kernel_sources[j].name, i != j);
                    CHECK(false);
                }
            cl_kernel k = cl_runtime_kernel(rt, name, &d);
            CHECK(k != NULL);
            if (!k) continue;
            CHECK(rt->programs[i].program != NULL && kernel_program(k) == rt->programs[i].program);
            clReleaseKernel(k);
            CHECK(cl_runtime_programs_built(rt) == i + 1); /* this source's, once */
        }
        CHECK(kernels > 0);
        for (int j = i + 1; j < sources; ++j) CHECK(rt->programs[j].program == NULL);
    }
    /* a name no source declares: an error naming it, nothing built */
    CHECK(cl_runtime_kernel(rt, "no_such_kernel", &d) == NULL);
    CHECK(strstr(d.message, "OpenCL kernel 'no_such_kernel' not found") != NULL);
    CHECK(cl_runtime_programs_built(rt) == sources);
    cl_runtime_destroy(rt);
}

/* The index of the embedded source called name, or -1. */
static int source_index(const char *name)
{
    for (int i = 0; wedge_kernel_sources[i].name; ++i)
        if (!strcmp(wedge_kernel_sources[i].name, name)) return i;
    return -1;
}

/* A method's device set-up on a fresh runtime: succeeds and builds its source alone. */
#define METHOD_BUILDS_ONLY(file, create, destroy)                                               \
    do {                                                                                        \
        Diag d_ = {0};                                                                          \
        ClRuntime *rt_ = cl_runtime_create(NULL, &d_);                                          \
        CHECK(rt_ != NULL);                                                                     \
        if (!rt_) break;                                                                        \
        void *m_ = create(rt_, &d_);                                                            \
        if (!m_) fprintf(stderr, "%s: %s\n", file, d_.message);                               \
        CHECK(m_ != NULL);                                                                      \
        int i_ = source_index(file);                                                            \
        CHECK(i_ >= 0 && rt_->programs[i_].program != NULL);                                    \
        CHECK(cl_runtime_programs_built(rt_) == 1);                                             \
        if (m_) destroy(m_);                                                                    \
        cl_runtime_destroy(rt_);                                                                \
    } while (0)

int main(void)
{
    declarations();
    embedded_sources();
    METHOD_BUILDS_ONLY("aaf.cl", aaf_filter_create, aaf_filter_destroy);
    METHOD_BUILDS_ONLY("fsf.cl", fsf_cl_create, fsf_cl_destroy);
    METHOD_BUILDS_ONLY("lr.cl", lr_cl_create, lr_cl_destroy);
    METHOD_BUILDS_ONLY("maaf.cl", maaf_filter_create, maaf_filter_destroy);
    CHECK_DONE();
}
