/* A small string -> int hash map (open addressing) for the parser's name lookups (named
 * materials, textures, objects, coordinate systems), so that big scenes with many names
 * stay linear. Keys are not copied: they must outlive the map (the parser's arena). */
#ifndef WEDGE_SCENE_NAME_MAP_H
#define WEDGE_SCENE_NAME_MAP_H

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    const char **keys;
    int *values;
    size_t cap, count; /* cap is 0 or a power of two */
} NameMap;

/* The value stored for key, or -1. */
int name_map_get(const NameMap *m, const char *key);
/* Inserts or overwrites; false when out of memory. */
bool name_map_put(NameMap *m, const char *key, int value);
void name_map_free(NameMap *m);

#endif
