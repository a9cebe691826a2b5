/* OpenCL device choice, context and program build (see cl_runtime.h). */
#include "recon/cl/cl_runtime_internal.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/clock.h"
#include "core/env_knob.h"
#include "recon/cl/icd_preload.h"
#include "recon/cl/kernel_cache.h"
#include "recon/cl/kernel_decl.h"
#include "recon/cl/program_cache.h"
#include "recon/cl/kernel_sources.h"

#define MAX_PLATFORMS 16
#define MAX_DEVICES_PER_PLATFORM 32

const char *cl_error_name(cl_int err)
{
    switch (err) {
    case CL_SUCCESS: return "CL_SUCCESS";
    case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND";
    case CL_DEVICE_NOT_AVAILABLE: return "CL_DEVICE_NOT_AVAILABLE";
    case CL_COMPILER_NOT_AVAILABLE: return "CL_COMPILER_NOT_AVAILABLE";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE: return "CL_INVALID_VALUE";
    case CL_INVALID_PLATFORM: return "CL_INVALID_PLATFORM";
    case CL_INVALID_DEVICE: return "CL_INVALID_DEVICE";
    case CL_INVALID_CONTEXT: return "CL_INVALID_CONTEXT";
    case CL_INVALID_COMMAND_QUEUE: return "CL_INVALID_COMMAND_QUEUE";
    case CL_INVALID_MEM_OBJECT: return "CL_INVALID_MEM_OBJECT";
    case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE";
    case CL_INVALID_PROGRAM: return "CL_INVALID_PROGRAM";
    case CL_INVALID_PROGRAM_EXECUTABLE: return "CL_INVALID_PROGRAM_EXECUTABLE";
    case CL_INVALID_KERNEL_NAME: return "CL_INVALID_KERNEL_NAME";
    case CL_INVALID_KERNEL: return "CL_INVALID_KERNEL";
    case CL_INVALID_ARG_INDEX: return "CL_INVALID_ARG_INDEX";
    case CL_INVALID_ARG_VALUE: return "CL_INVALID_ARG_VALUE";
    case CL_INVALID_ARG_SIZE: return "CL_INVALID_ARG_SIZE";
    case CL_INVALID_KERNEL_ARGS: return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_WORK_DIMENSION: return "CL_INVALID_WORK_DIMENSION";
    case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_GLOBAL_WORK_SIZE: return "CL_INVALID_GLOBAL_WORK_SIZE";
    case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
    default: return "unknown OpenCL error";
    }
}

/* One device of the flattened (platform, device) list that --cl-device N indexes. */
typedef struct {
    cl_platform_id platform;
    cl_device_id device;
    cl_device_type type;
    char name[256];
    char platform_name[256];
} DeviceEntry;

typedef struct {
    DeviceEntry entries[MAX_PLATFORMS * MAX_DEVICES_PER_PLATFORM];
    int count;
    int platform_count;
} DeviceList;

/* Fills list; returns false with d set when there is no platform at all. */
static bool list_devices(DeviceList *list, Diag *d)
{
    cl_platform_id platforms[MAX_PLATFORMS];
    cl_uint nplat = 0;
    list->count = 0;
    list->platform_count = 0;
    kernel_cache_prepare(); /* before the driver looks for its cache */
    cl_icd_preload();       /* the driver bound to its own libraries first */
    cl_int err = clGetPlatformIDs(MAX_PLATFORMS, platforms, &nplat);
    if (err != CL_SUCCESS || nplat == 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "no OpenCL platform found (%s): install an OpenCL driver, e.g. the Debian "
                 "package %s for the CPU",
                 err == CL_SUCCESS ? "0 platforms" : cl_error_name(err), WEDGE_CL_PACKAGE_HINT);
        return false;
    }
    if (nplat > MAX_PLATFORMS) nplat = MAX_PLATFORMS;
    list->platform_count = (int)nplat;
    for (cl_uint p = 0; p < nplat; ++p) {
        char pname[256] = "";
        clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof pname - 1, pname, NULL);
        cl_device_id devs[MAX_DEVICES_PER_PLATFORM];
        cl_uint ndev = 0;
        if (clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES_PER_PLATFORM, devs, &ndev) !=
            CL_SUCCESS)
            continue; /* a platform without devices is listed by recon_print_devices only */
        if (ndev > MAX_DEVICES_PER_PLATFORM) ndev = MAX_DEVICES_PER_PLATFORM;
        for (cl_uint i = 0; i < ndev; ++i) {
            DeviceEntry *e = &list->entries[list->count++];
            memset(e, 0, sizeof *e);
            e->platform = platforms[p];
            e->device = devs[i];
            clGetDeviceInfo(devs[i], CL_DEVICE_TYPE, sizeof e->type, &e->type, NULL);
            clGetDeviceInfo(devs[i], CL_DEVICE_NAME, sizeof e->name - 1, e->name, NULL);
            memcpy(e->platform_name, pname, sizeof pname);
        }
    }
    if (list->count == 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "OpenCL platforms found but no device: install an OpenCL driver, e.g. the "
                 "Debian package %s for the CPU (PoCL also needs a writable kernel cache: $POCL_CACHE_DIR)",
                 WEDGE_CL_PACKAGE_HINT);
        return false;
    }
    return true;
}

static bool contains_nocase(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    if (n == 0) return false;
    for (const char *h = hay; *h; ++h) {
        size_t i = 0;
        while (i < n && h[i] && tolower((unsigned char)h[i]) == tolower((unsigned char)needle[i])) ++i;
        if (i == n) return true;
    }
    return false;
}

static bool is_index(const char *s)
{
    if (!*s) return false;
    for (; *s; ++s)
        if (!isdigit((unsigned char)*s)) return false;
    return true;
}

/* Index into list of the chosen device, or -1 with d set. */
static int choose_device(const DeviceList *list, const char *choice, Diag *d)
{
    if (!choice || !*choice) {
        for (int i = 0; i < list->count; ++i)
            if (list->entries[i].type & CL_DEVICE_TYPE_GPU) return i;
        for (int i = 0; i < list->count; ++i)
            if (list->entries[i].type & CL_DEVICE_TYPE_CPU) return i;
        return 0;
    }
    if (is_index(choice)) {
        long n = strtol(choice, NULL, 10);
        if (n >= 0 && n < list->count) return (int)n;
        diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0},
                 "OpenCL device %s does not exist: there %s %d device%s (see 'wedge info --cl')",
                 choice, list->count == 1 ? "is" : "are", list->count, list->count == 1 ? "" : "s");
        return -1;
    }
    for (int i = 0; i < list->count; ++i)
        if (contains_nocase(list->entries[i].name, choice)) return i;
    for (int i = 0; i < list->count; ++i)
        if (contains_nocase(list->entries[i].platform_name, choice)) return i;
    diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0},
             "no OpenCL device matches '%s' (see 'wedge info --cl')", choice);
    return -1;
}

/* OpenCL C 1.2, float only, no extensions: the same kernels must build on every driver. */
static const char BUILD_OPTIONS[] = "-cl-std=CL1.2";

/* Builds slot's program (from the cached binary when there is one); false + Diag with the
 * build log on failure. */
static bool build_program(ClRuntime *rt, ClProgramSlot *slot, Diag *d)
{
    double t0 = clock_wall_seconds();
    bool cached = true;
    slot->program = program_cache_load(rt, slot->sources, slot->source_count, BUILD_OPTIONS);
    if (!slot->program) {
        cached = false;
        cl_int err = CL_SUCCESS;
        slot->program = clCreateProgramWithSource(rt->context, (cl_uint)slot->source_count,
                                                  (const char **)slot->sources, NULL, &err);
        if (err != CL_SUCCESS) {
            slot->program = NULL;
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL program creation failed: %s", cl_error_name(err));
            return false;
        }
        err = clBuildProgram(slot->program, 1, &rt->device, BUILD_OPTIONS, NULL, NULL);
        if (err != CL_SUCCESS) {
            size_t log_size = 0;
            clGetProgramBuildInfo(slot->program, rt->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &log_size);
            char *log = calloc(log_size + 1, 1);
            if (log) clGetProgramBuildInfo(slot->program, rt->device, CL_PROGRAM_BUILD_LOG, log_size, log, NULL);
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL kernel build failed on %s (%s); build log:",
                     rt->label, cl_error_name(err));
            diag_append(d, "%s", log && *log ? log : "(empty build log)");
            free(log);
            clReleaseProgram(slot->program);
            slot->program = NULL;
            return false;
        }
        program_cache_store(rt, slot->program, slot->sources, slot->source_count, BUILD_OPTIONS);
    }
    ++rt->programs_built;
    if (env_knob_switch("WEDGE_CL_LOG", false))
        fprintf(stderr, "wedge: cl program %s built %s in %.1f ms\n", slot->name,
                cached ? "from the cached binary" : "from source", 1e3 * (clock_wall_seconds() - t0));
    return true;
}

bool cl_runtime_check_device(const char *device_choice, Diag *d)
{
    DeviceList *list = calloc(1, sizeof *list);
    if (!list) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    bool ok = list_devices(list, d);
    if (ok) {
        if (!device_choice || !*device_choice) device_choice = getenv(WEDGE_CL_DEVICE_ENV);
        ok = choose_device(list, device_choice, d) >= 0;
    }
    free(list);
    return ok;
}

/* The chosen device's context and queue, no program yet. */
static ClRuntime *open_device(const char *device_choice, Diag *d)
{
    DeviceList *list = calloc(1, sizeof *list);
    if (!list) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return NULL;
    }
    if (!list_devices(list, d)) {
        free(list);
        return NULL;
    }
    if (!device_choice || !*device_choice) device_choice = getenv(WEDGE_CL_DEVICE_ENV);
    int idx = choose_device(list, device_choice, d);
    if (idx < 0) {
        free(list);
        return NULL;
    }
    ClRuntime *rt = calloc(1, sizeof *rt);
    if (!rt) {
        free(list);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return NULL;
    }
    const DeviceEntry *e = &list->entries[idx];
    rt->platform = e->platform;
    rt->device = e->device;
    snprintf(rt->label, sizeof rt->label, "%s (%s)", e->name, e->platform_name);
    free(list);

    cl_int err = CL_SUCCESS;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)rt->platform, 0};
    rt->context = clCreateContext(props, 1, &rt->device, NULL, NULL, &err);
    if (err != CL_SUCCESS) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot create an OpenCL context on %s: %s",
                 rt->label, cl_error_name(err));
        cl_runtime_destroy(rt);
        return NULL;
    }
    rt->queue = clCreateCommandQueue(rt->context, rt->device, CL_QUEUE_PROFILING_ENABLE, &err);
    if (err != CL_SUCCESS) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot create an OpenCL queue on %s: %s",
                 rt->label, cl_error_name(err));
        cl_runtime_destroy(rt);
        return NULL;
    }
    return rt;
}

ClRuntime *cl_runtime_create_with_sources(const char *device_choice, const char *const *sources,
                                          int source_count, Diag *d)
{
    ClRuntime *rt = open_device(device_choice, d);
    if (!rt || source_count <= 0) return rt;
    /* one program of all the given sources, built now: its build errors are the caller's */
    rt->programs[0] = (ClProgramSlot){"(given sources)", sources, source_count, NULL};
    rt->program_count = 1;
    if (!build_program(rt, &rt->programs[0], d)) {
        cl_runtime_destroy(rt);
        return NULL;
    }
    return rt;
}

ClRuntime *cl_runtime_create(const char *device_choice, Diag *d)
{
    ClRuntime *rt = open_device(device_choice, d);
    if (!rt) return NULL;
    /* one program per embedded source, each built when a kernel of it is first asked for */
    for (const WedgeKernelSource *k = wedge_kernel_sources; k->name; ++k) {
        if (rt->program_count == CL_RUNTIME_MAX_PROGRAMS) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "more than %d embedded OpenCL sources",
                     CL_RUNTIME_MAX_PROGRAMS);
            cl_runtime_destroy(rt);
            return NULL;
        }
        rt->programs[rt->program_count++] = (ClProgramSlot){k->name, &k->source, 1, NULL};
    }
    return rt;
}

void cl_runtime_destroy(ClRuntime *rt)
{
    if (!rt) return;
    for (int i = 0; i < rt->program_count; ++i)
        if (rt->programs[i].program) clReleaseProgram(rt->programs[i].program);
    if (rt->queue) clReleaseCommandQueue(rt->queue);
    if (rt->context) clReleaseContext(rt->context);
    free(rt);
}

const char *cl_runtime_device_label(const ClRuntime *rt) { return rt ? rt->label : "(none)"; }

/* The slot whose sources declare kernel name, or NULL. A runtime of given sources has one
 * program: the driver finds the kernel there (or says it is missing). */
static ClProgramSlot *slot_declaring(ClRuntime *rt, const char *name)
{
    if (rt->program_count == 1 && rt->programs[0].program) return &rt->programs[0];
    for (int j = 0; j < rt->program_count; ++j) {
        int i = (rt->last_slot + j) % rt->program_count; /* a method asks for its kernels in a row */
        for (int s = 0; s < rt->programs[i].source_count; ++s)
            if (kernel_declared(rt->programs[i].sources[s], name)) {
                rt->last_slot = i;
                return &rt->programs[i];
            }
    }
    return NULL;
}

cl_kernel cl_runtime_kernel(ClRuntime *rt, const char *name, Diag *d)
{
    ClProgramSlot *slot = slot_declaring(rt, name);
    if (!slot) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL kernel '%s' not found: no OpenCL source declares it",
                 name);
        return NULL;
    }
    if (!slot->program && !build_program(rt, slot, d)) return NULL;
    cl_int err = CL_SUCCESS;
    cl_kernel k = clCreateKernel(slot->program, name, &err);
    if (err != CL_SUCCESS) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL kernel '%s' not found in %s: %s", name, slot->name,
                 cl_error_name(err));
        return NULL;
    }
    return k;
}

int cl_runtime_programs_built(const ClRuntime *rt) { return rt ? rt->programs_built : 0; }

bool cl_launch_2d(ClRuntime *rt, cl_kernel k, size_t gx, size_t gy, cl_event *ev, Diag *d)
{
    size_t lx = CL_LAUNCH_LOCAL_X, ly = CL_LAUNCH_LOCAL_Y, most = 0;
    if (clGetKernelWorkGroupInfo(k, rt->device, CL_KERNEL_WORK_GROUP_SIZE, sizeof most, &most, NULL) == CL_SUCCESS)
        while (lx * ly > most && ly > 1) ly /= 2;
    while (lx * ly > most && lx > 1 && most > 0) lx /= 2;
    size_t global[2] = {(gx + lx - 1) / lx * lx, (gy + ly - 1) / ly * ly}, local[2] = {lx, ly};
    cl_int err = clEnqueueNDRangeKernel(rt->queue, k, 2, NULL, global, local, 0, NULL, ev);
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL kernel launch failed: %s", cl_error_name(err));
    return false;
}

bool cl_launch_serial_2d(ClRuntime *rt, cl_kernel k, size_t gx, size_t gy, cl_event *ev, Diag *d)
{
    size_t global[2] = {gx, gy}, local[2] = {1, 1};
    cl_int err = clEnqueueNDRangeKernel(rt->queue, k, 2, NULL, global, local, 0, NULL, ev);
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL kernel launch failed: %s", cl_error_name(err));
    return false;
}

double cl_event_seconds(cl_event ev)
{
    cl_ulong t0 = 0, t1 = 0;
    if (!ev || clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof t0, &t0, NULL) != CL_SUCCESS ||
        clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof t1, &t1, NULL) != CL_SUCCESS)
        return 0.0;
    return t1 > t0 ? (double)(t1 - t0) * 1e-9 : 0.0;
}

static const char *type_name(cl_device_type t)
{
    if (t & CL_DEVICE_TYPE_GPU) return "GPU";
    if (t & CL_DEVICE_TYPE_CPU) return "CPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

bool recon_print_devices(FILE *out)
{
    Diag d;
    DeviceList *list = calloc(1, sizeof *list);
    if (!list) return false;
    if (!list_devices(list, &d)) {
        fprintf(out, "%s\n", d.message);
        free(list);
        return false;
    }
    int chosen = choose_device(list, NULL, &d);
    const char *last_platform = NULL;
    for (int i = 0; i < list->count; ++i) {
        const DeviceEntry *e = &list->entries[i];
        if (!last_platform || strcmp(last_platform, e->platform_name) != 0) {
            fprintf(out, "platform: %s\n", e->platform_name);
            last_platform = e->platform_name;
        }
        char version[128] = "";
        cl_uint units = 0;
        cl_ulong mem = 0;
        clGetDeviceInfo(e->device, CL_DEVICE_VERSION, sizeof version - 1, version, NULL);
        clGetDeviceInfo(e->device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
        clGetDeviceInfo(e->device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof mem, &mem, NULL);
        fprintf(out, "  device %d: %s [%s, %u compute units, %llu MiB, %s]%s\n", i, e->name,
                type_name(e->type), units, (unsigned long long)(mem >> 20), version,
                i == chosen ? " (default)" : "");
    }
    free(list);
    return true;
}
