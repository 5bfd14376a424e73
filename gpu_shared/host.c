/* pgt: host-side helpers shared by the GPU backends and the harness. */
#include "host.h"

#include <stdlib.h>
#include <string.h>

int pgt_gpu_profile_add(pgt_gpu_profile *p, const char *name, double ms) {
    if (!p) return 1;
    if (p->count == p->capacity) {
        uint32_t cap = p->capacity ? 2 * p->capacity : 64;
        pgt_gpu_event *e = realloc(p->events, (size_t)cap * sizeof(*e));
        if (!e) return 0;
        p->events = e, p->capacity = cap;
    }
    pgt_gpu_event *e = &p->events[p->count++];
    memset(e->name, 0, sizeof(e->name));
    strncpy(e->name, name, sizeof(e->name) - 1);
    e->ms = ms;
    return 1;
}

void pgt_gpu_profile_free(pgt_gpu_profile *p) {
    if (!p) return;
    free(p->events);
    memset(p, 0, sizeof(*p));
}
