/* pgt: the Vulkan backend's context: the loader (opened at run time), the instance with optional
 * validation, device listing, the compute device, its queue and the compute pipelines.
 *
 * Vulkan 1.1+ compute only: no surface, no window, no graphics queue. The instance costs
 * 30-250 ms on lavapipe, so a context is created once and reused for every call. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vk_internal.h"

/* The SPIR-V of every pipeline, embedded at build time (CMakeLists.txt: glslc, then embed.cmake).
 */
extern const unsigned char pgt_vk_spv_s3_classify[], pgt_vk_spv_s3_scan_local[],
    pgt_vk_spv_s3_scan_add[], pgt_vk_spv_s3_vertices[], pgt_vk_spv_s3_faces[],
    pgt_vk_spv_march_walk[];
extern const unsigned long pgt_vk_spv_s3_classify_size, pgt_vk_spv_s3_scan_local_size,
    pgt_vk_spv_s3_scan_add_size, pgt_vk_spv_s3_vertices_size, pgt_vk_spv_s3_faces_size,
    pgt_vk_spv_march_walk_size;

static const struct {
    const char *name; /* the pgt_gpu_event name of its dispatches */
    const unsigned char *spv;
    const unsigned long *size;
} vk_pipes[PGT_VK_PIPE_COUNT] = {
    {"s3_classify", pgt_vk_spv_s3_classify, &pgt_vk_spv_s3_classify_size},
    {"s3_scan_local", pgt_vk_spv_s3_scan_local, &pgt_vk_spv_s3_scan_local_size},
    {"s3_scan_add", pgt_vk_spv_s3_scan_add, &pgt_vk_spv_s3_scan_add_size},
    {"s3_vertices", pgt_vk_spv_s3_vertices, &pgt_vk_spv_s3_vertices_size},
    {"s3_faces", pgt_vk_spv_s3_faces, &pgt_vk_spv_s3_faces_size},
    {"march_walk", pgt_vk_spv_march_walk, &pgt_vk_spv_march_walk_size},
};

const char *pgt_vk_pipe_name(pgt_vk_pipe p) { return vk_pipes[p].name; }

#define VK_VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"

/* GLSL lays the push-constant block out as 4-byte members in order (std430); every device offers
 * at least 128 bytes of push constants. */
_Static_assert(sizeof(pgt_vk_s3_push) == 4 * (8 + 13),
               "pgt_vk_s3_push: 4-byte members, no padding");
_Static_assert(sizeof(pgt_vk_s3_push) <= 128, "pgt_vk_s3_push: beyond the guaranteed 128 bytes");
/* The pipeline layout's one push-constant range and one set layout serve every pipeline. */
_Static_assert(sizeof(pgt_gpu_march_params) <= PGT_VK_PUSH_BYTES,
               "the march's parameters fit the push-constant range");
_Static_assert(PGT_VK_M_BINDINGS <= PGT_VK_S3_BINDINGS, "the march's bindings fit the set layout");
_Static_assert(PGT_GPU_MARCH_GROUP_SIZE <= PGT_S3_GROUP_SIZE,
               "pgt_vk_create checks the work-group size against PGT_S3_GROUP_SIZE");

/* ---- errors -------------------------------------------------------------------------------- */

const char *pgt_vk_result_name(VkResult r) {
    switch (r) {
#define CASE(x)                                                                                    \
    case x:                                                                                        \
        return #x;
        CASE(VK_SUCCESS)
        CASE(VK_NOT_READY)
        CASE(VK_TIMEOUT)
        CASE(VK_INCOMPLETE)
        CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        CASE(VK_ERROR_INITIALIZATION_FAILED)
        CASE(VK_ERROR_DEVICE_LOST)
        CASE(VK_ERROR_MEMORY_MAP_FAILED)
        CASE(VK_ERROR_LAYER_NOT_PRESENT)
        CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        CASE(VK_ERROR_TOO_MANY_OBJECTS)
        CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        CASE(VK_ERROR_FRAGMENTED_POOL)
        CASE(VK_ERROR_UNKNOWN)
        CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        CASE(VK_ERROR_FRAGMENTATION)
        CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
#undef CASE
    default:
        return "unknown VkResult";
    }
}

pgt_result pgt_vk_fail(pgt_error *err, const char *file, int line, const char *call, VkResult r) {
    const char *base = strrchr(file, '/');
    return pgt_error_set(err, PGT_ERROR_BACKEND, "vulkan: %s:%d: %s failed: %s (%d)",
                         base ? base + 1 : file, line, call, pgt_vk_result_name(r), (int)r);
}

/* ---- validation messages ------------------------------------------------------------------ */

static VKAPI_ATTR VkBool32 VKAPI_CALL vk_on_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
    pgt_vk *ctx = user;
    const char *msg = data && data->pMessage ? data->pMessage : "(no text)";
    (void)types;
    fprintf(stderr, "pgt vulkan validation %s: %s\n",
            severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning", msg);
    ctx->messages++;
    if (!ctx->call_messages++) snprintf(ctx->call_first, sizeof(ctx->call_first), "%s", msg);
    return VK_FALSE;
}

void pgt_vk_call_begin(pgt_vk *ctx) {
    ctx->call_messages = 0;
    ctx->call_first[0] = '\0';
}

pgt_result pgt_vk_call_end(pgt_vk *ctx, const char *what, pgt_result r, pgt_error *err) {
    if (ctx->call_messages && r == PGT_OK)
        r = pgt_error_set(
            err, PGT_ERROR_BACKEND, "vulkan: %u validation message%s during %s; the first: %s",
            ctx->call_messages, ctx->call_messages == 1 ? "" : "s", what, ctx->call_first);
    return r;
}

/* ---- the loader and the instance ---------------------------------------------------------- */

/* A symbol's address as a function pointer (ISO C has no cast between the two). */
static void vk_sym(void *dst, void *sym) { memcpy(dst, &sym, sizeof(sym)); }
static void vk_fn(void *dst, PFN_vkVoidFunction fn) { memcpy(dst, &fn, sizeof(fn)); }

/* Opens libvulkan.so.1 and the global entry points. PGT_ERROR_BACKEND when there is no loader. */
static pgt_result vk_open_loader(pgt_vk_fns *vk, pgt_error *err) {
    memset(vk, 0, sizeof(*vk));
    vk->lib = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!vk->lib) vk->lib = dlopen("libvulkan.so", RTLD_NOW | RTLD_LOCAL);
    if (!vk->lib) {
        const char *why = dlerror();
        return pgt_error_set(err, PGT_ERROR_BACKEND, "vulkan: no loader (libvulkan.so.1): %s",
                             why ? why : "not found");
    }
    vk_sym(&vk->vkGetInstanceProcAddr, dlsym(vk->lib, "vkGetInstanceProcAddr"));
    if (!vk->vkGetInstanceProcAddr) {
        dlclose(vk->lib);
        vk->lib = NULL;
        return pgt_error_set(err, PGT_ERROR_BACKEND,
                             "vulkan: libvulkan.so.1 has no vkGetInstanceProcAddr");
    }
    vk_fn(&vk->vkEnumerateInstanceVersion,
          vk->vkGetInstanceProcAddr(NULL, "vkEnumerateInstanceVersion"));
#define LOAD(name)                                                                                 \
    vk_fn(&vk->name, vk->vkGetInstanceProcAddr(NULL, #name));                                      \
    if (!vk->name) {                                                                               \
        dlclose(vk->lib);                                                                          \
        vk->lib = NULL;                                                                            \
        return pgt_error_set(err, PGT_ERROR_BACKEND, "vulkan: the loader has no %s", #name);       \
    }
    PGT_VK_GLOBAL_FUNCS(LOAD)
#undef LOAD
    return PGT_OK;
}

static void vk_close_loader(pgt_vk_fns *vk) {
    if (vk->lib) dlclose(vk->lib);
    memset(vk, 0, sizeof(*vk));
}

static pgt_result vk_load_instance(pgt_vk_fns *vk, VkInstance instance, pgt_error *err) {
#define LOAD(name)                                                                                 \
    vk_fn(&vk->name, vk->vkGetInstanceProcAddr(instance, #name));                                  \
    if (!vk->name) return pgt_error_set(err, PGT_ERROR_BACKEND, "vulkan: no %s", #name);
    PGT_VK_INSTANCE_FUNCS(LOAD)
#undef LOAD
    vk_fn(&vk->vkGetPhysicalDeviceProperties2,
          vk->vkGetInstanceProcAddr(instance, "vkGetPhysicalDeviceProperties2"));
    vk_fn(&vk->vkCreateDebugUtilsMessengerEXT,
          vk->vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    vk_fn(&vk->vkDestroyDebugUtilsMessengerEXT,
          vk->vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    return PGT_OK;
}

static pgt_result vk_load_device(pgt_vk_fns *vk, VkDevice device, pgt_error *err) {
#define LOAD(name)                                                                                 \
    vk_fn(&vk->name, vk->vkGetDeviceProcAddr(device, #name));                                      \
    if (!vk->name) return pgt_error_set(err, PGT_ERROR_BACKEND, "vulkan: no %s", #name);
    PGT_VK_DEVICE_FUNCS(LOAD)
#undef LOAD
    return PGT_OK;
}

/* The API version the instance asks for: the loader's, capped at 1.3 (what we were built with). */
static uint32_t vk_instance_api(const pgt_vk_fns *vk) {
    uint32_t v = VK_API_VERSION_1_0;
    if (vk->vkEnumerateInstanceVersion && vk->vkEnumerateInstanceVersion(&v) != VK_SUCCESS)
        v = VK_API_VERSION_1_0;
    v = VK_MAKE_API_VERSION(0, VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), 0);
    return v > VK_API_VERSION_1_3 ? VK_API_VERSION_1_3 : v;
}

static int vk_has_layer(const pgt_vk_fns *vk, const char *name) {
    uint32_t n = 0;
    if (vk->vkEnumerateInstanceLayerProperties(&n, NULL) != VK_SUCCESS || !n) return 0;
    VkLayerProperties *p = calloc(n, sizeof(*p));
    int found = 0;
    if (p && vk->vkEnumerateInstanceLayerProperties(&n, p) == VK_SUCCESS)
        for (uint32_t i = 0; i < n && !found; ++i) found = !strcmp(p[i].layerName, name);
    free(p);
    return found;
}

/* Whether instance extension `ext` is offered by the loader and implicit layers (layer NULL) or
 * by `layer`. */
static int vk_has_extension(const pgt_vk_fns *vk, const char *layer, const char *ext) {
    uint32_t n = 0;
    if (vk->vkEnumerateInstanceExtensionProperties(layer, &n, NULL) != VK_SUCCESS || !n) return 0;
    VkExtensionProperties *p = calloc(n, sizeof(*p));
    int found = 0;
    if (p && vk->vkEnumerateInstanceExtensionProperties(layer, &n, p) == VK_SUCCESS)
        for (uint32_t i = 0; i < n && !found; ++i) found = !strcmp(p[i].extensionName, ext);
    free(p);
    return found;
}

/* Creates the instance. With ctx, validation is on: the layer (an error when missing), a
 * VK_EXT_debug_utils messenger reporting to ctx (also during instance creation and destruction),
 * and synchronization validation when the layer offers VK_EXT_validation_features.
 * *out_vr receives vkCreateInstance's result, so that the device list can take "no driver" as
 * 0 devices. */
static pgt_result vk_create_instance(pgt_vk_fns *vk, pgt_vk *ctx, VkInstance *out,
                                     uint32_t *out_api, VkResult *out_vr, pgt_error *err) {
    pgt_result r = PGT_OK;
    *out = VK_NULL_HANDLE;
    *out_vr = VK_SUCCESS;
    const uint32_t api = vk_instance_api(vk);
    *out_api = api;
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "pgt";
    app.applicationVersion = 1;
    app.pEngineName = "pgt";
    app.apiVersion = api;
    VkInstanceCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    const char *layers[1] = {VK_VALIDATION_LAYER};
    const char *exts[2];
    uint32_t n_ext = 0;
    VkDebugUtilsMessengerCreateInfoEXT mi = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    VkValidationFeaturesEXT vf = {.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    const VkValidationFeatureEnableEXT enables[1] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    if (ctx) {
        if (!vk_has_layer(vk, VK_VALIDATION_LAYER))
            return pgt_error_set(err, PGT_ERROR_BACKEND,
                                 "vulkan: validation asked but the layer %s is not installed "
                                 "(Debian: vulkan-validationlayers)",
                                 VK_VALIDATION_LAYER);
        if (!vk_has_extension(vk, NULL, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) &&
            !vk_has_extension(vk, VK_VALIDATION_LAYER, VK_EXT_DEBUG_UTILS_EXTENSION_NAME))
            return pgt_error_set(err, PGT_ERROR_BACKEND,
                                 "vulkan: validation asked but %s is not available",
                                 VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        ci.enabledLayerCount = 1;
        ci.ppEnabledLayerNames = layers;
        exts[n_ext++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        mi.pfnUserCallback = vk_on_message;
        mi.pUserData = ctx;
        ci.pNext = &mi;
        if (vk_has_extension(vk, VK_VALIDATION_LAYER, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME)) {
            exts[n_ext++] = VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME;
            vf.enabledValidationFeatureCount = 1;
            vf.pEnabledValidationFeatures = enables;
            mi.pNext = &vf;
            ctx->sync_validation = 1;
        }
        ci.enabledExtensionCount = n_ext;
        ci.ppEnabledExtensionNames = exts;
    }
    VkResult vr = vk->vkCreateInstance(&ci, NULL, out);
    *out_vr = vr;
    PGT_VK_CHECK(vr);
    PGT_VK_TRY(vk_load_instance(vk, *out, err));
    if (ctx) {
        if (!vk->vkCreateDebugUtilsMessengerEXT || !vk->vkDestroyDebugUtilsMessengerEXT) {
            r = pgt_error_set(err, PGT_ERROR_BACKEND, "vulkan: no vkCreateDebugUtilsMessengerEXT");
            goto cleanup;
        }
        mi.pNext = NULL;
        PGT_VK_CHECK(vk->vkCreateDebugUtilsMessengerEXT(*out, &mi, NULL, &ctx->messenger));
    }
cleanup:
    if (r != PGT_OK && *out) {
        if (vk->vkDestroyInstance) vk->vkDestroyInstance(*out, NULL);
        *out = VK_NULL_HANDLE;
    }
    return r;
}

/* ---- devices ------------------------------------------------------------------------------ */

/* The first queue family with compute, or PGT_NONE. */
static uint32_t vk_compute_family(const pgt_vk_fns *vk, VkPhysicalDevice p,
                                  uint32_t *out_timestamp_bits) {
    uint32_t n = 0, found = PGT_NONE;
    vk->vkGetPhysicalDeviceQueueFamilyProperties(p, &n, NULL);
    VkQueueFamilyProperties *q = calloc(n ? n : 1, sizeof(*q));
    if (!q) return PGT_NONE;
    vk->vkGetPhysicalDeviceQueueFamilyProperties(p, &n, q);
    for (uint32_t i = 0; i < n && found == PGT_NONE; ++i)
        if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
            found = i;
            if (out_timestamp_bits) *out_timestamp_bits = q[i].timestampValidBits;
        }
    free(q);
    return found;
}

/* The physical devices with a compute queue, in enumeration order (the --device numbering). */
static pgt_result vk_compute_devices(const pgt_vk_fns *vk, VkInstance instance,
                                     VkPhysicalDevice **out, uint32_t *out_count, pgt_error *err) {
    pgt_result r = PGT_OK;
    uint32_t n = 0, kept = 0;
    VkPhysicalDevice *all = NULL;
    *out = NULL;
    *out_count = 0;
    VkResult vr = vk->vkEnumeratePhysicalDevices(instance, &n, NULL);
    if (vr == VK_ERROR_INITIALIZATION_FAILED || n == 0) return PGT_OK; /* no device */
    PGT_VK_CHECK(vr);
    all = calloc(n, sizeof(*all));
    if (!all) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "vulkan: out of memory");
    vr = vk->vkEnumeratePhysicalDevices(instance, &n, all);
    if (vr != VK_INCOMPLETE) PGT_VK_CHECK(vr);
    for (uint32_t i = 0; i < n; ++i)
        if (vk_compute_family(vk, all[i], NULL) != PGT_NONE) all[kept++] = all[i];
    *out = all;
    *out_count = kept;
    all = NULL;
cleanup:
    free(all);
    return r;
}

static const char *vk_type_name(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return "integrated-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return "discrete-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return "virtual-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return "cpu";
    default:
        return "other";
    }
}

/* Platform (the driver name when the device and instance speak 1.2, else "vulkan"), name,
 * version and type of one device. */
static void vk_describe(const pgt_vk_fns *vk, VkPhysicalDevice p, uint32_t instance_api,
                        pgt_gpu_device_info *info, VkDriverId *driver) {
    VkPhysicalDeviceProperties props;
    if (driver) *driver = (VkDriverId)0; /* unknown before Vulkan 1.2 */
    vk->vkGetPhysicalDeviceProperties(p, &props);
    snprintf(info->platform, sizeof(info->platform), "vulkan");
    const uint32_t api = props.apiVersion < instance_api ? props.apiVersion : instance_api;
    if (api >= VK_API_VERSION_1_2 && vk->vkGetPhysicalDeviceProperties2) {
        VkPhysicalDeviceDriverProperties drv = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        p2.pNext = &drv;
        vk->vkGetPhysicalDeviceProperties2(p, &p2);
        if (driver) *driver = drv.driverID;
        if (drv.driverName[0])
            snprintf(info->platform, sizeof(info->platform), "%.*s",
                     (int)sizeof(info->platform) - 1, drv.driverName);
    }
    snprintf(info->name, sizeof(info->name), "%.*s", (int)sizeof(info->name) - 1, props.deviceName);
    snprintf(info->version, sizeof(info->version), "Vulkan %u.%u.%u",
             VK_API_VERSION_MAJOR(props.apiVersion), VK_API_VERSION_MINOR(props.apiVersion),
             VK_API_VERSION_PATCH(props.apiVersion));
    snprintf(info->type, sizeof(info->type), "%s", vk_type_name(props.deviceType));
}

pgt_result pgt_vk_list_devices(pgt_gpu_device_list *out, pgt_error *err) {
    pgt_result r = PGT_OK;
    pgt_vk_fns vk;
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice *devs = NULL;
    uint32_t n = 0, api = 0;
    VkResult vr;
    memset(out, 0, sizeof(*out));
    if (vk_open_loader(&vk, NULL) != PGT_OK) return PGT_OK; /* no loader: no device */
    if (vk_create_instance(&vk, NULL, &instance, &api, &vr, NULL) != PGT_OK) {
        /* no driver (ICD) is 0 devices; anything else is an error */
        if (vr != VK_ERROR_INCOMPATIBLE_DRIVER && vr != VK_ERROR_INITIALIZATION_FAILED &&
            vr != VK_ERROR_EXTENSION_NOT_PRESENT)
            r = pgt_vk_fail(err, __FILE__, __LINE__, "vkCreateInstance", vr);
        goto cleanup;
    }
    PGT_VK_TRY(vk_compute_devices(&vk, instance, &devs, &n, err));
    for (uint32_t i = 0; i < n && i < PGT_GPU_MAX_DEVICES; ++i) {
        out->devices[i].index = i;
        vk_describe(&vk, devs[i], api, &out->devices[i], NULL);
        out->count++;
    }
cleanup:
    free(devs);
    if (instance) vk.vkDestroyInstance(instance, NULL);
    vk_close_loader(&vk);
    return r;
}

/* ---- the context -------------------------------------------------------------------------- */

/* PGT_VK_MAX_BINDING_BYTES lowers the binding limit (to test the split of large outputs on small
 * meshes); it never raises it. */
/* A device limit lowered for tests by the environment variable `name` (a decimal number; never
 * raised, never below `least`; anything else leaves the limit as it is). */
static uint64_t vk_env_limit(const char *name, uint64_t limit, uint64_t least) {
    const char *s = getenv(name);
    if (!s || !*s) return limit;
    char *end = NULL;
    unsigned long long v = strtoull(s, &end, 10);
    if (!end || *end) return limit;
    if (v < least) v = least;
    return v < limit ? v : limit;
}

/* PGT_VK_MAX_BINDING_BYTES: a window must hold one face's writes (9 indices) past an aligned
 * start; a multiple of 4 bytes. */
static VkDeviceSize vk_binding_override(VkDeviceSize limit, VkDeviceSize align) {
    const uint64_t v = vk_env_limit("PGT_VK_MAX_BINDING_BYTES", limit, 64 + 2 * (uint64_t)align);
    return v - v % 4;
}

static pgt_result vk_create_pipelines(pgt_vk *ctx, pgt_error *err) {
    pgt_result r = PGT_OK;
    uint32_t *code = NULL;
    VkShaderModule module = VK_NULL_HANDLE;
    VkDescriptorSetLayoutBinding b[PGT_VK_S3_BINDINGS];
    for (uint32_t i = 0; i < PGT_VK_S3_BINDINGS; ++i) {
        b[i].binding = i;
        b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        b[i].descriptorCount = 1;
        b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
        b[i].pImmutableSamplers = NULL;
    }
    VkDescriptorSetLayoutCreateInfo dl = {.sType =
                                              VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = PGT_VK_S3_BINDINGS;
    dl.pBindings = b;
    PGT_VK_CHECK(ctx->vk.vkCreateDescriptorSetLayout(ctx->device, &dl, NULL, &ctx->set_layout));
    VkPushConstantRange pcr = {VK_SHADER_STAGE_COMPUTE_BIT, 0, PGT_VK_PUSH_BYTES};
    VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &ctx->set_layout;
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &pcr;
    PGT_VK_CHECK(ctx->vk.vkCreatePipelineLayout(ctx->device, &pl, NULL, &ctx->pipe_layout));
    for (uint32_t p = 0; p < PGT_VK_PIPE_COUNT; ++p) {
        /* SPIR-V words must be 4-byte aligned; the embedded bytes need not be */
        const size_t size = *vk_pipes[p].size;
        code = malloc(size ? size : 4);
        if (!code) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "vulkan: out of memory");
            goto cleanup;
        }
        memcpy(code, vk_pipes[p].spv, size);
        VkShaderModuleCreateInfo sm = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        sm.codeSize = size;
        sm.pCode = code;
        PGT_VK_CHECK(ctx->vk.vkCreateShaderModule(ctx->device, &sm, NULL, &module));
        VkComputePipelineCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        ci.stage.module = module;
        ci.stage.pName = "main";
        ci.layout = ctx->pipe_layout;
        PGT_VK_CHECK(ctx->vk.vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &ci, NULL,
                                                      &ctx->pipes[p]));
        ctx->vk.vkDestroyShaderModule(ctx->device, module, NULL);
        module = VK_NULL_HANDLE;
        free(code);
        code = NULL;
    }
cleanup:
    if (module) ctx->vk.vkDestroyShaderModule(ctx->device, module, NULL);
    free(code);
    return r;
}

/* The device, its queue, pipelines and the recorder's objects. */
static pgt_result vk_open_device(pgt_vk *ctx, uint32_t device, uint32_t api, pgt_error *err) {
    pgt_result r = PGT_OK;
    VkPhysicalDevice *devs = NULL;
    uint32_t n = 0, ts_bits = 0;
    PGT_VK_TRY(vk_compute_devices(&ctx->vk, ctx->instance, &devs, &n, err));
    if (device >= n) {
        r = pgt_error_set(
            err, PGT_ERROR_INVALID_ARGUMENT,
            "vulkan: no device %u (%u device%s with a compute queue; see pgt devices)", device, n,
            n == 1 ? "" : "s");
        goto cleanup;
    }
    ctx->phys = devs[device];
    pgt_gpu_device_info info;
    VkDriverId driver;
    vk_describe(&ctx->vk, ctx->phys, api, &info, &driver);
    snprintf(ctx->name, sizeof(ctx->name), "%s / %s", info.platform, info.name);

    VkPhysicalDeviceProperties props;
    ctx->vk.vkGetPhysicalDeviceProperties(ctx->phys, &props);
    if (props.apiVersion < VK_API_VERSION_1_1 || api < VK_API_VERSION_1_1 ||
        !ctx->vk.vkGetPhysicalDeviceProperties2) {
        r = pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                          "vulkan: %s: Vulkan 1.1 needed (device %u.%u, loader %u.%u)", ctx->name,
                          VK_API_VERSION_MAJOR(props.apiVersion),
                          VK_API_VERSION_MINOR(props.apiVersion), VK_API_VERSION_MAJOR(api),
                          VK_API_VERSION_MINOR(api));
        goto cleanup;
    }
    VkPhysicalDeviceMaintenance3Properties m3 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &m3;
    ctx->vk.vkGetPhysicalDeviceProperties2(ctx->phys, &p2);
    const VkPhysicalDeviceLimits *lim = &props.limits;
    if (lim->maxPerStageDescriptorStorageBuffers < PGT_VK_S3_BINDINGS ||
        lim->maxDescriptorSetStorageBuffers < PGT_VK_S3_BINDINGS ||
        lim->maxPushConstantsSize < sizeof(pgt_vk_s3_push) ||
        lim->maxComputeWorkGroupSize[0] < PGT_S3_GROUP_SIZE ||
        lim->maxComputeWorkGroupInvocations < PGT_S3_GROUP_SIZE) {
        r = pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                          "vulkan: %s: needs %u storage buffers per stage (has %u), %u bytes of "
                          "push constants (has %u), work-groups of %u (has %u)",
                          ctx->name, PGT_VK_S3_BINDINGS, lim->maxPerStageDescriptorStorageBuffers,
                          (unsigned)sizeof(pgt_vk_s3_push), lim->maxPushConstantsSize,
                          PGT_S3_GROUP_SIZE, lim->maxComputeWorkGroupSize[0]);
        goto cleanup;
    }
    ctx->device_binding = lim->maxStorageBufferRange;
    ctx->binding_align =
        lim->minStorageBufferOffsetAlignment < 4 ? 4 : lim->minStorageBufferOffsetAlignment;
    ctx->max_binding = vk_binding_override(ctx->device_binding, ctx->binding_align);
    ctx->max_allocation = m3.maxMemoryAllocationSize;
    /* PGT_VK_MAX_GROUPS: tests the dispatches cut in ranges on small inputs */
    ctx->max_groups =
        (uint32_t)vk_env_limit("PGT_VK_MAX_GROUPS", lim->maxComputeWorkGroupCount[0], 1);
    /* lavapipe's loop limit (s3_vk_layout.h); PGT_VK_S3_WALK lowers the bound for tests */
    ctx->s3_walk = (uint32_t)vk_env_limit(
        "PGT_VK_S3_WALK",
        driver == VK_DRIVER_ID_MESA_LLVMPIPE ? PGT_VK_S3_WALK_LAVAPIPE : PGT_VK_S3_WALK_NONE, 1);
    ctx->timestamp_ns = lim->timestampPeriod;
    ctx->vk.vkGetPhysicalDeviceMemoryProperties(ctx->phys, &ctx->memory);
    ctx->queue_family = vk_compute_family(&ctx->vk, ctx->phys, &ts_bits);
    ctx->timestamp_mask = ts_bits == 0    ? 0
                          : ts_bits >= 64 ? ~(uint64_t)0
                                          : ((uint64_t)1 << ts_bits) - 1;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = ctx->queue_family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo di = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    PGT_VK_CHECK(ctx->vk.vkCreateDevice(ctx->phys, &di, NULL, &ctx->device));
    PGT_VK_TRY(vk_load_device(&ctx->vk, ctx->device, err));
    ctx->vk.vkGetDeviceQueue(ctx->device, ctx->queue_family, 0, &ctx->queue);

    PGT_VK_TRY(vk_create_pipelines(ctx, err));

    VkCommandPoolCreateInfo cp = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    cp.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    cp.queueFamilyIndex = ctx->queue_family;
    PGT_VK_CHECK(ctx->vk.vkCreateCommandPool(ctx->device, &cp, NULL, &ctx->cmd_pool));
    VkCommandBufferAllocateInfo ca = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ca.commandPool = ctx->cmd_pool;
    ca.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ca.commandBufferCount = 1;
    PGT_VK_CHECK(ctx->vk.vkAllocateCommandBuffers(ctx->device, &ca, &ctx->cmd));
    VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    PGT_VK_CHECK(ctx->vk.vkCreateFence(ctx->device, &fi, NULL, &ctx->fence));
    VkDescriptorPoolSize ps = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                               PGT_VK_BATCH * PGT_VK_S3_BINDINGS};
    VkDescriptorPoolCreateInfo dp = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dp.maxSets = PGT_VK_BATCH;
    dp.poolSizeCount = 1;
    dp.pPoolSizes = &ps;
    PGT_VK_CHECK(ctx->vk.vkCreateDescriptorPool(ctx->device, &dp, NULL, &ctx->desc_pool));
    if (ctx->profile && ctx->timestamp_mask) {
        VkQueryPoolCreateInfo qp = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qp.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qp.queryCount = 2 * PGT_VK_BATCH;
        PGT_VK_CHECK(ctx->vk.vkCreateQueryPool(ctx->device, &qp, NULL, &ctx->queries));
    }
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &ctx->dummy, 16, "the dummy binding", err));
cleanup:
    free(devs);
    return r;
}

pgt_result pgt_vk_create(pgt_vk **out, uint32_t device, pgt_gpu_profile *profile, int validation,
                         pgt_error *err) {
    pgt_result r = PGT_OK;
    uint32_t api = 0;
    VkResult vr;
    if (!out) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "vulkan: no output handle");
    *out = NULL;
    pgt_vk *ctx = calloc(1, sizeof(*ctx));
    if (!ctx) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "vulkan: out of memory");
    const char *env = getenv("PGT_VK_VALIDATION");
    if (env && *env && strcmp(env, "0") != 0) validation = 1;
    ctx->validation = validation != 0;
    ctx->profile = profile;
    pgt_vk_call_begin(ctx);
    PGT_VK_TRY(vk_open_loader(&ctx->vk, err));
    PGT_VK_TRY(
        vk_create_instance(&ctx->vk, ctx->validation ? ctx : NULL, &ctx->instance, &api, &vr, err));
    PGT_VK_TRY(vk_open_device(ctx, device, api, err));
cleanup:
    r = pgt_vk_call_end(ctx, "pgt_vk_create", r, err);
    if (r != PGT_OK) {
        pgt_vk_destroy(ctx);
        return r;
    }
    *out = ctx;
    return PGT_OK;
}

void pgt_vk_destroy(pgt_vk *ctx) {
    if (!ctx) return;
    const pgt_vk_fns *vk = &ctx->vk;
    if (ctx->device) {
        vk->vkDeviceWaitIdle(ctx->device);
        for (uint32_t i = 0; i < ctx->garbage_count; ++i) pgt_vk_buf_destroy(ctx, &ctx->garbage[i]);
        pgt_vk_buf_destroy(ctx, &ctx->dummy);
        if (ctx->queries) vk->vkDestroyQueryPool(ctx->device, ctx->queries, NULL);
        if (ctx->desc_pool) vk->vkDestroyDescriptorPool(ctx->device, ctx->desc_pool, NULL);
        if (ctx->fence) vk->vkDestroyFence(ctx->device, ctx->fence, NULL);
        if (ctx->cmd_pool) vk->vkDestroyCommandPool(ctx->device, ctx->cmd_pool, NULL);
        for (uint32_t p = 0; p < PGT_VK_PIPE_COUNT; ++p)
            if (ctx->pipes[p]) vk->vkDestroyPipeline(ctx->device, ctx->pipes[p], NULL);
        if (ctx->pipe_layout) vk->vkDestroyPipelineLayout(ctx->device, ctx->pipe_layout, NULL);
        if (ctx->set_layout) vk->vkDestroyDescriptorSetLayout(ctx->device, ctx->set_layout, NULL);
        vk->vkDestroyDevice(ctx->device, NULL);
    }
    free(ctx->garbage);
    if (ctx->messenger) vk->vkDestroyDebugUtilsMessengerEXT(ctx->instance, ctx->messenger, NULL);
    if (ctx->instance) vk->vkDestroyInstance(ctx->instance, NULL);
    vk_close_loader(&ctx->vk);
    free(ctx);
}

const char *pgt_vk_device_name(const pgt_vk *ctx) { return ctx ? ctx->name : ""; }

uint32_t pgt_vk_validation_messages(const pgt_vk *ctx) { return ctx ? ctx->messages : 0; }
