/* pgt: buffers, host <-> device copies and the command recorder of the Vulkan backend.
 *
 * Storage buffers take device-local memory when the device has it. When that memory is also
 * host-visible (lavapipe, integrated GPUs) the host reads and writes it in place; otherwise
 * (a discrete GPU) copies go through host-visible staging buffers, so the same code is correct
 * on both.
 *
 * Dispatches are recorded into one command buffer ("batch") and submitted when the host needs a
 * result (a scan total, a download) or the batch is full; every dispatch is followed by a global
 * memory barrier, so each pass sees the writes of the passes before it (and synchronization
 * validation agrees). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vk_internal.h"

/* ---- buffers ------------------------------------------------------------------------------ */

typedef enum vk_use {
    VK_USE_DEVICE,   /* storage: device-local first, any type if that has no room */
    VK_USE_UPLOAD,   /* staging host -> device: host-visible, coherent first */
    VK_USE_READBACK, /* staging device -> host: host-visible, cached first */
} vk_use;

/* How well memory type flags suit a use: lower is better, -1 unusable. */
static int vk_memory_rank(VkMemoryPropertyFlags f, vk_use use) {
    const int visible = (f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
    const int coherent = (f & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    const int cached = (f & VK_MEMORY_PROPERTY_HOST_CACHED_BIT) != 0;
    if (f & VK_MEMORY_PROPERTY_PROTECTED_BIT) return -1;
    switch (use) {
    case VK_USE_DEVICE:
        return (f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) ? 0 : 1;
    case VK_USE_UPLOAD:
        return !visible ? -1 : coherent ? 0 : 1;
    case VK_USE_READBACK:
        return !visible ? -1 : cached ? (coherent ? 0 : 1) : (coherent ? 2 : 3);
    }
    return -1;
}

static pgt_result vk_buf_alloc(pgt_vk *ctx, pgt_vk_buf *b, VkDeviceSize bytes, vk_use use,
                               const char *what, pgt_error *err) {
    pgt_result r = PGT_OK;
    const pgt_vk_fns *vk = &ctx->vk;
    memset(b, 0, sizeof(*b));
    VkDeviceSize size = bytes < 16 ? 16 : (bytes + 15) / 16 * 16;
    if (size > ctx->max_allocation)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "vulkan: %s needs %llu bytes in one allocation; %s allows %llu "
                             "(maxMemoryAllocationSize)",
                             what, (unsigned long long)bytes, ctx->name,
                             (unsigned long long)ctx->max_allocation);
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size;
    bi.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (use == VK_USE_DEVICE) bi.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    PGT_VK_CHECK(vk->vkCreateBuffer(ctx->device, &bi, NULL, &b->buf));
    b->size = size;
    VkMemoryRequirements req;
    vk->vkGetBufferMemoryRequirements(ctx->device, b->buf, &req);
    /* Memory types from the best rank down, in the driver's order within a rank; a type whose
     * heap is full is skipped for the next. */
    uint32_t type = PGT_NONE;
    for (int rank = 0; rank <= 3 && !b->mem; ++rank)
        for (uint32_t t = 0; t < ctx->memory.memoryTypeCount && !b->mem; ++t) {
            if (!(req.memoryTypeBits & (1u << t)) ||
                vk_memory_rank(ctx->memory.memoryTypes[t].propertyFlags, use) != rank)
                continue;
            VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
            ai.allocationSize = req.size;
            ai.memoryTypeIndex = t;
            VkResult vr = vk->vkAllocateMemory(ctx->device, &ai, NULL, &b->mem);
            if (vr == VK_ERROR_OUT_OF_DEVICE_MEMORY || vr == VK_ERROR_OUT_OF_HOST_MEMORY) {
                b->mem = VK_NULL_HANDLE;
                continue;
            }
            PGT_VK_CHECK(vr);
            type = t;
        }
    if (!b->mem) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                          "vulkan: out of device memory for %s (%llu bytes) on %s", what,
                          (unsigned long long)bytes, ctx->name);
        goto cleanup;
    }
    PGT_VK_CHECK(vk->vkBindBufferMemory(ctx->device, b->buf, b->mem, 0));
    const VkMemoryPropertyFlags flags = ctx->memory.memoryTypes[type].propertyFlags;
    if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        PGT_VK_CHECK(vk->vkMapMemory(ctx->device, b->mem, 0, VK_WHOLE_SIZE, 0, &b->map));
        b->coherent = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    }
cleanup:
    if (r != PGT_OK) pgt_vk_buf_destroy(ctx, b);
    return r;
}

pgt_result pgt_vk_buf_create(pgt_vk *ctx, pgt_vk_buf *b, VkDeviceSize bytes, const char *what,
                             pgt_error *err) {
    return vk_buf_alloc(ctx, b, bytes, VK_USE_DEVICE, what, err);
}

void pgt_vk_buf_destroy(pgt_vk *ctx, pgt_vk_buf *b) {
    if (b->buf) ctx->vk.vkDestroyBuffer(ctx->device, b->buf, NULL);
    if (b->mem) ctx->vk.vkFreeMemory(ctx->device, b->mem, NULL); /* unmaps */
    memset(b, 0, sizeof(*b));
}

static void vk_garbage_free(pgt_vk *ctx) {
    for (uint32_t i = 0; i < ctx->garbage_count; ++i) pgt_vk_buf_destroy(ctx, &ctx->garbage[i]);
    ctx->garbage_count = 0;
}

pgt_result pgt_vk_buf_release(pgt_vk *ctx, pgt_vk_buf *b, pgt_error *err) {
    pgt_result r = PGT_OK;
    if (!b->buf) return PGT_OK;
    if (ctx->recording && ctx->garbage_count == ctx->garbage_capacity) {
        uint32_t cap = ctx->garbage_capacity ? 2 * ctx->garbage_capacity : 32;
        pgt_vk_buf *g = realloc(ctx->garbage, cap * sizeof(*g));
        if (g) {
            ctx->garbage = g;
            ctx->garbage_capacity = cap;
        } else {
            r = pgt_vk_flush(ctx, err); /* no room to defer: wait, then free now */
        }
    }
    if (ctx->recording)
        ctx->garbage[ctx->garbage_count++] = *b, memset(b, 0, sizeof(*b));
    else
        pgt_vk_buf_destroy(ctx, b);
    return r;
}

/* ---- recorder ----------------------------------------------------------------------------- */

/* Makes compute and transfer writes visible to the compute, transfer and host accesses after. */
static void vk_barrier(pgt_vk *ctx, int to_host) {
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = to_host ? VK_ACCESS_HOST_READ_BIT
                               : VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                     VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    const VkPipelineStageFlags src =
        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    const VkPipelineStageFlags dst = to_host ? VK_PIPELINE_STAGE_HOST_BIT : src;
    ctx->vk.vkCmdPipelineBarrier(ctx->cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}

static pgt_result vk_begin(pgt_vk *ctx, pgt_error *err) {
    pgt_result r = PGT_OK;
    if (ctx->recording) return PGT_OK;
    PGT_VK_CHECK(ctx->vk.vkResetDescriptorPool(ctx->device, ctx->desc_pool, 0));
    PGT_VK_CHECK(ctx->vk.vkResetCommandBuffer(ctx->cmd, 0));
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    PGT_VK_CHECK(ctx->vk.vkBeginCommandBuffer(ctx->cmd, &bi));
    if (ctx->queries) ctx->vk.vkCmdResetQueryPool(ctx->cmd, ctx->queries, 0, 2 * PGT_VK_BATCH);
    ctx->recording = 1;
    ctx->dispatches = 0;
cleanup:
    return r;
}

pgt_result pgt_vk_flush(pgt_vk *ctx, pgt_error *err) {
    pgt_result r = PGT_OK;
    uint64_t *ts = NULL;
    if (!ctx->recording) return PGT_OK;
    vk_barrier(ctx, 1);
    ctx->recording = 0;
    PGT_VK_CHECK(ctx->vk.vkEndCommandBuffer(ctx->cmd));
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &ctx->cmd;
    PGT_VK_CHECK(ctx->vk.vkQueueSubmit(ctx->queue, 1, &si, ctx->fence));
    PGT_VK_CHECK(ctx->vk.vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, UINT64_MAX));
    PGT_VK_CHECK(ctx->vk.vkResetFences(ctx->device, 1, &ctx->fence));
    if (ctx->queries && ctx->dispatches) {
        const uint32_t n = 2 * ctx->dispatches;
        ts = malloc(n * sizeof(*ts));
        if (!ts) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "vulkan: out of memory");
            goto cleanup;
        }
        PGT_VK_CHECK(ctx->vk.vkGetQueryPoolResults(
            ctx->device, ctx->queries, 0, n, n * sizeof(*ts), ts, sizeof(*ts),
            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        for (uint32_t d = 0; d < ctx->dispatches; ++d) {
            /* the difference modulo the counter's valid bits survives a wrap */
            const uint64_t ticks = (ts[2 * d + 1] - ts[2 * d]) & ctx->timestamp_mask;
            const double ms = (double)ticks * ctx->timestamp_ns * 1e-6;
            ctx->batch_ms += ms;
            pgt_gpu_profile_add(ctx->profile, ctx->names[d], ms); /* dropped when out of memory */
        }
    }
cleanup:
    ctx->dispatches = 0;
    free(ts);
    vk_garbage_free(ctx);
    return r;
}

void pgt_vk_abandon(pgt_vk *ctx) {
    if (ctx->recording) {
        ctx->vk.vkEndCommandBuffer(ctx->cmd); /* never submitted; reset by the next batch */
        ctx->recording = 0;
    }
    ctx->vk.vkQueueWaitIdle(ctx->queue);
    ctx->dispatches = 0;
    vk_garbage_free(ctx);
}

pgt_result pgt_vk_dispatch(pgt_vk *ctx, pgt_vk_pipe pipe, const pgt_vk_binding *bindings,
                           const void *push, uint32_t push_bytes, uint32_t groups, pgt_error *err) {
    pgt_result r = PGT_OK;
    const pgt_vk_fns *vk = &ctx->vk;
    if (groups == 0) return PGT_OK;
    if (ctx->recording && ctx->dispatches == PGT_VK_BATCH) PGT_VK_TRY(pgt_vk_flush(ctx, err));
    PGT_VK_TRY(vk_begin(ctx, err));
    VkDescriptorSet set;
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = ctx->desc_pool;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &ctx->set_layout;
    PGT_VK_CHECK(vk->vkAllocateDescriptorSets(ctx->device, &ai, &set));
    VkDescriptorBufferInfo info[PGT_VK_S3_BINDINGS];
    VkWriteDescriptorSet w[PGT_VK_S3_BINDINGS];
    for (uint32_t i = 0; i < PGT_VK_S3_BINDINGS; ++i) {
        const pgt_vk_binding *b = &bindings[i];
        if (b->buf && b->buf->buf) {
            info[i].buffer = b->buf->buf;
            info[i].offset = b->offset;
            info[i].range = b->range;
        } else {
            info[i].buffer = ctx->dummy.buf;
            info[i].offset = 0;
            info[i].range = ctx->dummy.size;
        }
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w[i].dstSet = set;
        w[i].dstBinding = i;
        w[i].descriptorCount = 1;
        w[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w[i].pBufferInfo = &info[i];
    }
    vk->vkUpdateDescriptorSets(ctx->device, PGT_VK_S3_BINDINGS, w, 0, NULL);
    vk->vkCmdBindPipeline(ctx->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->pipes[pipe]);
    vk->vkCmdBindDescriptorSets(ctx->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->pipe_layout, 0, 1,
                                &set, 0, NULL);
    vk->vkCmdPushConstants(ctx->cmd, ctx->pipe_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes,
                           push);
    const uint32_t d = ctx->dispatches++;
    snprintf(ctx->names[d], sizeof(ctx->names[d]), "%s", pgt_vk_pipe_name(pipe));
    if (ctx->queries)
        vk->vkCmdWriteTimestamp(ctx->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, ctx->queries, 2 * d);
    vk->vkCmdDispatch(ctx->cmd, groups, 1, 1);
    if (ctx->queries)
        vk->vkCmdWriteTimestamp(ctx->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, ctx->queries,
                                2 * d + 1);
    vk_barrier(ctx, 0);
cleanup:
    return r;
}

pgt_vk_binding pgt_vk_whole(const pgt_vk *ctx, const pgt_vk_buf *b) {
    pgt_vk_binding w = {NULL, 0, 0};
    if (!b->buf) return w;
    w.buf = b;
    w.range = b->size < ctx->max_binding ? b->size : ctx->max_binding;
    return w;
}

pgt_result pgt_vk_fits(const pgt_vk *ctx, uint64_t bytes, const char *what, const char *reads,
                       pgt_error *err) {
    if (bytes <= ctx->max_binding) return PGT_OK;
    return pgt_error_set(
        err, PGT_ERROR_LIMIT,
        "%s is %llu bytes, but %s through one storage-buffer binding and %s allows %llu bytes "
        "(maxStorageBufferRange %llu%s)",
        what, (unsigned long long)bytes, reads, ctx->name, (unsigned long long)ctx->max_binding,
        (unsigned long long)ctx->device_binding,
        ctx->max_binding < ctx->device_binding ? ", lowered by PGT_VK_MAX_BINDING_BYTES" : "");
}

/* ---- copies ------------------------------------------------------------------------------- */

pgt_result pgt_vk_upload(pgt_vk *ctx, pgt_vk_buf *b, const void *src, size_t bytes,
                         pgt_error *err) {
    pgt_result r = PGT_OK;
    pgt_vk_buf staging = {0};
    if (!bytes) return PGT_OK;
    if (b->map) {
        memcpy(b->map, src, bytes);
        if (!b->coherent) {
            VkMappedMemoryRange mr = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
            mr.memory = b->mem;
            mr.size = VK_WHOLE_SIZE;
            PGT_VK_CHECK(ctx->vk.vkFlushMappedMemoryRanges(ctx->device, 1, &mr));
        }
        return PGT_OK;
    }
    PGT_VK_TRY(vk_buf_alloc(ctx, &staging, bytes, VK_USE_UPLOAD, "an upload staging buffer", err));
    memcpy(staging.map, src, bytes);
    if (!staging.coherent) {
        VkMappedMemoryRange mr = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
        mr.memory = staging.mem;
        mr.size = VK_WHOLE_SIZE;
        PGT_VK_CHECK(ctx->vk.vkFlushMappedMemoryRanges(ctx->device, 1, &mr));
    }
    PGT_VK_TRY(vk_begin(ctx, err));
    VkBufferCopy region = {0, 0, bytes};
    ctx->vk.vkCmdCopyBuffer(ctx->cmd, staging.buf, b->buf, 1, &region);
    vk_barrier(ctx, 0);
    PGT_VK_TRY(pgt_vk_buf_release(ctx, &staging, err)); /* freed once the copy has run */
cleanup:
    pgt_vk_buf_destroy(ctx, &staging);
    return r;
}

pgt_result pgt_vk_zero(pgt_vk *ctx, pgt_vk_buf *b, VkDeviceSize bytes, pgt_error *err) {
    pgt_result r = PGT_OK;
    if (!bytes) return PGT_OK;
    if (b->map) { /* a fresh buffer the device does not use yet */
        memset(b->map, 0, bytes);
        if (!b->coherent) {
            VkMappedMemoryRange mr = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
            mr.memory = b->mem;
            mr.size = VK_WHOLE_SIZE;
            PGT_VK_CHECK(ctx->vk.vkFlushMappedMemoryRanges(ctx->device, 1, &mr));
        }
        return PGT_OK;
    }
    PGT_VK_TRY(vk_begin(ctx, err));
    ctx->vk.vkCmdFillBuffer(ctx->cmd, b->buf, 0, (bytes + 3) / 4 * 4, 0);
    vk_barrier(ctx, 0);
cleanup:
    return r;
}

pgt_result pgt_vk_download(pgt_vk *ctx, const pgt_vk_buf *b, VkDeviceSize offset, size_t bytes,
                           void *dst, pgt_error *err) {
    pgt_result r = PGT_OK;
    pgt_vk_buf staging = {0};
    const pgt_vk_buf *from = b;
    VkDeviceSize at = offset;
    if (!bytes) return PGT_OK;
    if (!b->map) {
        PGT_VK_TRY(
            vk_buf_alloc(ctx, &staging, bytes, VK_USE_READBACK, "a download staging buffer", err));
        PGT_VK_TRY(vk_begin(ctx, err));
        VkBufferCopy region = {offset, 0, bytes};
        ctx->vk.vkCmdCopyBuffer(ctx->cmd, b->buf, staging.buf, 1, &region);
        from = &staging;
        at = 0;
    }
    PGT_VK_TRY(pgt_vk_flush(ctx, err)); /* ends with a barrier to host reads */
    if (!from->coherent) {
        VkMappedMemoryRange mr = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
        mr.memory = from->mem;
        mr.size = VK_WHOLE_SIZE;
        PGT_VK_CHECK(ctx->vk.vkInvalidateMappedMemoryRanges(ctx->device, 1, &mr));
    }
    memcpy(dst, (const unsigned char *)from->map + at, bytes);
cleanup:
    if (r != PGT_OK && staging.buf) pgt_vk_abandon(ctx); /* the copy may be recorded */
    pgt_vk_buf_destroy(ctx, &staging);
    return r;
}
