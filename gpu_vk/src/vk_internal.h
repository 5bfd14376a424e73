/* pgt: what the Vulkan backend's sources share: the entry points loaded at run time, the context,
 * buffers, and the command recorder that batches dispatches between waits. Not a public header. */
#ifndef PGT_VK_INTERNAL_H
#define PGT_VK_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h> /* with VK_NO_PROTOTYPES: types only, the loader is opened at run time */

#include "march_vk_layout.h"
#include "pgt_vk.h"
#include "s3_vk_layout.h"

/* ---- entry points ------------------------------------------------------------------------- */

/* The loader (libvulkan.so.1) is dlopen'ed, so that a machine without Vulkan still runs every
 * other backend and lists 0 Vulkan devices. Functions come from vkGetInstanceProcAddr and
 * vkGetDeviceProcAddr, in three tables. */
#define PGT_VK_GLOBAL_FUNCS(X)                                                                     \
    X(vkCreateInstance)                                                                            \
    X(vkEnumerateInstanceExtensionProperties)                                                      \
    X(vkEnumerateInstanceLayerProperties)

#define PGT_VK_INSTANCE_FUNCS(X)                                                                   \
    X(vkDestroyInstance)                                                                           \
    X(vkEnumeratePhysicalDevices)                                                                  \
    X(vkGetPhysicalDeviceProperties)                                                               \
    X(vkGetPhysicalDeviceProperties2)                                                              \
    X(vkGetPhysicalDeviceQueueFamilyProperties)                                                    \
    X(vkGetPhysicalDeviceMemoryProperties)                                                         \
    X(vkEnumerateDeviceExtensionProperties)                                                        \
    X(vkCreateDevice)                                                                              \
    X(vkGetDeviceProcAddr)

#define PGT_VK_DEVICE_FUNCS(X)                                                                     \
    X(vkDestroyDevice)                                                                             \
    X(vkGetDeviceQueue)                                                                            \
    X(vkDeviceWaitIdle)                                                                            \
    X(vkCreateBuffer)                                                                              \
    X(vkDestroyBuffer)                                                                             \
    X(vkGetBufferMemoryRequirements)                                                               \
    X(vkAllocateMemory)                                                                            \
    X(vkFreeMemory)                                                                                \
    X(vkBindBufferMemory)                                                                          \
    X(vkMapMemory)                                                                                 \
    X(vkUnmapMemory)                                                                               \
    X(vkFlushMappedMemoryRanges)                                                                   \
    X(vkInvalidateMappedMemoryRanges)                                                              \
    X(vkCreateShaderModule)                                                                        \
    X(vkDestroyShaderModule)                                                                       \
    X(vkCreateDescriptorSetLayout)                                                                 \
    X(vkDestroyDescriptorSetLayout)                                                                \
    X(vkCreatePipelineLayout)                                                                      \
    X(vkDestroyPipelineLayout)                                                                     \
    X(vkCreateComputePipelines)                                                                    \
    X(vkDestroyPipeline)                                                                           \
    X(vkCreateDescriptorPool)                                                                      \
    X(vkDestroyDescriptorPool)                                                                     \
    X(vkResetDescriptorPool)                                                                       \
    X(vkAllocateDescriptorSets)                                                                    \
    X(vkUpdateDescriptorSets)                                                                      \
    X(vkCreateCommandPool)                                                                         \
    X(vkDestroyCommandPool)                                                                        \
    X(vkAllocateCommandBuffers)                                                                    \
    X(vkResetCommandBuffer)                                                                        \
    X(vkBeginCommandBuffer)                                                                        \
    X(vkEndCommandBuffer)                                                                          \
    X(vkCmdBindPipeline)                                                                           \
    X(vkCmdBindDescriptorSets)                                                                     \
    X(vkCmdPushConstants)                                                                          \
    X(vkCmdDispatch)                                                                               \
    X(vkCmdPipelineBarrier)                                                                        \
    X(vkCmdCopyBuffer)                                                                             \
    X(vkCmdFillBuffer)                                                                             \
    X(vkCmdResetQueryPool)                                                                         \
    X(vkCmdWriteTimestamp)                                                                         \
    X(vkCreateQueryPool)                                                                           \
    X(vkDestroyQueryPool)                                                                          \
    X(vkGetQueryPoolResults)                                                                       \
    X(vkCreateFence)                                                                               \
    X(vkDestroyFence)                                                                              \
    X(vkWaitForFences)                                                                             \
    X(vkResetFences)                                                                               \
    X(vkQueueSubmit)                                                                               \
    X(vkQueueWaitIdle)

#define PGT_VK_PFN(name) PFN_##name name;
typedef struct pgt_vk_fns {
    void *lib; /* dlopen handle of the loader */
    PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr;
    PFN_vkEnumerateInstanceVersion vkEnumerateInstanceVersion; /* NULL on a 1.0 loader */
    PGT_VK_GLOBAL_FUNCS(PGT_VK_PFN)
    PGT_VK_INSTANCE_FUNCS(PGT_VK_PFN)
    PFN_vkCreateDebugUtilsMessengerEXT vkCreateDebugUtilsMessengerEXT;   /* with validation */
    PFN_vkDestroyDebugUtilsMessengerEXT vkDestroyDebugUtilsMessengerEXT; /* with validation */
    PGT_VK_DEVICE_FUNCS(PGT_VK_PFN)
} pgt_vk_fns;
#undef PGT_VK_PFN

/* ---- errors ------------------------------------------------------------------------------- */

/* Records a failed call (the first only, see pgt_error_set) and returns PGT_ERROR_BACKEND. */
pgt_result pgt_vk_fail(pgt_error *err, const char *file, int line, const char *call, VkResult r);
const char *pgt_vk_result_name(VkResult r);

/* The one check of every vk* call that returns a VkResult: on failure, records file, line, the
 * call's text and the error code in `err`, sets `r` and jumps to `cleanup` (both must be in
 * scope), where the function releases what it holds. */
#define PGT_VK_CHECK(call)                                                                         \
    do {                                                                                           \
        VkResult pgt_vk_r_ = (call);                                                               \
        if (pgt_vk_r_ != VK_SUCCESS) {                                                             \
            r = pgt_vk_fail(err, __FILE__, __LINE__, #call, pgt_vk_r_);                            \
            goto cleanup;                                                                          \
        }                                                                                          \
    } while (0)

/* Jumps to cleanup when a helper returned an error (it already filled err). */
#define PGT_VK_TRY(expr)                                                                           \
    do {                                                                                           \
        if ((r = (expr)) != PGT_OK) goto cleanup;                                                  \
    } while (0)

/* ---- context ------------------------------------------------------------------------------ */

typedef enum pgt_vk_pipe {
    PGT_VK_PIPE_S3_CLASSIFY,
    PGT_VK_PIPE_S3_SCAN_LOCAL,
    PGT_VK_PIPE_S3_SCAN_ADD,
    PGT_VK_PIPE_S3_VERTICES,
    PGT_VK_PIPE_S3_FACES,
    PGT_VK_PIPE_MARCH_WALK,
    PGT_VK_PIPE_COUNT
} pgt_vk_pipe;

/* A buffer with its own memory. `map` is set when the memory is host-visible (lavapipe, UMA):
 * the host then reads and writes it directly; otherwise copies go through a staging buffer. */
typedef struct pgt_vk_buf {
    VkBuffer buf;
    VkDeviceMemory mem;
    VkDeviceSize size; /* bytes allocated (a multiple of 16, at least 16) */
    void *map;
    int coherent;
} pgt_vk_buf;

/* Dispatches recorded between two waits: at most this many (descriptor sets, query pairs).
 * A step needs about ten; a smaller value (-DPGT_VK_BATCH=3u) tests the flush of a full batch. */
#ifndef PGT_VK_BATCH
#define PGT_VK_BATCH 256u
#endif

struct pgt_vk {
    pgt_vk_fns vk;
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice phys;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    char name[300];

    /* limits */
    VkDeviceSize max_binding;    /* bytes one storage-buffer binding may span (maybe lowered) */
    VkDeviceSize device_binding; /* the device's maxStorageBufferRange */
    VkDeviceSize binding_align;  /* minStorageBufferOffsetAlignment (at least 4) */
    VkDeviceSize max_allocation; /* maxMemoryAllocationSize */
    uint32_t max_groups;         /* maxComputeWorkGroupCount[0] */
    uint32_t s3_walk;            /* sqrt(3) fan walks' iteration bound (s3_vk_layout.h) */
    double timestamp_ns;         /* timestampPeriod */
    uint64_t timestamp_mask;     /* timestampValidBits of the queue family, as a mask (0: none) */
    VkPhysicalDeviceMemoryProperties memory;

    /* validation: messages counted by the messenger; `call_*` for the API call in progress */
    int validation, sync_validation;
    uint32_t messages, call_messages;
    char call_first[PGT_ERROR_MESSAGE_SIZE];

    VkDescriptorSetLayout set_layout;
    VkPipelineLayout pipe_layout;
    VkPipeline pipes[PGT_VK_PIPE_COUNT];

    /* the recorder */
    VkCommandPool cmd_pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkDescriptorPool desc_pool;
    VkQueryPool queries; /* with a profile: two timestamps per dispatch */
    int recording;
    uint32_t dispatches;          /* in the open batch */
    char names[PGT_VK_BATCH][40]; /* of those dispatches */
    pgt_vk_buf *garbage;          /* freed once the batch has run (staging, old levels) */
    uint32_t garbage_count, garbage_capacity;
    pgt_vk_buf dummy; /* bound to the bindings a pass does not use */

    pgt_gpu_profile *profile;
    double batch_ms; /* device time of the dispatches measured since the last reset */
};

const char *pgt_vk_pipe_name(pgt_vk_pipe p);

/* Starts an API call: its validation messages are counted from here. */
void pgt_vk_call_begin(pgt_vk *ctx);
/* PGT_ERROR_BACKEND naming the count and the first message when the call drew any, else r. */
pgt_result pgt_vk_call_end(pgt_vk *ctx, const char *what, pgt_result r, pgt_error *err);

/* ---- buffers ------------------------------------------------------------------------------ */

/* A storage buffer of `bytes` (device-local memory preferred), for `what` (named in errors).
 * PGT_ERROR_LIMIT when it exceeds maxMemoryAllocationSize, PGT_ERROR_OUT_OF_MEMORY when the
 * device has no room. */
pgt_result pgt_vk_buf_create(pgt_vk *ctx, pgt_vk_buf *b, VkDeviceSize bytes, const char *what,
                             pgt_error *err);
void pgt_vk_buf_destroy(pgt_vk *ctx, pgt_vk_buf *b);
/* Destroys b once the batch in flight has run (b is zeroed now). */
pgt_result pgt_vk_buf_release(pgt_vk *ctx, pgt_vk_buf *b, pgt_error *err);

/* PGT_OK when `bytes` fit one storage-buffer binding; else PGT_ERROR_LIMIT: "<what> is N bytes,
 * but <reads> through one storage-buffer binding and <device> allows M bytes (...)". */
pgt_result pgt_vk_fits(const pgt_vk *ctx, uint64_t bytes, const char *what, const char *reads,
                       pgt_error *err);

/* Host -> device: written now when mapped, else staged and copied in the open batch. */
pgt_result pgt_vk_upload(pgt_vk *ctx, pgt_vk_buf *b, const void *src, size_t bytes, pgt_error *err);
/* Zero-fills the first `bytes` in the open batch. */
pgt_result pgt_vk_zero(pgt_vk *ctx, pgt_vk_buf *b, VkDeviceSize bytes, pgt_error *err);
/* Device -> host: runs the open batch, then reads (through staging when not mapped). */
pgt_result pgt_vk_download(pgt_vk *ctx, const pgt_vk_buf *b, VkDeviceSize offset, size_t bytes,
                           void *dst, pgt_error *err);

/* ---- recorder ----------------------------------------------------------------------------- */

/* One binding of a dispatch: a window [offset, offset + range) of a buffer. */
typedef struct pgt_vk_binding {
    const pgt_vk_buf *buf; /* NULL: the dummy buffer */
    VkDeviceSize offset, range;
} pgt_vk_binding;

/* A whole buffer in one binding (its range capped at the binding limit); a buffer that does not
 * exist gives the dummy's binding. */
pgt_vk_binding pgt_vk_whole(const pgt_vk *ctx, const pgt_vk_buf *b);

/* The push-constant range of the pipeline layout, which every pipeline shares (the largest
 * block: pgt_vk_s3_push). */
#define PGT_VK_PUSH_BYTES ((uint32_t)sizeof(pgt_vk_s3_push))

/* Records one dispatch of `groups` work-groups with these bindings (PGT_VK_S3_BINDINGS of them)
 * and push constants (push_bytes <= PGT_VK_PUSH_BYTES, from offset 0), timed when profiling,
 * followed by a barrier making its writes visible to what comes next. */
pgt_result pgt_vk_dispatch(pgt_vk *ctx, pgt_vk_pipe pipe, const pgt_vk_binding *bindings,
                           const void *push, uint32_t push_bytes, uint32_t groups, pgt_error *err);
/* Submits the open batch (if any), waits for it, collects its timestamps into the profile and
 * ctx->batch_ms, and frees its garbage. */
pgt_result pgt_vk_flush(pgt_vk *ctx, pgt_error *err);
/* After an error: drops the open batch unsubmitted, waits for the queue, frees the garbage. */
void pgt_vk_abandon(pgt_vk *ctx);

#endif
