/* pgt devices: the OpenCL and Vulkan devices this machine offers (the N of --device N). */
#include <string.h>

#include "backend.h"
#include "cli.h"

static const char *devices_usage =
    "usage: pgt devices [--json]\n"
    "\n"
    "Lists every OpenCL device (platform by platform) and every Vulkan device with a compute\n"
    "queue, numbered per API from 0: pass the number as --device N with --backend cl or vk.\n"
    "  --json   one JSON object\n";

int pgt_cmd_devices(int argc, char **argv) {
    int json = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(devices_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(argv[i], "--json")) {
            json = 1;
        } else {
            return pgt_cli_fail("devices", "unknown argument '%s' (see pgt devices --help)",
                                argv[i]);
        }
    }
    const pgt_backend_kind kinds[2] = {PGT_BACKEND_CL, PGT_BACKEND_VK};
    const char *titles[2] = {"OpenCL", "Vulkan"};
    if (json) printf("{");
    for (int k = 0; k < 2; ++k) {
        pgt_gpu_device_list list;
        pgt_error err = {0};
        if (pgt_backend_list(kinds[k], &list, &err) != PGT_OK)
            return pgt_cli_fail("devices", "%s: %s", titles[k], err.message);
        if (json) {
            printf("%s\"%s\":[", k ? "," : "", pgt_backend_kind_name(kinds[k]));
            for (uint32_t i = 0; i < list.count; ++i) {
                const pgt_gpu_device_info *d = &list.devices[i];
                printf("%s{\"index\":%u,\"platform\":", i ? "," : "", d->index);
                pgt_cli_json_string(stdout, d->platform);
                printf(",\"name\":");
                pgt_cli_json_string(stdout, d->name);
                printf(",\"version\":");
                pgt_cli_json_string(stdout, d->version);
                printf(",\"type\":");
                pgt_cli_json_string(stdout, d->type);
                printf("}");
            }
            printf("]");
            continue;
        }
        printf("%s:%s\n", titles[k], list.count ? "" : " no device");
        for (uint32_t i = 0; i < list.count; ++i) {
            const pgt_gpu_device_info *d = &list.devices[i];
            printf("  %s %u: %s / %s (%s) %s\n", pgt_backend_kind_name(kinds[k]), d->index,
                   d->platform, d->name, d->type, d->version);
        }
    }
    if (json) printf("}\n");
    return PGT_EXIT_OK;
}
