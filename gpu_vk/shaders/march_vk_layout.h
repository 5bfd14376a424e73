/* pgt: what the Vulkan host (src/vk_march.c) and shaders/march_walk.comp agree on beyond
 * gpu_shared/march_layout.h: the binding of every storage buffer. Read by C and GLSL. The march
 * uses the context's one descriptor set layout (PGT_VK_S3_BINDINGS storage buffers) and its
 * push-constant range; the bindings it does not list hold the dummy buffer. */
#ifndef PGT_VK_MARCH_LAYOUT_H
#define PGT_VK_MARCH_LAYOUT_H

#include "lang.h"

#include "march_layout.h"

/* The atlas view (ref_cpu/include/pgt/march.h), as the host holds it */
#define PGT_VK_M_CODES 0u  /* uint per texel */
#define PGT_VK_M_TEXELS 1u /* pgt_march_texel: x, y, z, code */
#define PGT_VK_M_JUMPS 2u  /* pgt_march_jump: u | v << 16 (two uint16), rot */
#define PGT_VK_M_RINGS 3u  /* uint16 per texel, two to a uint */
#define PGT_VK_M_ROTCS 4u  /* (cosf(rot), sinf(rot)) per texel, from pgt_gpu_march_prepare */
#define PGT_VK_M_MASK 5u   /* float per texel, read with PGT_GPU_MARCH_MASK */
/* The walkers */
#define PGT_VK_M_STATES 6u     /* pgt_march_state per walker, updated in place */
#define PGT_VK_M_REC_STATES 7u /* count x steps pgt_march_state, with PGT_GPU_MARCH_RECORD */
#define PGT_VK_M_REC_EVENTS 8u /* count x steps event words (PGT_MARCH_EVENT_WORD) */
#define PGT_VK_M_TAKEN 9u      /* steps taken per walker */
#define PGT_VK_M_BINDINGS 10u

/* Steps per walker in one dispatch. lavapipe (gallivm) ends every loop of a shader invocation
 * once the loops' iterations reach LP_MAX_TGSI_LOOP_ITERATIONS = 65535 in all (one counter per
 * call of the compiled shader, which runs 8 invocations in SIMD lanes, each loop counting the
 * most iterations any lane needs: s3_vk_layout.h), and a walker cut off so returns garbage:
 * measured, a walker of spot's atlas went wrong after 7213 steps (about 9 loop iterations a step
 * inside a chart) and after 1158 with a crossing nearly every step. A step iterates at most about
 * 1430 times: up to 17 passes of its jump loop, each with the binary search (24), 5.1's ring and
 * candidates (25) and the no-bounce search (25), the Jacobian's 3 and the rim position's 6, if none
 * of those loops is unrolled: a bound of each loop, so it holds for the lanes together as well. 32
 * steps (about 45,800 iterations, with the STOP records' loop) stay under. */
#define PGT_VK_MARCH_DISPATCH_STEPS 32u
#endif
