/* PLACEHOLDER: replaced by the work that implements 'wedge converge'. */
#include <stdio.h>

#include "app/commands.h"
#include "core/diag.h"

int cmd_converge(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "wedge converge: not implemented yet\n");
    return WEDGE_EXIT_RUNTIME;
}
