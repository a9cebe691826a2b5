/* The wedge subcommands. Each returns a WEDGE_EXIT_* code; argv[0] is the subcommand name. */
#ifndef WEDGE_APP_COMMANDS_H
#define WEDGE_APP_COMMANDS_H

int cmd_render(int argc, char **argv);
int cmd_preview(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_converge(int argc, char **argv);

/* The scene embedded in the binary (scenes/default.pbrt), NUL-terminated. */
extern const char wedge_default_scene[];

#endif
