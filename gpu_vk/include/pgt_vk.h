/* pgt: the Vulkan backend (Vulkan 1.1+ compute only: no window, no graphics queue; GLSL compute
 * shaders compiled to SPIR-V by glslc at build time and embedded).
 *
 * Every entry point takes and returns the reference's flat arrays and has the reference's
 * contract (the headers in ref_cpu/include/pgt); errors come back as pgt_result + pgt_error naming
 * the failing Vulkan call with file, line and error code, never an abort. */
#ifndef PGT_VK_H
#define PGT_VK_H

#include "host.h"
#include "pgt/march.h"
#include "pgt/mesh.h"
#include "pgt/sqrt3.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pgt_vk pgt_vk;

/* Lists every physical device (numbered from 0 in enumeration order) that has a compute queue.
 * No loader, no ICD or no device is not an error: count 0. */
pgt_result pgt_vk_list_devices(pgt_gpu_device_list *out, pgt_error *err);

/* Opens device `device` (an index of pgt_vk_list_devices) and creates every compute pipeline.
 * With validation, the instance enables VK_LAYER_KHRONOS_validation with a debug messenger:
 * every validation message is printed on stderr and counted, and any call during which a message
 * arrived fails with PGT_ERROR_BACKEND (a missing layer is an error too). With a profile,
 * dispatches are timed with timestamp queries and appended to it. */
pgt_result pgt_vk_create(pgt_vk **out, uint32_t device, pgt_gpu_profile *profile, int validation,
                         pgt_error *err);
void pgt_vk_destroy(pgt_vk *ctx);

/* "driver / device" of an open context. */
const char *pgt_vk_device_name(const pgt_vk *ctx);

/* Validation messages received since the context was created. */
uint32_t pgt_vk_validation_messages(const pgt_vk *ctx);

/* pgt_sqrt3_subdivide on the device: same output, element by element (positions within the
 * tolerance table, everything else equal). opts->threads is ignored; per-corner UVs are not
 * carried (out->uvs is NULL); labels are inherited through the parent faces. times may be NULL. */
pgt_result pgt_vk_sqrt3(pgt_vk *ctx, pgt_mesh *out, const pgt_mesh *in,
                        const pgt_sqrt3_options *opts, pgt_gpu_times *times, pgt_error *err);

/* pgt_march_step on the device, with pgt_cl_march's contract (gpu_cl/include/pgt_cl.h): `count`
 * walkers from `states` (updated in place), each taking up to `steps` steps of `length` texels
 * with angle 0 and stopping at its first STOP; options as pgt_march_options (NULL: the paper's
 * defaults), a condition callback refused; out_taken, records (both NULL or both count x steps,
 * walker-major, event words PGT_MARCH_EVENT_WORD) and times may be NULL. Every array goes through
 * one storage-buffer binding: one larger than maxStorageBufferRange (the records of many walkers
 * and steps, a large atlas) fails with PGT_ERROR_LIMIT naming it. */
pgt_result pgt_vk_march(pgt_vk *ctx, const pgt_march_atlas *a, const pgt_march_options *o,
                        float length, uint32_t steps, uint32_t count, pgt_march_state *states,
                        pgt_march_state *rec_states, uint32_t *rec_events, uint32_t *out_taken,
                        pgt_gpu_times *times, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
