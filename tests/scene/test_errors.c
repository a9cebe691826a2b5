/* One test per class of malformed input: the exact message and its line:column, counted by
 * hand from the input text (columns are 1-based bytes). */
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene_test_util.h"

static void expect(const char *text, const char *message)
{
    CHECK_STR(parse_err(text), message);
}

/* Builds "DATA/name" for messages that quote resolved paths. */
static const char *in_data(const char *fmt, const char *name)
{
    static char buf[3][8192];
    static int k = 0;
    k = (k + 1) % 3;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", data_dir(), name);
    snprintf(buf[k], sizeof buf[k], fmt, path, path, path);
    return buf[k];
}

int main(void)
{
    /* Lexical errors. */
    expect("Shape \"sphere", "t.pbrt:1:7: error: unterminated string");
    expect("WorldBegin\nShape \"sphere\n\"", "t.pbrt:2:7: error: unterminated string");
    expect("\x01\x02", "t.pbrt:1:1: error: unexpected byte 0x01");
    expect("WorldBegin\nShape\xff", "t.pbrt:2:6: error: unexpected byte 0xff");
    expect("WorldBegin\n  \"x\"", "t.pbrt:2:3: error: expected a directive, got the string \"x\"");

    /* Strings (issue 20 item 10): an unknown escape is an error at its backslash, not a
     * dropped character; control bytes in a quoted name are printed escaped (the message
     * stays one line); a name too long for the message loses its middle, not the reason. */
    expect("Camera \"persp\\qective\"",
           "t.pbrt:1:14: error: unknown escape '\\q' in a string (known: \\b \\f \\n \\r \\t \\\\ \\' \\\")");
    expect("WorldBegin\nObjectInstance \"ab\x01\x1b[31mcd\"",
           "t.pbrt:2:1: error: object \"ab\\x01\\x1b[31mcd\" not defined");
    {
        static char text[8192];
        int n = snprintf(text, sizeof text, "WorldBegin\nObjectInstance \"");
        for (int i = 0; i < 5000; ++i) text[n++] = 'x';
        snprintf(text + n, sizeof text - (size_t)n, "\"");
        const char *m = parse_err(text);
        size_t len = strlen(m);
        CHECK(len < 2048 && len > 1900);
        CHECK(strncmp(m, "t.pbrt:2:1: error: object \"xxx", 30) == 0);
        CHECK(strstr(m, "x...x") != NULL);
        CHECK(len > 13 && !strcmp(m + len - 13, "\" not defined"));
    }

    /* Brackets. */
    expect("WorldBegin\nShape \"sphere\" \"float radius\" [ 1\n",
           "t.pbrt:2:31: error: unbalanced '[': no matching ']'");
    expect("WorldBegin\nShape \"sphere\" \"float radius\" [ 1\nWorldBegin",
           "t.pbrt:2:31: error: unbalanced '[': no matching ']'");
    expect("WorldBegin ]", "t.pbrt:1:12: error: unbalanced ']': no matching '['");
    expect("[ 1 ]", "t.pbrt:1:1: error: unexpected '[' (expected a directive)");

    /* Value counts. */
    expect("WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 ]",
           "t.pbrt:2:20: error: parameter \"rgb reflectance\" needs a multiple of 3 values, got 2");
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 1 ] \"integer indices\" [ 0 1 2 ]",
           "t.pbrt:2:22: error: parameter \"point3 P\" needs a multiple of 3 values, got 5");
    expect("LookAt 0 0 0 1 1 1\nCamera \"perspective\"", "t.pbrt:1:1: error: LookAt expects 9 numbers, got 6");
    expect("Translate 1 2 3 4", "t.pbrt:1:1: error: Translate expects 3 numbers, got 4");
    expect("Transform [ 1 0 0 0 1 0 0 0 1 ]", "t.pbrt:1:1: error: Transform expects 16 numbers, got 9");
    expect("Camera \"perspective\" \"float fov\" [ 30 40 ]",
           "t.pbrt:1:22: error: parameter \"float fov\" expects 1 value, got 2");
    expect("WorldBegin\nLightSource \"point\" \"blackbody I\" [ 5500 1 ]",
           "t.pbrt:2:21: error: parameter \"blackbody I\" needs exactly 1 value (a temperature in Kelvin), got 2");
    expect("WorldBegin\nMaterial \"diffuse\" \"spectrum reflectance\" [ 400 0.5 500 ]",
           "t.pbrt:2:20: error: parameter \"spectrum reflectance\" needs (wavelength, value) pairs, got 3 values");
    expect("Camera \"perspective\" \"float fov\" [ ]", "t.pbrt:1:22: error: parameter \"float fov\" has no values");

    /* Wrong types. */
    expect("Camera \"perspective\" \"float fov\" \"wide\"",
           "t.pbrt:1:34: error: parameter \"float fov\" expects numbers, got \"wide\"");
    expect("Camera \"perspective\" \"integer fov\" 45",
           "t.pbrt:1:22: error: parameter \"integer fov\" has the wrong type (expected float)");
    expect("Sampler \"halton\" \"integer pixelsamples\" 1.5",
           "t.pbrt:1:41: error: parameter \"integer pixelsamples\" expects integers, got \"1.5\"");
    expect("WorldBegin\nAreaLightSource \"diffuse\" \"bool twosided\" \"yes\"",
           "t.pbrt:2:43: error: parameter \"bool twosided\" expects true or false, got \"yes\"");
    expect("Film \"rgb\" \"string filename\" out.exr",
           "t.pbrt:1:30: error: parameter \"string filename\" expects quoted strings, got \"out.exr\"");
    expect("Film \"rgb\" \"floot x\" 1", "t.pbrt:1:12: error: unknown parameter type \"floot\" in \"floot x\"");
    expect("Film \"rgb\" \"xresolution\" 1",
           "t.pbrt:1:12: error: invalid parameter declaration \"xresolution\" (expected \"TYPE NAME\")");
    expect("Film \"rgb\" \"integer xresolution\" 10 \"integer xresolution\" 20",
           "t.pbrt:1:37: error: parameter \"xresolution\" given twice");

    /* Index out of range, mesh consistency. */
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]",
           "t.pbrt:2:53: error: trianglemesh: index 3 (value 3 of \"integer indices\") is out of range [0, 3)");
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 -1]",
           "t.pbrt:2:53: error: trianglemesh: index -1 (value 3 of \"integer indices\") is out of range [0, 3)");
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"integer indices\" [0 1 2 3]",
           "t.pbrt:2:59: error: trianglemesh: \"integer indices\" needs a multiple of 3 values, got 4");
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]",
           "t.pbrt:2:1: error: trianglemesh: missing \"integer indices\"");
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 1]",
           "t.pbrt:2:53: error: trianglemesh: \"normal N\" has 1 entries but \"point3 P\" has 3 vertices");
    expect("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"point2 uv\" [0 0 1 0]",
           "t.pbrt:2:53: error: trianglemesh: \"point2 uv\" has 2 entries but \"point3 P\" has 3 vertices");
    expect("WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"integer indices\" [0 1 2]",
           "t.pbrt:2:59: error: bilinearmesh: \"integer indices\" needs a multiple of 4 values, got 3");
    expect("WorldBegin\nShape \"loopsubdiv\" \"integer levels\" -1 \"point3 P\" [0 0 0 1 0 0 0 1 0] "
           "\"integer indices\" [0 1 2]",
           "t.pbrt:2:20: error: loopsubdiv: \"integer levels\" must be in [0, 10], got -1");
    expect("WorldBegin\nShape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 5]",
           "t.pbrt:2:51: error: loopsubdiv: index 5 (value 3 of \"integer indices\") is out of range [0, 3)");
    /* Catmull-Clark faces of varying size: "nverts" must describe "indices" exactly. */
    expect("WorldBegin\nShape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"integer indices\" [0 1 3 2] "
           "\"integer nverts\" [3]",
           "t.pbrt:2:85: error: loopsubdiv: \"integer nverts\" adds up to 3 but \"integer indices\" has 4 values");
    expect("WorldBegin\nShape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"integer indices\" [0 1 3 2] "
           "\"integer nverts\" [2 2]",
           "t.pbrt:2:85: error: loopsubdiv: face 0 has 2 vertices in \"integer nverts\"; a face needs at least 3");
    expect("WorldBegin\nShape \"sphere\" \"float radius\" -2",
           "t.pbrt:2:16: error: sphere: \"float radius\" must not be negative, got -2");
    expect("WorldBegin\nShape \"disk\" \"float radius\" 1 \"float innerradius\" 2",
           "t.pbrt:2:31: error: disk: \"float innerradius\" 2 must be in [0, radius = 1]");

    /* Resolution and other option values. */
    expect("Film \"rgb\" \"integer xresolution\" -5", "t.pbrt:1:12: error: \"integer xresolution\" must be at least 1, got -5");
    expect("Film \"rgb\" \"integer yresolution\" 0", "t.pbrt:1:12: error: \"integer yresolution\" must be at least 1, got 0");
    expect("Sampler \"zsobol\" \"integer pixelsamples\" 0",
           "t.pbrt:1:18: error: \"integer pixelsamples\" must be at least 1, got 0");
    /* unbounded work from the scene: the same bound as wedge render --spp (issue 20 item 11) */
    expect("Sampler \"zsobol\" \"integer pixelsamples\" [ 2147483647 ]",
           "t.pbrt:1:18: error: \"integer pixelsamples\" must be at most 16777216, got 2147483647");
    expect("Sampler \"stratified\" \"integer xsamples\" 8192",
           "t.pbrt:1:22: error: \"integer xsamples\" must be at most 4096, got 8192");
    /* degenerate camera windows (item 8): an empty screen window, pixel bounds off the film */
    expect("Camera \"perspective\" \"float screenwindow\" [ 0 0 0 0 ]",
           "t.pbrt:1:22: error: \"float screenwindow\" needs xmin xmax ymin ymax with xmin < xmax and ymin < ymax, "
           "got [0 0 0 0]");
    expect("Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 48 \"integer pixelbounds\" [ 0 100000 -5 3 ]",
           "t.pbrt:1:62: error: \"integer pixelbounds\" needs 4 values x0 x1 y0 y1 inside the 64x48 film with x0 < x1 "
           "and y0 < y1");
    expect("Camera \"perspective\" \"float fov\" 180",
           "t.pbrt:1:22: error: \"float fov\" must be in (0, 180) degrees, got 180");
    expect("Scale 1 0 1\nCamera \"perspective\"", "t.pbrt:2:1: error: camera transform is singular");
    expect("Camera \"orthographic\"", "t.pbrt:1:8: error: camera \"orthographic\" is not supported (only \"perspective\")");

    /* NaN, infinity, overflow. */
    expect("Translate nan 0 0", "t.pbrt:1:11: error: invalid number \"nan\": NaN and infinity are not allowed");
    expect("Scale 1 -Inf 1", "t.pbrt:1:9: error: invalid number \"-Inf\": NaN and infinity are not allowed");
    expect("Camera \"perspective\" \"float fov\" 1e39", "t.pbrt:1:34: error: number \"1e39\" is out of range");
    expect("WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 4294967296 ]",
           "t.pbrt:2:42: error: number \"4294967296\" is out of range");
    expect("Scale 1e38 1 1\nScale 1e38 1 1\nScale 1e38 1 1\nScale 1e38 1 1\nScale 1e38 1 1\nScale 1e38 1 1\n"
           "Scale 1e38 1 1\nScale 1e38 1 1\nScale 1e38 1 1\n",
           "t.pbrt:9:1: error: the transformation overflows (matrix is not finite)");
    expect("Translate 1 2 3x", "t.pbrt:1:15: error: invalid number \"3x\"");

    /* Structure. */
    expect("Foo 1", "t.pbrt:1:1: error: unknown directive \"Foo\"");
    expect("WorldBegin\nAttributeEnd", "t.pbrt:2:1: error: AttributeEnd without matching AttributeBegin");
    expect("WorldBegin\nAttributeBegin\n", "t.pbrt:2:1: error: AttributeBegin without matching AttributeEnd");
    expect("WorldBegin\nAttributeBegin\nTransformEnd",
           "t.pbrt:3:1: error: TransformEnd does not match AttributeBegin at line 2:1");
    expect("WorldBegin\nObjectEnd", "t.pbrt:2:1: error: ObjectEnd without matching ObjectBegin");
    expect("WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\"",
           "t.pbrt:3:1: error: ObjectBegin inside the definition of object \"a\"");
    expect("WorldBegin\nObjectInstance \"ghost\"", "t.pbrt:2:1: error: object \"ghost\" not defined");
    expect("WorldBegin\nNamedMaterial \"ghost\"\nShape \"sphere\"",
           "t.pbrt:2:15: error: named material \"ghost\" not defined");
    expect("WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
           "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"",
           "t.pbrt:3:19: error: named material \"m\" redefined");
    expect("WorldBegin\nMakeNamedMaterial \"m\"", "t.pbrt:2:1: error: MakeNamedMaterial \"m\": missing \"string type\" parameter");
    expect("WorldBegin\nFilm \"rgb\"", "t.pbrt:2:1: error: Film is not allowed after WorldBegin");
    expect("Shape \"sphere\"", "t.pbrt:1:1: error: Shape is only allowed after WorldBegin");
    expect("WorldBegin\nWorldBegin", "t.pbrt:2:1: error: WorldBegin given twice");
    expect("Film \"rgb\"\n# no world\n", "t.pbrt:3:1: error: end of file before WorldBegin");
    expect("", "t.pbrt:1:1: error: end of file before WorldBegin");
    expect("AttributeBegin\nWorldBegin", "t.pbrt:1:1: error: AttributeBegin is only allowed after WorldBegin");
    expect("ActiveTransform Sometimes", "t.pbrt:1:17: error: ActiveTransform expects StartTime, EndTime or All, got \"Sometimes\"");
    expect("LookAt 0 0 0  0 0 1  0 0 1", "t.pbrt:1:1: error: LookAt: the up vector is parallel to the view direction (or eye equals look)");
    expect("WorldBegin\nAreaLightSource \"spot\"", "t.pbrt:2:17: error: area light type \"spot\" unknown (pbrt-v4 has only \"diffuse\")");
    expect("WorldBegin\nTexture \"t\" \"colour\" \"constant\"",
           "t.pbrt:2:13: error: texture type \"colour\" unknown (expected \"float\" or \"spectrum\")");
    expect("WorldBegin\nAttribute \"camera\" \"float fov\" 3",
           "t.pbrt:2:11: error: attribute target \"camera\" unknown (expected shape, light, material, medium or texture)");
    expect("WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"nowhere\"",
           "t.pbrt:2:20: error: texture \"nowhere\" not defined");
    expect("WorldBegin\nMaterial \"mix\" \"string materials\" [ \"a\" \"b\" ]",
           "t.pbrt:2:16: error: named material \"a\" not defined");
    expect("WorldBegin\nShape 3", "t.pbrt:2:7: error: Shape expects a quoted shape type, got \"3\"");

    /* Files: missing include, missing PLY, include cycle, errors inside includes. */
    CHECK_STR(parse_err("Include \"nope.pbrt\""),
              in_data("t.pbrt:1:9: error: cannot open included file \"%s\": No such file or directory", "nope.pbrt"));
    CHECK_STR(parse_err("WorldBegin\nShape \"plymesh\" \"string filename\" \"nope.ply\""),
              in_data("t.pbrt:2:17: error: cannot open PLY file \"%s\": No such file or directory", "nope.ply"));
    {
        char expected[16384], a[4096], b[4096];
        snprintf(a, sizeof a, "%s/cycle_a.pbrt", data_dir());
        snprintf(b, sizeof b, "%s/cycle_b.pbrt", data_dir());
        snprintf(expected, sizeof expected,
                 "%s:2:9: error: include cycle: \"%s\" is already being read\n"
                 "%s:2:9: note: included from here\n"
                 "t.pbrt:1:9: note: included from here",
                 b, a, a);
        CHECK_STR(parse_err("Include \"cycle_a.pbrt\""), expected);
        snprintf(a, sizeof a, "%s/bad_outer.pbrt", data_dir());
        snprintf(b, sizeof b, "%s/bad_inner.pbrt", data_dir());
        snprintf(expected, sizeof expected,
                 "%s:3:3: error: Translate expects 3 numbers, got 2\n"
                 "%s:2:9: note: included from here\n"
                 "t.pbrt:2:9: note: included from here",
                 b, a);
        CHECK_STR(parse_err("WorldBegin\nInclude \"bad_outer.pbrt\""), expected);
    }
    /* Include depth: a chain of 40 files, each including the next. */
    {
        char dir[] = "/tmp/wedge-deep-XXXXXX";
        CHECK(mkdtemp(dir) != NULL);
        for (int i = 0; i < 40; ++i) {
            char path[256];
            snprintf(path, sizeof path, "%s/d%02d.pbrt", dir, i);
            FILE *f = fopen(path, "w");
            CHECK(f != NULL);
            if (!f) break;
            if (i < 39) fprintf(f, "Include \"d%02d.pbrt\"\n", i + 1);
            fclose(f);
        }
        char text[512];
        snprintf(text, sizeof text, "Include \"%s/d00.pbrt\"", dir);
        SceneDesc s;
        Diag d;
        CHECK(!scene_parse_string(text, strlen(text), "t.pbrt", NULL, &s, &d));
        char want[512];
        /* The main text is not a file on the include stack: 32 files open, the 32nd
         * (d31.pbrt) cannot include d32.pbrt. */
        snprintf(want, sizeof want, "%s/d31.pbrt:1:9: error: includes nested too deeply (limit 32)\n", dir);
        CHECK(strncmp(d.message, want, strlen(want)) == 0);
        if (strncmp(d.message, want, strlen(want))) fprintf(stderr, "got: %.300s\n", d.message);
        for (int i = 0; i < 40; ++i) {
            char path[256];
            snprintf(path, sizeof path, "%s/d%02d.pbrt", dir, i);
            unlink(path);
        }
        rmdir(dir);
    }
    /* A missing scene file. */
    {
        SceneDesc s;
        Diag d;
        CHECK(!scene_parse_file("/nonexistent/x.pbrt", &s, &d));
        CHECK_STR(d.message, "/nonexistent/x.pbrt: error: cannot open scene file: No such file or directory");
        CHECK(d.exit_code == WEDGE_EXIT_INPUT);
    }
    CHECK_DONE();
}
