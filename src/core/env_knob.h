/* Developer knobs read from the environment (measurement switches such as WEDGE_TRACE_BATCH).
 *
 * A knob takes one of a fixed list of names. Unset or empty means the default; a value that
 * names none of the choices is reported on stderr, naming the variable, the value and the
 * choices, and the default is used. A typo in a benchmark script then shows up in its log
 * instead of silently measuring the default. */
#ifndef WEDGE_CORE_ENV_KNOB_H
#define WEDGE_CORE_ENV_KNOB_H

#include <stdbool.h>

/* The index of value in choices[0..choice_count), or -1 (also for NULL or empty). */
int env_knob_match(const char *value, const char *const *choices, int choice_count);

/* The index of the variable's value in choices, or default_choice when it is unset, empty or
 * unknown (the last with a warning on stderr). */
int env_knob_choice(const char *var, const char *const *choices, int choice_count, int default_choice);

/* An on/off knob: "1" or "0" (env_knob_choice with those two names). */
bool env_knob_switch(const char *var, bool default_on);

#endif
