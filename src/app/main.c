/* wedge: command-line entry point; dispatches to one subcommand. */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "core/diag.h"
#include "recon/dist.h"

static const struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} commands[] = {
    {"render", cmd_render, "render a pbrt-v4 scene (or the embedded default) to EXR/PNG"},
    {"preview", cmd_preview, "render into a window, progressively: the filtered image sharpens as samples accumulate"},
    {"info", cmd_info, "summarise a scene: film, camera, shapes, lights, effects, warnings"},
    {"compare", cmd_compare, "error metrics of an image against a reference"},
    {"convert", cmd_convert, "convert an image between EXR and PNG (PNG through the OpenColorIO view)"},
    {"converge", cmd_converge, "error-versus-spp and error-versus-time sweeps against a cached reference"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: wedge COMMAND [OPTIONS]\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n'wedge COMMAND --help' describes a command's options.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return WEDGE_EXIT_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return WEDGE_EXIT_OK;
    }
    if (!strcmp(argv[1], "--version")) {
        /* what a script may need to know about this build */
        printf("wedge %s (MPI: %s)\n", WEDGE_VERSION, dist_available() ? "yes" : "no");
        return WEDGE_EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (!strcmp(argv[1], commands[i].name)) return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "wedge: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return WEDGE_EXIT_USAGE;
}
