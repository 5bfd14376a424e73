/* pgt: the OpenCL backend (OpenCL 1.2+ host API through the ICD loader; kernels in OpenCL C 1.2,
 * embedded in the program at build time).
 *
 * Every entry point takes and returns the reference's flat arrays and has the reference's
 * contract (the headers in ref_cpu/include/pgt); errors come back as pgt_result + pgt_error naming
 * the failing OpenCL call with file, line and error code, never an abort. */
#ifndef PGT_CL_H
#define PGT_CL_H

#include "host.h"
#include "pgt/march.h"
#include "pgt/mesh.h"
#include "pgt/sqrt3.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pgt_cl pgt_cl;

/* Lists every device of every platform, numbered from 0 across platforms in enumeration order.
 * No ICD or no platform is not an error: count 0. */
pgt_result pgt_cl_list_devices(pgt_gpu_device_list *out, pgt_error *err);

/* Opens device `device` (an index of pgt_cl_list_devices) and builds every kernel with
 * -cl-std=CL1.2; a build failure returns PGT_ERROR_BACKEND with the build log on stderr. With a
 * profile, kernel launches are timed with profiling events and appended to it. */
pgt_result pgt_cl_create(pgt_cl **out, uint32_t device, pgt_gpu_profile *profile, pgt_error *err);
void pgt_cl_destroy(pgt_cl *ctx);

/* "platform / device" of an open context. */
const char *pgt_cl_device_name(const pgt_cl *ctx);

/* pgt_sqrt3_subdivide on the device: same output, element by element (positions within the
 * tolerance table, everything else equal). opts->threads is ignored; per-corner UVs are not
 * carried (out->uvs is NULL); labels are inherited through the parent faces. times may be NULL. */
pgt_result pgt_cl_sqrt3(pgt_cl *ctx, pgt_mesh *out, const pgt_mesh *in,
                        const pgt_sqrt3_options *opts, pgt_gpu_times *times, pgt_error *err);

/* pgt_march_step on the device: `count` walkers from `states` (updated in place), each taking
 * up to `steps` steps of `length` texels with angle 0 and stopping at its first STOP, as
 * pgt_march_batch's walkers do (every state field, the no-bounce memory included, is the
 * reference's to the bit on an IEEE device; kernels/march.cl). Options as pgt_march_options
 * (NULL: the paper's defaults); a condition callback is refused (PGT_ERROR_INVALID_ARGUMENT).
 * out_taken (count, may be NULL): the steps each walker took (a STOP is not one). Records
 * (both NULL, or both count x steps, walker-major: walker i's step k at i * steps + k): the
 * state after the step (unchanged on STOP) and its event word (gpu_shared/march_event.h:
 * PGT_MARCH_EVENT_WORD(pgt_march_event, pgt_march_stop, chart crossings)); the records after a
 * walker's STOP repeat it. times may be NULL. */
pgt_result pgt_cl_march(pgt_cl *ctx, const pgt_march_atlas *a, const pgt_march_options *o,
                        float length, uint32_t steps, uint32_t count, pgt_march_state *states,
                        pgt_march_state *rec_states, uint32_t *rec_events, uint32_t *out_taken,
                        pgt_gpu_times *times, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
