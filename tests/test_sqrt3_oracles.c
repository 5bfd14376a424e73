/* Oracle agreement for sqrt(3): our reference against CGAL 5.5 (Surface_mesh, double) and
 * OpenMesh 9.0 (Sqrt3T, double) on every manifold mesh of ../shared/datasets/meshes and every
 * generated default dataset, k = 1, 2, 3; and MeshLab's Hausdorff distance between ours (with an
 * empty protected set) and CGAL's.
 *
 * Oracles run as separate programs (harness/oracles/) on an OFF file written with 17 significant
 * digits; their output is read back with our OFF reader. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "gen.h"
#include "oracle.h"
#include "pgt/mesh_io.h"
#include "pgt/sqrt3.h"
#include "test_util.h"

/* Vertex agreement bound, relative to the bounding-box diagonal (the 1e-5). Our positions
 * are float32 (about 6e-8 relative per rounding, a few roundings per level) while the oracles
 * compute in double; measured worst case here is far below this bound (see the printed value). */
#define ORACLE_VERTEX_TOL_REL 1e-5

/* Hausdorff bound for MeshLab, relative to the diagonal (the 1e-5). MeshLab prints its
 * distances with %f, so it resolves 1e-6 in mesh units: below this bound for every mesh used here
 * (diagonals 1.4 to 3.3), so the check can fail; meshlab_detects_a_shift proves it does. */
#define ORACLE_HAUSDORFF_TOL_REL 1e-5

static const char *shared_meshes[] = {"spot.obj",    "bob_tri.obj",      "human_neutral.obj",
                                      "pizza.obj",   "ogre_bs_rest.obj", "nefertiti-lowres.obj",
                                      "mountain.obj"};

static char tmpdir[256];

static void make_tmpdir(void) {
    if (tmpdir[0]) return;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/pgt-oracle-test-XXXXXX");
    if (!mkdtemp(tmpdir)) tmpdir[0] = 0;
}

static int load_named(const char *name, pgt_mesh *m) {
    pgt_error err = {0};
    uint32_t g = pgt_gen_default_find(name);
    if (g != PGT_NONE) return pgt_gen_default(g, m, &err) == PGT_OK;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", PGT_SHARED_MESH_DIR, name);
    pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
    if (pgt_mesh_read(m, path, &ro, &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 0;
    }
    return 1;
}

/* Compares ours to one oracle's output for mesh m at k; returns the number of failed checks. */
static int agree(const char *name, const pgt_mesh *m, const pgt_mesh *ours, const char *tool,
                 const char *in_off, uint32_t k) {
    char out_off[512];
    snprintf(out_off, sizeof out_off, "%s/%s.off", tmpdir, tool);
    pgt_oracle_run run;
    pgt_error err = {0};
    if (pgt_oracle_sqrt3(tool, in_off, k, out_off, 1, &run, &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 1;
    }
    pgt_mesh theirs;
    pgt_mesh_read_options ro = {PGT_FORMAT_OFF, 1, NULL};
    if (pgt_mesh_read(&theirs, out_off, &ro, &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 1;
    }
    remove(out_off);
    int fails = 0;
    if (theirs.vertex_count != ours->vertex_count || theirs.face_count != ours->face_count) {
        fprintf(stderr, "  %s k=%u %s: counts %u v %u f, ours %u v %u f\n", name, k, tool,
                theirs.vertex_count, theirs.face_count, ours->vertex_count, ours->face_count);
        fails++;
    } else {
        double diag = pgt_mesh_bbox_diagonal(m), tol = ORACLE_VERTEX_TOL_REL * diag;
        pgt_mesh_match mm;
        if (pgt_mesh_match_compute(ours, &theirs, tol, &mm, &err) != PGT_OK) {
            fails++;
        } else {
            printf("  %-24s k=%u %-15s %8u faces, max vertex distance %.2e x diagonal, %u "
                   "unmatched, %u face mismatches\n",
                   name, k, tool, ours->face_count, mm.max_vertex_distance / diag,
                   mm.unmatched_vertices, mm.face_mismatches);
            if (mm.unmatched_vertices || mm.face_mismatches) fails++;
        }
    }
    pgt_mesh_destroy(&theirs);
    return fails;
}

static void check_mesh(const char *name) {
    make_tmpdir();
    REQUIRE(tmpdir[0]);
    pgt_mesh m;
    REQUIRE(load_named(name, &m));
    char in_off[512];
    snprintf(in_off, sizeof in_off, "%s/in.off", tmpdir);
    pgt_mesh_write_options wo = {PGT_FORMAT_OFF, 1};
    REQUIRE(pgt_mesh_write(&m, in_off, &wo, NULL) == PGT_OK);
    for (uint32_t k = 1; k <= 3; ++k) {
        pgt_mesh ours;
        pgt_sqrt3_options o = {k, 2, NULL, NULL, NULL, NULL, NULL};
        pgt_error err = {0};
        CHECK_MSG(pgt_sqrt3_subdivide(&ours, &m, &o, &err) == PGT_OK, "%s", err.message);
        if (err.code != PGT_OK) break;
        CHECK(agree(name, &m, &ours, "cgal_sqrt3", in_off, k) == 0);
        CHECK(agree(name, &m, &ours, "openmesh_sqrt3", in_off, k) == 0);
        pgt_mesh_destroy(&ours);
    }
    remove(in_off);
    pgt_mesh_destroy(&m);
}

static void shared_meshes_agree(void) {
    for (size_t i = 0; i < sizeof shared_meshes / sizeof *shared_meshes; ++i)
        check_mesh(shared_meshes[i]);
}

static void generated_meshes_agree(void) {
    for (uint32_t i = 0; i < pgt_gen_default_count(); ++i) check_mesh(pgt_gen_default_name(i));
}

/* MeshLab's Hausdorff distance (symmetric) between ours with an empty protected set and CGAL's,
 * against the bounding-box diagonal. */
static void meshlab_hausdorff_to_cgal(void) {
    make_tmpdir();
    REQUIRE(tmpdir[0]);
    const char *names[] = {"hemisphere_jagged_12x32", "noisy_torus_48x24", "spot.obj"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
        pgt_mesh m;
        REQUIRE(load_named(names[i], &m));
        char in_off[512], ours_off[512], cgal_off[512];
        snprintf(in_off, sizeof in_off, "%s/in.off", tmpdir);
        snprintf(ours_off, sizeof ours_off, "%s/ours.off", tmpdir);
        snprintf(cgal_off, sizeof cgal_off, "%s/cgal.off", tmpdir);
        pgt_mesh_write_options wo = {PGT_FORMAT_OFF, 1};
        REQUIRE(pgt_mesh_write(&m, in_off, &wo, NULL) == PGT_OK);
        uint8_t *none = calloc(m.face_count, 1);
        pgt_sqrt3_options o = {2, 1, none, NULL, NULL, NULL, NULL};
        pgt_mesh ours;
        REQUIRE(pgt_sqrt3_subdivide(&ours, &m, &o, NULL) == PGT_OK);
        REQUIRE(pgt_mesh_write(&ours, ours_off, &wo, NULL) == PGT_OK);
        pgt_oracle_run run;
        pgt_error err = {0};
        REQUIRE(pgt_oracle_sqrt3("cgal_sqrt3", in_off, 2, cgal_off, 1, &run, &err) == PGT_OK);
        double h = -1.0, diag = pgt_mesh_bbox_diagonal(&m);
        CHECK_MSG(pgt_oracle_hausdorff(ours_off, cgal_off, &h, &err) == PGT_OK, "%s", err.message);
        printf("  %-24s k=2 MeshLab Hausdorff(ours, CGAL) = %.3e x diagonal\n", names[i], h / diag);
        CHECK(h >= 0.0 && h <= ORACLE_HAUSDORFF_TOL_REL * diag);
        remove(in_off), remove(ours_off), remove(cgal_off);
        free(none);
        pgt_mesh_destroy(&ours);
        pgt_mesh_destroy(&m);
    }
}

/* How far MeshLab's distance for the shifted copy may be from the shift, relative to the
 * diagonal: the distance equals the shift only where the surface normal is along it and MeshLab
 * finds its maximum by sampling and prints it with %f (1e-6 = 2.5e-7 x this diagonal), so it may
 * fall a little short; a tenth of the shift still tells it from a missed or mis-scaled one.
 * Measured: 1.2e-7. */
#define SHIFT_SEEN_TOL_REL 1e-4

/* Negative control: the same MeshLab check sees a copy of ours moved by 1e-3 x diagonal. */
static void meshlab_detects_a_shift(void) {
    make_tmpdir();
    REQUIRE(tmpdir[0]);
    pgt_mesh m;
    REQUIRE(load_named("noisy_torus_48x24", &m));
    char a[512], b[512];
    snprintf(a, sizeof a, "%s/a.off", tmpdir);
    snprintf(b, sizeof b, "%s/b.off", tmpdir);
    pgt_mesh_write_options wo = {PGT_FORMAT_OFF, 1};
    REQUIRE(pgt_mesh_write(&m, a, &wo, NULL) == PGT_OK);
    double diag = pgt_mesh_bbox_diagonal(&m);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        m.positions[3 * (size_t)v] += (float)(1e-3 * diag);
    REQUIRE(pgt_mesh_write(&m, b, &wo, NULL) == PGT_OK);
    double h = -1.0;
    pgt_error err = {0};
    CHECK_MSG(pgt_oracle_hausdorff(a, b, &h, &err) == PGT_OK, "%s", err.message);
    CHECK_MSG(fabs(h / diag - 1e-3) < SHIFT_SEEN_TOL_REL,
              "MeshLab saw %.3e x diagonal for a 1e-3 shift", h / diag);
    CHECK(h > ORACLE_HAUSDORFF_TOL_REL * diag);
    remove(a), remove(b);
    pgt_mesh_destroy(&m);
}

static const pgt_test_case cases[] = {
    {"generated_meshes_agree", generated_meshes_agree},
    {"shared_meshes_agree", shared_meshes_agree},
    {"meshlab_hausdorff_to_cgal", meshlab_hausdorff_to_cgal},
    {"meshlab_detects_a_shift", meshlab_detects_a_shift},
};

int main(int argc, char **argv) {
    int rc = pgt_test_main(argc, argv, cases, (int)(sizeof cases / sizeof *cases));
    if (tmpdir[0]) rmdir(tmpdir);
    return rc;
}
