/* Per OpenCL entry point: calls, wall time, the calling thread's CPU and the process's CPU
 * (milliseconds), printed on stderr at exit; with $CLTIME_EACH set, every call as it returns.
 * An LD_PRELOAD shim for taking a filtered frame's fixed cost apart (docs/benchmarks.md, "One
 * OpenCL program per method"); not part of the build:
 *   gcc -O2 -shared -fPIC -o /tmp/libcltime.so tools/cl-call-times.c -ldl
 *   LD_PRELOAD=/tmp/libcltime.so build/wedge render SCENE --res 32x24 --spp 1 --filter lr -o x.exr --quiet
 * The process CPU of a call made on the opener thread includes whatever the other threads do
 * meanwhile (pass 1's tracing): read the thread CPU there. */
#define _GNU_SOURCE
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <pthread.h>
#include <stdlib.h>
enum { MAXF = 64 };
static struct { const char *name; long n; double wall, tcpu, pcpu; } st[MAXF];
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static double now(clockid_t c) { struct timespec t; clock_gettime(c, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static void add(int i, const char *name, double w, double t, double p)
{ pthread_mutex_lock(&mu); st[i].name = name; st[i].n++; st[i].wall += w; st[i].tcpu += t; st[i].pcpu += p; pthread_mutex_unlock(&mu); if (getenv("CLTIME_EACH")) fprintf(stderr, "call %s wall %.3f tcpu %.3f pcpu %.3f\n", name, 1e3*w, 1e3*t, 1e3*p); }
__attribute__((destructor)) static void dump(void)
{
    double pc = now(CLOCK_PROCESS_CPUTIME_ID);
    for (int i = 0; i < MAXF; ++i) if (st[i].n)
        fprintf(stderr, "cltime %-28s n %4ld wall %8.3f tcpu %8.3f pcpu %8.3f\n", st[i].name, st[i].n, 1e3*st[i].wall, 1e3*st[i].tcpu, 1e3*st[i].pcpu);
    fprintf(stderr, "cltime process-cpu-at-exit %.3f\n", 1e3 * pc);
}
#define WRAP(idx, ret, name, params, args) \
ret name params { \
    static ret (*real) params; if (!real) real = (ret (*) params)dlsym(RTLD_NEXT, #name); \
    double w0 = now(CLOCK_MONOTONIC), t0 = now(CLOCK_THREAD_CPUTIME_ID), p0 = now(CLOCK_PROCESS_CPUTIME_ID); \
    ret r = real args; \
    add(idx, #name, now(CLOCK_MONOTONIC) - w0, now(CLOCK_THREAD_CPUTIME_ID) - t0, now(CLOCK_PROCESS_CPUTIME_ID) - p0); \
    return r; }
WRAP(0, cl_int, clGetPlatformIDs, (cl_uint a, cl_platform_id *b, cl_uint *c), (a, b, c))
WRAP(1, cl_context, clCreateContext, (const cl_context_properties *a, cl_uint b, const cl_device_id *c, void (CL_CALLBACK *e)(const char *, const void *, size_t, void *), void *f, cl_int *g), (a, b, c, e, f, g))
WRAP(2, cl_command_queue, clCreateCommandQueue, (cl_context a, cl_device_id b, cl_command_queue_properties c, cl_int *e), (a, b, c, e))
WRAP(3, cl_program, clCreateProgramWithBinary, (cl_context a, cl_uint b, const cl_device_id *c, const size_t *e, const unsigned char **f, cl_int *g, cl_int *h), (a, b, c, e, f, g, h))
WRAP(4, cl_int, clBuildProgram, (cl_program a, cl_uint b, const cl_device_id *c, const char *e, void (CL_CALLBACK *f)(cl_program, void *), void *g), (a, b, c, e, f, g))
WRAP(5, cl_kernel, clCreateKernel, (cl_program a, const char *b, cl_int *c), (a, b, c))
WRAP(6, cl_mem, clCreateBuffer, (cl_context a, cl_mem_flags b, size_t c, void *e, cl_int *f), (a, b, c, e, f))
WRAP(7, cl_int, clEnqueueNDRangeKernel, (cl_command_queue a, cl_kernel b, cl_uint c, const size_t *e, const size_t *f, const size_t *g, cl_uint h, const cl_event *i, cl_event *j), (a, b, c, e, f, g, h, i, j))
WRAP(8, cl_int, clFinish, (cl_command_queue a), (a))
WRAP(9, cl_int, clWaitForEvents, (cl_uint a, const cl_event *b), (a, b))
WRAP(10, cl_int, clEnqueueReadBuffer, (cl_command_queue a, cl_mem b, cl_bool c, size_t e, size_t f, void *g, cl_uint h, const cl_event *i, cl_event *j), (a, b, c, e, f, g, h, i, j))
WRAP(11, cl_int, clEnqueueWriteBuffer, (cl_command_queue a, cl_mem b, cl_bool c, size_t e, size_t f, const void *g, cl_uint h, const cl_event *i, cl_event *j), (a, b, c, e, f, g, h, i, j))
WRAP(12, cl_int, clGetKernelWorkGroupInfo, (cl_kernel a, cl_device_id b, cl_kernel_work_group_info c, size_t e, void *f, size_t *g), (a, b, c, e, f, g))
WRAP(13, cl_int, clReleaseKernel, (cl_kernel a), (a))
WRAP(14, cl_int, clReleaseProgram, (cl_program a), (a))
WRAP(15, cl_int, clReleaseContext, (cl_context a), (a))
WRAP(16, cl_int, clReleaseCommandQueue, (cl_command_queue a), (a))
WRAP(17, cl_int, clReleaseMemObject, (cl_mem a), (a))
WRAP(18, cl_int, clSetKernelArg, (cl_kernel a, cl_uint b, size_t c, const void *e), (a, b, c, e))
WRAP(19, cl_int, clGetDeviceIDs, (cl_platform_id a, cl_device_type b, cl_uint c, cl_device_id *e, cl_uint *f), (a, b, c, e, f))
WRAP(20, cl_int, clGetDeviceInfo, (cl_device_id a, cl_device_info b, size_t c, void *e, size_t *f), (a, b, c, e, f))
WRAP(21, cl_int, clEnqueueFillBuffer, (cl_command_queue a, cl_mem b, const void *c, size_t e, size_t f, size_t g, cl_uint h, const cl_event *i, cl_event *j), (a, b, c, e, f, g, h, i, j))
WRAP(22, cl_int, clReleaseEvent, (cl_event a), (a))
WRAP(23, void *, clEnqueueMapBuffer, (cl_command_queue a, cl_mem b, cl_bool c, cl_map_flags e, size_t f, size_t g, cl_uint h, const cl_event *i, cl_event *j, cl_int *k), (a, b, c, e, f, g, h, i, j, k))
WRAP(24, cl_int, clGetPlatformInfo, (cl_platform_id a, cl_platform_info b, size_t c, void *e, size_t *f), (a, b, c, e, f))
WRAP(25, cl_int, clGetEventProfilingInfo, (cl_event a, cl_profiling_info b, size_t c, void *e, size_t *f), (a, b, c, e, f))
WRAP(26, cl_int, clEnqueueReadBufferRect, (cl_command_queue a, cl_mem b, cl_bool c, const size_t *e, const size_t *f, const size_t *g, size_t h, size_t i, size_t j, size_t k, void *l, cl_uint m, const cl_event *n, cl_event *o), (a, b, c, e, f, g, h, i, j, k, l, m, n, o))
WRAP(27, cl_int, clEnqueueUnmapMemObject, (cl_command_queue a, cl_mem b, void *c, cl_uint e, const cl_event *f, cl_event *g), (a, b, c, e, f, g))
WRAP(28, cl_int, clGetProgramInfo, (cl_program a, cl_program_info b, size_t c, void *e, size_t *f), (a, b, c, e, f))
