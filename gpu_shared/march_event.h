/* pgt: the event word of one recorded marching step, as every backend's pgt_backend_march
 * records it (harness/backend.h; gpu_cl/kernels/march.cl; gpu_vk/shaders/march_walk.comp). Read
 * by C, OpenCL C and GLSL (lang.h): a #define only. Bits 0-7: the pgt_march_event; 8-15: the
 * pgt_march_stop; 16-31: the step's chart crossings (pgt_march_info.jumps). */
#ifndef PGT_GPU_MARCH_EVENT_H
#define PGT_GPU_MARCH_EVENT_H

#include "lang.h"

#define PGT_MARCH_EVENT_WORD(ev, stop, jumps)                                                      \
    (PGT_UINT(ev) | PGT_UINT(stop) << 8 | PGT_UINT(jumps) << 16)
/* Its fields back. */
#define PGT_MARCH_EVENT_OF(word) (PGT_UINT(word) & 0xFFu)
#define PGT_MARCH_STOP_OF(word) (PGT_UINT(word) >> 8 & 0xFFu)

#endif
