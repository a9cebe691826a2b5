/* The OpenCL device a kernel-against-C test runs on, or the test skipped (exit 77, ctest's
 * SKIP_RETURN_CODE for C tests) where the machine has none. */
#ifndef WEDGE_TESTS_RECON_CL_TEST_DEVICE_H
#define WEDGE_TESTS_RECON_CL_TEST_DEVICE_H

#include <stdio.h>
#include <stdlib.h>

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"

static inline ClRuntime *cl_test_device_or_skip(void)
{
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    if (!rt) {
        fprintf(stderr, "skipped, no OpenCL device: %s\n", d.message);
        exit(77);
    }
    return rt;
}

#endif
