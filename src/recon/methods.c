/* The registry of reconstruction methods (method.h). A new method adds its class here, in
 * the order `wedge info --filters` lists them, and its measured row to select.c. */
#include <string.h>

#include "recon/method.h"

extern const ReconMethodClass recon_method_aaf; /* recon/aaf/aaf_method.c */
extern const ReconMethodClass recon_method_lr;  /* recon/lr/lr_method.c */
extern const ReconMethodClass recon_method_maaf; /* recon/maaf/maaf_method.c */
extern const ReconMethodClass recon_method_fsf; /* recon/fsf/fsf_method.c */

const ReconMethodClass *const recon_methods[] = {
    &recon_method_aaf,
    &recon_method_lr,
    &recon_method_maaf,
    &recon_method_fsf,
    NULL,
};

const ReconMethodClass *recon_method_find(const char *name)
{
    for (int i = 0; recon_methods[i]; ++i)
        if (!strcmp(recon_methods[i]->name, name)) return recon_methods[i];
    return NULL;
}
