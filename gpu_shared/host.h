/* pgt: host-side types every GPU backend and the harness share (C only, not read by kernels). */
#ifndef PGT_GPU_HOST_H
#define PGT_GPU_HOST_H

#include <stdint.h>

#include "march_layout.h"
#include "pgt/adjacency.h"
#include "pgt/march.h"
#include "pgt/mesh.h"
#include "pgt/result.h"
#include "pgt/sqrt3.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One kernel execution measured on the device (OpenCL profiling events, Vulkan timestamps). */
typedef struct pgt_gpu_event {
    char name[40]; /* kernel or shader name, e.g. "s3_faces" */
    double ms;     /* device execution time */
} pgt_gpu_event;

/* Growing list of events; a backend appends when the list is given (profiling on). */
typedef struct pgt_gpu_profile {
    pgt_gpu_event *events;
    uint32_t count, capacity;
} pgt_gpu_profile;

/* Appends (name, ms); returns 0 when out of memory (the event is dropped). */
int pgt_gpu_profile_add(pgt_gpu_profile *p, const char *name, double ms);
void pgt_gpu_profile_free(pgt_gpu_profile *p);

/* Milliseconds of a monotonic clock (the host-measured copy times of every GPU backend). */
double pgt_gpu_now_ms(void);

/* Times of one call of an algorithm on a backend, in milliseconds (0 when not measured). */
typedef struct pgt_gpu_times {
    double device_ms;   /* sum of the kernels' device execution times */
    double upload_ms;   /* host -> device copies, host-measured */
    double download_ms; /* device -> host copies, host-measured */
} pgt_gpu_times;

/* One device as `pgt devices` lists it. Devices are numbered per API from 0, platform by
 * platform (OpenCL) or in enumeration order (Vulkan): the N of --device N. */
typedef struct pgt_gpu_device_info {
    uint32_t index;
    char platform[128]; /* OpenCL platform name, or the Vulkan driver name */
    char name[128];
    char version[128]; /* OpenCL device version + OpenCL C version, or Vulkan API version */
    char type[32];     /* "cpu", "gpu", "accelerator", "integrated-gpu", ... */
} pgt_gpu_device_info;

#define PGT_GPU_MAX_DEVICES 32u

typedef struct pgt_gpu_device_list {
    uint32_t count;
    pgt_gpu_device_info devices[PGT_GPU_MAX_DEVICES];
} pgt_gpu_device_list;

/* What every GPU backend's sqrt(3) call prepares on the host before uploading, exactly as the
 * reference does: one copy of it for all backends. */
typedef struct pgt_gpu_sqrt3_input {
    pgt_adjacency adj;    /* opposite half-edges of the input (built once, uploaded) */
    uint32_t *vh;         /* V: the smallest half-edge leaving each vertex, PGT_NONE if isolated */
    uint32_t *prot;       /* F: 1 = protected (uint, as kernels read it) */
    uint32_t n_protected; /* protected faces (the same in every level of the call) */
    float *alpha;         /* alpha_count entries: pgt_sqrt3_alpha(n) */
    uint32_t alpha_count; /* 2 + the largest fan of the input, at least 64: an interior
                             unprotected vertex keeps its valence, new points have at most 6, and
                             border or protected vertices do not use alpha */
} pgt_gpu_sqrt3_input;

/* The reference's checks in its order and with its messages (input, iterations, output bound,
 * adjacency, manifold), then the level-0 arrays above. On failure *out is zeroed. */
pgt_result pgt_gpu_sqrt3_prepare(pgt_gpu_sqrt3_input *out, const pgt_mesh *in,
                                 const pgt_sqrt3_options *opts, pgt_error *err);
void pgt_gpu_sqrt3_input_free(pgt_gpu_sqrt3_input *p);

/* k = 0: the reference's copy (without UVs, which GPU backends do not carry) and the optional
 * outputs (protected flags, identity parents, the input adjacency). */
pgt_result pgt_gpu_sqrt3_copy(pgt_mesh *out, const pgt_mesh *in, const pgt_sqrt3_options *opts,
                              const pgt_adjacency *adj, pgt_error *err);

/* What every GPU backend's marching (pgt_cl_march, pgt_vk_march) prepares on the host: the
 * checks of the call (a condition callback is refused: it is a host function; the step length; the
 * records: both arrays or neither), the kernel's parameters (march_layout.h, with first = 0) and
 * the cosine and sine of every texel's jump rot in *out_rotcs, computed with the reference's cosf
 * and sinf (a device's cos may differ in the last bit, and a walker's path with it). With no
 * walker or no step there is nothing to run: out_taken (when not NULL) is zeroed and *out_rotcs
 * is NULL. `api` names the backend in messages. Free *out_rotcs with free(). */
pgt_result pgt_gpu_march_prepare(const char *api, const pgt_march_atlas *a,
                                 const pgt_march_options *o, float length, uint32_t steps,
                                 uint32_t count, const pgt_march_state *rec_states,
                                 const uint32_t *rec_events, uint32_t *out_taken,
                                 pgt_gpu_march_params *out, float **out_rotcs, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
