/* OpenCL runtime: device listing, device choice, a given program's build, build-log reporting,
 * and the "no platform" message. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/cl/cl_runtime.h"

int main(void)
{
    Diag d = {0};

    /* Listing works and marks a default device. */
    char buf[8192] = "";
    FILE *f = fmemopen(buf, sizeof buf - 1, "w");
    CHECK(f != NULL);
    CHECK(recon_print_devices(f));
    fclose(f);
    CHECK(strstr(buf, "device 0:") != NULL);
    CHECK(strstr(buf, "(default)") != NULL);

    /* The default device opens (its programs build on demand: test_cl_programs). */
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    CHECK(rt != NULL);
    if (!rt) fprintf(stderr, "%s\n", d.message);
    cl_runtime_destroy(rt);

    /* Choice by index and by (case-insensitive) name substring. */
    rt = cl_runtime_create("0", &d);
    CHECK(rt != NULL);
    cl_runtime_destroy(rt);

    /* An index past the end and an unknown name are usage errors naming the choice. */
    rt = cl_runtime_create("999", &d);
    CHECK(rt == NULL);
    CHECK(d.exit_code == WEDGE_EXIT_USAGE);
    CHECK(strstr(d.message, "OpenCL device 999 does not exist") != NULL);
    rt = cl_runtime_create("no-such-device-xyz", &d);
    CHECK(rt == NULL);
    CHECK_STR(d.message, "error: no OpenCL device matches 'no-such-device-xyz' (see 'wedge info --cl')");

    /* $WEDGE_CL_DEVICE is honoured when no explicit choice is given. */
    setenv("WEDGE_CL_DEVICE", "no-such-device-xyz", 1);
    rt = cl_runtime_create(NULL, &d);
    CHECK(rt == NULL);
    CHECK(strstr(d.message, "no-such-device-xyz") != NULL);
    unsetenv("WEDGE_CL_DEVICE");

    /* A kernel that does not compile: runtime error carrying the compiler's build log. */
    const char *bad[] = {"__kernel void broken(__global float *x) { x[0] = undeclared_name; }\n"};
    rt = cl_runtime_create_with_sources(NULL, bad, 1, &d);
    CHECK(rt == NULL);
    CHECK(d.exit_code == WEDGE_EXIT_RUNTIME);
    CHECK(strstr(d.message, "OpenCL kernel build failed") != NULL);
    CHECK(strstr(d.message, "undeclared_name") != NULL);

    CHECK_DONE();
}
