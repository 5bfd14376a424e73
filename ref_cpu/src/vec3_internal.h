/* pgt: the float32 3-vector helpers the reference's modules share (march, terminals, woven).
 * Private to ref_cpu, and read as it is by the OpenCL marching kernel (gpu_cl/kernels/march.cl,
 * concatenated into its program), so it must stay valid OpenCL C 1.2: no includes, float only.
 * The operations are written in one fixed order (the reference is built with -ffp-contract=off),
 * so every module and the kernel get the same bits. */
#ifndef PGT_VEC3_INTERNAL_H
#define PGT_VEC3_INTERNAL_H

static inline float dot3(const float a[3], const float b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void cross3(const float a[3], const float b[3], float out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

#endif
