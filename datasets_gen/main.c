/* pgt_datasets: writes the default generated datasets (gen.h) to a folder.
 *
 * Exit codes: 0 done, 1 a file could not be generated or written, 2 bad command line. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <pgt/mesh_io.h>

#include "facade_quads.h"
#include "facade_scene.h"
#include "gen.h"

/* The grammar of `pgt_datasets city` when --grammar is not given. */
#define CITY_DEFAULT_GRAMMAR PGT_SOURCE_DIR "/grammars/facade.grammar"

static const char usage[] =
    "usage: pgt_datasets OUT_DIR [--only NAME] [--format off|ply|obj] [--list]\n"
    "       pgt_datasets city N SEED -o FILE.scene [--grammar FILE]\n"
    "       pgt_datasets tower -o FILE.obj [AX AZ HEIGHT TWIST SEGMENTS ROWS]\n"
    "\n"
    "Writes every default generated dataset (or one) to OUT_DIR/NAME.EXT, creating OUT_DIR\n"
    "(and its parents) when missing, and prints one line per file: name, V, F, path.\n"
    "\n"
    "  --only NAME     write only the dataset NAME (see --list)\n"
    "  --format FMT    off (default), ply or obj. OFF keeps positions and triangles only, so\n"
    "                  with off a dataset with UVs (cube_sphere_8, grid_16x16) is also\n"
    "                  written as .obj;\n"
    "                  obj keeps per-corner UVs; ply (binary) keeps UVs and face labels.\n"
    "  --list          print the dataset names with V and F and write nothing (OUT_DIR is\n"
    "                  then optional)\n"
    "  --help          this text\n"
    "\n"
    "city N SEED: the facade city of paper 003 (pgt_gen_city: N buildings, 1 to 4194304, on a\n"
    "grid of lots, from SEED) as a facade scene file (harness/README.md) at FILE.scene, with\n"
    "the grammar FILE (default grammars/facade.grammar, written relative to the scene's\n"
    "folder). pgt facade --scene FILE.scene renders it. (An OUT_DIR called city: ./city.)\n"
    "\n"
    "tower: a non-box building for facades on generic meshes (paper 003 sec. 10;\n"
    "pgt_gen_tower): a twisted elliptic tower of quads, semi-axes AX and AZ, HEIGHT metres,\n"
    "turned by TWIST degrees bottom to top, SEGMENTS quads around and ROWS up (default 14 9 42\n"
    "45 32 12), as an OBJ of quads with UVs in metres (u around, v up) and normals. pgt facade\n"
    "--mesh FILE.obj renders it. (An OUT_DIR called tower: ./tower.)\n"
    "\n"
    "Exit status: 0 on success, 1 when a dataset cannot be generated or written, 2 on a bad\n"
    "command line, a city's or tower's -o that cannot be written (checked before generating) or\n"
    "a city's grammar that cannot be read or compiled.\n";

/* Before generating: 0 when out can be written as far as can be told now (pgt_output_check),
 * else one line "pgt_datasets: VERB: cannot write OUT: why" and exit status 2, as pgt's verbs
 * (a city of millions of buildings does not end on a typo in -o). */
static int check_output(const char *verb, const char *out) {
    char why[128];
    if (!pgt_output_check(out, why, sizeof why)) return 0;
    fprintf(stderr, "pgt_datasets: %s: cannot write %s: %s\n", verb, out, why);
    return 2;
}

/* One line on stderr, naming the flag or value; exit status 2. */
static int bad_usage(const char *fmt, const char *arg) {
    fputs("pgt_datasets: ", stderr);
    fprintf(stderr, fmt, arg);
    fputs(strstr(fmt, "--list") ? "\n" : " (see --help)\n", stderr);
    return 2;
}

/* mkdir -p: creates every missing folder of path. Returns 0 or an errno value. */
static int make_dirs(const char *path) {
    size_t len = strlen(path);
    char *buf = malloc(len + 1);
    if (!buf) return ENOMEM;
    memcpy(buf, path, len + 1);
    int rc = 0;
    for (size_t i = 1; i <= len && rc == 0; ++i) {
        if (buf[i] != '/' && buf[i] != '\0') continue;
        char saved = buf[i];
        buf[i] = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST) rc = errno;
        buf[i] = saved;
    }
    struct stat st;
    if (rc == 0 && (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))) rc = ENOTDIR;
    free(buf);
    return rc;
}

static int write_one(const pgt_mesh *mesh, const char *name, const char *dir,
                     pgt_mesh_format format, const char *ext) {
    size_t size = strlen(dir) + strlen(name) + strlen(ext) + 3;
    char *path = malloc(size);
    if (!path) {
        fprintf(stderr, "pgt_datasets: out of memory\n");
        return 1;
    }
    snprintf(path, size, "%s/%s.%s", dir, name, ext);
    pgt_mesh_write_options opts;
    memset(&opts, 0, sizeof(opts));
    opts.format = format;
    pgt_error err;
    pgt_error_clear(&err);
    int rc = 0;
    if (pgt_mesh_write(mesh, path, &opts, &err) != PGT_OK) {
        fprintf(stderr, "pgt_datasets: %s: %s\n", path, err.message);
        rc = 1;
    } else {
        printf("%s %u %u %s\n", name, mesh->vertex_count, mesh->face_count, path);
    }
    free(path);
    return rc;
}

/* pgt_datasets city N SEED -o FILE.scene [--grammar FILE] */
static int city_main(int argc, char **argv) {
    const char *out = NULL, *grammar = CITY_DEFAULT_GRAMMAR;
    const char *num[2] = {NULL, NULL};
    int nums = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "-o") || !strcmp(a, "--grammar")) {
            if (i + 1 >= argc) return bad_usage("%s needs a value", a);
            if (a[1] == 'o')
                out = argv[++i];
            else
                grammar = argv[++i];
        } else if (a[0] == '-' && a[1] != '\0') {
            return bad_usage("city: unknown flag '%s'", a);
        } else if (nums == 2) {
            return bad_usage("city: unexpected argument '%s' (city N SEED -o FILE.scene)", a);
        } else {
            num[nums++] = a;
        }
    }
    if (nums < 2) return bad_usage("%s", "city: expected N and SEED (city N SEED -o FILE.scene)");
    if (!out) return bad_usage("%s", "city: no output: give -o FILE.scene");
    struct stat so, sg; /* the same existing file (pgt_cli_same_file's test; cli.c is not linked) */
    if (stat(out, &so) == 0 && stat(grammar, &sg) == 0 && so.st_dev == sg.st_dev &&
        so.st_ino == sg.st_ino)
        return bad_usage(
            "city: -o %s is the --grammar file; pgt_datasets never overwrites an input", out);
    unsigned long long v[2];
    for (int k = 0; k < 2; ++k) {
        char *end = NULL;
        errno = 0;
        v[k] = strtoull(num[k], &end, 10);
        if (num[k][0] < '0' || num[k][0] > '9' || *end || errno || v[k] > 0xFFFFFFFFull ||
            (k == 0 && (v[k] < 1 || v[k] > (1u << 22))))
            return bad_usage(k ? "city: SEED '%s' is not a whole number in [0, 4294967295]"
                               : "city: N '%s' is not a whole number in [1, 4194304]",
                             num[k]);
    }
    if (check_output("city", out)) return 2;
    pgt_facade_file f;
    pgt_error err;
    pgt_error_clear(&err);
    if (pgt_facade_file_city(&f, grammar, (uint32_t)v[0], (uint32_t)v[1], &err) != PGT_OK) {
        fprintf(stderr, "pgt_datasets: city: %s\n", err.message);
        /* the grammar (--grammar's file, or a city it cannot build) is input: 2, as pgt's */
        return err.code == PGT_ERROR_OUT_OF_MEMORY ? 1 : 2;
    }
    char comment[128];
    snprintf(comment, sizeof comment, "pgt_datasets city %llu %llu (pgt_gen_city)", v[0], v[1]);
    int rc = 0;
    if (pgt_facade_file_write(out, NULL, &f.scene, (const char *const *)f.names,
                              (const char *const *)f.paths, comment, &err) != PGT_OK) {
        fprintf(stderr, "pgt_datasets: city: %s\n", err.message);
        rc = 1;
    } else {
        printf("city %u buildings %u corners %s\n", f.scene.building_count, f.scene.corner_count,
               out);
    }
    pgt_facade_file_free(&f);
    return rc;
}

/* pgt_datasets tower -o FILE.obj [AX AZ HEIGHT TWIST SEGMENTS ROWS] */
static int tower_main(int argc, char **argv) {
    const char *out = NULL;
    double v[6] = {14.0, 9.0, 42.0, 45.0, 32.0, 12.0};
    int nums = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "-o")) {
            if (i + 1 >= argc) return bad_usage("%s needs a value", a);
            out = argv[++i];
        } else if (a[0] == '-' && (a[1] < '0' || a[1] > '9') && a[1] != '.') {
            return bad_usage("tower: unknown flag '%s'", a);
        } else if (nums == 6) {
            return bad_usage("tower: unexpected argument '%s' (tower -o FILE.obj [AX AZ HEIGHT "
                             "TWIST SEGMENTS ROWS])",
                             a);
        } else {
            char *end = NULL;
            v[nums] = strtod(a, &end);
            if (end == a || *end) return bad_usage("tower: '%s' is not a number", a);
            ++nums;
        }
    }
    if (nums != 0 && nums != 6)
        return bad_usage("%s", "tower: give all of AX AZ HEIGHT TWIST SEGMENTS ROWS or none");
    if (!out) return bad_usage("%s", "tower: no output: give -o FILE.obj");
    if (!(v[4] >= 0.0 && v[4] <= 4294967295.0 && v[4] == (double)(uint32_t)v[4] && v[5] >= 0.0 &&
          v[5] <= 4294967295.0 && v[5] == (double)(uint32_t)v[5]))
        return bad_usage("%s", "tower: SEGMENTS and ROWS are whole numbers");
    if (check_output("tower", out)) return 2;
    pgt_facade_quads m;
    pgt_error err;
    pgt_error_clear(&err);
    if (pgt_gen_tower(&m, v[0], v[1], v[2], v[3], (uint32_t)v[4], (uint32_t)v[5], &err) != PGT_OK) {
        fprintf(stderr, "pgt_datasets: tower: %s\n", err.message);
        return 2;
    }
    char comment[256];
    snprintf(comment, sizeof comment, "pgt_datasets tower %g %g %g %g %u %u (pgt_gen_tower)", v[0],
             v[1], v[2], v[3], (uint32_t)v[4], (uint32_t)v[5]);
    int rc = 0;
    if (pgt_facade_quads_write_obj(&m, out, comment, &err) != PGT_OK) {
        fprintf(stderr, "pgt_datasets: tower: %s\n", err.message);
        rc = 1;
    } else {
        printf("tower %u vertices %u quads %s\n", m.vertex_count, m.quad_count, out);
    }
    pgt_facade_quads_destroy(&m);
    return rc;
}

int main(int argc, char **argv) {
    if (argc > 1 && !strcmp(argv[1], "city")) return city_main(argc, argv);
    if (argc > 1 && !strcmp(argv[1], "tower")) return tower_main(argc, argv);
    const char *out_dir = NULL, *only = NULL, *format_name = "off";
    int list = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            return 0;
        } else if (strcmp(a, "--list") == 0) {
            list = 1;
        } else if (strcmp(a, "--only") == 0 || strcmp(a, "--format") == 0) {
            if (i + 1 >= argc) return bad_usage("%s needs a value", a);
            if (a[2] == 'o')
                only = argv[++i];
            else
                format_name = argv[++i];
        } else if (strncmp(a, "--only=", 7) == 0) {
            only = a + 7;
        } else if (strncmp(a, "--format=", 9) == 0) {
            format_name = a + 9;
        } else if (a[0] == '-' && a[1] != '\0') {
            return bad_usage("unknown flag '%s'", a);
        } else if (out_dir) {
            return bad_usage("unexpected argument '%s' (one OUT_DIR only)", a);
        } else {
            out_dir = a;
        }
    }

    pgt_mesh_format format;
    if (strcmp(format_name, "off") == 0)
        format = PGT_FORMAT_OFF;
    else if (strcmp(format_name, "ply") == 0)
        format = PGT_FORMAT_PLY;
    else if (strcmp(format_name, "obj") == 0)
        format = PGT_FORMAT_OBJ;
    else
        return bad_usage("--format must be off, ply or obj, not '%s'", format_name);

    uint32_t first = 0, end = pgt_gen_default_count();
    if (only) {
        first = pgt_gen_default_find(only);
        if (first == PGT_NONE) return bad_usage("no dataset named '%s' (--list shows them)", only);
        end = first + 1;
    }
    if (!list && !out_dir) return bad_usage("%s", "missing OUT_DIR");
    if (!list) {
        int rc = make_dirs(out_dir);
        if (rc != 0) {
            fprintf(stderr, "pgt_datasets: cannot create folder '%s': %s\n", out_dir, strerror(rc));
            return 1;
        }
    }

    int status = 0;
    for (uint32_t i = first; i < end; ++i) {
        const char *name = pgt_gen_default_name(i);
        pgt_mesh mesh;
        pgt_error err;
        pgt_error_clear(&err);
        if (pgt_gen_default(i, &mesh, &err) != PGT_OK) {
            fprintf(stderr, "pgt_datasets: %s: %s\n", name, err.message);
            status = 1;
            continue;
        }
        if (list) {
            printf("%s %u %u\n", name, mesh.vertex_count, mesh.face_count);
        } else {
            status |= write_one(&mesh, name, out_dir, format, format_name);
            /* OFF drops UVs: keep them in an OBJ beside it. */
            if (format == PGT_FORMAT_OFF && mesh.uvs)
                status |= write_one(&mesh, name, out_dir, PGT_FORMAT_OBJ, "obj");
        }
        pgt_mesh_destroy(&mesh);
    }
    return status;
}
