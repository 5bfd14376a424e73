/* pgt subdiv: sqrt(3) subdivision of a mesh file (ref_cpu/src/sqrt3.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "backend.h"
#include "cli.h"
#include "progress_line.h"
#include "pgt/adjacency.h"
#include "pgt/mesh_io.h"
#include "pgt/selection.h"
#include "pgt/sqrt3.h"

static const char *subdiv_usage =
    "usage: pgt subdiv IN --iters K -o OUT [--protect FILE | --group G] [--threads N]\n"
    "                  [--backend cpu|cl|vk] [--device N] [--profile] [--precise] [--json]\n"
    "\n"
    "sqrt(3) subdivision (Kobbelt 2000; paper 004 Algorithm 2): K iterations in one call, with\n"
    "Kobbelt's border rule on every second iteration of the call (as CGAL and OpenMesh).\n"
    "\n"
    "  IN             input mesh: .obj .off .ply (a consistently oriented 2-manifold, border "
    "allowed)\n"
    "  --iters K      iterations, 0 to 12 (default 1)\n"
    "  -o OUT         output mesh: .off .obj .ply (written to a temporary file, then renamed);\n"
    "                 must not be IN. PLY keeps per-face 'group' labels and per-corner UVs, OBJ\n"
    "                 keeps UVs, OFF keeps positions and triangles only.\n"
    "  --protect FILE protected faces (paper 004, 4.2.2): a file of 0-based face indices\n"
    "                 (white space or commas, # comments). They get no face point, their vertices\n"
    "                 do not move and edges next to them are not flipped.\n"
    "  --group G      smoothing group: subdivide only the faces whose PLY face property 'group'\n"
    "                 is G; every other face is protected.\n"
    "  --threads N    worker threads, 1 to 256 (default: the number of CPUs)\n"
    "  --backend B    cpu (the C reference, default), cl (OpenCL) or vk (Vulkan). The GPU\n"
    "                 backends give the reference's output element by element (pgt diff) but\n"
    "                 do not carry per-corner UVs (a note says so when the input has them).\n"
    "  --device N     device index of that API (see pgt devices; default 0; ignored by cpu)\n"
    "  --profile      print the per-kernel device times of a GPU backend (launches, total and\n"
    "                 median ms)\n"
    "  --precise      OFF/OBJ output with 17 significant digits instead of 9\n"
    "  --json         print the summary as one JSON object instead of one line\n"
    "\n"
    "Prints one summary line: input and output vertex/face counts and milliseconds (read,\n"
    "subdivide, write), and a progress line on stderr every 5 s of work (PGT_PROGRESS_SECONDS:\n"
    "the period, 0: none). Exit 0 on success, 2 on a bad flag or input.\n";

/* Where in the input file a subdivision error is: for a non-manifold edge or vertex or a
 * degenerate face, the line (binary PLY: the byte offset) of the face record the error is about,
 * found again with the reference's adjacency (only on this error path; every backend checks its
 * input with pgt_adjacency_require_manifold); for a coordinate beyond the limit, the vertex's
 * record (for a UV the record it was read from: an OBJ vt line, a PLY vertex's u v, or the face's
 * texcoord list); else the path alone. */
static const char *error_place(const pgt_mesh *in, const pgt_mesh_origin *origin, const char *path,
                               pgt_result code, char *buf, size_t size) {
    uint32_t k = 0;
    const int far = code == PGT_ERROR_LIMIT ? pgt_sqrt3_far_coordinate(in, &k, NULL) : 0;
    if (far == 1) return pgt_mesh_origin_vertex_where(origin, path, k, buf, size);
    if (far == 2) return pgt_mesh_origin_uv_where(origin, in, path, k, buf, size);
    if (code != PGT_ERROR_NON_MANIFOLD && code != PGT_ERROR_DEGENERATE) return path;
    pgt_adjacency adj;
    if (pgt_adjacency_build(&adj, in, 1, NULL) != PGT_OK) return path;
    const uint32_t f = pgt_adjacency_error_face(&adj);
    pgt_adjacency_destroy(&adj);
    return f == PGT_NONE ? path : pgt_mesh_origin_where(origin, path, f, buf, size);
}

int pgt_cmd_subdiv(int argc, char **argv) {
    const char *verb = "subdiv", *in_path = NULL, *out_path = NULL, *protect_path = NULL;
    pgt_backend_kind kind = PGT_BACKEND_CPU;
    uint32_t iters = 1, threads = pgt_cli_cpu_count(), device = 0;
    int32_t group = 0;
    int have_group = 0, json = 0, precise = 0, profile = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        int flag;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(subdiv_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--iters") || !strcmp(a, "-k")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, PGT_SQRT3_MAX_ITERATIONS, &iters))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--protect")) {
            if (!(protect_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--group")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) || pgt_cli_int(verb, a, v, &group))
                return PGT_EXIT_USAGE;
            have_group = 1;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 256, &threads))
                return PGT_EXIT_USAGE;
        } else if ((flag = pgt_backend_flags(verb, argc, argv, &i, &kind, &device)) != 0) {
            if (flag < 0) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--json")) {
            json = 1;
        } else if (!strcmp(a, "--profile")) {
            profile = 1;
        } else if (!strcmp(a, "--precise")) {
            precise = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt subdiv --help)", a);
        } else if (!in_path) {
            in_path = a;
        } else {
            return pgt_cli_fail(verb, "unexpected argument '%s' (one input mesh only)", a);
        }
    }
    if (!in_path) return pgt_cli_fail(verb, "no input mesh (see pgt subdiv --help)");
    if (!out_path) return pgt_cli_fail(verb, "no output: give -o OUT");
    if (protect_path && have_group)
        return pgt_cli_fail(verb, "--protect and --group exclude each other");
    if (pgt_mesh_format_from_path(out_path) == PGT_FORMAT_AUTO)
        return pgt_cli_fail(verb, "-o %s: unknown extension (use .off, .obj or .ply)", out_path);
    if (pgt_cli_same_file(in_path, out_path))
        return pgt_cli_fail(verb, "-o %s is the input file; pgt never overwrites an input",
                            out_path);
    if (protect_path && pgt_cli_same_file(protect_path, out_path))
        return pgt_cli_fail(verb, "-o %s is the --protect file; pgt never overwrites an input",
                            out_path);
    if (pgt_cli_check_outputs(verb, &out_path, 1)) return PGT_EXIT_USAGE;

    pgt_error err = {0};
    pgt_mesh in = {0}, out = {0};
    pgt_mesh_origin origin = {0};
    uint8_t *prot = NULL;
    int rc = PGT_EXIT_USAGE;
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    if (pgt_cli_progress_start(&prog, verb)) return PGT_EXIT_USAGE;
    pgt_cli_progress_stagef(prog.progress, "opening the %s backend", pgt_backend_kind_name(kind));
    pgt_backend backend;
    if (pgt_backend_open(&backend, kind, device, profile, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        pgt_cli_progress_stop(&prog);
        return PGT_EXIT_USAGE;
    }
    pgt_cli_progress_stagef(prog.progress, "reading %s", in_path);
    double t0 = pgt_cli_now_ms();
    const pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 0, &origin};
    if (pgt_mesh_read(&in, in_path, &ro, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    double t1 = pgt_cli_now_ms();
    uint32_t selected = 0;
    if (protect_path || have_group) {
        prot = malloc((size_t)in.face_count + 1);
        if (!prot) {
            pgt_cli_fail(verb, "out of memory");
            goto done;
        }
        if (protect_path) {
            if (pgt_selection_read(prot, in.face_count, protect_path, &selected, &err) != PGT_OK) {
                pgt_cli_fail(verb, "--protect %s", err.message);
                goto done;
            }
        } else {
            if (pgt_selection_from_label(prot, &in, group, &selected, &err) != PGT_OK) {
                pgt_cli_fail(verb, "--group %d: %s: %s", group, in_path, err.message);
                goto done;
            }
            if (selected == 0) {
                pgt_cli_fail(verb, "--group %d: no face of %s has that group", group, in_path);
                goto done;
            }
            for (uint32_t f = 0; f < in.face_count; ++f)
                prot[f] = !prot[f]; /* the rest is protected */
        }
    }
    pgt_sqrt3_options opts = {0};
    opts.iterations = iters;
    opts.threads = threads;
    opts.protected_faces = prot;
    opts.progress = prog.progress; /* the reference's iterations (a GPU backend: the stage) */
    pgt_cli_progress_stagef(prog.progress, "sqrt(3) on %s", pgt_backend_kind_name(kind));
    /* what the backend subdivides: a GPU backend gets the mesh without its UVs, which it would
     * drop, so that a UV it never reads (one beyond the coordinate limit) is not refused */
    pgt_mesh view = in;
    if (kind != PGT_BACKEND_CPU && in.uvs) {
        fprintf(stderr,
                "pgt subdiv: note: the %s backend does not carry UVs; %s is written "
                "without them (use --backend cpu to keep them)\n",
                pgt_backend_kind_name(kind), out_path);
        view.uvs = NULL;
    }
    if (pgt_backend_sqrt3(&backend, &out, &view, &opts, NULL, &err) != PGT_OK) {
        char place[4200];
        pgt_cli_fail(verb, "%s: %s",
                     error_place(&view, &origin, in_path, err.code, place, sizeof(place)),
                     err.message);
        goto done;
    }
    double t2 = pgt_cli_now_ms();
    pgt_cli_progress_stagef(prog.progress, "writing %s (%u vertices, %u faces)", out_path,
                            out.vertex_count, out.face_count);
    pgt_mesh_write_options wo = {PGT_FORMAT_AUTO, precise};
    if (pgt_mesh_write(&out, out_path, &wo, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    double t3 = pgt_cli_now_ms();
    if (json) {
        printf("{\"verb\":\"subdiv\",\"input\":");
        pgt_cli_json_string(stdout, in_path);
        printf(",\"output\":");
        pgt_cli_json_string(stdout, out_path);
        printf(",\"backend\":\"%s\",\"iterations\":%u,\"threads\":%u,\"vertices_in\":%u,"
               "\"faces_in\":%u,\"vertices_out\":%u,\"faces_out\":%u,\"protected_faces\":%u,"
               "\"read_ms\":%.3f,\"subdivide_ms\":%.3f,\"write_ms\":%.3f}\n",
               pgt_backend_kind_name(kind), iters, threads, in.vertex_count, in.face_count,
               out.vertex_count, out.face_count,
               protect_path ? selected
               : have_group ? in.face_count - selected
                            : 0,
               t1 - t0, t2 - t1, t3 - t2);
    } else {
        printf("subdiv: %s (%u vertices, %u faces) -> %s (%u vertices, %u faces), k=%u, %u "
               "threads, %s: %.2f ms subdivide (read %.2f ms, write %.2f ms)\n",
               in_path, in.vertex_count, in.face_count, out_path, out.vertex_count, out.face_count,
               iters, threads, pgt_backend_kind_name(kind), t2 - t1, t1 - t0, t3 - t2);
    }
    if (profile) pgt_backend_print_profile(&backend, json ? stderr : stdout);
    rc = PGT_EXIT_OK;
done:
    pgt_cli_progress_stop(&prog);
    pgt_backend_close(&backend);
    free(prot);
    pgt_mesh_destroy(&in);
    pgt_mesh_origin_destroy(&origin);
    pgt_mesh_destroy(&out);
    return rc;
}
