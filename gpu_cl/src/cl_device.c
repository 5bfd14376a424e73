/* pgt: the OpenCL backend's devices and contexts (pgt_cl.h): enumeration across platforms,
 * context, in-order queue, and the program built once per context from the embedded source. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <CL/cl_ext.h>

#include "cl_internal.h"
#include "sqrt3_cl.h"
#include "sqrt3_layout.h"

/* The program source: gpu_shared/lang.h, gpu_shared/sqrt3_layout.h, kernels/sqrt3_cl.h and
 * kernels/sqrt3.cl, embedded at build time (../CMakeLists.txt). NUL-terminated. */
extern const unsigned char pgt_cl_program_source[];
extern const unsigned long pgt_cl_program_source_size;

const char *const pgt_cl_kernel_names[PGT_CL_KERNEL_COUNT] = {
    "s3_classify",        "s3_scan",         "s3_scan_add", "s3_vertices", "s3_faces",
    "s3_vertices_closed", "s3_faces_closed", "march_walk",
};

static const char *cl_error_name(cl_int code) {
    switch (code) {
#define PGT_CL_NAME(c)                                                                             \
    case c:                                                                                        \
        return #c;
        PGT_CL_NAME(CL_DEVICE_NOT_FOUND)
        PGT_CL_NAME(CL_DEVICE_NOT_AVAILABLE)
        PGT_CL_NAME(CL_COMPILER_NOT_AVAILABLE)
        PGT_CL_NAME(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        PGT_CL_NAME(CL_OUT_OF_RESOURCES)
        PGT_CL_NAME(CL_OUT_OF_HOST_MEMORY)
        PGT_CL_NAME(CL_PROFILING_INFO_NOT_AVAILABLE)
        PGT_CL_NAME(CL_MEM_COPY_OVERLAP)
        PGT_CL_NAME(CL_IMAGE_FORMAT_MISMATCH)
        PGT_CL_NAME(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        PGT_CL_NAME(CL_BUILD_PROGRAM_FAILURE)
        PGT_CL_NAME(CL_MAP_FAILURE)
        PGT_CL_NAME(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        PGT_CL_NAME(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        PGT_CL_NAME(CL_COMPILE_PROGRAM_FAILURE)
        PGT_CL_NAME(CL_LINKER_NOT_AVAILABLE)
        PGT_CL_NAME(CL_LINK_PROGRAM_FAILURE)
        PGT_CL_NAME(CL_DEVICE_PARTITION_FAILED)
        PGT_CL_NAME(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        PGT_CL_NAME(CL_INVALID_VALUE)
        PGT_CL_NAME(CL_INVALID_DEVICE_TYPE)
        PGT_CL_NAME(CL_INVALID_PLATFORM)
        PGT_CL_NAME(CL_INVALID_DEVICE)
        PGT_CL_NAME(CL_INVALID_CONTEXT)
        PGT_CL_NAME(CL_INVALID_QUEUE_PROPERTIES)
        PGT_CL_NAME(CL_INVALID_COMMAND_QUEUE)
        PGT_CL_NAME(CL_INVALID_HOST_PTR)
        PGT_CL_NAME(CL_INVALID_MEM_OBJECT)
        PGT_CL_NAME(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        PGT_CL_NAME(CL_INVALID_IMAGE_SIZE)
        PGT_CL_NAME(CL_INVALID_SAMPLER)
        PGT_CL_NAME(CL_INVALID_BINARY)
        PGT_CL_NAME(CL_INVALID_BUILD_OPTIONS)
        PGT_CL_NAME(CL_INVALID_PROGRAM)
        PGT_CL_NAME(CL_INVALID_PROGRAM_EXECUTABLE)
        PGT_CL_NAME(CL_INVALID_KERNEL_NAME)
        PGT_CL_NAME(CL_INVALID_KERNEL_DEFINITION)
        PGT_CL_NAME(CL_INVALID_KERNEL)
        PGT_CL_NAME(CL_INVALID_ARG_INDEX)
        PGT_CL_NAME(CL_INVALID_ARG_VALUE)
        PGT_CL_NAME(CL_INVALID_ARG_SIZE)
        PGT_CL_NAME(CL_INVALID_KERNEL_ARGS)
        PGT_CL_NAME(CL_INVALID_WORK_DIMENSION)
        PGT_CL_NAME(CL_INVALID_WORK_GROUP_SIZE)
        PGT_CL_NAME(CL_INVALID_WORK_ITEM_SIZE)
        PGT_CL_NAME(CL_INVALID_GLOBAL_OFFSET)
        PGT_CL_NAME(CL_INVALID_EVENT_WAIT_LIST)
        PGT_CL_NAME(CL_INVALID_EVENT)
        PGT_CL_NAME(CL_INVALID_OPERATION)
        PGT_CL_NAME(CL_INVALID_GL_OBJECT)
        PGT_CL_NAME(CL_INVALID_BUFFER_SIZE)
        PGT_CL_NAME(CL_INVALID_MIP_LEVEL)
        PGT_CL_NAME(CL_INVALID_GLOBAL_WORK_SIZE)
        PGT_CL_NAME(CL_INVALID_PROPERTY)
        PGT_CL_NAME(CL_INVALID_IMAGE_DESCRIPTOR)
        PGT_CL_NAME(CL_INVALID_COMPILER_OPTIONS)
        PGT_CL_NAME(CL_INVALID_LINKER_OPTIONS)
        PGT_CL_NAME(CL_INVALID_DEVICE_PARTITION_COUNT)
        PGT_CL_NAME(CL_PLATFORM_NOT_FOUND_KHR)
#undef PGT_CL_NAME
    default:
        return "unknown OpenCL error";
    }
}

pgt_result pgt_cl_fail(pgt_error *err, const char *file, int line, const char *call, cl_int code) {
    const char *base = strrchr(file, '/');
    return pgt_error_set(err, PGT_ERROR_BACKEND, "OpenCL: %s:%d: %s failed: %s (%d)",
                         base ? base + 1 : file, line, call, cl_error_name(code), (int)code);
}

/* String queries: the size first, so a long name is truncated to `cap`, never an error. One
 * helper for platform and device strings: `query` is clGetPlatformInfo or clGetDeviceInfo. */
typedef cl_int (*cl_info_fn)(void *object, cl_uint what, size_t size, void *value, size_t *ret);

static cl_int cl_info_string(cl_info_fn query, void *object, cl_uint what, char *dst, size_t cap) {
    size_t n = 0;
    cl_int rc = query(object, what, 0, NULL, &n);
    char *s = rc == CL_SUCCESS ? malloc(n + 1) : NULL;
    if (rc == CL_SUCCESS && !s) rc = CL_OUT_OF_HOST_MEMORY;
    if (rc == CL_SUCCESS) rc = query(object, what, n, s, NULL);
    if (rc == CL_SUCCESS) {
        s[n] = '\0';
        snprintf(dst, cap, "%s", s);
    }
    free(s);
    return rc;
}

static cl_int platform_info(void *p, cl_uint what, size_t size, void *value, size_t *ret) {
    return clGetPlatformInfo((cl_platform_id)p, what, size, value, ret);
}

static cl_int device_info(void *d, cl_uint what, size_t size, void *value, size_t *ret) {
    return clGetDeviceInfo((cl_device_id)d, what, size, value, ret);
}

static cl_int cl_platform_string(cl_platform_id p, cl_platform_info what, char *dst, size_t cap) {
    return cl_info_string(platform_info, p, what, dst, cap);
}

static cl_int cl_device_string(cl_device_id d, cl_device_info what, char *dst, size_t cap) {
    return cl_info_string(device_info, d, what, dst, cap);
}

/* Every device of every platform, platform by platform (at most PGT_GPU_MAX_DEVICES). No ICD
 * or no platform gives 0 devices, and so does a platform without devices. */
typedef struct cl_device_table {
    uint32_t count;
    cl_platform_id platform[PGT_GPU_MAX_DEVICES];
    cl_device_id device[PGT_GPU_MAX_DEVICES];
} cl_device_table;

static pgt_result cl_enumerate(cl_device_table *t, pgt_error *err) {
    pgt_result r = PGT_OK;
    cl_platform_id *platforms = NULL;
    cl_uint np = 0;
    t->count = 0;
    cl_int rc;
    /* ocl-icd answers CL_PLATFORM_NOT_FOUND_KHR when no ICD is installed: 0 devices. */
    PGT_CL_CHECK((rc = clGetPlatformIDs(0, NULL, &np)) == CL_PLATFORM_NOT_FOUND_KHR ? CL_SUCCESS
                                                                                    : rc);
    if (np == 0) return PGT_OK;
    platforms = malloc(np * sizeof(*platforms));
    if (!platforms) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "OpenCL: out of memory");
    PGT_CL_CHECK(clGetPlatformIDs(np, platforms, NULL));
    for (cl_uint p = 0; p < np && t->count < PGT_GPU_MAX_DEVICES; ++p) {
        cl_uint nd = 0;
        PGT_CL_CHECK((rc = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 0, NULL, &nd)) ==
                             CL_DEVICE_NOT_FOUND
                         ? CL_SUCCESS
                         : rc);
        if (nd == 0) continue;
        if (nd > PGT_GPU_MAX_DEVICES - t->count) nd = PGT_GPU_MAX_DEVICES - t->count;
        PGT_CL_CHECK(
            clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, nd, t->device + t->count, NULL));
        for (cl_uint d = 0; d < nd; ++d) t->platform[t->count + d] = platforms[p];
        t->count += nd;
    }
cleanup:
    free(platforms);
    if (r != PGT_OK) t->count = 0;
    return r;
}

static const char *cl_type_name(cl_device_id d) {
    cl_device_type type = 0;
    cl_bool unified = CL_FALSE;
    if (clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof(type), &type, NULL) != CL_SUCCESS) return "?";
    if (type & CL_DEVICE_TYPE_GPU) {
        /* Deprecated in 2.0 but answered by every 1.2+ driver: tells an iGPU from a card. */
        if (clGetDeviceInfo(d, CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof(unified), &unified, NULL) ==
                CL_SUCCESS &&
            unified)
            return "integrated-gpu";
        return "gpu";
    }
    if (type & CL_DEVICE_TYPE_CPU) return "cpu";
    if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    if (type & CL_DEVICE_TYPE_CUSTOM) return "custom";
    return "other";
}

pgt_result pgt_cl_list_devices(pgt_gpu_device_list *out, pgt_error *err) {
    pgt_result r = PGT_OK;
    cl_device_table t;
    char ver[62], cver[62]; /* both fit pgt_gpu_device_info.version with " / " */
    memset(out, 0, sizeof(*out));
    r = cl_enumerate(&t, err);
    if (r != PGT_OK) return r;
    for (uint32_t i = 0; i < t.count; ++i) {
        pgt_gpu_device_info *d = &out->devices[i];
        d->index = i;
        PGT_CL_CHECK(
            cl_platform_string(t.platform[i], CL_PLATFORM_NAME, d->platform, sizeof(d->platform)));
        PGT_CL_CHECK(cl_device_string(t.device[i], CL_DEVICE_NAME, d->name, sizeof(d->name)));
        PGT_CL_CHECK(cl_device_string(t.device[i], CL_DEVICE_VERSION, ver, sizeof(ver)));
        PGT_CL_CHECK(cl_device_string(t.device[i], CL_DEVICE_OPENCL_C_VERSION, cver, sizeof(cver)));
        snprintf(d->version, sizeof(d->version), "%s / %s", ver, cver);
        snprintf(d->type, sizeof(d->type), "%s", cl_type_name(t.device[i]));
        out->count = i + 1;
    }
cleanup:
    if (r != PGT_OK) memset(out, 0, sizeof(*out));
    return r;
}

/* Prints the build log on stderr when clBuildProgram failed; returns its code unchanged. */
static cl_int cl_build_log(cl_int rc, cl_program program, cl_device_id device, const char *name) {
    if (rc == CL_SUCCESS) return rc;
    size_t n = 0;
    char *log = NULL;
    if (clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, NULL, &n) == CL_SUCCESS)
        log = malloc(n + 1);
    if (log &&
        clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, n, log, NULL) == CL_SUCCESS) {
        log[n] = '\0';
        fprintf(stderr, "pgt: OpenCL build log for %s:\n%s\n", name, log);
    } else {
        fprintf(stderr, "pgt: OpenCL build failed for %s (no build log)\n", name);
    }
    free(log);
    return rc;
}

/* The OpenCL C version a device compiles, as major * 10 + minor ("OpenCL C 1.2 ..." -> 12). */
static int cl_c_version(const char *s) {
    int major = 0, minor = 0;
    if (sscanf(s, "OpenCL C %d.%d", &major, &minor) != 2) return 0;
    return major * 10 + minor;
}

pgt_result pgt_cl_create(pgt_cl **out, uint32_t device, pgt_gpu_profile *profile, pgt_error *err) {
    pgt_result r = PGT_OK;
    cl_int rc = CL_SUCCESS;
    cl_device_table t;
    *out = NULL;
    r = cl_enumerate(&t, err);
    if (r != PGT_OK) return r;
    if (device >= t.count)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "OpenCL: no device %u (%u found; see pgt devices)", device, t.count);
    pgt_cl *c = calloc(1, sizeof(*c));
    if (!c) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "OpenCL: out of memory");
    c->device = t.device[device];
    c->profile = profile;
    char platform[128], name[128], cver[64];
    PGT_CL_CHECK(
        cl_platform_string(t.platform[device], CL_PLATFORM_NAME, platform, sizeof(platform)));
    PGT_CL_CHECK(cl_device_string(c->device, CL_DEVICE_NAME, name, sizeof(name)));
    snprintf(c->name, sizeof(c->name), "%s / %s", platform, name);
    PGT_CL_CHECK(cl_device_string(c->device, CL_DEVICE_OPENCL_C_VERSION, cver, sizeof(cver)));
    if (cl_c_version(cver) < 12) {
        r = pgt_error_set(err, PGT_ERROR_BACKEND,
                          "OpenCL: %s compiles '%s'; pgt needs OpenCL C 1.2", c->name, cver);
        goto cleanup;
    }
    PGT_CL_CHECK(clGetDeviceInfo(c->device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof(c->max_alloc),
                                 &c->max_alloc, NULL));
    cl_device_fp_config fp = 0;
    PGT_CL_CHECK(clGetDeviceInfo(c->device, CL_DEVICE_SINGLE_FP_CONFIG, sizeof(fp), &fp, NULL));

    const cl_context_properties props[] = {CL_CONTEXT_PLATFORM,
                                           (cl_context_properties)t.platform[device], 0};
    PGT_CL_CHECK((c->context = clCreateContext(props, 1, &c->device, NULL, NULL, &rc), rc));
    const cl_command_queue_properties qp = profile ? CL_QUEUE_PROFILING_ENABLE : 0;
    PGT_CL_CHECK((c->queue = clCreateCommandQueue(c->context, c->device, qp, &rc), rc));

    const char *src = (const char *)pgt_cl_program_source;
    const size_t len = (size_t)pgt_cl_program_source_size;
    PGT_CL_CHECK((c->program = clCreateProgramWithSource(c->context, 1, &src, &len, &rc), rc));
    /* OpenCL C 1.2 lets a float division be off by 2.5 ulp; the reference's divisions (by 3,
     * 27 and n) are IEEE-rounded, so ask for that where the device offers it. */
    const char *options = fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT
                              ? "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt"
                              : "-cl-std=CL1.2";
    PGT_CL_CHECK(cl_build_log(clBuildProgram(c->program, 1, &c->device, options, NULL, NULL),
                              c->program, c->device, c->name));
    for (int k = 0; k < PGT_CL_KERNEL_COUNT; ++k) {
        PGT_CL_CHECK((c->kernels[k] = clCreateKernel(c->program, pgt_cl_kernel_names[k], &rc), rc));
        size_t wg = 0;
        PGT_CL_CHECK(clGetKernelWorkGroupInfo(c->kernels[k], c->device, CL_KERNEL_WORK_GROUP_SIZE,
                                              sizeof(wg), &wg, NULL));
        if (wg < PGT_S3_GROUP_SIZE) {
            r = pgt_error_set(
                err, PGT_ERROR_BACKEND,
                "OpenCL: %s runs %s with at most %zu work-items a group; pgt needs %u", c->name,
                pgt_cl_kernel_names[k], wg, PGT_S3_GROUP_SIZE);
            goto cleanup;
        }
    }
    PGT_CL_CHECK(
        (c->placeholder = clCreateBuffer(c->context, CL_MEM_READ_WRITE, 4, NULL, &rc), rc));
    *out = c;
    return PGT_OK;
cleanup:
    pgt_cl_destroy(c);
    return r;
}

void pgt_cl_destroy(pgt_cl *c) {
    if (!c) return;
    if (c->placeholder) clReleaseMemObject(c->placeholder);
    for (int k = 0; k < PGT_CL_KERNEL_COUNT; ++k)
        if (c->kernels[k]) clReleaseKernel(c->kernels[k]);
    if (c->program) clReleaseProgram(c->program);
    if (c->queue) clReleaseCommandQueue(c->queue);
    if (c->context) clReleaseContext(c->context);
    free(c);
}

const char *pgt_cl_device_name(const pgt_cl *c) { return c ? c->name : ""; }

/* A device buffer of `bytes` (4 at least: OpenCL has no empty buffer). */
pgt_result pgt_cl_buffer(pgt_cl *cl, cl_mem *out, uint64_t bytes, pgt_error *err) {
    pgt_result r = PGT_OK;
    cl_int rc = CL_SUCCESS;
    if (bytes < 4) bytes = 4;
    if (bytes > cl->max_alloc || bytes > (uint64_t)SIZE_MAX)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "OpenCL: a buffer of %llu bytes exceeds what %s allocates at once "
                             "(CL_DEVICE_MAX_MEM_ALLOC_SIZE %llu)",
                             (unsigned long long)bytes, cl->name,
                             (unsigned long long)cl->max_alloc);
    PGT_CL_CHECK(
        (*out = clCreateBuffer(cl->context, CL_MEM_READ_WRITE, (size_t)bytes, NULL, &rc), rc));
cleanup:
    return r;
}
