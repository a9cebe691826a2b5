/* Outputs checked before rendering (see output_check.h). */
#include "app/output_check.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The same file: the same device and inode (links and different spellings included). */
static bool same_file(const struct stat *out, const char *path)
{
    struct stat st;
    return path && stat(path, &st) == 0 && st.st_dev == out->st_dev && st.st_ino == out->st_ino;
}

/* A data file named by a statement, relative to the directory of the file that named it. */
static bool same_data_file(const struct stat *out, const char *base_dir, const char *name)
{
    if (!name) return false;
    if (name[0] == '/' || !base_dir || !base_dir[0]) return same_file(out, name);
    char path[8192];
    int n = snprintf(path, sizeof path, "%s/%s", base_dir, name);
    return n > 0 && (size_t)n < sizeof path && same_file(out, path);
}

/* The scene's input file the existing output is, or NULL. */
static const char *input_named_by(const struct stat *out, const SceneDesc *s)
{
    for (int i = 0; i < s->source_file_count; ++i)
        if (same_file(out, s->source_files[i])) return s->source_files[i];
    for (int i = 0; i < s->shape_count; ++i) {
        const char *f = params_string(&s->shapes[i].params, "filename", NULL);
        if (same_data_file(out, s->shapes[i].base_dir, f)) return f;
    }
    for (int i = 0; i < s->texture_count; ++i) {
        const char *f = params_string(&s->textures[i].params, "filename", NULL);
        if (same_data_file(out, s->textures[i].base_dir, f)) return f;
    }
    for (int i = 0; i < s->light_count; ++i) {
        const char *f = params_string(&s->lights[i].params, "filename", NULL);
        if (same_data_file(out, s->lights[i].base_dir, f)) return f;
    }
    return NULL;
}

bool output_check(const char *path, const char *what, const SceneDesc *scene, Diag *err)
{
    struct stat out;
    if (stat(path, &out) == 0) {
        const char *input = input_named_by(&out, scene);
        if (input) {
            diag_set(err, WEDGE_EXIT_USAGE, (SrcLoc){0},
                     "the %s '%s' is one of the scene's input files ('%s'): writing it would destroy it; choose "
                     "another name with -o",
                     what, path, input);
            return false;
        }
        if (S_ISDIR(out.st_mode)) {
            diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "the %s '%s' is a directory: give a file name", what, path);
            return false;
        }
    }
    /* the file is written as a temporary next to it, then renamed: its directory must take it */
    char dir[8192];
    const char *slash = strrchr(path, '/');
    if (slash) snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
    else snprintf(dir, sizeof dir, ".");
    struct stat ds;
    if (stat(dir, &ds) != 0 || !S_ISDIR(ds.st_mode)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot write the %s '%s': the directory '%s' %s", what, path,
                 dir, stat(dir, &ds) != 0 ? "does not exist" : "is not a directory");
        return false;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot write the %s '%s': the directory '%s' is not writable (%s)",
                 what, path, dir, strerror(errno));
        return false;
    }
    return true;
}
