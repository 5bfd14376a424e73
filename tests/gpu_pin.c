/* Test helper for the Sanitize build: LD_PRELOADed into `pgt` by the diff_cl / diff_vk tests, it
 * keeps the GPU driver libraries loaded until exit (RTLD_NODELETE). The Vulkan loader unloads
 * lavapipe and the validation layer when an instance is destroyed; memory those libraries never
 * free is then reported by LeakSanitizer with "<unknown module>" frames that no suppression can
 * name. Pinned, their frames keep their module names and tests/lsan.supp suppresses exactly
 * them, so every leak of pgt's own host code is still reported. A library that is not installed
 * is skipped. */
#include <dlfcn.h>

static const char *const pinned[] = {"libvulkan.so.1", "libvulkan_lvp.so",
                                     "libVkLayer_khronos_validation.so", "libOpenCL.so.1",
                                     "libpocl.so.2"};

__attribute__((constructor)) static void pgt_pin_gpu_libraries(void) {
    for (unsigned i = 0; i < sizeof pinned / sizeof *pinned; ++i)
        dlopen(pinned[i], RTLD_NOW | RTLD_NODELETE);
}
