/* pgt: the procedural-geometry testbed's command-line program. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "signal_cleanup.h"

static const char *usage =
    "usage: pgt <verb> [flags]   (pgt <verb> --help for the verb's flags)\n"
    "\n"
    "verbs:\n"
    "  subdiv     sqrt(3) subdivision of a mesh (Kobbelt 2000; paper 004), k iterations,\n"
    "             with protected faces or a smoothing group\n"
    "  bench      benchmarks that write CSV tables to results/: subdiv, atlas (Table 1),\n"
    "             march, ivy (Table 2, Fig. 11), woven, facade (pgt bench --help)\n"
    "  diff       reference vs an OpenCL or Vulkan backend, element by element (pgt diff all)\n"
    "  devices    the OpenCL and Vulkan devices (the N of --device N)\n"
    "  atlas      multi-chart geometry-image atlas with indirection pointers (paper 000, sec. 4)\n"
    "  march      marching on an atlas across charts (paper 000, sec. 5)\n"
    "  grammar    compile a grammar (ivy, facades) and list its rule table (paper 000, sec. 7)\n"
    "  ivy        grow ivy on a mesh: grammar, marching, G1 Bezier, bark and leaves\n"
    "             (paper 000, sec. 6-8), with masks and painted strokes\n"
    "  render     ray trace meshes into a PNG for figures (Embree)\n"
    "  woven      the woven-sphere reference model (paper 002, App. A), animated and timed\n"
    "  facade     per-pixel procedural facades of a city (paper 003), with the explicit twin\n"
    "             and the Embree cross-check\n"
    "\n"
    "global flags:\n"
    "  --help, -h     this text\n"
    "  --version      the version\n"
    "\n"
    "subdiv, march and diff take --backend cpu|cl|vk and --device N, bench subdiv and bench\n"
    "march --backends cl|vk|both|none and --device N: sqrt(3) and marching have OpenCL and\n"
    "Vulkan versions (diff sqrt3, diff march); the other algorithms run on the CPU reference\n"
    "only.\n"
    "\n"
    "Exit codes: 0 success, 1 the work ran and found a problem, 2 bad flag, value or input.\n"
    "Meshes: OBJ, OFF, PLY (ascii or binary little-endian) in; OFF, OBJ, binary PLY out.\n";

int main(int argc, char **argv) {
    /* a run stopped by Ctrl-C, kill or timeout removes its temporary outputs (signal_cleanup.h);
     * without the thread it stops as before */
    (void)pgt_cli_signals_start();
    if (argc < 2) {
        fputs(usage, stderr);
        return PGT_EXIT_USAGE;
    }
    const char *verb = argv[1];
    if (!strcmp(verb, "--help") || !strcmp(verb, "-h") || !strcmp(verb, "help")) {
        fputs(usage, stdout);
        return PGT_EXIT_OK;
    }
    if (!strcmp(verb, "--version")) {
        printf("pgt 0.1.0\n");
        return PGT_EXIT_OK;
    }
    if (!strcmp(verb, "subdiv")) return pgt_cmd_subdiv(argc - 1, argv + 1);
    if (!strcmp(verb, "bench")) return pgt_cmd_bench(argc - 1, argv + 1);
    if (!strcmp(verb, "diff")) return pgt_cmd_diff(argc - 1, argv + 1);
    if (!strcmp(verb, "devices")) return pgt_cmd_devices(argc - 1, argv + 1);
    if (!strcmp(verb, "atlas")) return pgt_cmd_atlas(argc - 1, argv + 1);
    if (!strcmp(verb, "march")) return pgt_cmd_march(argc - 1, argv + 1);
    if (!strcmp(verb, "grammar")) return pgt_cmd_grammar(argc - 1, argv + 1);
    if (!strcmp(verb, "ivy")) return pgt_cmd_ivy(argc - 1, argv + 1);
    if (!strcmp(verb, "render")) return pgt_cmd_render(argc - 1, argv + 1);
    if (!strcmp(verb, "woven")) return pgt_cmd_woven(argc - 1, argv + 1);
    if (!strcmp(verb, "facade")) return pgt_cmd_facade(argc - 1, argv + 1);
    fprintf(stderr, "pgt: unknown verb '%s' (see pgt --help)\n", verb);
    return PGT_EXIT_USAGE;
}
