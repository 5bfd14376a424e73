/* pgt: marching on an OpenCL device (pgt_cl_march), the host side of kernels/march.cl.
 *
 * The atlas view's four arrays (ref_cpu/include/pgt/march.h) go up as they are, with one more:
 * the cosine and sine of every jump record's rot, computed here with the reference's cosf and
 * sinf (an OpenCL cos may differ in the last bit, and a walker's path with it). The walkers'
 * states go up as pgt_march_state arrays; march_walk runs one work item per walker for all its
 * steps, and the states, and with records every step's state and event word, come back. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cl_internal.h"
#include "march_cl.h"
#include "sqrt3_layout.h"

_Static_assert(PGT_CL_MARCH_MAX_JUMPS == PGT_MARCH_MAX_JUMPS, "march_cl.h follows march.h");
_Static_assert(PGT_CL_MARCH_BOUNCE_TEXELS == PGT_MARCH_BOUNCE_TEXELS, "march_cl.h follows march.h");
_Static_assert(PGT_CL_MARCH_MAX_BOUNCES == PGT_MARCH_MAX_BOUNCES, "march_cl.h follows march.h");
_Static_assert(PGT_CL_MARCH_SEARCH_ITERATIONS == PGT_MARCH_SEARCH_ITERATIONS,
               "march_cl.h follows march.h");
_Static_assert(PGT_CL_MARCH_RING_EDGES == PGT_MARCH_RING_EDGES, "march_cl.h follows march.h");
_Static_assert(PGT_CL_MARCH_GROUP_SIZE >= PGT_S3_GROUP_SIZE,
               "pgt_cl_create checks every kernel's group size against PGT_S3_GROUP_SIZE");
/* the kernel's mc_texel, mc_jump and mc_state */
_Static_assert(sizeof(pgt_march_texel) == 16 && sizeof(pgt_march_jump) == 8 &&
                   sizeof(pgt_march_state) == 36,
               "march.cl reads the reference's structs as they are");

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
    if (o && o->condition)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "OpenCL: marching with a condition (a host function, such as a "
                             "density) runs on the cpu backend only");
    if (!(length > 0.0f && length <= PGT_MARCH_MAX_LENGTH))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "step length %g is outside (0, %g] texels", (double)length,
                             (double)PGT_MARCH_MAX_LENGTH);
    const int record = rec_states || rec_events;
    if (record && (!rec_states || !rec_events))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "OpenCL march: records need both the states and the events");
    if (record && (uint64_t)count * steps > UINT32_MAX)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "OpenCL march: %u walkers x %u recorded steps exceed 2^32 records",
                             count, steps);
    if (count == 0 || steps == 0) {
        if (out_taken)
            for (uint32_t i = 0; i < count; ++i) out_taken[i] = 0;
        return PGT_OK;
    }
    pgt_result r = PGT_OK;
    const uint64_t texels = (uint64_t)a->width * a->height;
    const uint64_t records = record ? (uint64_t)count * steps : 0;
    cl_mem codes = NULL, tex = NULL, jumps = NULL, rings = NULL, rotcs = NULL, mask = NULL;
    cl_mem st = NULL, rst = NULL, rev = NULL, taken = NULL;
    cl_event ev = NULL;
    float *cs = malloc((size_t)texels * 2 * sizeof(float));
    if (!cs) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "OpenCL march: out of memory");
    for (uint64_t t = 0; t < texels; ++t) {
        const float rot = a->jumps[t].rot; /* 0 off indirection texels: (1, 0), never read */
        cs[2 * t] = cosf(rot), cs[2 * t + 1] = sinf(rot);
    }
    double t0 = pgt_cl_now_ms();
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
    if (times) times->upload_ms = pgt_cl_now_ms() - t0;

    pgt_cl_march_params p;
    memset(&p, 0, sizeof p);
    p.width = a->width, p.height = a->height, p.count = count, p.steps = steps;
    p.flags = (o && o->no_best_pointer ? PGT_CL_MARCH_NO_BEST_POINTER : 0u) |
              (o && o->no_rotation ? PGT_CL_MARCH_NO_ROTATION : 0u) |
              (o && o->rotation == PGT_MARCH_ROTATION_JACOBIAN ? PGT_CL_MARCH_JACOBIAN : 0u) |
              (o && o->mask ? PGT_CL_MARCH_MASK : 0u) | (record ? PGT_CL_MARCH_RECORD : 0u);
    p.length = length;
    p.mask_threshold =
        o && o->mask_threshold != 0.0f ? o->mask_threshold : PGT_MARCH_MASK_THRESHOLD;
    p.max_length_ratio = PGT_MARCH_MAX_LENGTH_RATIO;
    p.min_jacobian_sine2 = PGT_MARCH_MIN_JACOBIAN_SINE2;
    p.jacobian_scale_min = PGT_MARCH_JACOBIAN_SCALE_MIN;
    p.jacobian_scale_max = PGT_MARCH_JACOBIAN_SCALE_MAX;
    p.max_length = PGT_MARCH_MAX_LENGTH;
    cl_kernel k = cl->kernels[PGT_CL_K_MARCH_WALK];
    cl_mem *bufs[] = {&codes, &tex, &jumps, &rings, &rotcs, &mask};
    cl_uint arg = 0;
    for (; arg < 6; ++arg) PGT_CL_CHECK(clSetKernelArg(k, arg, sizeof(cl_mem), bufs[arg]));
    PGT_CL_CHECK(clSetKernelArg(k, arg++, sizeof p, &p));
    cl_mem *outs[] = {&st, record ? &rst : &cl->placeholder, record ? &rev : &cl->placeholder,
                      &taken};
    for (int i = 0; i < 4; ++i, ++arg)
        PGT_CL_CHECK(clSetKernelArg(k, arg, sizeof(cl_mem), outs[i]));
    const size_t local = PGT_CL_MARCH_GROUP_SIZE;
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

    t0 = pgt_cl_now_ms();
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
    if (times) times->download_ms = pgt_cl_now_ms() - t0;
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
