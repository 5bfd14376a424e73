/* pgt_datasets: writes the default generated datasets (gen.h) to a folder.
 *
 * Exit codes: 0 done, 1 a file could not be generated or written, 2 bad command line. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <pgt/mesh_io.h>

#include "gen.h"

static const char usage[] =
    "usage: pgt_datasets OUT_DIR [--only NAME] [--format off|ply|obj] [--list]\n"
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
    "Exit status: 0 on success, 1 when a dataset cannot be generated or written, 2 on a bad\n"
    "command line.\n";

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

int main(int argc, char **argv) {
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
            if (a[2] == 'o') only = argv[++i];
            else format_name = argv[++i];
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
    if (strcmp(format_name, "off") == 0) format = PGT_FORMAT_OFF;
    else if (strcmp(format_name, "ply") == 0) format = PGT_FORMAT_PLY;
    else if (strcmp(format_name, "obj") == 0) format = PGT_FORMAT_OBJ;
    else return bad_usage("--format must be off, ply or obj, not '%s'", format_name);

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
            fprintf(stderr, "pgt_datasets: cannot create folder '%s': %s\n", out_dir,
                    strerror(rc));
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
