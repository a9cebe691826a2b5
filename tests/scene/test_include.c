/* Include and Import: paths relative to the including file, source file list, Import's
 * private graphics state. (Missing includes, cycles and depth: test_errors.c.) */
#include "scene_test_util.h"

int main(void)
{
    char path[4096], want[4096];
    SceneDesc s;

    /* sub/part.pbrt includes "leaf.pbrt" and names "tri.ply": both resolve inside sub/. */
    CHECK(parse_ok("WorldBegin\nInclude \"sub/part.pbrt\"\n", &s));
    CHECK(s.shape_count == 2);
    CHECK_STR(s.shapes[0].type, "sphere");
    CHECK_STR(s.shapes[1].type, "plymesh");
    snprintf(want, sizeof want, "%s/sub", data_dir());
    CHECK_STR(s.shapes[1].base_dir, want);
    snprintf(want, sizeof want, "%s/sub/leaf.pbrt", data_dir());
    CHECK_STR(s.shapes[0].loc.path, want);
    CHECK(s.shapes[0].loc.line == 2 && s.shapes[0].loc.col == 1);
    CHECK(s.source_file_count == 2);
    snprintf(want, sizeof want, "%s/sub/part.pbrt", data_dir());
    CHECK_STR(s.source_files[0], want);
    snprintf(want, sizeof want, "%s/sub/leaf.pbrt", data_dir());
    CHECK_STR(s.source_files[1], want);
    scene_desc_free(&s);

    /* A file on disk: it comes first in source_files; repeated includes are listed once. */
    Diag d;
    snprintf(path, sizeof path, "%s/include_main.pbrt", data_dir());
    CHECK(scene_parse_file(path, &s, &d));
    CHECK(s.shape_count == 4);
    CHECK(s.source_file_count == 3);
    CHECK_STR(s.source_files[0], path);
    CHECK_STR(s.path, path);
    snprintf(want, sizeof want, "%s/sub/part.pbrt", data_dir());
    CHECK_STR(s.source_files[1], want);
    scene_desc_free(&s);

    /* Include is textual: its Translate stays in effect. Import keeps it private. */
    CHECK(parse_ok("WorldBegin\nInclude \"imported.pbrt\"\nShape \"sphere\"\n", &s));
    CHECK(s.shapes[0].world_from_object.m[0].m[0][3] == 5.0);
    CHECK(s.shapes[1].world_from_object.m[0].m[0][3] == 5.0);
    scene_desc_free(&s);
    CHECK(parse_ok("WorldBegin\nImport \"imported.pbrt\"\nShape \"sphere\"\n", &s));
    CHECK(s.shapes[0].world_from_object.m[0].m[0][3] == 5.0);
    CHECK(s.shapes[1].world_from_object.m[0].m[0][3] == 0.0);
    scene_desc_free(&s);

    /* An imported file cannot close its importer's attribute block (it is parsed with its
     * own attribute stack, as in pbrt-v4); an included file can (Include is textual). */
    {
        char expected[8192];
        snprintf(expected, sizeof expected,
                 "%s/import_unbalanced.pbrt:2:1: error: AttributeEnd without matching AttributeBegin\n"
                 "t.pbrt:3:8: note: included from here",
                 data_dir());
        CHECK_STR(parse_err("WorldBegin\nAttributeBegin\nImport \"import_unbalanced.pbrt\"\nAttributeEnd\n"),
                  expected);
        CHECK(parse_ok("WorldBegin\nAttributeBegin\nInclude \"import_unbalanced.pbrt\"\n", &s));
        scene_desc_free(&s);
    }

    /* Absolute include paths are used as given. */
    char text[4200];
    snprintf(text, sizeof text, "WorldBegin\nInclude \"%s/sub/leaf.pbrt\"\n", data_dir());
    if (data_dir()[0] == '/') {
        CHECK(parse_ok(text, &s));
        CHECK(s.shape_count == 1);
        scene_desc_free(&s);
    }
    /* Directories and devices are not scene files. */
    CHECK(strstr(parse_err("Include \"sub\""), "cannot open included file") != NULL);
    CHECK(strstr(parse_err("Include \"sub\""), ": Is a directory") != NULL);
    CHECK(strstr(parse_err("Include \"/dev/zero\""), "\"/dev/zero\": not a regular file") != NULL);
    CHECK_DONE();
}
