#include "core/env_knob.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int env_knob_match(const char *value, const char *const *choices, int choice_count)
{
    if (!value || !*value) return -1;
    for (int i = 0; i < choice_count; ++i)
        if (strcmp(value, choices[i]) == 0) return i;
    return -1;
}

int env_knob_choice(const char *var, const char *const *choices, int choice_count, int default_choice)
{
    const char *value = getenv(var);
    int found = env_knob_match(value, choices, choice_count);
    if (found >= 0) return found;
    if (value && *value) {
        /* the value is the user's: its first 64 bytes, control bytes escaped */
        fprintf(stderr, "wedge: warning: %s=\"", var);
        for (int i = 0; value[i] && i < 64; ++i) {
            unsigned char c = (unsigned char)value[i];
            if (c < 0x20 || c == 0x7f) fprintf(stderr, "\\x%02x", c);
            else fputc(c, stderr);
        }
        fprintf(stderr, "\" is not one of");
        for (int i = 0; i < choice_count; ++i) fprintf(stderr, "%s %s", i ? "," : "", choices[i]);
        fprintf(stderr, "; using %s\n", choices[default_choice]);
    }
    return default_choice;
}

bool env_knob_switch(const char *var, bool default_on)
{
    static const char *const names[] = {"0", "1"};
    return env_knob_choice(var, names, 2, default_on ? 1 : 0) == 1;
}
