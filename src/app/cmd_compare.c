/* PLACEHOLDER: replaced by the work that implements 'wedge compare'. */
#include <stdio.h>

#include "app/commands.h"
#include "core/diag.h"

int cmd_compare(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "wedge compare: not implemented yet\n");
    return WEDGE_EXIT_RUNTIME;
}
