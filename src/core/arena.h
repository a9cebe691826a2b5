/* Arena allocator: many small allocations freed together (a parsed scene, a frame). */
#ifndef WEDGE_CORE_ARENA_H
#define WEDGE_CORE_ARENA_H

#include <stddef.h>

typedef struct ArenaBlock ArenaBlock;
typedef struct {
    ArenaBlock *head;
    size_t bytes_total; /* bytes obtained from malloc, for memory reports and caps */
} Arena;

/* Returns zeroed, 16-byte aligned memory, or NULL when out of memory. */
void *arena_alloc(Arena *a, size_t size);
char *arena_strdup(Arena *a, const char *s);
char *arena_strndup(Arena *a, const char *s, size_t n);
void arena_free(Arena *a); /* releases everything; the arena can be reused afterwards */

#endif
