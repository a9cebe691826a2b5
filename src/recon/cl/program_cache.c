/* Compiled OpenCL programs kept between runs (see program_cache.h). */
#include "recon/cl/program_cache.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/cache_home.h"
#include "core/env_knob.h"

/* The file: this magic, the key again (a file renamed by hand is not trusted), the binary's
 * size, the binary. */
static const char MAGIC[8] = {'W', 'E', 'D', 'G', 'E', 'C', 'L', '1'};

typedef struct {
    uint64_t a, b; /* two FNV-1a lanes with different offsets: 128 bits */
} Key;

static void key_bytes(Key *k, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; ++i) {
        k->a = (k->a ^ p[i]) * 0x100000001b3ull;
        k->b = (k->b ^ p[i]) * 0x100000001b3ull;
    }
    unsigned char end = 0xff; /* separates fields: ("ab", "c") differs from ("a", "bc") */
    k->a = (k->a ^ end) * 0x100000001b3ull;
    k->b = (k->b ^ end) * 0x100000001b3ull;
}

static void key_device_info(Key *k, cl_device_id dev, cl_device_info what)
{
    char buf[1024] = {0};
    clGetDeviceInfo(dev, what, sizeof buf - 1, buf, NULL);
    key_bytes(k, buf, strlen(buf));
}

static Key program_key(const ClRuntime *rt, const char *const *sources, int count, const char *options)
{
    Key k = {0xcbf29ce484222325ull, 0x84222325cbf29ce4ull};
    for (int i = 0; i < count; ++i) key_bytes(&k, sources[i], strlen(sources[i]));
    key_bytes(&k, options, strlen(options));
    key_device_info(&k, rt->device, CL_DEVICE_NAME);
    key_device_info(&k, rt->device, CL_DEVICE_VENDOR);
    key_device_info(&k, rt->device, CL_DEVICE_VERSION);
    key_device_info(&k, rt->device, CL_DRIVER_VERSION);
    char platform[1024] = {0};
    clGetPlatformInfo(rt->platform, CL_PLATFORM_VERSION, sizeof platform - 1, platform, NULL);
    key_bytes(&k, platform, strlen(platform));
    return k;
}

static bool cache_on(void)
{
    return env_knob_switch("WEDGE_CL_PROGRAM_CACHE", true);
}

/* The cache folder into dir and the key's file in it into path. */
static bool file_path(const Key *k, char dir[4096], char *path, size_t n)
{
    if (!cache_home("wedge", dir, 4096)) return false;
    int w = snprintf(path, n, "%s/cl-%016llx%016llx.bin", dir, (unsigned long long)k->a, (unsigned long long)k->b);
    return w > 0 && (size_t)w < n;
}

cl_program program_cache_load(const ClRuntime *rt, const char *const *sources, int count, const char *options)
{
    if (!cache_on()) return NULL;
    Key k = program_key(rt, sources, count, options);
    char dir[4096], path[4200];
    if (!file_path(&k, dir, path, sizeof path)) return NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char magic[8];
    Key stored;
    uint64_t size = 0;
    unsigned char *bin = NULL;
    bool ok = fread(magic, 1, 8, f) == 8 && memcmp(magic, MAGIC, 8) == 0 && fread(&stored, sizeof stored, 1, f) == 1 &&
              stored.a == k.a && stored.b == k.b && fread(&size, sizeof size, 1, f) == 1 && size > 0 &&
              size < ((uint64_t)1 << 30);
    if (ok) {
        bin = malloc((size_t)size);
        ok = bin && fread(bin, 1, (size_t)size, f) == (size_t)size && fgetc(f) == EOF;
    }
    fclose(f);
    cl_program program = NULL;
    if (ok) {
        size_t len = (size_t)size;
        const unsigned char *p = bin;
        cl_int status = CL_SUCCESS, err = CL_SUCCESS;
        program = clCreateProgramWithBinary(rt->context, 1, &rt->device, &len, &p, &status, &err);
        if (err != CL_SUCCESS || status != CL_SUCCESS) {
            if (program) clReleaseProgram(program);
            program = NULL;
        } else if (clBuildProgram(program, 1, &rt->device, options, NULL, NULL) != CL_SUCCESS) {
            clReleaseProgram(program);
            program = NULL;
        }
    }
    free(bin);
    return program;
}

void program_cache_store(const ClRuntime *rt, cl_program program, const char *const *sources, int count,
                         const char *options)
{
    if (!cache_on()) return;
    Key k = program_key(rt, sources, count, options);
    char path[4200], dir[4096], tmp[4300];
    if (!file_path(&k, dir, path, sizeof path)) return;
    cl_uint devices = 0;
    size_t size = 0;
    if (clGetProgramInfo(program, CL_PROGRAM_NUM_DEVICES, sizeof devices, &devices, NULL) != CL_SUCCESS || devices != 1 ||
        clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, NULL) != CL_SUCCESS || size == 0)
        return;
    unsigned char *bin = malloc(size);
    if (!bin) return;
    if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof bin, &bin, NULL) != CL_SUCCESS) {
        free(bin);
        return;
    }
    /* the folder may not exist yet (a first run that renders no reference) */
    int n = make_dirs(dir) ? snprintf(tmp, sizeof tmp, "%s/.cl-XXXXXX", dir) : -1;
    int fd = n > 0 && (size_t)n < sizeof tmp ? mkstemp(tmp) : -1;
    if (fd < 0) {
        free(bin);
        return;
    }
    FILE *f = fdopen(fd, "wb");
    uint64_t size64 = size;
    bool ok = f && fwrite(MAGIC, 1, 8, f) == 8 && fwrite(&k, sizeof k, 1, f) == 1 && fwrite(&size64, sizeof size64, 1, f) == 1 &&
              fwrite(bin, 1, size, f) == size;
    if (f) ok = fclose(f) == 0 && ok;
    else close(fd);
    if (!ok || rename(tmp, path) != 0) remove(tmp);
    free(bin);
}
