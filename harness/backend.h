/* pgt harness: one entry point per algorithm for every backend (cpu = the reference, cl =
 * OpenCL, vk = Vulkan), taking and returning the reference's flat arrays. Verbs open a backend
 * once (device choice, kernel builds, profiling) and run algorithms on it. */
#ifndef PGT_BACKEND_H
#define PGT_BACKEND_H

#include <stdint.h>
#include <stdio.h>

#include "host.h"
#include "march_event.h"
#include "pgt/march.h"
#include "pgt/mesh.h"
#include "pgt/sqrt3.h"

typedef enum pgt_backend_kind {
    PGT_BACKEND_CPU = 0,
    PGT_BACKEND_CL = 1,
    PGT_BACKEND_VK = 2
} pgt_backend_kind;

typedef struct pgt_backend {
    pgt_backend_kind kind;
    uint32_t device;
    struct pgt_cl *cl;
    struct pgt_vk *vk;
    int profiling;
    pgt_gpu_profile profile; /* kernel events of every call since open (profiling on) */
    char name[320];          /* "cpu (reference)", "cl 0: platform / device", ... */
} pgt_backend;

/* "cpu", "cl", "vk". */
const char *pgt_backend_kind_name(pgt_backend_kind kind);

/* Parses --backend's value; on failure prints a one-line error for `verb` and returns nonzero. */
int pgt_backend_parse(const char *verb, const char *text, pgt_backend_kind *out);

/* The flags `--backend B` and `--device N` (0 to 1024) at argv[*i], as every verb that runs on a
 * backend takes them: 1 when argv[*i] is one of them (parsed into *kind or *device, *i moved to
 * its value), 0 when it is not, -1 after printing why its value is bad. */
int pgt_backend_flags(const char *verb, int argc, char **argv, int *i, pgt_backend_kind *kind,
                      uint32_t *device);

/* The bench verbs' `--backends LIST`: cl, vk, both (or cl,vk / vk,cl) or none, into asked[0]
 * (cl) and asked[1] (vk). Anything else: a one-line error for `verb` and nonzero. */
int pgt_backend_parse_list(const char *verb, const char *text, int asked[2]);

/* Opens the backend on device `device` (GPU backends; ignored by cpu). Profiling records every
 * kernel launch (OpenCL events, Vulkan timestamps). Vulkan validation is on when the environment
 * sets PGT_VK_VALIDATION=1 (the tests do): any validation message fails the call. */
pgt_result pgt_backend_open(pgt_backend *b, pgt_backend_kind kind, uint32_t device, int profiling,
                            pgt_error *err);
void pgt_backend_close(pgt_backend *b);

/* Opens, with profiling, the GPU backends asked for (gpu[0] cl, gpu[1] vk; both start closed) on
 * device `device`, once, so that kernel builds and instance creation stay out of the timings. One
 * that does not open is an error when `must` (printed for `verb`, both closed, nonzero returned);
 * otherwise a note on stderr, and it stays closed (kind CPU), its columns or rows left out. */
int pgt_backend_open_asked(const char *verb, pgt_backend gpu[2], const int asked[2],
                           uint32_t device, int must);

/* sqrt(3) subdivision: pgt_sqrt3_subdivide on the chosen backend. GPU backends do not carry
 * per-corner UVs (out->uvs is NULL). times may be NULL (cpu leaves it zeroed). */
pgt_result pgt_backend_sqrt3(pgt_backend *b, pgt_mesh *out, const pgt_mesh *in,
                             const pgt_sqrt3_options *opts, pgt_gpu_times *times, pgt_error *err);

/* Marching (pgt_march_step with angle 0) of `count` walkers from `states` (updated in place),
 * up to `steps` steps of `length` texels each, a walker stopping at its first STOP, as
 * pgt_cl_march describes (records, out_taken and times may be NULL; event words:
 * PGT_MARCH_EVENT_WORD, gpu_shared/march_event.h; the records after a STOP repeat it). cpu:
 * pgt_march_step walker by walker; cl: pgt_cl_march; vk: pgt_vk_march. */
pgt_result pgt_backend_march(pgt_backend *b, const pgt_march_atlas *a, const pgt_march_options *o,
                             float length, uint32_t steps, uint32_t count, pgt_march_state *states,
                             pgt_march_state *rec_states, uint32_t *rec_events, uint32_t *out_taken,
                             pgt_gpu_times *times, pgt_error *err);

/* Whether a backend's recorded step is one the reference could have made, so that the reference
 * may re-run a step from it or place it (pgt_march_step and pgt_march_position assert their
 * contract): an event and a stop reason that exist, finite directions, and a position inside an
 * inner texel of its chart. A backend cut short (a driver limit) or broken returns other things. */
int pgt_backend_march_record_valid(const pgt_march_atlas *a, const pgt_march_state *s,
                                   uint32_t word);

/* The --profile table of the events recorded since open: kernel, launches, total ms, median ms
 * (nothing for cpu). */
void pgt_backend_print_profile(const pgt_backend *b, FILE *f);

/* Both APIs' devices, as `pgt devices` prints them. */
pgt_result pgt_backend_list(pgt_backend_kind kind, pgt_gpu_device_list *out, pgt_error *err);

#endif
