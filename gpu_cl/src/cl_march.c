/* pgt: marching on an OpenCL device (pgt_cl_march), the host side of kernels/march.cl.
 *
 * The atlas view's four arrays (ref_cpu/include/pgt/march.h) go up as they are, with one more:
 * the cosine and sine of every jump record's rot, computed on the host with the reference's cosf
 * and sinf (pgt_gpu_march_prepare; an OpenCL cos may differ in the last bit). The walkers'
 * states go up as pgt_march_state arrays; march_walk runs one work item per walker for all its
 * steps, and the states, and with records every step's state and event word, come back. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cl_internal.h"
#include "sqrt3_layout.h"

_Static_assert(PGT_GPU_MARCH_GROUP_SIZE >= PGT_S3_GROUP_SIZE,
               "pgt_cl_create checks every kernel's group size against PGT_S3_GROUP_SIZE");

static void cl_march_release(cl_mem *m) {
    if (*m) clReleaseMemObject(*m);
    *m = NULL;
}

/* pgt_cl_buffer, filled from `data` when it is not NULL (the copy is queued, not waited for). */
static pgt_result cl_march_buffer(pgt_cl *cl, cl_mem *out, uint64_t bytes, const void *data,
                                  pgt_error *err) {
    pgt_result r = pgt_cl_buffer(cl, out, bytes, err);
    if (r != PGT_OK || !data) return r;
    PGT_CL_CHECK(
        clEnqueueWriteBuffer(cl->queue, *out, CL_FALSE, 0, (size_t)bytes, data, 0, NULL, NULL));
cleanup:
    return r;
}

pgt_result pgt_cl_march(pgt_cl *cl, const pgt_march_atlas *a, const pgt_march_options *o,
                        float length, uint32_t steps, uint32_t count, pgt_march_state *states,
                        pgt_march_state *rec_states, uint32_t *rec_events, uint32_t *out_taken,
                        pgt_gpu_times *times, pgt_error *err) {
    if (times) memset(times, 0, sizeof(*times));
    pgt_gpu_march_params p;
    float *cs = NULL;
    pgt_result r = pgt_gpu_march_prepare("OpenCL", a, o, length, steps, count, rec_states,
                                         rec_events, out_taken, &p, &cs, err);
    if (r != PGT_OK || !cs) return r; /* no table: nothing to run */
    const int record = rec_states != NULL;
    const uint64_t texels = (uint64_t)a->width * a->height;
    const uint64_t records = record ? (uint64_t)count * steps : 0;
    cl_mem codes = NULL, tex = NULL, jumps = NULL, rings = NULL, rotcs = NULL, mask = NULL;
    cl_mem st = NULL, rst = NULL, rev = NULL, taken = NULL;
    cl_event ev = NULL;
    double t0 = pgt_gpu_now_ms();
    if ((r = cl_march_buffer(cl, &codes, texels * 4, a->codes, err)) ||
        (r = cl_march_buffer(cl, &tex, texels * sizeof(pgt_march_texel), a->texels, err)) ||
        (r = cl_march_buffer(cl, &jumps, texels * sizeof(pgt_march_jump), a->jumps, err)) ||
        (r = cl_march_buffer(cl, &rings, texels * 2, a->rings, err)) ||
        (r = cl_march_buffer(cl, &rotcs, texels * 8, cs, err)) ||
        (r = cl_march_buffer(cl, &mask, o && o->mask ? texels * 4 : 4, o ? o->mask : NULL, err)) ||
        (r = cl_march_buffer(cl, &st, (uint64_t)count * sizeof(pgt_march_state), states, err)) ||
        (r = cl_march_buffer(cl, &rst, records * sizeof(pgt_march_state), NULL, err)) ||
        (r = cl_march_buffer(cl, &rev, records * 4, NULL, err)) ||
        (r = cl_march_buffer(cl, &taken, (uint64_t)count * 4, NULL, err)))
        goto cleanup;
    PGT_CL_CHECK(clFinish(cl->queue));
    if (times) times->upload_ms = pgt_gpu_now_ms() - t0;

    cl_kernel k = cl->kernels[PGT_CL_K_MARCH_WALK];
    cl_mem *bufs[] = {&codes, &tex, &jumps, &rings, &rotcs, &mask};
    cl_uint arg = 0;
    for (; arg < 6; ++arg) PGT_CL_CHECK(clSetKernelArg(k, arg, sizeof(cl_mem), bufs[arg]));
    PGT_CL_CHECK(clSetKernelArg(k, arg++, sizeof p, &p));
    cl_mem *outs[] = {&st, record ? &rst : &cl->placeholder, record ? &rev : &cl->placeholder,
                      &taken};
    for (int i = 0; i < 4; ++i, ++arg)
        PGT_CL_CHECK(clSetKernelArg(k, arg, sizeof(cl_mem), outs[i]));
    const size_t local = PGT_GPU_MARCH_GROUP_SIZE;
    const size_t global = ((size_t)count + local - 1) / local * local;
    PGT_CL_CHECK(clEnqueueNDRangeKernel(cl->queue, k, 1, NULL, &global, &local, 0, NULL,
                                        cl->profile ? &ev : NULL));
    PGT_CL_CHECK(clFinish(cl->queue));
    if (ev) {
        cl_ulong e0 = 0, e1 = 0;
        PGT_CL_CHECK(clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof e0, &e0, NULL));
        PGT_CL_CHECK(clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof e1, &e1, NULL));
        const double ms = e1 > e0 ? (double)(e1 - e0) * 1e-6 : 0.0;
        if (times) times->device_ms = ms;
        if (!pgt_gpu_profile_add(cl->profile, pgt_cl_kernel_names[PGT_CL_K_MARCH_WALK], ms)) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "OpenCL: out of memory (profile)");
            goto cleanup;
        }
    }

    t0 = pgt_gpu_now_ms();
    PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, st, CL_TRUE, 0, count * sizeof(pgt_march_state),
                                     states, 0, NULL, NULL));
    if (out_taken)
        PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, taken, CL_TRUE, 0, (size_t)count * 4, out_taken,
                                         0, NULL, NULL));
    if (record) {
        PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, rst, CL_TRUE, 0,
                                         (size_t)records * sizeof(pgt_march_state), rec_states, 0,
                                         NULL, NULL));
        PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, rev, CL_TRUE, 0, (size_t)records * 4,
                                         rec_events, 0, NULL, NULL));
    }
    if (times) times->download_ms = pgt_gpu_now_ms() - t0;
cleanup:
    clFinish(cl->queue); /* no copy from cs or into the caller's arrays still pending */
    if (ev) clReleaseEvent(ev);
    cl_march_release(&codes), cl_march_release(&tex), cl_march_release(&jumps);
    cl_march_release(&rings), cl_march_release(&rotcs), cl_march_release(&mask);
    cl_march_release(&st), cl_march_release(&rst), cl_march_release(&rev);
    cl_march_release(&taken);
    free(cs);
    return r;
}
