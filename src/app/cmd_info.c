/* PLACEHOLDER: replaced by the work that implements 'wedge info'. */
#include <stdio.h>

#include "app/commands.h"
#include "core/diag.h"

int cmd_info(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "wedge info: not implemented yet\n");
    return WEDGE_EXIT_RUNTIME;
}
