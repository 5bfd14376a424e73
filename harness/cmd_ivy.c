/* pgt ivy: ivy grown on a mesh by the grammar of paper 000 section 8 (ref_cpu/src/ivy.c: expand,
 * G1 Bezier, terminals), with masks, painted strokes and seed files. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "ivy_scene.h"
#include "pgt/bezier.h"
#include "pgt/ivy.h"
#include "pgt/kdtree.h"
#include "pgt/mesh_io.h"
#include "pgt/parallel.h"
#include "pgt/rng.h"
#include "png_io.h"
#include "progress_line.h"
#include "text_line.h"

/* Most seeds: each seed keeps its own output buffers while the seeds expand; 2^20 is far beyond
 * the paper's 64 and bounds a typo's memory. */
#define IVY_MAX_SEEDS (1u << 20)

/* Largest --max-total-items: every seed at the expander's max_items (a larger total changes
 * nothing). */
#define IVY_MAX_TOTAL_ITEMS ((uint64_t)IVY_MAX_SEEDS * PGT_EXPAND_DEFAULT_MAX_ITEMS)

/* A 3D point of a seed or stroke file farther than this from the nearest inner texel (in median
 * texel sizes) is an error: it is not on the surface (a typo, or another mesh's coordinates),
 * while a point picked on the mesh lies within a texel of one. */
#define IVY_SNAP_MAX_TEXELS 16.0

/* A painted seed heads towards the first later point of its stroke at least this many texels
 * away in the same chart (the paper: "the marching direction is initialized from the difference
 * of texture coordinates between the release and picking events"); nearer points give a
 * direction quantised by the texel grid. */
#define IVY_SEED_DIR_MIN_TEXELS 2.0f

/* RNG stream of the directions of seeds that have none ("SDIR"). */
#define IVY_SEED_DIR_STREAM 0x53444952u

/* Longest line of a seed or stroke file. */
#define IVY_MAX_LINE 4096

static const char *ivy_usage =
    "usage: pgt ivy MESH_OR_ATLAS --seeds N -o IVY.ply [--grammar FILE] [--param NAME=VALUE ...]\n"
    "               [--seed-file FILE] [--mask FILE] [--paint FILE] [--brush R] [--no-leaves]\n"
    "               [--no-secondary] [--threads N] [--curves CURVES.csv] [--res N] [--seed S]\n"
    "               [--rotation atlas|jacobian] [--mask-out MASK.png] [--forbid FILE]\n"
    "               [--mask-mesh PAINT.ply] [--density FILE] [--max-total-items N]\n"
    "\n"
    "Grows ivy over a mesh (paper 000 sections 5-8): the grammar's rules expand per seed on the\n"
    "mesh's geometry-image atlas by marching, the marched polylines become G1 cubic Bezier\n"
    "curves, and the terminals (bark tubes of 216 quads per segment, leaf quads) are deformed\n"
    "along them. Prints seeds, points, segments, polygons and milliseconds per stage.\n"
    "\n"
    "  MESH_OR_ATLAS   a mesh with UVs (OBJ/OFF/PLY, a file of ../shared/datasets/meshes or a\n"
    "                  generated dataset such as cube_sphere_8), whose atlas is built here, or\n"
    "                  an atlas .exr written by pgt atlas\n"
    "  --seeds N       number of seeds, 1 to 1048576. Where they start: the first N seeds of\n"
    "                  --seed-file; else, with --paint, the starts of the strokes in turn\n"
    "                  (seed i on stroke i mod S), heading along the stroke; else uniformly\n"
    "                  random inner texels with random directions (--seed)\n"
    "  -o IVY.ply      output: binary PLY, vertex x y z nx ny nz u v, triangles (a bark quad\n"
    "                  or a leaf is two triangles); written to a temporary file, then renamed\n"
    "  --grammar FILE  the grammar (default grammars/ivy.grammar, paper 000 section 8)\n"
    "  --param N=V     override a grammar param (repeatable; see pgt grammar FILE)\n"
    "  --seed-file F   seeds, one per line: 'texel U V [DU DV]' (texel space, like pgt march\n"
    "                  --from and --dir; no direction: a random one) or 'point X Y Z' (3D,\n"
    "                  snapped to the nearest inner texel; a random direction); '#' comments\n";
static const char *ivy_usage2 =
    "  --mask FILE     forbidden areas (paper Fig. 10b): a PNG or EXR of the atlas's size\n"
    "                  (PNG: first channel; EXR: 'mask', 'Y', 'R' or the only channel); a texel\n"
    "                  >= 0.5 is forbidden. Applied to every march as its external context and\n"
    "                  readable by the grammar as context.mask(texCoord)\n"
    "  --density FILE  a density (paper 000 sec. 3: a spatially varying parameter) for the\n"
    "                  grammar's context.density(texCoord): an image like --mask (EXR channel\n"
    "                  'density', else 'Y', 'R' or the only one; PNG 0..255 as 0..1); without\n"
    "                  it context.density reads 0. The grammar decides what it does, e.g. a\n"
    "                  marching condition rand(0, 1) < context.density(texCoord)\n"
    "  --paint FILE    painted paths (paper Fig. 10c): growth only within the brush of the\n"
    "                  strokes (texels farther are forbidden, combined with --mask). Lines:\n"
    "                  'stroke' starts a stroke, then 'texel U V' or 'point X Y Z' lines list\n"
    "                  its points; points before the first 'stroke' form one; '#' comments\n"
    "  --forbid FILE   painted forbidden areas (paper Fig. 10b): strokes in the --paint format;\n"
    "                  texels within the brush are forbidden (combined with --mask, --paint)\n"
    "  --brush R       brush radius of --paint and --forbid in mesh units (default 6 median\n"
    "                  texel sizes)\n"
    "  --no-leaves     no leaves (Leaves records are dropped before the terminals)\n"
    "  --no-secondary  the main branch alone: sets the grammar param secondaryBranches to 0\n"
    "                  (grammars/ivy.grammar has it; another grammar without it is an error;\n"
    "                  not with --param secondaryBranches=V)\n"
    "  --threads N     threads of every stage (default: the number of CPUs)\n"
    "  --curves F.csv  one row per Bezier segment: branch,segment,p0x,p0y,p0z,b1x,b1y,b1z,\n"
    "                  b2x,b2y,b2z,p1x,p1y,p1z,n0x,n0y,n0z,n1x,n1y,n1z (segment: its index\n"
    "                  along its branch from 0; n0, n1: the surface normals at its ends). A\n"
    "                  branch is a chain of first children (pgt/expand.h): with ivy.grammar,\n"
    "                  whose Branch lists the secondary branch first, a branch is one main-stem\n"
    "                  segment followed by a secondary branch, and the stem goes on in a new one\n"
    "  --res N         atlas resolution when MESH_OR_ATLAS is a mesh (default 1024)\n"
    "  --seed S        seed id of seed 0 (seed i has id S + i: the grammar's rand and the\n"
    "                  leaves) and of the random seed placement; default 1\n"
    "  --rotation R    direction at chart jumps: atlas (the paper, default) or jacobian\n"
    "  --mask-out F    write the mask the marches used as a grey PNG of the atlas's size:\n"
    "                  forbidden texels white, the others black (--mask reads it back)\n"
    "  --mask-mesh F   write the painted surface as a mesh for figures (paper Fig. 10's red\n"
    "                  areas): the texels --paint and --forbid brushed, else those --mask\n"
    "                  forbids, as triangles between texel centres lifted off the surface\n"
    "  --max-total-items N  grammar items all seeds together may run, 1 to 2^46 (default\n"
    "                  2^31 = 2147483648, a minute or two on one core): each seed may run\n"
    "                  N / seeds of them (at least 1, at most 2^26 = 67108864); a seed that\n"
    "                  needs more fails (exit 2), naming the grammar item. The paper's\n"
    "                  scenes run about 30k a seed; the bound stops a runaway grammar over\n"
    "                  many seeds\n"
    "\n"
    "The same inputs, seeds and flags give the same bytes for any --threads.\n"
    "A progress line on stderr every 5 s of work (PGT_PROGRESS_SECONDS: the period, 0: none).\n"
    "Exit 0 on success, 2 on a bad flag, value, input file or grammar, or a grammar exceeding\n"
    "the expander's bounds.\n";

/* Points of a seed or stroke file. */
typedef struct ivy_points {
    uint32_t n, cap;
    float *tex; /* 2n: texel-space position (snapped for 3D points) */
    float *p3;  /* 3n: 3D position (the file's for 3D points, P at tex for texel points) */
    float *dir; /* 2n: texel-space direction, or 0,0 */
    uint32_t *line;
    uint32_t strokes, stroke_cap;
    uint32_t *stroke_first; /* strokes + 1 */
} ivy_points;

static void points_free(ivy_points *p) {
    free(p->tex), free(p->p3), free(p->dir), free(p->line), free(p->stroke_first);
    memset(p, 0, sizeof(*p));
}

static int points_push(ivy_points *p) {
    if (p->n == p->cap) {
        const uint32_t cap = p->cap ? 2u * p->cap : 64u;
        float *tex = realloc(p->tex, (size_t)cap * 2u * sizeof(float));
        if (tex) p->tex = tex;
        float *p3 = realloc(p->p3, (size_t)cap * 3u * sizeof(float));
        if (p3) p->p3 = p3;
        float *dir = realloc(p->dir, (size_t)cap * 2u * sizeof(float));
        if (dir) p->dir = dir;
        uint32_t *line = realloc(p->line, (size_t)cap * sizeof(uint32_t));
        if (line) p->line = line;
        if (!tex || !p3 || !dir || !line) return -1;
        p->cap = cap;
    }
    p->n++;
    return 0;
}

static int stroke_push(ivy_points *p) {
    if (p->strokes + 1u >= p->stroke_cap) {
        const uint32_t cap = p->stroke_cap ? 2u * p->stroke_cap : 16u;
        uint32_t *s = realloc(p->stroke_first, (size_t)cap * sizeof(uint32_t));
        if (!s) return -1;
        p->stroke_first = s, p->stroke_cap = cap;
    }
    p->stroke_first[p->strokes++] = p->n;
    return 0;
}

/* Up to max numbers after the keyword; returns how many, or -1 on a non-number. */
static int parse_numbers(char *s, float *out, int max) {
    int n = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == ',') ++s;
        if (!*s || *s == '\n' || *s == '#') return n;
        if (n == max) return -1;
        char *end = NULL;
        const float v = strtof(s, &end); /* underflow: a denormal or zero, as in pgt_cli_floats */
        if (end == s || !isfinite(v)) return -1;
        out[n++] = v;
        s = end;
        if (*s && *s != ' ' && *s != '\t' && *s != '\r' && *s != '\n' && *s != ',' && *s != '#')
            return -1;
    }
}

/* Reads a seed file (strokes = 0) or a stroke file (strokes = 1). Texel points must lie on inner
 * texels; 3D points are snapped with `tree` (built on first need over the inner texels). */
static int read_points(const char *verb, const char *flag, const char *path, int strokes,
                       const pgt_ivy_scene *s, pgt_kdtree *tree, uint32_t **tree_ids,
                       uint32_t threads, ivy_points *out) {
    memset(out, 0, sizeof(*out));
    FILE *f = fopen(path, "rb");
    if (!f) return pgt_cli_fail(verb, "%s %s: cannot open: %s", flag, path, strerror(errno));
    const pgt_march_atlas *a = &s->atlas;
    char buf[IVY_MAX_LINE + 2];
    uint32_t line = 0;
    int rc = -1;
    if (strokes && stroke_push(out)) goto oom;
    pgt_text_line got;
    size_t len;
    while ((got = pgt_text_line_read(f, buf, IVY_MAX_LINE + 1, &len, line == 0)) !=
           PGT_TEXT_LINE_END) {
        ++line;
        if (got != PGT_TEXT_LINE_OK) { /* too long, or a NUL */
            char msg[PGT_TEXT_LINE_MESSAGE];
            pgt_text_line_message(got, path, line, len, IVY_MAX_LINE, msg, sizeof msg);
            pgt_cli_fail(verb, "%s", msg);
            goto done;
        }
        char *p = buf;
        while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
        if (!*p || *p == '\n' || *p == '#') continue;
        char *word = p;
        while (*p && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
        const size_t wl = (size_t)(p - word);
        float v[8];
        if (wl == 6 && !strncmp(word, "stroke", 6)) {
            if (!strokes) {
                pgt_cli_fail(verb, "%s:%u: 'stroke' belongs in a --paint file, not %s", path, line,
                             flag);
                goto done;
            }
            if (parse_numbers(p, v, 0) != 0) {
                pgt_cli_fail(verb, "%s:%u: 'stroke' takes no values", path, line);
                goto done;
            }
            if (out->stroke_first[out->strokes - 1u] != out->n && stroke_push(out)) goto oom;
            continue;
        }
        const int texel = wl == 5 && !strncmp(word, "texel", 5);
        const int point = wl == 5 && !strncmp(word, "point", 5);
        if (!texel && !point) {
            pgt_cli_fail(verb, "%s:%u: expected 'texel U V%s', 'point X Y Z'%s, found '%.*s'", path,
                         line, strokes ? "" : " [DU DV]", strokes ? " or 'stroke'" : "",
                         (int)(wl > 40 ? 40 : wl), word);
            goto done;
        }
        const int n = parse_numbers(p, v, 5);
        const int ok = texel ? (n == 2 || (!strokes && n == 4)) : n == 3;
        if (!ok) {
            pgt_cli_fail(verb, "%s:%u: '%s' takes %s finite numbers", path, line,
                         texel ? "texel" : "point",
                         texel ? (strokes ? "2 (U V)" : "2 (U V) or 4 (U V DU DV)") : "3 (X Y Z)");
            goto done;
        }
        if (points_push(out)) goto oom;
        const uint32_t k = out->n - 1u;
        out->line[k] = line;
        out->dir[2u * k] = out->dir[2u * k + 1u] = 0.0f;
        if (texel) {
            const float u = v[0], w = v[1];
            if (!(u >= 0.0f && w >= 0.0f && u < (float)a->width && w < (float)a->height) ||
                (a->codes[(size_t)(uint32_t)w * a->width + (uint32_t)u] & 3u) != PGT_TEXEL_INNER) {
                pgt_cli_fail(verb, "%s:%u: texel %g %g is not on an inner texel of the atlas", path,
                             line, (double)u, (double)w);
                goto done;
            }
            out->tex[2u * k] = u, out->tex[2u * k + 1u] = w;
            pgt_march_position(a, u, w, &out->p3[3u * k]);
            if (n == 4) {
                if (v[2] == 0.0f && v[3] == 0.0f) {
                    pgt_cli_fail(verb, "%s:%u: the direction 0 0 has no heading", path, line);
                    goto done;
                }
                out->dir[2u * k] = v[2], out->dir[2u * k + 1u] = v[3];
            }
        } else {
            if (!tree->nodes) {
                pgt_error err = {0};
                const size_t texels = (size_t)a->width * a->height;
                uint32_t inner = 0;
                for (size_t i = 0; i < texels; ++i) inner += (a->codes[i] & 3u) == PGT_TEXEL_INNER;
                float *xyz = malloc(((size_t)inner + 1u) * 3u * sizeof(float));
                *tree_ids = malloc(((size_t)inner + 1u) * sizeof(uint32_t));
                if (!xyz || !*tree_ids) {
                    free(xyz);
                    goto oom;
                }
                uint32_t m = 0;
                for (size_t i = 0; i < texels; ++i)
                    if ((a->codes[i] & 3u) == PGT_TEXEL_INNER) {
                        xyz[3u * m] = a->texels[i].x, xyz[3u * m + 1u] = a->texels[i].y;
                        xyz[3u * m + 2u] = a->texels[i].z;
                        (*tree_ids)[m++] = (uint32_t)i;
                    }
                const pgt_result r = pgt_kdtree_build(tree, xyz, m, threads, &err);
                free(xyz);
                if (r != PGT_OK) {
                    pgt_cli_fail(verb, "%s", err.message);
                    goto done;
                }
            }
            const double lim = IVY_SNAP_MAX_TEXELS * s->texel_size;
            float d2 = 0.0f;
            const uint32_t id = pgt_kdtree_nearest(tree, v, (float)(lim * lim), NULL, NULL, &d2);
            if (id == PGT_NONE) {
                pgt_cli_fail(verb,
                             "%s:%u: point %g %g %g is farther than %g (%g texels) from every "
                             "inner texel of the atlas: not on the surface",
                             path, line, (double)v[0], (double)v[1], (double)v[2], lim,
                             IVY_SNAP_MAX_TEXELS);
                goto done;
            }
            const uint32_t t = (*tree_ids)[id];
            out->tex[2u * k] = (float)(t % a->width) + 0.5f;
            out->tex[2u * k + 1u] = (float)(t / a->width) + 0.5f;
            memcpy(&out->p3[3u * k], v, 3u * sizeof(float));
        }
    }
    if (ferror(f)) { /* errno: the failed read's (a folder: EISDIR) */
        pgt_cli_fail(verb, "%s %s: read error: %s", flag, path, strerror(errno));
        goto done;
    }
    if (strokes) {
        if (out->strokes > 1u && out->stroke_first[out->strokes - 1u] == out->n) out->strokes--;
        out->stroke_first[out->strokes] = out->n;
    }
    if (!out->n) {
        pgt_cli_fail(verb, "%s %s: no points", flag, path);
        goto done;
    }
    rc = 0;
    goto done;
oom:
    pgt_cli_fail(verb, "out of memory");
done:
    fclose(f);
    if (rc) points_free(out);
    return rc;
}

/* A random unit direction for seed i without one. */
static void random_dir(uint32_t seed, uint32_t i, float *dx, float *dy) {
    const double a = 6.283185307179586 * pgt_rng_double(seed, IVY_SEED_DIR_STREAM, i);
    *dx = (float)cos(a), *dy = (float)sin(a);
}

static int write_curves(const char *path, const pgt_ivy_output *o) {
    char tmp[4200];
    FILE *f = pgt_cli_tmp_open(path, tmp, sizeof tmp);
    if (!f) return pgt_cli_fail("ivy", "cannot write %s: %s", tmp, strerror(errno));
    const pgt_expand_output *ex = &o->expand;
    uint32_t *index = malloc(((size_t)ex->point_count + 1u) * sizeof(uint32_t));
    if (!index) {
        fclose(f);
        remove(tmp);
        return pgt_cli_fail("ivy", "out of memory");
    }
    fputs("branch,segment,p0x,p0y,p0z,b1x,b1y,b1z,b2x,b2y,b2z,p1x,p1y,p1z,n0x,n0y,n0z,n1x,n1y,"
          "n1z\n",
          f);
    for (uint32_t i = 0; i < ex->point_count; ++i) {
        const uint32_t p = ex->parent[i];
        if (p == PGT_NONE) {
            index[i] = 0;
            continue;
        }
        /* a point continuing its parent's branch is one segment further along it */
        index[i] = ex->branch[p] == ex->branch[i] && ex->parent[p] != PGT_NONE ? index[p] + 1u : 0u;
        const float *q[6] = {&o->positions[3u * (size_t)p], &o->b1[3u * (size_t)i],
                             &o->b2[3u * (size_t)i],        &o->positions[3u * (size_t)i],
                             &o->normals[3u * (size_t)p],   &o->normals[3u * (size_t)i]};
        fprintf(f, "%u,%u", ex->branch[i], index[i]);
        for (int k = 0; k < 6; ++k)
            fprintf(f, ",%.9g,%.9g,%.9g", (double)q[k][0], (double)q[k][1], (double)q[k][2]);
        fputc('\n', f);
    }
    free(index);
    return pgt_cli_table_close(f, tmp, path, "ivy") ? -1 : 0;
}

/* The mask as --mask reads it back (its first channel / 255): grey, forbidden texels white (1),
 * the others black (0). */
static int write_mask_png(const char *path, const float *mask, uint32_t w, uint32_t h) {
    uint8_t *px = malloc((size_t)w * h);
    if (!px) return pgt_cli_fail("ivy", "out of memory");
    for (size_t i = 0; i < (size_t)w * h; ++i)
        px[i] = mask && mask[i] >= PGT_MARCH_MASK_THRESHOLD ? 255 : 0;
    pgt_error err = {0};
    const pgt_result r = pgt_png_write(path, w, h, 1, px, &err);
    free(px);
    return r == PGT_OK ? 0 : pgt_cli_fail("ivy", "--mask-out %s", err.message);
}

/* Lift of the --mask-mesh surface along the normal, in median texel sizes: off the base mesh
 * (no z-fighting in a render) while still hugging it. */
#define IVY_MASK_MESH_LIFT 0.05

/* --mask-mesh: the marked texels (brushed, else forbidden) as a mesh: two triangles per 2 x 2
 * block of marked inner texels of one chart, vertices at their P lifted along N. */
static int write_mask_mesh(const char *path, const pgt_ivy_scene *s) {
    const pgt_march_atlas *a = &s->atlas;
    const uint32_t w = a->width, h = a->height;
    const size_t texels = (size_t)w * h;
    const float *N[3] = {pgt_image_plane(&s->img, s->ch.nx), pgt_image_plane(&s->img, s->ch.ny),
                         pgt_image_plane(&s->img, s->ch.nz)};
    uint32_t *id = malloc(texels * sizeof(uint32_t));
    float *pos = malloc(texels * 3u * sizeof(float)), *nrm = malloc(texels * 3u * sizeof(float));
    uint32_t *tri = malloc(texels * 6u * sizeof(uint32_t));
    int rc = -1;
    if (!id || !pos || !nrm || !tri) {
        pgt_cli_fail("ivy", "out of memory");
        goto done;
    }
    uint32_t nv = 0, nt = 0;
    const float lift = (float)(IVY_MASK_MESH_LIFT * s->texel_size);
    for (size_t i = 0; i < texels; ++i) {
        id[i] = PGT_NONE;
        const int marked =
            s->brushed ? s->brushed[i] != 0 : s->mask && s->mask[i] >= PGT_MARCH_MASK_THRESHOLD;
        if (!marked || (a->codes[i] & 3u) != PGT_TEXEL_INNER) continue;
        const float p[3] = {a->texels[i].x, a->texels[i].y, a->texels[i].z};
        for (int k = 0; k < 3; ++k) {
            nrm[3u * nv + (uint32_t)k] = N[k][i];
            pos[3u * nv + (uint32_t)k] = p[k] + lift * N[k][i];
        }
        id[i] = nv++;
    }
    for (uint32_t y = 0; y + 1u < h; ++y)
        for (uint32_t x = 0; x + 1u < w; ++x) {
            const size_t i = (size_t)y * w + x;
            const uint32_t q[4] = {id[i], id[i + 1], id[i + w + 1], id[i + w]};
            if (q[0] == PGT_NONE || q[1] == PGT_NONE || q[2] == PGT_NONE || q[3] == PGT_NONE)
                continue;
            if (a->codes[i + 1] != a->codes[i] || a->codes[i + w] != a->codes[i] ||
                a->codes[i + w + 1] != a->codes[i])
                continue; /* one chart only: no triangle across a seam */
            const uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
            memcpy(&tri[3u * (size_t)nt], t, sizeof t);
            nt += 2u;
        }
    pgt_error err = {0};
    const pgt_vertex_mesh soup = {nv, nt, pos, nrm, NULL, tri};
    if (pgt_mesh_write_ply_soup(&soup, path, &err) != PGT_OK) {
        pgt_cli_fail("ivy", "--mask-mesh %s", err.message);
        goto done;
    }
    rc = 0;
done:
    free(id), free(pos), free(nrm), free(tri);
    return rc;
}

int pgt_cmd_ivy(int argc, char **argv) {
    const char *verb = "ivy", *in_path = NULL, *out_path = NULL, *grammar_path = NULL;
    const char *seed_file = NULL, *mask_path = NULL, *paint_path = NULL, *curves_path = NULL;
    const char *forbid_path = NULL, *mask_mesh = NULL;
    const char *mask_out = NULL, *density_path = NULL;
    const char *params[PGT_CLI_MAX_PARAM_FLAGS];
    uint32_t param_count = 0, seeds = 0, threads = pgt_cli_cpu_count(), res = 1024, seed = 1;
    float brush = 0.0f;
    int have_seeds = 0, no_leaves = 0, no_secondary = 0;
    pgt_march_rotation rotation = PGT_MARCH_ROTATION_ATLAS;
    uint64_t max_total_items = PGT_EXPAND_DEFAULT_MAX_TOTAL_ITEMS;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(ivy_usage, stdout);
            fputs(ivy_usage2, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--seeds")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, IVY_MAX_SEEDS, &seeds))
                return PGT_EXIT_USAGE;
            have_seeds = 1;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--grammar")) {
            if (!(grammar_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--param")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_push(verb, a, v, params, &param_count, PGT_CLI_MAX_PARAM_FLAGS))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed-file")) {
            if (!(seed_file = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--mask")) {
            if (!(mask_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--density")) {
            if (!(density_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--paint")) {
            if (!(paint_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--forbid")) {
            if (!(forbid_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--mask-mesh")) {
            if (!(mask_mesh = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--brush")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_float(verb, a, v, 0.0f, 1e30f, &brush))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--no-leaves")) {
            no_leaves = 1;
        } else if (!strcmp(a, "--no-secondary")) {
            no_secondary = 1;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_MAX_THREADS, &threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--curves")) {
            if (!(curves_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--res")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, PGT_ATLAS_MIN_RES, PGT_ATLAS_MAX_RES, &res))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, UINT32_MAX, &seed))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--rotation")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            if (!strcmp(v, "atlas"))
                rotation = PGT_MARCH_ROTATION_ATLAS;
            else if (!strcmp(v, "jacobian"))
                rotation = PGT_MARCH_ROTATION_JACOBIAN;
            else
                return pgt_cli_fail(verb, "--rotation: expected atlas or jacobian, got '%s'", v);
        } else if (!strcmp(a, "--mask-out")) {
            if (!(mask_out = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--max-total-items")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_u64(verb, a, v, 1, IVY_MAX_TOTAL_ITEMS, &max_total_items))
                return PGT_EXIT_USAGE;
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt ivy --help)", a);
        } else if (!in_path) {
            in_path = a;
        } else {
            return pgt_cli_fail(verb, "unexpected argument '%s' (one mesh or atlas only)", a);
        }
    }
    if (!in_path) return pgt_cli_fail(verb, "no mesh or atlas (see pgt ivy --help)");
    if (!have_seeds) return pgt_cli_fail(verb, "no seed count: give --seeds N");
    if (!out_path) return pgt_cli_fail(verb, "no output: give -o IVY.ply");
    if (!grammar_path) grammar_path = PGT_IVY_DEFAULT_GRAMMAR;
    for (uint32_t k = 0; k < param_count && no_secondary; ++k) /* one would silently win */
        if (!strncmp(params[k], "secondaryBranches=", 18))
            return pgt_cli_fail(verb,
                                "--param %s and --no-secondary both set secondaryBranches "
                                "(--no-secondary sets it to 0): give one",
                                params[k]);
    {
        const char *inputs[7] = {in_path,    grammar_path, seed_file,   mask_path,
                                 paint_path, forbid_path,  density_path};
        const char *outputs[4] = {out_path, curves_path, mask_out, mask_mesh};
        static const char *const flags[4] = {"-o", "--curves", "--mask-out", "--mask-mesh"};
        if (pgt_cli_refuse_overwrite(verb, inputs, 7, outputs, 4) ||
            pgt_cli_check_outputs(verb, outputs, 4))
            return PGT_EXIT_USAGE;
        /* the input named as a shared mesh ("spot.obj") is a file of the shared folder */
        for (int k = 0; k < 4; ++k)
            if (outputs[k] && pgt_cli_refuse_named_inputs(
                                  verb, &in_path, 1, PGT_CLI_SHARED_MESH_DIR, flags[k], outputs[k]))
                return PGT_EXIT_USAGE;
    }
    /* the writers write PLY and PNG whatever the name says */
    if (!pgt_cli_ends_with_ci(out_path, ".ply"))
        return pgt_cli_fail(verb, "-o %s: the output is a PLY file (name it *.ply)", out_path);
    if (mask_mesh && !pgt_cli_ends_with_ci(mask_mesh, ".ply"))
        return pgt_cli_fail(verb, "--mask-mesh %s: the output is a PLY file (name it *.ply)",
                            mask_mesh);
    if (mask_out && !pgt_cli_ends_with_ci(mask_out, ".png"))
        return pgt_cli_fail(verb, "--mask-out %s: the picture is a .png file", mask_out);

    /* the outputs appear together once all are written, none on failure (pgt_cli_stage) */
    pgt_cli_stage stage;
    stage.count = stage.dir_count = 0;
    pgt_ivy_scene s;
    pgt_ivy_output out;
    memset(&out, 0, sizeof out);
    ivy_points seedp = {0}, paint = {0}, forbid = {0};
    pgt_kdtree tree = {0};
    uint32_t *tree_ids = NULL;
    int rc = PGT_EXIT_USAGE;
    pgt_error err = {0};
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    if (pgt_cli_memory_env_check(verb) || pgt_cli_progress_start(&prog, verb))
        return PGT_EXIT_USAGE;
    pgt_progress_stage(prog.progress, "atlas", 0, "");
    if (pgt_ivy_scene_atlas(&s, verb, in_path, res, threads)) {
        pgt_cli_progress_stop(&prog);
        return PGT_EXIT_USAGE;
    }
    pgt_progress_stage(prog.progress, "inputs", 0, "");
    if (pgt_ivy_scene_grammar(&s, verb, grammar_path, params, param_count)) goto done;
    if (no_secondary && pgt_grammar_set_param(&s.grammar, "secondaryBranches", 0.0f, &err)) {
        pgt_cli_fail(verb, "--no-secondary sets the param secondaryBranches to 0: %s", err.message);
        goto done;
    }
    const pgt_march_atlas *a = &s.atlas;
    if (mask_path &&
        pgt_cli_read_context(verb, "--mask", mask_path, "mask", a->width, a->height, &s.mask))
        goto done;
    if (density_path && pgt_cli_read_context(verb, "--density", density_path, "density", a->width,
                                             a->height, &s.density))
        goto done;
    uint64_t painted = 0, forbidden = 0;
    if (paint_path || forbid_path)
        brush = brush > 0.0f ? brush : (float)(PGT_IVY_DEFAULT_BRUSH_TEXELS * s.texel_size);
    if (paint_path) {
        if (read_points(verb, "--paint", paint_path, 1, &s, &tree, &tree_ids, threads, &paint) ||
            pgt_ivy_scene_paint(&s, verb, paint.p3, paint.n, paint.stroke_first, paint.strokes,
                                brush, threads, 0, &painted))
            goto done;
    }
    if (forbid_path) {
        if (read_points(verb, "--forbid", forbid_path, 1, &s, &tree, &tree_ids, threads, &forbid) ||
            pgt_ivy_scene_paint(&s, verb, forbid.p3, forbid.n, forbid.stroke_first, forbid.strokes,
                                brush, threads, 1, &forbidden))
            goto done;
    }
    if (seed_file &&
        read_points(verb, "--seed-file", seed_file, 0, &s, &tree, &tree_ids, threads, &seedp))
        goto done;
    if (!(s.seeds = malloc((size_t)seeds * sizeof(pgt_expand_seed)))) {
        pgt_cli_fail(verb, "out of memory");
        goto done;
    }
    s.seed_count = seeds;
    const char *placement = "random";
    if (seed_file) {
        if (seedp.n < seeds) {
            pgt_cli_fail(verb, "--seeds %u: %s lists %u seeds", seeds, seed_file, seedp.n);
            goto done;
        }
        placement = seed_file;
        for (uint32_t i = 0; i < seeds; ++i) {
            pgt_expand_seed *q = &s.seeds[i];
            q->x = seedp.tex[2u * i], q->y = seedp.tex[2u * i + 1u];
            q->dx = seedp.dir[2u * i], q->dy = seedp.dir[2u * i + 1u];
            if (q->dx == 0.0f && q->dy == 0.0f) random_dir(seed, i, &q->dx, &q->dy);
        }
    } else if (paint_path) {
        placement = "stroke starts";
        for (uint32_t i = 0; i < seeds; ++i) {
            const uint32_t k = i % paint.strokes, f = paint.stroke_first[k];
            const uint32_t e = paint.stroke_first[k + 1u];
            pgt_expand_seed *q = &s.seeds[i];
            q->x = paint.tex[2u * f], q->y = paint.tex[2u * f + 1u];
            q->dx = q->dy = 0.0f;
            const size_t c0 = (size_t)(uint32_t)q->y * a->width + (uint32_t)q->x;
            for (uint32_t j = f + 1u; j < e; ++j) {
                const float du = paint.tex[2u * j] - q->x, dv = paint.tex[2u * j + 1u] - q->y;
                const size_t c = (size_t)(uint32_t)paint.tex[2u * j + 1u] * a->width +
                                 (uint32_t)paint.tex[2u * j];
                if (a->codes[c] != a->codes[c0]) break; /* left the chart */
                if (du * du + dv * dv >= IVY_SEED_DIR_MIN_TEXELS * IVY_SEED_DIR_MIN_TEXELS) {
                    q->dx = du, q->dy = dv;
                    break;
                }
            }
            if (q->dx == 0.0f && q->dy == 0.0f) random_dir(seed, i, &q->dx, &q->dy);
        }
    } else if (pgt_ivy_random_seeds(s.seeds, seeds, a, s.mask, seed, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    if (mask_out &&
        write_mask_png(pgt_cli_stage_add(&stage, mask_out), s.mask, a->width, a->height))
        goto done;

    pgt_expand_input in;
    pgt_ivy_scene_input(&s, &in);
    in.seed_base = seed;
    pgt_ivy_options o;
    memset(&o, 0, sizeof o);
    o.expand.march.rotation = rotation;
    o.expand.march.mask = s.mask;
    o.expand.max_total_items = max_total_items;
    o.no_leaves = no_leaves;
    o.terminals.no_triangle_segment = 1;
    /* the bark and leaves within the memory available now (about 58 MB a seed on spot with the
     * paper's grammar): past it a clear error instead of an overcommitted allocation that gets
     * the process killed while it writes */
    o.terminals.max_bytes = pgt_cli_available_bytes();
    o.threads = threads;
    o.progress = prog.progress;
    if (pgt_ivy_generate(&out, &in, &o, &err) != PGT_OK) {
        if (err.code == PGT_ERROR_LIMIT && !strncmp(err.message, "terminals:", 10))
            pgt_cli_fail(verb,
                         "%s now (--seeds %u; the grammar's Leaves and Bark records "
                         "set the size)",
                         err.message, seeds);
        else
            pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    const double t0 = pgt_cli_now_ms();
    const pgt_terminals_output *m = &out.mesh;
    const pgt_vertex_mesh soup = {m->vertex_count, m->triangle_count, m->positions, m->normals,
                                  m->uvs,          m->triangles};
    char size_text[32];
    /* binary PLY: 8 floats a vertex, a count byte and 3 indices a triangle */
    pgt_cli_progress_stagef(
        prog.progress, "writing %s (%s)", out_path,
        pgt_cli_bytes_text(size_text, sizeof size_text,
                           32u * (uint64_t)m->vertex_count + 13u * (uint64_t)m->triangle_count));
    if (pgt_mesh_write_ply_soup(&soup, pgt_cli_stage_add(&stage, out_path), &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    if (curves_path && write_curves(pgt_cli_stage_add(&stage, curves_path), &out)) goto done;
    if (mask_mesh && write_mask_mesh(pgt_cli_stage_add(&stage, mask_mesh), &s)) goto done;
    if (pgt_cli_stage_commit(&stage, verb)) goto done;
    const double ms_write = pgt_cli_now_ms() - t0;

    printf("ivy %s: atlas %ux%u (%s, %.0f ms), %u seeds (%s), %u threads\n", in_path, a->width,
           a->height, s.built ? "built" : "read", s.ms_atlas, seeds, placement, threads);
    if (paint_path)
        printf("  painted %u strokes, %u points, brush %.4g: %llu texels\n", paint.strokes, paint.n,
               (double)brush, (unsigned long long)painted);
    if (forbid_path)
        printf("  forbidden %u strokes, %u points, brush %.4g: %llu texels\n", forbid.strokes,
               forbid.n, (double)brush, (unsigned long long)forbidden);
    printf("  %u points, %u segments, %u branches; %llu stopped marches, %llu on a candidate "
           "direction\n",
           out.expand.point_count, out.segments, out.expand.branch_count,
           (unsigned long long)out.expand.stopped_marches,
           (unsigned long long)out.expand.candidates_used);
    printf("  polygons %llu: bark %llu quads on %u segments, %u leaves; %u vertices, %u "
           "triangles\n",
           (unsigned long long)out.polygons, (unsigned long long)m->bark_quads, m->bark_segments,
           m->leaf_count, m->vertex_count, m->triangle_count);
    printf("  ms: expand %.1f, bezier %.1f, terminals %.1f (total %.1f); write %.0f\n",
           out.ms_expand, out.ms_bezier, out.ms_terminals,
           out.ms_expand + out.ms_bezier + out.ms_terminals, ms_write);
    if (m->triangle_count == 0) /* a valid PLY, but not a mesh render or subdiv will read */
        fprintf(stderr,
                "pgt ivy: note: no polygons (%u segments grew): %s has no faces, which pgt "
                "render and pgt subdiv refuse\n",
                out.segments, out_path);
    rc = PGT_EXIT_OK;
done:
    pgt_cli_progress_stop(&prog);
    pgt_cli_stage_abort(&stage);
    pgt_ivy_destroy(&out);
    points_free(&seedp);
    points_free(&paint);
    points_free(&forbid);
    pgt_kdtree_destroy(&tree);
    free(tree_ids);
    pgt_ivy_scene_free(&s);
    return rc;
}
