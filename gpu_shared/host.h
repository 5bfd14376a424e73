/* pgt: host-side types every GPU backend and the harness share (C only, not read by kernels). */
#ifndef PGT_GPU_HOST_H
#define PGT_GPU_HOST_H

#include <stdint.h>

#include "pgt/result.h"

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

#ifdef __cplusplus
}
#endif

#endif
