/* pgt harness: oracle programs and order-independent mesh comparison. */
#include "oracle.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

int pgt_oracle_path(const char *name, char *buf, size_t size) {
    const char *dir = getenv("PGT_ORACLE_DIR");
    int script = strstr(name, ".sh") != NULL;
    if (!dir || !*dir) dir = script ? PGT_SOURCE_DIR "/harness/oracles" : PGT_ORACLE_DIR;
    snprintf(buf, size, "%s/%s", dir, name);
    return access(buf, X_OK) == 0 ? 0 : -1;
}

/* Runs a shell command line and captures the first line of stdout. */
static int run_capture(const char *cmd, char *line, size_t size) {
    FILE *p = popen(cmd, "r");
    if (!p) return -1;
    line[0] = 0;
    if (!fgets(line, (int)size, p)) line[0] = 0;
    char rest[256];
    while (fgets(rest, sizeof rest, p)) {
    }
    int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static double json_number(const char *line, const char *key) {
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(line, pat);
    return p ? strtod(p + strlen(pat), NULL) : NAN;
}

pgt_result pgt_oracle_sqrt3(const char *tool, const char *in_off, uint32_t k, const char *out_off,
                            uint32_t repeat, pgt_oracle_run *out, pgt_error *err) {
    char exe[1024], cmd[4096], line[1024];
    if (pgt_oracle_path(tool, exe, sizeof exe) != 0)
        return pgt_error_set(err, PGT_ERROR_IO,
                             "oracle %s not found (build it, or set PGT_ORACLE_DIR)", exe);
    snprintf(cmd, sizeof cmd, "'%s' '%s' %u '%s' --repeat %u", exe, in_off, k, out_off,
             repeat ? repeat : 1);
    int status = run_capture(cmd, line, sizeof line);
    if (status != 0)
        return pgt_error_set(err, PGT_ERROR_IO, "oracle %s failed (exit %d) on %s", tool, status,
                             in_off);
    out->vertices_out = (uint32_t)json_number(line, "vertices_out");
    out->faces_out = (uint32_t)json_number(line, "faces_out");
    out->median_ms = json_number(line, "median_ms");
    out->best_ms = json_number(line, "best_ms");
    if (isnan(out->median_ms))
        return pgt_error_set(err, PGT_ERROR_PARSE, "oracle %s printed no timing: '%s'", tool, line);
    return PGT_OK;
}

pgt_result pgt_oracle_hausdorff(const char *a, const char *b, double *out_max, pgt_error *err) {
    char exe[1024], cmd[4096], line[1024];
    if (pgt_oracle_path("meshlab_hausdorff.sh", exe, sizeof exe) != 0)
        return pgt_error_set(err, PGT_ERROR_IO, "oracle %s not found", exe);
    snprintf(cmd, sizeof cmd, "bash '%s' '%s' '%s'", exe, a, b);
    int status = run_capture(cmd, line, sizeof line);
    if (status != 0)
        return pgt_error_set(err, PGT_ERROR_IO, "MeshLab Hausdorff failed (exit %d) on %s, %s",
                             status, a, b);
    const char *p = strstr(line, "max=");
    if (!p) return pgt_error_set(err, PGT_ERROR_PARSE, "MeshLab Hausdorff printed '%s'", line);
    *out_max = strtod(p + 4, NULL);
    return PGT_OK;
}

/* ---- order-independent comparison ---------------------------------------------------------- */

typedef struct {
    double x;
    uint32_t i;
} xkey;

static int cmp_xkey(const void *a, const void *b) {
    double x = ((const xkey *)a)->x, y = ((const xkey *)b)->x;
    if (x != y) return (x > y) - (x < y);
    return (((const xkey *)a)->i > ((const xkey *)b)->i) -
           (((const xkey *)a)->i < ((const xkey *)b)->i);
}

typedef struct {
    uint32_t v[3];
} tri;

static int cmp_tri(const void *a, const void *b) { return memcmp(a, b, sizeof(tri)); }

/* Rotation that puts the smallest index first (orientation kept). Compared as big-endian-like
 * memcmp keys is fine: we only need a total order consistent between both lists. */
static tri canon(uint32_t a, uint32_t b, uint32_t c) {
    tri t;
    if (a <= b && a <= c)
        t = (tri){{a, b, c}};
    else if (b <= a && b <= c)
        t = (tri){{b, c, a}};
    else
        t = (tri){{c, a, b}};
    return t;
}

pgt_result pgt_mesh_match_compute(const pgt_mesh *a, const pgt_mesh *b, double tol,
                                  pgt_mesh_match *out, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    const uint32_t VA = a->vertex_count, VB = b->vertex_count;
    xkey *kb = malloc(((size_t)VB + 1) * sizeof(xkey));
    uint32_t *map = malloc(((size_t)VA + 1) * sizeof(uint32_t));
    uint8_t *taken = calloc((size_t)VB + 1, 1);
    tri *ta = malloc(((size_t)a->face_count + 1) * sizeof(tri));
    tri *tb = malloc(((size_t)b->face_count + 1) * sizeof(tri));
    if (!kb || !map || !taken || !ta || !tb) {
        free(kb), free(map), free(taken), free(ta), free(tb);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "mesh match: out of memory");
    }
    for (uint32_t v = 0; v < VB; ++v) kb[v] = (xkey){b->positions[3 * (size_t)v], v};
    qsort(kb, VB, sizeof(xkey), cmp_xkey);
    for (uint32_t v = 0; v < VA; ++v) {
        const float *p = a->positions + 3 * (size_t)v;
        /* first candidate with x >= p.x - tol */
        size_t lo = 0, hi = VB;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (kb[mid].x < (double)p[0] - tol)
                lo = mid + 1;
            else
                hi = mid;
        }
        double best = INFINITY;
        uint32_t bi = PGT_NONE;
        for (size_t j = lo; j < VB && kb[j].x <= (double)p[0] + tol; ++j) {
            const float *q = b->positions + 3 * (size_t)kb[j].i;
            double d = 0.0;
            for (int k = 0; k < 3; ++k) d += ((double)p[k] - q[k]) * ((double)p[k] - q[k]);
            d = sqrt(d);
            if (d <= tol && d < best && !taken[kb[j].i]) best = d, bi = kb[j].i;
        }
        map[v] = bi;
        if (bi == PGT_NONE) {
            out->unmatched_vertices++;
        } else {
            taken[bi] = 1;
            if (best > out->max_vertex_distance) out->max_vertex_distance = best;
        }
    }
    out->unmatched_vertices += VA > VB ? 0 : VB - VA;
    for (uint32_t f = 0; f < a->face_count; ++f) {
        const uint32_t *t = a->indices + 3 * (size_t)f;
        ta[f] = canon(map[t[0]], map[t[1]], map[t[2]]);
    }
    for (uint32_t f = 0; f < b->face_count; ++f) {
        const uint32_t *t = b->indices + 3 * (size_t)f;
        tb[f] = canon(t[0], t[1], t[2]);
    }
    qsort(ta, a->face_count, sizeof(tri), cmp_tri);
    qsort(tb, b->face_count, sizeof(tri), cmp_tri);
    uint32_t i = 0, j = 0, common = 0;
    while (i < a->face_count && j < b->face_count) {
        int c = cmp_tri(&ta[i], &tb[j]);
        if (c == 0)
            common++, i++, j++;
        else if (c < 0)
            i++;
        else
            j++;
    }
    uint32_t nmax = a->face_count > b->face_count ? a->face_count : b->face_count;
    out->face_mismatches = nmax - common;
    free(kb), free(map), free(taken), free(ta), free(tb);
    return PGT_OK;
}
