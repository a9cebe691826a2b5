/* String hash map with linear probing (FNV-1a hashes, load factor <= 1/2). */
#include "scene/name_map.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint64_t hash_str(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; ++s) h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

int name_map_get(const NameMap *m, const char *key)
{
    if (!m->cap) return -1;
    for (size_t i = hash_str(key) & (m->cap - 1);; i = (i + 1) & (m->cap - 1)) {
        if (!m->keys[i]) return -1;
        if (!strcmp(m->keys[i], key)) return m->values[i];
    }
}

static bool grow_map(NameMap *m)
{
    size_t ncap = m->cap ? 2 * m->cap : 64;
    const char **keys = calloc(ncap, sizeof *keys);
    int *values = calloc(ncap, sizeof *values);
    if (!keys || !values) {
        free(keys);
        free(values);
        return false;
    }
    for (size_t i = 0; i < m->cap; ++i) {
        if (!m->keys[i]) continue;
        size_t j = hash_str(m->keys[i]) & (ncap - 1);
        while (keys[j]) j = (j + 1) & (ncap - 1);
        keys[j] = m->keys[i];
        values[j] = m->values[i];
    }
    free(m->keys);
    free(m->values);
    m->keys = keys;
    m->values = values;
    m->cap = ncap;
    return true;
}

bool name_map_put(NameMap *m, const char *key, int value)
{
    if (2 * (m->count + 1) > m->cap && !grow_map(m)) return false;
    size_t i = hash_str(key) & (m->cap - 1);
    while (m->keys[i] && strcmp(m->keys[i], key)) i = (i + 1) & (m->cap - 1);
    if (!m->keys[i]) {
        m->keys[i] = key;
        m->count++;
    }
    m->values[i] = value;
    return true;
}

void name_map_free(NameMap *m)
{
    free(m->keys);
    free(m->values);
    memset(m, 0, sizeof *m);
}
