/* pgt: what the OpenCL host code (src/cl_sqrt3.c) and kernels/sqrt3.cl agree on beyond
 * gpu_shared/sqrt3_layout.h. Read by C and OpenCL C (lang.h); #defines only. */
#ifndef PGT_CL_SQRT3_CL_H
#define PGT_CL_SQRT3_CL_H

/* Bits of the `flags` argument of the sqrt(3) kernels: which optional per-face arrays this call
 * carries. Without PGT_CL_S3_PROT no face of the call is protected (none ever becomes one), so
 * `prot` is neither read nor written; without PGT_CL_S3_PARENT nobody asked for parents (no
 * out_face_parent, no labels). */
#define PGT_CL_S3_PROT 1u
#define PGT_CL_S3_PARENT 2u

/* The prefix sum: each work-group of PGT_S3_GROUP_SIZE items scans PGT_CL_S3_SCAN_BLOCK
 * elements (PGT_CL_S3_SCAN_ITEMS consecutive ones per item), so every level of the scan divides
 * the count by 512: four levels reach one group sum for the largest face count. */
#define PGT_CL_S3_SCAN_ITEMS 8u
#define PGT_CL_S3_SCAN_BLOCK (PGT_S3_GROUP_SIZE * PGT_CL_S3_SCAN_ITEMS)

#endif
