/* pgt: marching on Vulkan (pgt_vk_march), the host side of shaders/march_walk.comp.
 *
 * As pgt_cl_march: the atlas view's four arrays (ref_cpu/include/pgt/march.h) go up as they are,
 * with the cosine and sine of every texel's rot (pgt_gpu_march_prepare: the reference's cosf and
 * sinf); the walkers' states go up as pgt_march_state arrays; march_walk runs one invocation per
 * walker, in dispatches of at most maxComputeWorkGroupCount groups (the push constant `first`
 * numbers a dispatch's first walker) and PGT_VK_MARCH_DISPATCH_STEPS steps (`step_first`,
 * `step_count`: lavapipe's loop limit, march_vk_layout.h); the states, the steps taken and, with
 * records, every step's state and event word come back. Each array is bound whole, so each must
 * fit one storage-buffer binding. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vk_internal.h"

/* One array of the call: its binding, buffer, size, what it is (for errors), the host data an
 * input starts from and where an output goes (NULL: not read back). */
typedef struct vm_array {
    uint32_t binding;
    const char *what;
    uint64_t bytes;
    const void *data;
    void *out;
    pgt_vk_buf buf;
} vm_array;

static pgt_result vm_device(pgt_vk *ctx, vm_array *arrays, uint32_t n_arrays,
                            pgt_gpu_march_params *p, pgt_gpu_times *times, pgt_error *err) {
    pgt_result r = PGT_OK;
    for (uint32_t i = 0; i < n_arrays; ++i) {
        char what[96];
        snprintf(what, sizeof what, "march on vulkan: the %s array", arrays[i].what);
        PGT_VK_TRY(pgt_vk_fits(ctx, arrays[i].bytes, what, "the shader reads it", err));
    }
    const double t_up = pgt_gpu_now_ms();
    pgt_vk_binding bind[PGT_VK_S3_BINDINGS];
    memset(bind, 0, sizeof(bind)); /* unlisted bindings: the dummy buffer */
    for (uint32_t i = 0; i < n_arrays; ++i) {
        vm_array *a = &arrays[i];
        if (!a->bytes) continue; /* not used by this call: the dummy */
        PGT_VK_TRY(pgt_vk_buf_create(ctx, &a->buf, a->bytes, a->what, err));
        if (a->data) PGT_VK_TRY(pgt_vk_upload(ctx, &a->buf, a->data, (size_t)a->bytes, err));
        bind[a->binding] = pgt_vk_whole(ctx, &a->buf);
    }
    if (times) times->upload_ms = pgt_gpu_now_ms() - t_up;

    const uint32_t groups = (p->count + PGT_GPU_MARCH_GROUP_SIZE - 1) / PGT_GPU_MARCH_GROUP_SIZE;
    const uint32_t steps = p->steps;
    for (uint32_t k = 0; k < steps; k += PGT_VK_MARCH_DISPATCH_STEPS) {
        p->step_first = k;
        p->step_count =
            steps - k < PGT_VK_MARCH_DISPATCH_STEPS ? steps - k : PGT_VK_MARCH_DISPATCH_STEPS;
        for (uint32_t g = 0; g < groups;) {
            const uint32_t n = groups - g < ctx->max_groups ? groups - g : ctx->max_groups;
            p->first = g * PGT_GPU_MARCH_GROUP_SIZE;
            PGT_VK_TRY(pgt_vk_dispatch(ctx, PGT_VK_PIPE_MARCH_WALK, bind, p, (uint32_t)sizeof(*p),
                                       n, err));
            g += n;
        }
    }
    PGT_VK_TRY(pgt_vk_flush(ctx, err));

    const double t_down = pgt_gpu_now_ms();
    for (uint32_t i = 0; i < n_arrays; ++i)
        if (arrays[i].out && arrays[i].bytes)
            PGT_VK_TRY(pgt_vk_download(ctx, &arrays[i].buf, 0, (size_t)arrays[i].bytes,
                                       arrays[i].out, err));
    if (times) times->download_ms = pgt_gpu_now_ms() - t_down;
cleanup:
    return r;
}

pgt_result pgt_vk_march(pgt_vk *ctx, const pgt_march_atlas *a, const pgt_march_options *o,
                        float length, uint32_t steps, uint32_t count, pgt_march_state *states,
                        pgt_march_state *rec_states, uint32_t *rec_events, uint32_t *out_taken,
                        pgt_gpu_times *times, pgt_error *err) {
    if (times) memset(times, 0, sizeof(*times));
    if (!ctx) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "march on vulkan: no context");
    pgt_gpu_march_params p;
    float *cs = NULL;
    pgt_result r = pgt_gpu_march_prepare("Vulkan", a, o, length, steps, count, rec_states,
                                         rec_events, out_taken, &p, &cs, err);
    if (r != PGT_OK || !cs) return r; /* no table: nothing to run */
    const uint64_t texels = (uint64_t)a->width * a->height;
    const uint64_t records = rec_states ? (uint64_t)count * steps : 0;
    vm_array arrays[PGT_VK_M_BINDINGS] = {
        {PGT_VK_M_CODES, "texel codes", texels * 4, a->codes, NULL, {0}},
        {PGT_VK_M_TEXELS, "texels", texels * sizeof(pgt_march_texel), a->texels, NULL, {0}},
        {PGT_VK_M_JUMPS, "jump records", texels * sizeof(pgt_march_jump), a->jumps, NULL, {0}},
        {PGT_VK_M_RINGS, "rings", texels * 2, a->rings, NULL, {0}},
        {PGT_VK_M_ROTCS, "rot cosines and sines", texels * 8, cs, NULL, {0}},
        {PGT_VK_M_MASK, "mask", o && o->mask ? texels * 4 : 0, o ? o->mask : NULL, NULL, {0}},
        {PGT_VK_M_STATES,
         "walker states",
         (uint64_t)count * sizeof(pgt_march_state),
         states,
         states,
         {0}},
        {PGT_VK_M_REC_STATES,
         "recorded states",
         records * sizeof(pgt_march_state),
         NULL,
         rec_states,
         {0}},
        {PGT_VK_M_REC_EVENTS, "recorded events", records * 4, NULL, rec_events, {0}},
        {PGT_VK_M_TAKEN, "steps taken", (uint64_t)count * 4, NULL, out_taken, {0}},
    };
    pgt_vk_call_begin(ctx);
    ctx->batch_ms = 0.0;
    r = vm_device(ctx, arrays, PGT_VK_M_BINDINGS, &p, times, err);
    if (r != PGT_OK) pgt_vk_abandon(ctx);
    for (uint32_t i = 0; i < PGT_VK_M_BINDINGS; ++i) pgt_vk_buf_destroy(ctx, &arrays[i].buf);
    free(cs);
    r = pgt_vk_call_end(ctx, "pgt_vk_march", r, err);
    if (r != PGT_OK) {
        if (times) memset(times, 0, sizeof(*times));
        return r;
    }
    if (times) times->device_ms = ctx->queries ? ctx->batch_ms : 0.0;
    return PGT_OK;
}
