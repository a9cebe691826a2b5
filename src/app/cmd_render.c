/* PLACEHOLDER: replaced by the work that implements 'wedge render'. */
#include <stdio.h>

#include "app/commands.h"
#include "core/diag.h"

int cmd_render(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "wedge render: not implemented yet\n");
    return WEDGE_EXIT_RUNTIME;
}
