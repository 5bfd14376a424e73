/* pgt: what the OpenCL backend's source files share (not installed, not part of the API). */
#ifndef PGT_CL_INTERNAL_H
#define PGT_CL_INTERNAL_H

#include <CL/cl.h>

#include "pgt_cl.h"

/* The kernels of the program, built once in pgt_cl_create. */
enum {
    PGT_CL_K_S3_CLASSIFY,
    PGT_CL_K_S3_SCAN,
    PGT_CL_K_S3_SCAN_ADD,
    PGT_CL_K_S3_VERTICES,
    PGT_CL_K_S3_FACES,
    PGT_CL_K_S3_VERTICES_CLOSED,
    PGT_CL_K_S3_FACES_CLOSED,
    PGT_CL_K_MARCH_WALK,
    PGT_CL_KERNEL_COUNT
};

/* Kernel names, indexed by PGT_CL_K_*: as in kernels/sqrt3.cl and kernels/march.cl, and in profile
 * events. */
extern const char *const pgt_cl_kernel_names[PGT_CL_KERNEL_COUNT];

struct pgt_cl {
    cl_device_id device;
    cl_context context;
    cl_command_queue queue; /* in order; profiling enabled when `profile` is set */
    cl_program program;
    cl_kernel kernels[PGT_CL_KERNEL_COUNT];
    cl_mem placeholder;       /* 4 bytes, bound to buffer arguments a launch does not read */
    cl_ulong max_alloc;       /* CL_DEVICE_MAX_MEM_ALLOC_SIZE */
    pgt_gpu_profile *profile; /* not owned; NULL: no profiling */
    char name[2 * 128 + 4];   /* "platform / device" */
};

/* Records a failed OpenCL call in err (first error wins) and returns PGT_ERROR_BACKEND. */
pgt_result pgt_cl_fail(pgt_error *err, const char *file, int line, const char *call, cl_int code);

/* The one check every cl* call goes through. `call` is an expression giving a cl_int; for the
 * calls that return an object, write `(x = clCreateX(..., &rc), rc)`. On failure it records the
 * call's text, file, line and error name in err, sets the enclosing function's `pgt_result r`
 * and jumps to its `cleanup:` label, which releases whatever was created. */
#define PGT_CL_CHECK(call)                                                                         \
    do {                                                                                           \
        const cl_int pgt_cl_rc_ = (call);                                                          \
        if (pgt_cl_rc_ != CL_SUCCESS) {                                                            \
            r = pgt_cl_fail(err, __FILE__, __LINE__, #call, pgt_cl_rc_);                           \
            goto cleanup;                                                                          \
        }                                                                                          \
    } while (0)

/* A device buffer of `bytes` (4 at least: OpenCL has no empty buffer); a size beyond
 * CL_DEVICE_MAX_MEM_ALLOC_SIZE is PGT_ERROR_OUT_OF_MEMORY naming it. */
pgt_result pgt_cl_buffer(pgt_cl *cl, cl_mem *out, uint64_t bytes, pgt_error *err);

#endif
