/* pgt: the few macros that let one header be read by C11 (host and ref_cpu), OpenCL C 1.2
 * (gpu_cl kernels) and GLSL 4.50 (gpu_vk shaders, through glslc's #include).
 *
 * Only what all three share goes into a shared header: #define constants, and structs of 32-bit
 * scalars (uint, int, float) with no arrays, vectors or pointers, so that the C, OpenCL and std430
 * (or push-constant) layouts are the same: 4-byte members, in order, no padding. PGT_UINT(x)
 * converts to a 32-bit unsigned integer in each language (GLSL has no cast syntax). */
#ifndef PGT_GPU_LANG_H
#define PGT_GPU_LANG_H

#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)
#define PGT_LANG_OPENCL 1
#define PGT_U32 uint
#define PGT_I32 int
#define PGT_F32 float
#define PGT_STRUCT(name) typedef struct name
#define PGT_STRUCT_END(name) name
#define PGT_UINT(x) ((uint)(x))
#elif defined(GL_core_profile) || defined(GL_es_profile) || defined(VULKAN)
#define PGT_LANG_GLSL 1
#define PGT_U32 uint
#define PGT_I32 int
#define PGT_F32 float
#define PGT_STRUCT(name) struct name
#define PGT_STRUCT_END(name)
#define PGT_UINT(x) uint(x)
#else
#define PGT_LANG_C 1
#include <stdint.h>
#define PGT_U32 uint32_t
#define PGT_I32 int32_t
#define PGT_F32 float
#define PGT_STRUCT(name) typedef struct name
#define PGT_STRUCT_END(name) name
#define PGT_UINT(x) ((uint32_t)(x))
#endif

/* An unsigned literal all three accept (GLSL and OpenCL C both take the u suffix). */
#define PGT_GPU_NONE 0xFFFFFFFFu

#endif
