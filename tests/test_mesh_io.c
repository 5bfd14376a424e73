/* pgt tests: mesh file reading and writing (ref_cpu/src/mesh_io*.c).
 *
 * The malformed corpus (tests/data/malformed, listed with expected codes in its MANIFEST), every
 * truncation of small valid files, random and mutated bytes (for ASan/UBSan), round trips
 * through all three writers, fan triangulation with UVs, PLY groups and skipped properties, the
 * real meshes of ../shared/datasets/meshes (counts from its SOURCES.md), and atomic writes. */
#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <pgt/mesh_io.h>
#include <pgt/result.h>

#include "test_scratch.h"
#include "test_util.h"

/* ---- helpers ---- */

static const pgt_mesh_read_options quiet_opts = {PGT_FORMAT_AUTO, 1, NULL};

static int mesh_is_zero(const pgt_mesh *m) {
    static const pgt_mesh zero;
    return memcmp(m, &zero, sizeof(zero)) == 0;
}

/* "NAME:<digits>:" somewhere in the message. */
static int has_line_location(const char *msg, const char *name) {
    for (const char *p = strstr(msg, name); p; p = strstr(p + 1, name)) {
        const char *q = p + strlen(name);
        if (*q++ != ':') continue;
        const char *d = q;
        while (*q >= '0' && *q <= '9') q++;
        if (q > d && *q == ':') return 1;
    }
    return 0;
}

static int has_offset_location(const char *msg, const char *name) {
    const char *p = strstr(msg, name);
    return p && strncmp(p + strlen(name), ": byte offset ", 14) == 0;
}

/* Reads from memory with garbage in *out first, so that "zeroed on failure" is really tested. */
static pgt_result read_mem(pgt_mesh *out, const void *data, size_t size, const char *name,
                           pgt_error *err) {
    memset(out, 0xAB, sizeof(*out));
    pgt_error_clear(err);
    return pgt_mesh_read_memory(out, data, size, name, &quiet_opts, err);
}

/* After a successful read, the mesh must satisfy the contract. */
static int mesh_is_valid(const pgt_mesh *m) {
    if (m->face_count == 0 || !m->positions || !m->indices) return 0;
    for (size_t i = 0; i < (size_t)m->vertex_count * 3; ++i)
        if (!isfinite(m->positions[i])) return 0;
    for (size_t i = 0; i < (size_t)m->face_count * 3; ++i)
        if (m->indices[i] >= m->vertex_count) return 0;
    if (m->uvs)
        for (size_t i = 0; i < (size_t)m->face_count * 6; ++i)
            if (!isfinite(m->uvs[i])) return 0;
    return 1;
}

static uint64_t rng_state;
static uint32_t rnd(void) {
    /* splitmix64: the tests need reproducible bytes, not quality */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (uint32_t)((z ^ (z >> 31)) >> 32);
}

/* A float from random bits: every exponent, denormals included; non-finite patterns become 0.5. */
static float rnd_float(void) {
    uint32_t u = rnd();
    float f;
    memcpy(&f, &u, sizeof(f));
    return isfinite(f) ? f : 0.5f;
}

static int same_bits(const void *a, const void *b, size_t bytes) {
    return (a == NULL && b == NULL) || (a && b && memcmp(a, b, bytes) == 0);
}

static void scratch_make(void) { scratch_make_for("mesh_io"); }

/* stderr captured into a temporary file, to count the notes a read prints. */
static int saved_stderr = -1;
static FILE *captured;
static void capture_begin(void) {
    fflush(stderr);
    captured = tmpfile();
    saved_stderr = dup(2);
    dup2(fileno(captured), 2);
}
static char *capture_end(void) {
    fflush(stderr);
    dup2(saved_stderr, 2);
    close(saved_stderr);
    long n = ftell(captured);
    char *text = calloc((size_t)(n > 0 ? n : 0) + 1, 1);
    rewind(captured);
    if (n > 0 && fread(text, 1, (size_t)n, captured) != (size_t)n) text[0] = '\0';
    fclose(captured);
    return text;
}
static int count_lines_with(const char *text, const char *needle) {
    int n = 0;
    for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle)) n++;
    return n;
}

/* ---- the malformed corpus ---- */

static void test_malformed_corpus(void) {
    char path[512];
    snprintf(path, sizeof(path), "%s/malformed/MANIFEST", PGT_TEST_DATA_DIR);
    FILE *f = fopen(path, "r");
    REQUIRE(f != NULL);
    char line[512], fname[256], code[64];
    int files = 0;
    while (fgets(line, sizeof(line), f)) {
        if (line[0] == '#' || line[0] == '\n') continue;
        REQUIRE(sscanf(line, "%255s %63s", fname, code) == 2);
        files++;
        snprintf(path, sizeof(path), "%s/malformed/%s", PGT_TEST_DATA_DIR, fname);
        pgt_mesh m;
        pgt_error err;
        memset(&m, 0xAB, sizeof(m));
        pgt_error_clear(&err);
        pgt_result r = pgt_mesh_read(&m, path, &quiet_opts, &err);
        CHECK_MSG(strcmp(pgt_result_name(r), code) == 0, "%s: got %s, expected %s (%s)", fname,
                  pgt_result_name(r), code, err.message);
        CHECK_MSG(err.code == r, "%s: err.code %d", fname, (int)err.code);
        CHECK_MSG(mesh_is_zero(&m), "%s: output mesh not zeroed", fname);
        CHECK_MSG(err.message[0] != '\0' && strstr(err.message, fname), "%s: message '%s'", fname,
                  err.message);
        /* Text formats (and the PLY header) name a line; binary PLY data a byte offset. */
        int ply = strstr(fname, ".ply") != NULL;
        CHECK_MSG(has_line_location(err.message, path) ||
                      (ply && has_offset_location(err.message, path)),
                  "%s: no location in '%s'", fname, err.message);
        /* The memory reader shares the code path: same code. */
        size_t size = 0;
        char *data = load_file(path, &size);
        REQUIRE(data != NULL);
        pgt_result r2 = read_mem(&m, data, size, fname, &err);
        CHECK_MSG(r2 == r, "%s: memory read gave %s", fname, pgt_result_name(r2));
        CHECK(mesh_is_zero(&m));
        free(data);
    }
    fclose(f);
    CHECK(files >= 40);

    /* Every corpus file is in the manifest. */
    snprintf(path, sizeof(path), "%s/malformed", PGT_TEST_DATA_DIR);
    DIR *d = opendir(path);
    REQUIRE(d != NULL);
    int on_disk = 0;
    for (struct dirent *e; (e = readdir(d));) {
        const char *dot = strrchr(e->d_name, '.');
        if (dot && (!strcmp(dot, ".obj") || !strcmp(dot, ".off") || !strcmp(dot, ".ply")))
            on_disk++;
    }
    closedir(d);
    CHECK_MSG(on_disk == files, "%d mesh files on disk, %d in MANIFEST", on_disk, files);
}

/* ---- truncation and garbage ---- */

/* A binary PLY with skipped vertex/face properties, a group, texcoords, a quad and an extra
 * element: the bytes of groups_extra.ply in binary. */
static size_t put(unsigned char *p, const void *v, size_t n) {
    /* The tests run on little-endian hosts only (x86-64, arm64), like the GPUs they compare. */
    memcpy(p, v, n);
    return n;
}
static size_t build_binary_ply(unsigned char buf[2048]) {
    static const char header[] =
        "ply\r\nformat binary_little_endian 1.0\ncomment groups, texcoords, skipped things\n"
        "element vertex 5\nproperty float x\nproperty float nx\nproperty double y\n"
        "property float z\nproperty uchar red\n"
        "element face 2\nproperty uchar red\nproperty list uchar int vertex_indices\n"
        "property int group\nproperty list uchar float texcoord\n"
        "property list ushort short junk\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    static const float xz[5][2] = {{0, 0}, {1, 0}, {1, 0}, {0, 0}, {0.5f, 0}};
    static const double y[5] = {0, 0, 1, 1, 2};
    size_t n = put(buf, header, sizeof(header) - 1);
    for (int v = 0; v < 5; ++v) {
        float nx = 9;
        unsigned char red = v == 4 ? 7 : 255;
        n += put(buf + n, &xz[v][0], 4);
        n += put(buf + n, &nx, 4);
        n += put(buf + n, &y[v], 8);
        n += put(buf + n, &xz[v][1], 4);
        n += put(buf + n, &red, 1);
    }
    {
        unsigned char red = 10, cnt = 3, tcnt = 6;
        int32_t idx[3] = {0, 1, 2}, group = -5;
        float tc[6] = {0, 0, 1, 0, 1, 1};
        uint16_t jcnt = 2;
        int16_t junk[2] = {7, 8};
        n += put(buf + n, &red, 1);
        n += put(buf + n, &cnt, 1);
        n += put(buf + n, idx, sizeof(idx));
        n += put(buf + n, &group, 4);
        n += put(buf + n, &tcnt, 1);
        n += put(buf + n, tc, sizeof(tc));
        n += put(buf + n, &jcnt, 2);
        n += put(buf + n, junk, sizeof(junk));
    }
    {
        unsigned char red = 20, cnt = 4, tcnt = 8;
        int32_t idx[4] = {0, 2, 3, 4}, group = 7;
        float tc[8] = {0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 0.875f, 1};
        uint16_t jcnt = 0;
        n += put(buf + n, &red, 1);
        n += put(buf + n, &cnt, 1);
        n += put(buf + n, idx, sizeof(idx));
        n += put(buf + n, &group, 4);
        n += put(buf + n, &tcnt, 1);
        n += put(buf + n, tc, sizeof(tc));
        n += put(buf + n, &jcnt, 2);
    }
    int32_t edge[2] = {0, 1};
    n += put(buf + n, edge, sizeof(edge));
    return n;
}

static void truncations(const char *data, size_t size, const char *name) {
    pgt_mesh m;
    pgt_error err;
    for (size_t len = 0; len < size; ++len) {
        /* A heap copy of exactly len bytes, so ASan sees any read past the end. */
        char *copy = malloc(len ? len : 1);
        memcpy(copy, data, len);
        pgt_result r = read_mem(&m, copy, len, name, &err);
        CHECK_MSG(r != PGT_OK, "%s: prefix of %zu of %zu bytes was accepted", name, len, size);
        CHECK_MSG(mesh_is_zero(&m), "%s: prefix %zu: mesh not zeroed", name, len);
        CHECK_MSG(err.message[0] != '\0', "%s: prefix %zu: no message", name, len);
        pgt_mesh_destroy(&m);
        free(copy);
    }
    char *copy = malloc(size);
    memcpy(copy, data, size);
    CHECK_MSG(read_mem(&m, copy, size, name, &err) == PGT_OK, "%s: %s", name, err.message);
    pgt_mesh_destroy(&m);
    free(copy);
}

static void test_truncated_binary_ply(void) {
    unsigned char buf[2048];
    size_t n = build_binary_ply(buf);
    truncations((const char *)buf, n, "groups.ply");
}

static void test_truncated_off(void) {
    static const char off[] = "OFF\n# a comment\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 2 0\n"
                              "3 0 1 2\n4 0 2 3 4 255 0 0\n";
    truncations(off, sizeof(off) - 1, "small.off");
}

static void test_truncated_ascii_ply(void) {
    size_t size = 0;
    char *data = load_file(PGT_TEST_DATA_DIR "/valid/groups_extra.ply", &size);
    REQUIRE(data != NULL);
    truncations(data, size, "groups_extra.ply");
    free(data);
}

/* Random bytes and valid files with random bytes changed: any result, never a crash, and a
 * success is a valid mesh. */
static void test_garbage_and_mutations(void) {
    static const char *const names[] = {"g.obj", "g.off", "g.ply"};
    unsigned char buf[4096];
    pgt_mesh m;
    pgt_error err;
    rng_state = 42;
    for (int i = 0; i < 600; ++i) {
        size_t len = rnd() % 300;
        for (size_t k = 0; k < len; ++k) buf[k] = (unsigned char)rnd();
        if (i % 3 == 2 && len >= 4) memcpy(buf, "ply\n", 4);
        pgt_result r = read_mem(&m, buf, len, names[i % 3], &err);
        CHECK(r != PGT_OK && mesh_is_zero(&m));
    }
    /* Mutations of the binary PLY and the small valid text files. */
    size_t sizes[4];
    char *files[4];
    const char *fnames[4] = {"m.ply", "m.off", "m.obj", "m.ply"};
    unsigned char ply[2048];
    sizes[0] = build_binary_ply(ply);
    files[0] = malloc(sizes[0]);
    memcpy(files[0], ply, sizes[0]);
    files[1] = load_file(PGT_TEST_DATA_DIR "/valid/quad_pentagon.off", &sizes[1]);
    files[2] = load_file(PGT_TEST_DATA_DIR "/valid/quad_pentagon_uv.obj", &sizes[2]);
    files[3] = load_file(PGT_TEST_DATA_DIR "/valid/groups_extra.ply", &sizes[3]);
    for (int f = 0; f < 4; ++f) {
        REQUIRE(files[f] != NULL);
        int ok = 0;
        for (int i = 0; i < 1500; ++i) {
            char *copy = malloc(sizes[f]);
            memcpy(copy, files[f], sizes[f]);
            int changes = 1 + (int)(rnd() % 3);
            for (int c = 0; c < changes; ++c) {
                size_t at = rnd() % sizes[f];
                /* Text: mostly digits, signs and separators, which reach deeper than noise. */
                static const char text_bytes[] = "0123456789-+./ \n#eEnaif";
                copy[at] = (char)(f == 0 || rnd() % 4 == 0
                                      ? rnd()
                                      : (uint32_t)text_bytes[rnd() % (sizeof(text_bytes) - 1)]);
            }
            size_t len = sizes[f] - (rnd() % 4 == 0 ? rnd() % sizes[f] : 0);
            pgt_result r = read_mem(&m, copy, len, fnames[f], &err);
            if (r == PGT_OK) {
                ok++;
                CHECK(mesh_is_valid(&m));
            } else {
                CHECK(mesh_is_zero(&m) && err.message[0] != '\0');
            }
            pgt_mesh_destroy(&m);
            free(copy);
        }
        printf("  %s: %d of 1500 mutations still read\n", fnames[f], ok);
        free(files[f]);
    }
}

/* ---- round trips ---- */

static void make_mesh(pgt_mesh *m, uint32_t nv, uint32_t nf, int uvs, int labels) {
    static const float special[] = {-0.0f,       FLT_MAX, -FLT_MAX,    FLT_MIN, 1e-40f,
                                    1.0f / 3.0f, 0.1f,    16777217.0f, -1e-45f};
    REQUIRE(pgt_mesh_create(m, nv, nf, uvs, labels, NULL) == PGT_OK);
    for (size_t i = 0; i < (size_t)nv * 3; ++i)
        m->positions[i] = i < sizeof(special) / sizeof(special[0]) ? special[i] : rnd_float();
    for (size_t i = 0; i < (size_t)nf * 3; ++i) m->indices[i] = rnd() % nv;
    m->indices[0] = m->indices[1] = 0; /* a repeated vertex is not the reader's business */
    if (uvs)
        for (size_t i = 0; i < (size_t)nf * 6; ++i) m->uvs[i] = i < 2 ? special[i] : rnd_float();
    if (labels)
        for (size_t i = 0; i < nf; ++i) m->labels[i] = i == 0 ? INT32_MIN : (int32_t)rnd();
}

static void round_trip(const pgt_mesh *src, const char *file, const pgt_mesh_write_options *wo,
                       int keeps_uvs, int keeps_labels) {
    char path[512];
    snprintf(path, sizeof(path), "%s/%s", scratch, file);
    pgt_error err;
    pgt_error_clear(&err);
    REQUIRE(pgt_mesh_write(src, path, wo, &err) == PGT_OK);
    pgt_mesh back;
    pgt_error_clear(&err);
    REQUIRE(pgt_mesh_read(&back, path, &quiet_opts, &err) == PGT_OK);
    CHECK(back.vertex_count == src->vertex_count && back.face_count == src->face_count);
    CHECK_MSG(same_bits(back.positions, src->positions, src->vertex_count * 3 * sizeof(float)),
              "%s: positions differ", file);
    CHECK_MSG(same_bits(back.indices, src->indices, src->face_count * 3 * sizeof(uint32_t)),
              "%s: indices differ", file);
    CHECK_MSG(same_bits(back.uvs, keeps_uvs ? src->uvs : NULL, src->face_count * 6 * sizeof(float)),
              "%s: uvs differ", file);
    CHECK_MSG(same_bits(back.labels, keeps_labels ? src->labels : NULL,
                        src->face_count * sizeof(int32_t)),
              "%s: labels differ", file);
    pgt_mesh_destroy(&back);
}

static void test_round_trips(void) {
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    rng_state = 7;
    const pgt_mesh_write_options plain = {PGT_FORMAT_AUTO, 0}, precise = {PGT_FORMAT_AUTO, 1};
    for (int variant = 0; variant < 4; ++variant) {
        int uvs = variant & 1, labels = variant >> 1;
        pgt_mesh m;
        make_mesh(&m, 500, 997, uvs, labels);
        round_trip(&m, "a.ply", NULL, uvs, labels);
        round_trip(&m, "a.off", &plain, 0, 0);
        round_trip(&m, "b.off", &precise, 0, 0);
        round_trip(&m, "a.obj", &plain, uvs, 0);
        round_trip(&m, "b.obj", &precise, uvs, 0);
        /* an explicit format overrides the extension */
        const pgt_mesh_write_options as_ply = {PGT_FORMAT_PLY, 0};
        char path[512];
        snprintf(path, sizeof(path), "%s/ply.dat", scratch);
        CHECK(pgt_mesh_write(&m, path, &as_ply, NULL) == PGT_OK);
        pgt_mesh back;
        const pgt_mesh_read_options read_ply = {PGT_FORMAT_PLY, 1, NULL};
        CHECK(pgt_mesh_read(&back, path, &read_ply, NULL) == PGT_OK);
        CHECK(back.face_count == m.face_count);
        pgt_mesh_destroy(&back);
        pgt_mesh_destroy(&m);
    }
    /* The valid files of tests/data/valid through every writer. */
    static const char *const valid[] = {"quad_pentagon_uv.obj", "quad_pentagon.off",
                                        "mixed_crlf.obj", "groups_extra.ply"};
    for (size_t i = 0; i < sizeof(valid) / sizeof(valid[0]); ++i) {
        char path[512];
        snprintf(path, sizeof(path), "%s/valid/%s", PGT_TEST_DATA_DIR, valid[i]);
        pgt_mesh m;
        REQUIRE(pgt_mesh_read(&m, path, &quiet_opts, NULL) == PGT_OK);
        round_trip(&m, "v.ply", NULL, 1, 1);
        round_trip(&m, "v.obj", NULL, 1, 0);
        round_trip(&m, "v.off", NULL, 0, 0);
        pgt_mesh_destroy(&m);
    }

    /* Exactly the layout the issue asks for. */
    pgt_mesh t;
    REQUIRE(pgt_mesh_create(&t, 3, 1, 0, 0, NULL) == PGT_OK);
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 0.5f, -2};
    memcpy(t.positions, pos, sizeof(pos));
    t.indices[0] = 0, t.indices[1] = 1, t.indices[2] = 2;
    char path[512];
    snprintf(path, sizeof(path), "%s/t.off", scratch);
    REQUIRE(pgt_mesh_write(&t, path, NULL, NULL) == PGT_OK);
    size_t size;
    char *text = load_file(path, &size);
    REQUIRE(text != NULL);
    static const char expect[] = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 0.5 -2\n3 0 1 2\n";
    CHECK(size == sizeof(expect) - 1 && memcmp(text, expect, size) == 0);
    free(text);
    pgt_mesh_destroy(&t);
    CHECK(scratch_count() == 10); /* no temporary files left behind */
    scratch_remove();
}

/* ---- fan triangulation and UVs ---- */

/* quad 0 1 2 3 with vt 2 3 4 1 (1-based), pentagon 4..8 with vt 5..9 */
static const uint32_t fan_indices[15] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8};
static const float fan_uvs[30] = {
    1,      0,      1,      1,      0,      1, /* quad: vt 2 3 4 */
    1,      0,      0,      1,      0,      0, /* quad: vt 2 4 1 */
    0.125f, 0.25f,  0.375f, 0.5f,   0.625f, 0.75f,  0.125f, 0.25f, 0.625f,
    0.75f,  0.875f, 1,      0.125f, 0.25f,  0.875f, 1,      0.5f,  0.5f,
};
static const float fan_positions[27] = {0, 0, 0, 1, 0,    0, 1, 1,    0, 0, 1,    0, 2, 0,
                                        0, 3, 0, 0, 3.5f, 1, 0, 2.5f, 2, 0, 1.5f, 1, 0};

static void check_fan(const char *file, int with_uvs) {
    pgt_mesh m;
    pgt_error err;
    pgt_error_clear(&err);
    const pgt_mesh_read_options loud = {PGT_FORMAT_AUTO, 0, NULL};
    capture_begin();
    pgt_result r = pgt_mesh_read(&m, file, &loud, &err);
    char *notes = capture_end();
    REQUIRE(r == PGT_OK);
    CHECK_MSG(count_lines_with(notes, "\n") == 1 &&
                  count_lines_with(notes, "fan-triangulated 2 polygons") == 1 &&
                  strstr(notes, file),
              "notes: '%s'", notes);
    free(notes);
    CHECK(m.vertex_count == 9 && m.face_count == 5);
    CHECK(memcmp(m.positions, fan_positions, sizeof(fan_positions)) == 0);
    CHECK(memcmp(m.indices, fan_indices, sizeof(fan_indices)) == 0);
    CHECK(with_uvs ? m.uvs && memcmp(m.uvs, fan_uvs, sizeof(fan_uvs)) == 0 : m.uvs == NULL);
    CHECK(m.labels == NULL);
    pgt_mesh_destroy(&m);
    /* quiet: no notes */
    capture_begin();
    r = pgt_mesh_read(&m, file, &quiet_opts, NULL);
    notes = capture_end();
    CHECK(r == PGT_OK && notes[0] == '\0');
    free(notes);
    pgt_mesh_destroy(&m);
}

static void test_fan_obj(void) { check_fan(PGT_TEST_DATA_DIR "/valid/quad_pentagon_uv.obj", 1); }
static void test_fan_off(void) { check_fan(PGT_TEST_DATA_DIR "/valid/quad_pentagon.off", 0); }

static void test_obj_forms(void) {
    /* CRLF, v//vn, negative indices, w and vertex colours, nan normals, a repeated vertex. */
    pgt_mesh m;
    pgt_error err;
    pgt_error_clear(&err);
    REQUIRE(pgt_mesh_read(&m, PGT_TEST_DATA_DIR "/valid/mixed_crlf.obj", &quiet_opts, &err) ==
            PGT_OK);
    static const uint32_t idx[9] = {0, 1, 2, 0, 1, 3, 0, 0, 1};
    CHECK(m.vertex_count == 4 && m.face_count == 3 && m.uvs == NULL);
    CHECK(memcmp(m.indices, idx, sizeof(idx)) == 0);
    CHECK(m.positions[9] == 0 && m.positions[10] == 0 && m.positions[11] == 1);
    pgt_mesh_destroy(&m);

    /* Only some faces have vt: UVs dropped with one note. */
    const pgt_mesh_read_options loud = {PGT_FORMAT_AUTO, 0, NULL};
    capture_begin();
    pgt_result r = pgt_mesh_read(&m, PGT_TEST_DATA_DIR "/valid/partial_uv.obj", &loud, &err);
    char *notes = capture_end();
    CHECK(r == PGT_OK && m.face_count == 2 && m.uvs == NULL);
    CHECK_MSG(count_lines_with(notes, "UVs dropped") == 1 && count_lines_with(notes, "\n") == 1,
              "notes: '%s'", notes);
    free(notes);
    pgt_mesh_destroy(&m);

    /* Forward references and v/vt/vn. */
    static const char fwd[] = "f 1/1/1 2/2/1 3/3/1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                              "vt 0 1\nvn 0 0 1\n";
    REQUIRE(read_mem(&m, fwd, sizeof(fwd) - 1, "fwd.obj", &err) == PGT_OK);
    CHECK(m.uvs && m.uvs[2] == 1 && m.uvs[5] == 1);
    pgt_mesh_destroy(&m);
}

/* A UTF-8 byte order mark (Windows editors) before an OBJ or OFF is read past: the same mesh as
 * without it, and errors keep the file's line numbers; before "ply" it is named in the error
 * (the format's first bytes are its magic). */
static void test_byte_order_mark(void) {
    static const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    static const char off[] = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    static const char *const texts[2] = {obj, off}, *const names[2] = {"bom.obj", "bom.off"};
    char buf[256];
    pgt_error err;
    for (int k = 0; k < 2; ++k) {
        pgt_mesh plain, marked;
        const size_t n = strlen(texts[k]);
        REQUIRE(read_mem(&plain, texts[k], n, names[k], &err) == PGT_OK);
        memcpy(buf, "\xEF\xBB\xBF", 3), memcpy(buf + 3, texts[k], n);
        CHECK_MSG(read_mem(&marked, buf, n + 3, names[k], &err) == PGT_OK, "%s", err.message);
        CHECK(marked.vertex_count == plain.vertex_count && marked.face_count == plain.face_count &&
              !memcmp(marked.positions, plain.positions, 9 * sizeof(float)) &&
              !memcmp(marked.indices, plain.indices, 3 * sizeof(uint32_t)) &&
              (k == 1 || !memcmp(marked.uvs, plain.uvs, 6 * sizeof(float))));
        pgt_mesh_destroy(&plain), pgt_mesh_destroy(&marked);
    }
    /* line 3 stays line 3; a mark that is not at the start is not skipped */
    pgt_mesh m;
    static const char bad[] = "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nq 1 2 3\n";
    CHECK(read_mem(&m, bad, sizeof bad - 1, "bad.obj", &err) != PGT_OK &&
          strstr(err.message, "bad.obj:3: ") != NULL);
    static const char inner[] = "v 0 0 0\n\xEF\xBB\xBFv 1 0 0\n";
    CHECK(read_mem(&m, inner, sizeof inner - 1, "inner.obj", &err) != PGT_OK &&
          strstr(err.message, "inner.obj:2: ") != NULL);
    static const char ply[] = "\xEF\xBB\xBFply\nformat ascii 1.0\nend_header\n";
    CHECK_MSG(read_mem(&m, ply, sizeof ply - 1, "bom.ply", &err) == PGT_ERROR_PARSE &&
                  strstr(err.message, "bom.ply:1: ") && strstr(err.message, "byte order mark"),
              "%s", err.message);
}

/* The reader's decimal fast path must give exactly strtof's float: random decimals of up to 18
 * digits, and decimals at or next to the midpoint between two floats (where rounding through
 * double could go wrong). */
static void test_numbers_match_strtof(void) {
    enum { COUNT = 60000 };
    char *text = malloc((size_t)COUNT * 40 + 64);
    float *expect = malloc(COUNT * sizeof(float));
    REQUIRE(text && expect);
    size_t len = 0;
    rng_state = 1234;
    for (int i = 0; i < COUNT; ++i) {
        char tok[40];
        int kind = (int)(rnd() % 4);
        if (kind == 0) { /* random digits with a random point */
            int digits = 1 + (int)(rnd() % 18), point = (int)(rnd() % (unsigned)(digits + 1));
            int k = 0;
            if (rnd() % 2) tok[k++] = '-';
            for (int d = 0; d < digits; ++d) {
                if (d == point && d > 0) tok[k++] = '.';
                tok[k++] = (char)('0' + rnd() % 10);
            }
            tok[k] = '\0';
        } else { /* a midpoint between a float and its neighbour, or a hair beside it */
            float f = rnd_float();
            if (fabsf(f) > 1e15f || fabsf(f) < 1e-15f) f = (float)(rnd() % 100000) * 0.37f;
            float g = nextafterf(f, INFINITY);
            double mid = ((double)f + (double)g) * 0.5;
            if (kind == 2) mid = nextafter(mid, 0.0);
            if (kind == 3) mid = nextafter(mid, INFINITY);
            if (rnd() % 2)
                snprintf(tok, sizeof(tok), "%.*g", 9 + (int)(rnd() % 9), mid);
            else
                snprintf(tok, sizeof(tok), "%.*f", (int)(rnd() % 12), mid);
        }
        expect[i] = strtof(tok, NULL);
        if (!isfinite(expect[i])) {
            snprintf(tok, sizeof(tok), "1");
            expect[i] = 1.0f;
        }
        len += (size_t)sprintf(text + len, "%s%s", i % 3 == 0 ? "v " : " ", tok);
        if (i % 3 == 2) text[len++] = '\n';
    }
    len += (size_t)sprintf(text + len, "f 1 2 3\n");
    pgt_mesh m;
    pgt_error err;
    REQUIRE(read_mem(&m, text, len, "numbers.obj", &err) == PGT_OK);
    REQUIRE(m.vertex_count == COUNT / 3);
    int bad = 0;
    for (int i = 0; i < COUNT; ++i)
        if (memcmp(&m.positions[i], &expect[i], sizeof(float)) != 0 && bad++ < 5)
            CHECK_MSG(0, "value %d: %.9g, strtof gives %.9g", i, (double)m.positions[i],
                      (double)expect[i]);
    CHECK(bad == 0);
    pgt_mesh_destroy(&m);
    free(text);
    free(expect);
}

/* Numbers longer than the readers' stack copy (PGT_IO_MAX_NUMBER, 255 bytes) are still numbers:
 * 0.5 followed by 1000 zeros is 0.5; 0.(340 zeros)123e345 is 12300; 1 followed by 400 zeros is
 * beyond float and refused as such, naming the line, in OBJ, OFF and ASCII PLY alike. */
static void test_long_numbers(void) {
    char half[1100], big[420], tiny[400];
    snprintf(half, sizeof half, "0.5%01000d", 0);
    snprintf(big, sizeof big, "1%0400d", 0);
    snprintf(tiny, sizeof tiny, "0.%0340d123e345", 0);
    REQUIRE(strlen(half) == 1003 && strlen(big) == 401 && strlen(tiny) == 349);
    static const char *const form[3][2] = {
        {"v %s %s 0\nv 1 0 0\nv 0 1 %s\nf 1 2 3\n", "long.obj"},
        {"OFF\n3 1 0\n%s %s 0\n1 0 0\n0 1 %s\n3 0 1 2\n", "long.off"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "%s %s 0\n1 0 0\n0 1 %s\n3 0 1 2\n",
         "long.ply"}};
    static const unsigned bad_line[3] = {1, 3, 10};
    char *text = malloc(4096);
    REQUIRE(text);
    for (int k = 0; k < 3; ++k) {
        pgt_mesh m;
        pgt_error err;
        int n = snprintf(text, 4096, form[k][0], half, tiny, half);
        CHECK(read_mem(&m, text, (size_t)n, form[k][1], &err) == PGT_OK);
        if (err.code == PGT_OK) {
            CHECK(m.positions[0] == 0.5f && m.positions[1] == 12300.0f && m.positions[8] == 0.5f);
            pgt_mesh_destroy(&m);
        } else {
            CHECK_MSG(0, "%s: %s", form[k][1], err.message);
        }
        n = snprintf(text, 4096, form[k][0], big, tiny, half);
        char where[32];
        snprintf(where, sizeof where, "%s:%u:", form[k][1], bad_line[k]);
        CHECK(read_mem(&m, text, (size_t)n, form[k][1], &err) == PGT_ERROR_NOT_FINITE);
        CHECK_MSG(strstr(err.message, where) && strstr(err.message, "not a finite float"), "%s",
                  err.message);
    }
    /* values read only to be skipped: an OFF face colour, a PLY property pgt does not keep */
    static const char *const skipped[2][2] = {
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 %s\n", "skip.off"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nproperty float quality\nelement face 1\nproperty list uchar int "
         "vertex_indices\nend_header\n0 0 0 %s\n1 0 0 1\n0 1 0 1\n3 0 1 2\n",
         "skip.ply"}};
    for (int k = 0; k < 2; ++k) {
        pgt_mesh m;
        pgt_error err;
        int n = snprintf(text, 4096, skipped[k][0], half);
        CHECK_MSG(read_mem(&m, text, (size_t)n, skipped[k][1], &err) == PGT_OK, "%s", err.message);
        if (err.code == PGT_OK) pgt_mesh_destroy(&m);
        n = snprintf(text, 4096, skipped[k][0], "0.5x");
        CHECK(read_mem(&m, text, (size_t)n, skipped[k][1], &err) == PGT_ERROR_PARSE);
    }
    free(text);
}

/* ---- PLY groups and skipped properties ---- */

static void check_groups_mesh(const pgt_mesh *m) {
    static const float pos[15] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 2, 0};
    static const uint32_t idx[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    static const int32_t labels[3] = {-5, 7, 7};
    static const float uvs[18] = {0,      0,     1,      0,     1,      1,
                                  0.125f, 0.25f, 0.375f, 0.5f,  0.625f, 0.75f,
                                  0.125f, 0.25f, 0.625f, 0.75f, 0.875f, 1};
    CHECK(m->vertex_count == 5 && m->face_count == 3);
    CHECK(m->positions && memcmp(m->positions, pos, sizeof(pos)) == 0);
    CHECK(m->indices && memcmp(m->indices, idx, sizeof(idx)) == 0);
    CHECK(m->labels && memcmp(m->labels, labels, sizeof(labels)) == 0);
    CHECK(m->uvs && memcmp(m->uvs, uvs, sizeof(uvs)) == 0);
}

static void test_ply_groups_ascii(void) {
    pgt_mesh m;
    pgt_error err;
    pgt_error_clear(&err);
    REQUIRE(pgt_mesh_read(&m, PGT_TEST_DATA_DIR "/valid/groups_extra.ply", &quiet_opts, &err) ==
            PGT_OK);
    check_groups_mesh(&m);
    pgt_mesh_destroy(&m);
}

/* Per-vertex texture coordinates (u v, s t, texture_u texture_v: pgt's own soups write u and
 * v) become each corner's UV when the faces carry no texcoord list; a texcoord list wins. */
static void test_ply_vertex_uvs(void) {
    static const char *const pairs[3][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
    for (int p = 0; p < 3; ++p) {
        char text[1024];
        snprintf(text, sizeof text,
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                 "property float z\nproperty float %s\nproperty double %s\nelement face 2\n"
                 "property list uchar int vertex_indices\nend_header\n0 0 0 0 0.25\n1 0 0 0.5 0\n"
                 "1 1 0 0.75 1\n0 1 0 0.125 0.875\n3 0 1 2\n3 0 2 3\n",
                 pairs[p][0], pairs[p][1]);
        pgt_mesh m;
        pgt_error err;
        const pgt_result rr = read_mem(&m, text, strlen(text), "vuv.ply", &err);
        CHECK_MSG(rr == PGT_OK, "%s", err.message);
        REQUIRE(rr == PGT_OK);
        static const uint32_t corner[6] = {0, 1, 2, 0, 2, 3};
        static const float uv[4][2] = {{0, 0.25f}, {0.5f, 0}, {0.75f, 1}, {0.125f, 0.875f}};
        REQUIRE(m.uvs != NULL && m.face_count == 2);
        int same = 1;
        for (int c = 0; c < 6; ++c) /* each corner's vertex is the file's own (no reordering) */
            same &= m.indices[c] == corner[c] && m.uvs[2 * c] == uv[corner[c]][0] &&
                    m.uvs[2 * c + 1] == uv[corner[c]][1];
        CHECK_MSG(same, "%s %s: the corners' UVs are not their vertices'", pairs[p][0],
                  pairs[p][1]);
        pgt_mesh_destroy(&m);
    }
    { /* a texcoord list wins over per-vertex u v */
        static const char text[] =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nproperty float u\nproperty float v\nelement face 1\n"
            "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
            "end_header\n0 0 0 9 9\n1 0 0 9 9\n0 1 0 9 9\n3 0 1 2 6 0 0 1 0 0 1\n";
        pgt_mesh m;
        pgt_error err;
        const pgt_result rr = read_mem(&m, text, sizeof text - 1, "both.ply", &err);
        CHECK_MSG(rr == PGT_OK, "%s", err.message);
        REQUIRE(rr == PGT_OK);
        CHECK(m.uvs != NULL && m.uvs[0] == 0.0f && m.uvs[2] == 1.0f && m.uvs[5] == 1.0f);
        pgt_mesh_destroy(&m);
    }
    { /* integer coordinates are refused, naming the property's line */
        static const char text[] =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nproperty int u\nproperty float v\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n"
            "0 1 0 0 1\n3 0 1 2\n";
        pgt_mesh m;
        pgt_error err;
        CHECK(read_mem(&m, text, sizeof text - 1, "intu.ply", &err) == PGT_ERROR_UNSUPPORTED);
        CHECK_MSG(strstr(err.message, "intu.ply:7:") && strstr(err.message, "'u' is a int"),
                  "message '%s'", err.message);
    }
}

static void test_ply_groups_binary(void) {
    unsigned char buf[2048];
    size_t n = build_binary_ply(buf);
    pgt_mesh m;
    pgt_error err;
    REQUIRE(read_mem(&m, buf, n, "groups.ply", &err) == PGT_OK);
    check_groups_mesh(&m);
    pgt_mesh_destroy(&m);
    /* vertex_index (singular), uchar/ushort counts, uint and ushort indices */
    static const char *const variants[] = {
        "property list uchar uint vertex_index", "property list ushort ushort vertex_indices",
        "property list int uchar vertex_indices", "property list char short vertex_indices"};
    static const size_t csize[] = {1, 2, 4, 1}, isize[] = {4, 2, 1, 2};
    for (int v = 0; v < 4; ++v) {
        unsigned char b[512];
        int h = snprintf((char *)b, sizeof(b),
                         "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float "
                         "x\nproperty float y\nproperty float z\nelement face 1\n%s\nend_header\n",
                         variants[v]);
        size_t k = (size_t)h;
        const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        k += put(b + k, pos, sizeof(pos));
        uint32_t three = 3;
        k += put(b + k, &three, csize[v]);
        for (uint32_t i = 0; i < 3; ++i) {
            uint32_t idx = 2 - i;
            k += put(b + k, &idx, isize[v]);
        }
        REQUIRE(read_mem(&m, b, k, "variant.ply", &err) == PGT_OK);
        CHECK(m.face_count == 1 && m.indices[0] == 2 && m.indices[1] == 1 && m.indices[2] == 0);
        pgt_mesh_destroy(&m);
    }
}

/* ---- where each face came from ---- */

/* lines[0..n) into text, each ended by '\n'; returns the length. */
static size_t join_lines(char *text, size_t size, const char *const *lines, size_t n) {
    size_t len = 0;
    for (size_t i = 0; i < n && len < size; ++i)
        len += (size_t)snprintf(text + len, size - len, "%s\n", lines[i]);
    CHECK(len < size); /* the fixture fits */
    return len < size ? len : size - 1;
}

/* Reads text (lines[0..n), each ended by '\n') with an origin and checks that triangle t names
 * the line of face record k where faces[k] = (1-based line, corners): the lines are counted
 * here as the text is built, and a polygon of c corners is c - 2 triangles in file order. */
static void check_text_origin(const char *name, const char *const *lines, size_t n,
                              const size_t (*faces)[2], size_t nf, const size_t *vertex_lines) {
    char text[1024];
    const size_t len = join_lines(text, sizeof text, lines, n);
    pgt_mesh m;
    pgt_mesh_origin o;
    memset(&o, 0xAB, sizeof(o));
    const pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, &o};
    pgt_error err = {0};
    const pgt_result r = pgt_mesh_read_memory(&m, text, len, name, &ro, &err);
    CHECK_MSG(r == PGT_OK, "%s: %s", name, err.message);
    if (r != PGT_OK) return;
    CHECK(!o.offsets && o.face_count == m.face_count);
    uint32_t t = 0;
    for (size_t k = 0; k < nf; ++k)
        for (size_t c = 2; c < faces[k][1]; ++c, ++t)
            CHECK_MSG(t < o.face_count && o.face[t] == faces[k][0], "%s: triangle %u", name, t);
    CHECK(t == m.face_count);
    char where[64];
    CHECK(strcmp(pgt_mesh_origin_where(&o, name, 0, where, sizeof(where)), name) != 0);
    char want[64];
    snprintf(want, sizeof(want), "%s:%zu", name, faces[0][0]);
    CHECK_MSG(strcmp(where, want) == 0, "%s", where);
    CHECK(o.vertex_count == m.vertex_count);
    for (uint32_t v = 0; v < m.vertex_count && v < o.vertex_count; ++v)
        CHECK_MSG(o.vertex[v] == vertex_lines[v], "%s: vertex %u at line %llu", name, v,
                  (unsigned long long)o.vertex[v]);
    snprintf(want, sizeof(want), "%s:%zu", name, vertex_lines[3]);
    CHECK_MSG(!strcmp(pgt_mesh_origin_vertex_where(&o, name, 3, where, sizeof(where)), want), "%s",
              where);
    CHECK(!strcmp(pgt_mesh_origin_vertex_where(&o, name, 4, where, sizeof(where)), name));
    pgt_mesh_origin_destroy(&o);
    CHECK(o.vertex == NULL && o.vertex_count == 0);
    pgt_mesh_destroy(&m);
}

/* Reads text (lines[0..n), each ended by '\n') with an origin and checks that every corner's UV
 * is named by the line it was read from, want[corner] (1-based, worked out by hand below). */
static void check_uv_origin(const char *name, const char *const *lines, size_t n,
                            const size_t *want, size_t corners) {
    char text[1024];
    const size_t len = join_lines(text, sizeof text, lines, n);
    pgt_mesh m;
    pgt_mesh_origin o;
    const pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, &o};
    pgt_error err = {0};
    const pgt_result r = pgt_mesh_read_memory(&m, text, len, name, &ro, &err);
    CHECK_MSG(r == PGT_OK, "%s: %s", name, err.message);
    if (r != PGT_OK) return;
    CHECK_MSG(m.uvs && 3u * m.face_count == corners, "%s: %u faces", name, m.face_count);
    for (uint32_t c = 0; c < corners && c < 3u * m.face_count; ++c) {
        char where[64], expect[64];
        snprintf(expect, sizeof expect, "%s:%zu", name, want[c]);
        pgt_mesh_origin_uv_where(&o, &m, name, c, where, sizeof where);
        CHECK_MSG(!strcmp(where, expect), "%s: corner %u: %s, want %s", name, c, where, expect);
    }
    char where[64]; /* past the faces, or no origin: the name alone */
    CHECK(!strcmp(pgt_mesh_origin_uv_where(&o, &m, name, (uint32_t)corners, where, sizeof where),
                  name));
    CHECK(!strcmp(pgt_mesh_origin_uv_where(NULL, &m, name, 0, where, sizeof where), name));
    /* keeping the vertices' places only: a UV or face is then named by the file alone */
    const uint32_t vertices = o.vertex_count;
    pgt_mesh_origin_keep_vertices(&o);
    CHECK(!strcmp(pgt_mesh_origin_uv_where(&o, &m, name, 0, where, sizeof where), name));
    CHECK(!strcmp(pgt_mesh_origin_where(&o, name, 0, where, sizeof where), name));
    CHECK(o.vertex && o.vertex_count == vertices && o.face == NULL && o.face_count == 0);
    pgt_mesh_origin_destroy(&o);
    CHECK(o.uv == NULL && o.uv_index == NULL && o.uv_count == 0 && !o.uv_of_vertex);
    pgt_mesh_destroy(&m);
}

/* The record each corner's UV comes from: an OBJ vt line (shared between faces, in any order,
 * through a fan-triangulated quad), a PLY vertex's u v (the vertex's line), a PLY face's
 * texcoord list (the face's line). */
static void test_uv_origins(void) {
    static const char *const obj[] = {
        "v 0 0 0", "v 1 0 0", "vt 0 0", "v 1 1 0",           "vt 1 0",       "# c",
        "vt 1 1",  "v 0 1 0", "vt 0 1", "f 1/1 2/2 3/3 4/4", "f 4/1 2/3 3/2"};
    /* vt 1..4 are lines 3, 5, 7, 9; the quad is (1 2 3), (1 3 4) */
    static const size_t obj_want[9] = {3, 5, 7, 3, 7, 9, 3, 7, 5};
    check_uv_origin("u.obj", obj, 11, obj_want, 9);
    static const char *const ply_vertex[] = {"ply",
                                             "format ascii 1.0",
                                             "element vertex 4",
                                             "property float x",
                                             "property float y",
                                             "property float z",
                                             "property float u",
                                             "property float v",
                                             "element face 2",
                                             "property list uchar int vertex_indices",
                                             "end_header",
                                             "0 0 0 0 0",
                                             "1 0 0 1 0",
                                             "1 1 0 1 1",
                                             "0 1 0 0 1",
                                             "4 0 1 2 3",
                                             "3 3 1 0"};
    /* vertices 0..3 on lines 12..15; triangles (0 1 2), (0 2 3), (3 1 0) */
    static const size_t ply_vertex_want[9] = {12, 13, 14, 12, 14, 15, 15, 13, 12};
    check_uv_origin("uv.ply", ply_vertex, 17, ply_vertex_want, 9);
    static const char *const ply_face[] = {"ply",
                                           "format ascii 1.0",
                                           "element vertex 3",
                                           "property float x",
                                           "property float y",
                                           "property float z",
                                           "element face 2",
                                           "property list uchar int vertex_indices",
                                           "property list uchar float texcoord",
                                           "end_header",
                                           "0 0 0",
                                           "1 0 0",
                                           "0 1 0",
                                           "3 0 1 2 6 0 0 1 0 0 1",
                                           "3 0 2 1 6 0 0 0 1 1 0"};
    static const size_t ply_face_want[6] = {14, 14, 14, 15, 15, 15};
    check_uv_origin("uf.ply", ply_face, 15, ply_face_want, 6);
}

static void test_origins(void) {
    static const char *const obj[] = {
        "# two faces", "v 0 0 0", "v 1 0 0",   "# between", "v 1 1 0",
        "v 0 1 0",     "",        "f 1 2 3 4", "g x",       "f 1 3 4 # a comment"};
    static const size_t obj_faces[][2] = {{8, 4}, {10, 3}}, obj_vertices[4] = {2, 3, 5, 6};
    check_text_origin("o.obj", obj, 10, obj_faces, 2, obj_vertices);
    static const char *const off[] = {"OFF",   "# counts next", "4 3 0",      "0 0 0",
                                      "1 0 0", "1 1 0",         "0 1 0",      "4 0 1 2 3",
                                      "",      "3 0 2 3",       "5 0 1 2 3 1"};
    static const size_t off_faces[][2] = {{8, 4}, {10, 3}, {11, 5}}, off_vertices[4] = {4, 5, 6, 7};
    check_text_origin("o.off", off, 11, off_faces, 3, off_vertices);
    static const char *const ply[] = {"ply",
                                      "format ascii 1.0",
                                      "element vertex 4",
                                      "property float x",
                                      "property float y",
                                      "property float z",
                                      "element face 2",
                                      "property list uchar int vertex_indices",
                                      "end_header",
                                      "0 0 0",
                                      "1 0 0",
                                      "1 1 0",
                                      "0 1 0",
                                      "4 0 1 2 3",
                                      "3 0 2 3"};
    static const size_t ply_faces[][2] = {{14, 4}, {15, 3}}, ply_vertices[4] = {10, 11, 12, 13};
    check_text_origin("o.ply", ply, 15, ply_faces, 2, ply_vertices);

    /* binary PLY: each triangle names its face record's byte offset, counted here */
    unsigned char b[512];
    size_t k = (size_t)snprintf((char *)b, sizeof(b),
                                "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty "
                                "float x\nproperty float y\nproperty float z\nelement face 2\n"
                                "property list uchar uint vertex_indices\nend_header\n");
    const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const size_t vertices_at = k;
    k += put(b + k, pos, sizeof(pos));
    const size_t quad_at = k;
    const unsigned char four = 4, three = 3;
    const uint32_t quad[4] = {0, 1, 2, 3}, tri[3] = {0, 2, 3};
    k += put(b + k, &four, 1);
    k += put(b + k, quad, sizeof(quad));
    const size_t tri_at = k;
    k += put(b + k, &three, 1);
    k += put(b + k, tri, sizeof(tri));
    pgt_mesh m;
    pgt_mesh_origin o;
    const pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, &o};
    pgt_error err = {0};
    REQUIRE(pgt_mesh_read_memory(&m, b, k, "o.ply", &ro, &err) == PGT_OK);
    REQUIRE(o.offsets && o.face_count == 3);
    CHECK(o.face[0] == quad_at && o.face[1] == quad_at && o.face[2] == tri_at);
    REQUIRE(o.vertex_count == 4);
    for (uint32_t v = 0; v < 4; ++v) CHECK(o.vertex[v] == vertices_at + 12u * v);
    char where[64], want[64];
    snprintf(want, sizeof(want), "o.ply: byte offset %zu", tri_at);
    CHECK_MSG(strcmp(pgt_mesh_origin_where(&o, "o.ply", 2, where, sizeof(where)), want) == 0, "%s",
              where);
    /* a face the origin does not cover, or no origin: the name alone */
    CHECK(strcmp(pgt_mesh_origin_where(&o, "o.ply", 3, where, sizeof(where)), "o.ply") == 0);
    CHECK(strcmp(pgt_mesh_origin_where(NULL, "o.ply", 0, where, sizeof(where)), "o.ply") == 0);
    pgt_mesh_origin_destroy(&o);
    pgt_mesh_destroy(&m);
    CHECK(o.face == NULL && o.face_count == 0 && o.vertex == NULL && o.vertex_count == 0);

    /* a failed read leaves the origin zeroed */
    memset(&o, 0xAB, sizeof(o));
    static const char bad[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n";
    CHECK(pgt_mesh_read_memory(&m, bad, sizeof(bad) - 1, "bad.obj", &ro, &err) ==
          PGT_ERROR_INDEX_RANGE);
    CHECK(o.face == NULL && o.face_count == 0 && o.offsets == 0);
    /* also when the failure comes before any parsing: a missing file, an unknown extension */
    memset(&o, 0xAB, sizeof(o));
    CHECK(pgt_mesh_read(&m, "/nonexistent/x.obj", &ro, &err) == PGT_ERROR_IO);
    CHECK(o.face == NULL && o.face_count == 0 && o.offsets == 0);
    memset(&o, 0xAB, sizeof(o));
    CHECK(pgt_mesh_read_memory(&m, bad, sizeof(bad) - 1, "bad.xyz", &ro, &err) ==
          PGT_ERROR_UNSUPPORTED);
    CHECK(o.face == NULL && o.face_count == 0 && o.offsets == 0);
}

/* ---- the real meshes ---- */

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static void test_real_meshes(void) {
    /* V, T and UVs from ../shared/datasets/meshes/SOURCES.md */
    static const struct {
        const char *file;
        uint32_t v, t;
        int uvs;
    } meshes[] = {
        {"spot.obj", 2930, 5856, 1},
        {"bob_tri.obj", 5344, 10688, 1},
        {"human_neutral.obj", 10475, 20908, 1},
        {"pizza.obj", 24916, 49954, 1},
        {"ogre_bs_rest.obj", 19985, 39856, 1},
        {"nefertiti-lowres.obj", 35002, 70000, 0},
        {"mountain.obj", 25600, 50562, 0},
    };
    for (size_t i = 0; i < sizeof(meshes) / sizeof(meshes[0]); ++i) {
        char path[512];
        snprintf(path, sizeof(path), "%s/%s", PGT_SHARED_MESH_DIR, meshes[i].file);
        pgt_mesh m;
        pgt_error err;
        pgt_error_clear(&err);
        double best = 1e30;
        for (int rep = 0; rep < 3; ++rep) {
            double t0 = now_ms();
            pgt_result r = pgt_mesh_read(&m, path, &quiet_opts, &err);
            double t1 = now_ms();
            if (t1 - t0 < best) best = t1 - t0;
            CHECK_MSG(r == PGT_OK, "%s", err.message);
            if (r != PGT_OK) break;
            if (rep < 2) pgt_mesh_destroy(&m);
        }
        if (err.code != PGT_OK) continue;
        CHECK_MSG(m.vertex_count == meshes[i].v && m.face_count == meshes[i].t &&
                      (m.uvs != NULL) == meshes[i].uvs && m.labels == NULL,
                  "%s: V=%u T=%u uvs=%d", meshes[i].file, m.vertex_count, m.face_count,
                  m.uvs != NULL);
        CHECK(mesh_is_valid(&m));
        /* Informational, not an assertion (STYLE.md: timing lives in the harness). */
        printf("  %-22s V=%-6u T=%-6u uvs=%d  read %.1f ms (best of 3)\n", meshes[i].file,
               m.vertex_count, m.face_count, m.uvs != NULL, best);
        pgt_mesh_destroy(&m);
    }
}

/* ---- errors that are not about content ---- */

static void test_paths_and_formats(void) {
    CHECK(pgt_mesh_format_from_path("a/b/c.OBJ") == PGT_FORMAT_OBJ);
    CHECK(pgt_mesh_format_from_path("x.Off") == PGT_FORMAT_OFF);
    CHECK(pgt_mesh_format_from_path("x.ply") == PGT_FORMAT_PLY);
    CHECK(pgt_mesh_format_from_path("dir.ply/file") == PGT_FORMAT_AUTO);
    CHECK(pgt_mesh_format_from_path("x.offf") == PGT_FORMAT_AUTO);
    CHECK(pgt_mesh_format_from_path("noext") == PGT_FORMAT_AUTO);

    pgt_mesh m;
    pgt_error err;
    pgt_error_clear(&err);
    CHECK(pgt_mesh_read(&m, "/nonexistent/x.obj", NULL, &err) == PGT_ERROR_IO);
    CHECK(mesh_is_zero(&m) && strstr(err.message, "/nonexistent/x.obj"));
    pgt_error_clear(&err);
    CHECK(pgt_mesh_read(&m, PGT_TEST_DATA_DIR, &(pgt_mesh_read_options){PGT_FORMAT_OBJ, 1, NULL},
                        &err) == PGT_ERROR_IO);
    pgt_error_clear(&err);
    CHECK(pgt_mesh_read(&m, PGT_TEST_DATA_DIR "/malformed/MANIFEST", NULL, &err) ==
          PGT_ERROR_UNSUPPORTED);
    CHECK(read_mem(&m, "v 0 0 0", 7, "noext", &err) == PGT_ERROR_UNSUPPORTED);
    CHECK(read_mem(&m, "v 0 0 0", 7, NULL, &err) == PGT_ERROR_UNSUPPORTED);
    static const char tri[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3";
    memset(&m, 0xAB, sizeof(m));
    CHECK(pgt_mesh_read_memory(&m, tri, sizeof(tri) - 1, NULL,
                               &(pgt_mesh_read_options){PGT_FORMAT_OBJ, 1, NULL}, NULL) == PGT_OK);
    CHECK(m.face_count == 1);
    pgt_mesh_destroy(&m);
    CHECK(read_mem(&m, NULL, 0, "x.obj", &err) == PGT_ERROR_EMPTY && mesh_is_zero(&m));
}

static void test_atomic_writes(void) {
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    rng_state = 99;
    pgt_mesh a, b;
    make_mesh(&a, 10, 12, 1, 1);
    make_mesh(&b, 20, 30, 0, 0);
    char path[512];
    pgt_error err;

    /* A folder that does not exist: IO, naming the path, nothing created. */
    snprintf(path, sizeof(path), "%s/no/such/dir/x.off", scratch);
    pgt_error_clear(&err);
    CHECK(pgt_mesh_write(&a, path, NULL, &err) == PGT_ERROR_IO && strstr(err.message, path));
    CHECK(scratch_count() == 0);

    /* Over an existing file: replaced whole, no temporary file left. */
    for (int f = 0; f < 3; ++f) {
        static const char *const files[] = {"r.ply", "r.off", "r.obj"};
        snprintf(path, sizeof(path), "%s/%s", scratch, files[f]);
        CHECK(pgt_mesh_write(&a, path, NULL, NULL) == PGT_OK);
        CHECK(pgt_mesh_write(&b, path, NULL, NULL) == PGT_OK);
        pgt_mesh back;
        CHECK(pgt_mesh_read(&back, path, &quiet_opts, NULL) == PGT_OK);
        CHECK(back.vertex_count == 20 && back.face_count == 30);
        pgt_mesh_destroy(&back);
    }
    CHECK(scratch_count() == 3);

    /* The target is a folder: rename fails, the temporary file is removed, the folder stays. */
    snprintf(path, sizeof(path), "%s/dir.ply", scratch);
    REQUIRE(mkdir(path, 0755) == 0);
    pgt_error_clear(&err);
    CHECK(pgt_mesh_write(&a, path, NULL, &err) == PGT_ERROR_IO && strstr(err.message, path));
    struct stat st;
    CHECK(stat(path, &st) == 0 && S_ISDIR(st.st_mode));
    CHECK(scratch_count() == 4);

    /* Unknown extension, or an index outside the mesh: nothing written. */
    snprintf(path, sizeof(path), "%s/x.stl", scratch);
    CHECK(pgt_mesh_write(&a, path, NULL, NULL) == PGT_ERROR_UNSUPPORTED);
    snprintf(path, sizeof(path), "%s/bad.off", scratch);
    a.indices[5] = a.vertex_count;
    CHECK(pgt_mesh_write(&a, path, NULL, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(scratch_count() == 4);

    pgt_mesh_destroy(&a);
    pgt_mesh_destroy(&b);
    scratch_remove();
}

/* pgt_replace_file, every writer's last step: a regular file is replaced; a folder (EISDIR) or a
 * fifo (EPERM) is refused and left as it was, with the temporary file left for the caller. */
static void test_replace_file(void) {
    scratch_make_for("replace");
    REQUIRE(scratch[0]);
    char tmp[512], fifo[512], dir[512], reg[512];
    snprintf(tmp, sizeof tmp, "%s", scratch_path("t.tmp"));
    snprintf(fifo, sizeof fifo, "%s", scratch_path("fifo.obj"));
    snprintf(dir, sizeof dir, "%s", scratch_path("dir.obj"));
    snprintf(reg, sizeof reg, "%s", scratch_path("reg.obj"));
    FILE *f = fopen(tmp, "w");
    REQUIRE(f);
    fputs("new\n", f);
    fclose(f);
    REQUIRE(mkfifo(fifo, 0600) == 0 && mkdir(dir, 0700) == 0);
    struct stat st;
    errno = 0;
    CHECK(pgt_replace_file(tmp, fifo) == -1 && errno == EPERM);
    CHECK(stat(fifo, &st) == 0 && S_ISFIFO(st.st_mode) && access(tmp, F_OK) == 0);
    errno = 0;
    CHECK(pgt_replace_file(tmp, dir) == -1 && errno == EISDIR);
    CHECK(stat(dir, &st) == 0 && S_ISDIR(st.st_mode) && access(tmp, F_OK) == 0);
    CHECK(pgt_replace_file(tmp, reg) == 0);
    CHECK(stat(reg, &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 4 && access(tmp, F_OK) != 0);
    scratch_remove();
}

/* pgt_tmp_name, every writer's temporary name: PATH.tmp.PID while the file name leaves room for
 * the suffix; a longer one (up to PGT_NAME_MAX) cut at a character's start, with a hash that
 * tells two such names apart, within the file-name limit; a mesh written under a 255-byte name
 * leaves nothing else behind. */
static void test_tmp_name(void) {
    char tmp[1024], want[1024], other[1024], name[300], path[600];
    snprintf(want, sizeof want, "dir/a.obj.tmp.%ld", (long)getpid());
    CHECK(pgt_tmp_name(tmp, sizeof tmp, "dir/a.obj") == 0 && !strcmp(tmp, want));
    CHECK(pgt_tmp_name(tmp, 8, "dir/a.obj") == -1);
    char suffix[32];
    const size_t ns = (size_t)snprintf(suffix, sizeof suffix, ".tmp.%ld", (long)getpid());
    /* the longest file name the suffix still fits is kept whole; one byte more is cut */
    memset(name, 'k', sizeof name);
    name[PGT_NAME_MAX - ns] = '\0';
    snprintf(path, sizeof path, "d/%s", name);
    snprintf(want, sizeof want, "%s%s", path, suffix);
    CHECK(pgt_tmp_name(tmp, sizeof tmp, path) == 0 && !strcmp(tmp, want));
    name[PGT_NAME_MAX - ns] = 'k';
    name[PGT_NAME_MAX - ns + 1] = '\0';
    snprintf(path, sizeof path, "d/%s", name);
    CHECK(pgt_tmp_name(tmp, sizeof tmp, path) == 0 && strchr(tmp, '~') &&
          strlen(tmp + 2) <= PGT_NAME_MAX);
    /* "a" or "" then two-byte characters up to 254 bytes, too long for the suffix: whatever the
     * PID's digits, one of the two would be cut inside a character without the back-off */
    for (size_t lead = 0; lead < 2; ++lead) {
        memset(name, 'a', lead);
        for (size_t k = lead; k + 1 < 250; k += 2) memcpy(name + k, "\xc3\xa9", 2);
        const size_t n = lead + 2 * ((250 - lead) / 2);
        memcpy(name + n, ".ply", 5);
        snprintf(path, sizeof path, "d/%s", name);
        CHECK(pgt_tmp_name(tmp, sizeof tmp, path) == 0);
        const char *base = tmp + 2, *tilde = strrchr(tmp, '~');
        CHECK(!strncmp(tmp, "d/", 2) && strlen(base) <= PGT_NAME_MAX && !strchr(base, '/'));
        CHECK(strlen(tmp) < strlen(path) + 32);
        REQUIRE(tilde);
        const size_t cut = (size_t)(tilde - base); /* whole characters: */
        CHECK_MSG(cut >= 200 && (cut - lead) % 2 == 0 && !strncmp(base, name, cut), "cut %zu", cut);
        CHECK(strlen(tilde) == 17 + ns && !strcmp(tilde + 17, suffix));
    }
    name[248] = 'x'; /* a byte past the cut changed: the same cut, another hash */
    snprintf(path, sizeof path, "d/%s", name);
    CHECK(pgt_tmp_name(other, sizeof other, path) == 0 && strcmp(other, tmp));

    scratch_make_for("tmpname");
    REQUIRE(scratch[0]);
    memset(name, 'n', 251);
    memcpy(name + 251, ".off", 5);
    pgt_mesh m;
    rng_state = 7;
    make_mesh(&m, 10, 12, 0, 0);
    pgt_error err = {0};
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    CHECK(pgt_mesh_write(&m, path, NULL, &err) == PGT_OK);
    CHECK(access(path, F_OK) == 0 && scratch_count() == 1);
    pgt_mesh_destroy(&m);
    scratch_remove();
}

/* The path helpers every output check uses: a path's file name and folder (the folder of a
 * bare name is ".", of a file at the root "/"; one past the buffer is refused, not cut), and
 * pgt_output_check's answers for a new name, an existing file, a folder, a missing folder, a
 * file in the folder's place and a name over PGT_NAME_MAX bytes. */
static void test_output_check(void) {
    char dir[16], why[128], path[600];
    CHECK(!strcmp(pgt_path_name("a/b/c.ply"), "c.ply") && !strcmp(pgt_path_name("c.ply"), "c.ply"));
    CHECK(!strcmp(pgt_path_name("a/"), ""));
    CHECK(pgt_path_folder("a/b/c.ply", dir, sizeof dir) == 0 && !strcmp(dir, "a/b"));
    CHECK(pgt_path_folder("c.ply", dir, sizeof dir) == 0 && !strcmp(dir, "."));
    CHECK(pgt_path_folder("/c.ply", dir, sizeof dir) == 0 && !strcmp(dir, "/"));
    CHECK(pgt_path_folder("0123456789abcde/c", dir, sizeof dir) == 0 &&
          !strcmp(dir, "0123456789abcde"));
    CHECK(pgt_path_folder("0123456789abcdef/c", dir, sizeof dir) == -1 && !strcmp(dir, "."));

    scratch_make_for("outcheck");
    REQUIRE(scratch[0]);
    snprintf(path, sizeof path, "%s/new.ply", scratch);
    CHECK(pgt_output_check(path, why, sizeof why) == 0); /* a new name in a folder */
    FILE *f = fopen(path, "wb");
    REQUIRE(f);
    fclose(f);
    CHECK(pgt_output_check(path, why, sizeof why) == 0); /* an existing file */
    CHECK(pgt_output_check(scratch, why, sizeof why) != 0 &&
          !strcmp(why, "it is a folder, not a regular file"));
    CHECK(pgt_output_check("/dev/null", why, sizeof why) != 0 &&
          !strcmp(why, "it is a device, fifo or socket, not a regular file"));
    CHECK(pgt_output_check("", why, sizeof why) != 0 && !strcmp(why, strerror(ENOENT)));
    snprintf(path, sizeof path, "%s/missing/new.ply", scratch);
    CHECK(pgt_output_check(path, why, sizeof why) != 0 && !strcmp(why, strerror(ENOENT)));
    snprintf(path, sizeof path, "%s/new.ply/x.ply", scratch); /* a file where a folder should be */
    CHECK(pgt_output_check(path, why, sizeof why) != 0 && !strcmp(why, strerror(ENOTDIR)));
    char name[PGT_NAME_MAX + 2];
    memset(name, 'n', sizeof name - 1);
    name[PGT_NAME_MAX] = '\0'; /* the longest name: writable */
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    CHECK(pgt_output_check(path, why, sizeof why) == 0);
    name[PGT_NAME_MAX] = 'n', name[PGT_NAME_MAX + 1] = '\0'; /* one byte more */
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    CHECK(pgt_output_check(path, why, sizeof why) != 0 && !strcmp(why, strerror(ENAMETOOLONG)));
    CHECK(scratch_count() == 1); /* the check writes nothing */
    scratch_remove();
}

/* pgt_mesh_repeated_faces: a rotation of a face's corners repeats it, the other orientation does
 * not; the first repeat is reported with the face it repeats; the shared meshes have none. */
static void test_repeated_faces(void) {
    pgt_mesh m;
    REQUIRE(pgt_mesh_create(&m, 4, 6, 0, 0, NULL) == PGT_OK);
    static const uint32_t tri[6][3] = {{0, 1, 2}, {0, 2, 3}, {2, 1, 0},
                                       {1, 2, 0}, {3, 0, 2}, {0, 1, 2}};
    for (uint32_t f = 0; f < 6; ++f) memcpy(m.indices + 3 * f, tri[f], sizeof tri[f]);
    for (uint32_t i = 0; i < 12; ++i) m.positions[i] = (float)i;
    uint32_t first = 0, face = 0;
    /* {1,2,0} and {0,1,2} repeat face 0, {3,0,2} repeats face 1; {2,1,0} is face 0 reversed */
    CHECK(pgt_mesh_repeated_faces(&m, &first, &face) == 3u);
    CHECK(first == 0u && face == 3u);
    m.face_count = 3; /* {0,1,2}, {0,2,3}, {2,1,0}: none */
    CHECK(pgt_mesh_repeated_faces(&m, &first, &face) == 0u);
    CHECK(first == PGT_NONE && face == PGT_NONE);
    /* a face that repeats an index, in its three rotations: two repeats of the first */
    static const uint32_t degenerate[3][3] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
    for (uint32_t f = 0; f < 3; ++f) memcpy(m.indices + 3 * f, degenerate[f], sizeof degenerate[f]);
    CHECK(pgt_mesh_repeated_faces(&m, &first, &face) == 2u);
    CHECK(first == 0u && face == 1u);
    pgt_mesh_destroy(&m);
    static const char *const shared[] = {"spot.obj", "bob_tri.obj", "human_neutral.obj",
                                         "pizza.obj"};
    for (size_t k = 0; k < sizeof shared / sizeof shared[0]; ++k) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", PGT_SHARED_MESH_DIR, shared[k]);
        pgt_mesh r;
        pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
        pgt_error err = {0};
        REQUIRE(pgt_mesh_read(&r, path, &ro, &err) == PGT_OK);
        CHECK_MSG(pgt_mesh_repeated_faces(&r, &first, &face) == 0u, "%s: face %u repeats %u",
                  shared[k], face, first);
        pgt_mesh_destroy(&r);
    }
}

static const pgt_test_case cases[] = {
    {"replace_file", test_replace_file},
    {"tmp_name", test_tmp_name},
    {"uv_origins", test_uv_origins},
    {"output_check", test_output_check},
    {"long_numbers", test_long_numbers},
    {"repeated_faces", test_repeated_faces},
    {"malformed_corpus", test_malformed_corpus},
    {"truncated_binary_ply", test_truncated_binary_ply},
    {"truncated_off", test_truncated_off},
    {"truncated_ascii_ply", test_truncated_ascii_ply},
    {"garbage_and_mutations", test_garbage_and_mutations},
    {"round_trips", test_round_trips},
    {"fan_obj", test_fan_obj},
    {"fan_off", test_fan_off},
    {"obj_forms", test_obj_forms},
    {"byte_order_mark", test_byte_order_mark},
    {"numbers_match_strtof", test_numbers_match_strtof},
    {"ply_groups_ascii", test_ply_groups_ascii},
    {"ply_groups_binary", test_ply_groups_binary},
    {"ply_vertex_uvs", test_ply_vertex_uvs},
    {"origins", test_origins},
    {"real_meshes", test_real_meshes},
    {"paths_and_formats", test_paths_and_formats},
    {"atomic_writes", test_atomic_writes},
};

PGT_TEST_MAIN(cases)
