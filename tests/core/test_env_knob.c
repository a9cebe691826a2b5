/* env_knob: a developer knob's value is one of its names; anything else is reported (with the
 * variable, the value and the choices) and the default is used, never a silent default. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "core/env_knob.h"

static const char *const modes[] = {"single", "stream", "packet16"};

/* env_knob_choice(var, modes, 3, 1) with var set to value (NULL: unset); what it wrote to
 * stderr goes into said. */
static int choice_with(const char *value, char *said, size_t n)
{
    if (value) setenv("WEDGE_TEST_KNOB", value, 1);
    else unsetenv("WEDGE_TEST_KNOB");
    fflush(stderr);
    FILE *tmp = tmpfile();
    int saved = dup(fileno(stderr));
    dup2(fileno(tmp), fileno(stderr));
    int got = env_knob_choice("WEDGE_TEST_KNOB", modes, 3, 1);
    fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    rewind(tmp);
    size_t len = fread(said, 1, n - 1, tmp);
    said[len] = '\0';
    fclose(tmp);
    return got;
}

int main(void)
{
    CHECK(env_knob_match("packet16", modes, 3) == 2);
    CHECK(env_knob_match("single", modes, 3) == 0);
    CHECK(env_knob_match("packet", modes, 3) == -1); /* a prefix is not a name */
    CHECK(env_knob_match("Single", modes, 3) == -1); /* names are case sensitive */
    CHECK(env_knob_match("", modes, 3) == -1);
    CHECK(env_knob_match(NULL, modes, 3) == -1);

    char said[512];
    CHECK(choice_with("packet16", said, sizeof said) == 2);
    CHECK_STR(said, "");
    CHECK(choice_with(NULL, said, sizeof said) == 1);
    CHECK_STR(said, "");
    CHECK(choice_with("", said, sizeof said) == 1);
    CHECK_STR(said, "");
    CHECK(choice_with("paket16", said, sizeof said) == 1);
    CHECK_STR(said, "wedge: warning: WEDGE_TEST_KNOB=\"paket16\" is not one of single, stream, packet16; "
                    "using stream\n");
    /* a control byte in the value is escaped, and a long value is cut at 64 bytes */
    CHECK(choice_with("a\tb", said, sizeof said) == 1);
    CHECK_STR(said, "wedge: warning: WEDGE_TEST_KNOB=\"a\\x09b\" is not one of single, stream, packet16; "
                    "using stream\n");
    char long_value[200];
    memset(long_value, 'x', sizeof long_value - 1);
    long_value[sizeof long_value - 1] = '\0';
    CHECK(choice_with(long_value, said, sizeof said) == 1);
    char cut[80] = "=\"";
    memset(cut + 2, 'x', 64);
    strcpy(cut + 66, "\" is not");
    CHECK(strstr(said, cut) != NULL);
    /* the on/off form: its two names, and the default otherwise */
    setenv("WEDGE_TEST_KNOB", "0", 1);
    CHECK(!env_knob_switch("WEDGE_TEST_KNOB", true));
    setenv("WEDGE_TEST_KNOB", "1", 1);
    CHECK(env_knob_switch("WEDGE_TEST_KNOB", false));
    unsetenv("WEDGE_TEST_KNOB");
    CHECK(env_knob_switch("WEDGE_TEST_KNOB", true) && !env_knob_switch("WEDGE_TEST_KNOB", false));
    return check_failures ? 1 : 0;
}
