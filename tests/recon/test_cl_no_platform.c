/* Without any OpenCL driver registered, the runtime fails with exit code 3 and a message that
 * names the package to install. The ICD loader (ocl-icd) reads its vendor list from
 * $OCL_ICD_VENDORS, which we point at an empty directory before the first OpenCL call. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "recon/cl/cl_runtime.h"

int main(void)
{
    char dir[] = "/tmp/wedge-no-icd-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    setenv("OCL_ICD_VENDORS", dir, 1);
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    CHECK(rt == NULL);
    CHECK(d.exit_code == WEDGE_EXIT_RUNTIME);
    CHECK(strstr(d.message, "no OpenCL platform found") != NULL);
    CHECK(strstr(d.message, "pocl-opencl-icd") != NULL);
    fprintf(stderr, "message: %s\n", d.message);
    char buf[1024] = "";
    FILE *f = fmemopen(buf, sizeof buf - 1, "w");
    CHECK(!recon_print_devices(f));
    fclose(f);
    CHECK(strstr(buf, "pocl-opencl-icd") != NULL);
    rmdir(dir);
    CHECK_DONE();
}
