/* pgt harness: facade scene files (facade_scene.h; the format is in harness/README.md). */
/* realpath() and PATH_MAX are XSI: declared under _DEFAULT_SOURCE. */
#define _DEFAULT_SOURCE
#include "facade_scene.h"

#include "gen.h"
#include "text_line.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- growable arrays ---- */

static int grow(void **p, uint32_t *cap, uint32_t need, size_t elem) {
    if (need <= *cap) return 0;
    uint32_t c = *cap ? *cap : 64u;
    while (c < need) c = c > UINT32_MAX / 2u ? need : 2u * c;
    void *q = realloc(*p, (size_t)c * elem);
    if (!q) return -1;
    *p = q, *cap = c;
    return 0;
}

static char *dup_string(const char *s) {
    const size_t n = strlen(s) + 1u;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

void pgt_facade_file_free(pgt_facade_file *f) {
    if (!f) return;
    pgt_facade_scene_destroy(&f->scene);
    for (uint32_t k = 0; k < f->grammar_count; ++k) {
        pgt_grammar_destroy(&f->grammars[k]);
        if (f->names) free(f->names[k]);
        if (f->paths) free(f->paths[k]);
    }
    free(f->grammars), free(f->names), free(f->paths), free(f->building_lines);
    memset(f, 0, sizeof *f);
}

pgt_result pgt_facade_file_add_grammar(pgt_facade_file *f, const char *name, const char *path,
                                       pgt_error *err) {
    if (f->grammar_count >= PGT_FACADE_FILE_MAX_GRAMMARS)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "more than %u grammars",
                             PGT_FACADE_FILE_MAX_GRAMMARS);
    const uint32_t n = f->grammar_count + 1u;
    pgt_grammar *g = realloc(f->grammars, n * sizeof *g);
    if (g) f->grammars = g;
    char **names = realloc(f->names, n * sizeof *names);
    if (names) f->names = names;
    char **paths = realloc(f->paths, n * sizeof *paths);
    if (paths) f->paths = paths;
    if (!g || !names || !paths) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    memset(&f->grammars[n - 1u], 0, sizeof f->grammars[0]);
    f->names[n - 1u] = dup_string(name);
    f->paths[n - 1u] = dup_string(path);
    f->grammar_count = n; /* from here on pgt_facade_file_free frees this slot */
    f->scene.grammars = f->grammars;
    f->scene.grammar_count = n;
    if (!f->names[n - 1u] || !f->paths[n - 1u])
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    return pgt_grammar_load(&f->grammars[n - 1u], path, err);
}

/* ---- params of one building ---- */

/* The reader's rule: params in order; a given one takes its value, any other keeps the
 * grammar's value when pgt_grammar_set_param fixed it, else is evaluated again from the values
 * so far (as pgt_grammar_set_param re-evaluates the params defined after an override). given[k]
 * nonzero: vec[k] holds the given value on entry. Evaluation errors name FILE:LINE:COL of the
 * param. */
static pgt_result resolve_params(const pgt_grammar *g, float *vec, const uint8_t *given,
                                 pgt_error *err) {
    uint64_t counter = 0;
    pgt_grammar_env env;
    memset(&env, 0, sizeof env);
    env.counter = &counter;
    env.params = vec; /* expressions read the building's values */
    for (uint32_t k = 0; k < g->param_count; ++k) {
        if (given[k]) continue;
        if (g->params[k].overridden) {
            vec[k] = g->param_values[k];
            continue;
        }
        float v = 0.0f;
        const pgt_result r = pgt_grammar_eval(g, g->params[k].expr, NULL, 0, &env, &v, err);
        if (r != PGT_OK) return r;
        vec[k] = v;
    }
    return PGT_OK;
}

/* ---- reading ---- */

typedef struct reader {
    const char *path;
    uint32_t line;
    pgt_facade_file *f;
    uint32_t building_cap, corner_cap, param_cap;
    uint32_t *lines; /* line of each building */
    uint32_t lines_cap;
} reader;

/* Next whitespace-separated token of *s (NUL-terminated in place), NULL at the end or at '#'. */
static char *next_token(char **s) {
    char *p = *s;
    while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') ++p;
    if (!*p || *p == '#') {
        *s = p;
        return NULL;
    }
    char *t = p;
    while (*p && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n' && *p != '#') ++p;
    if (*p == '#') {
        /* a comment glued to a token: the token ends there, the rest of the line is comment */
        *p = '\0';
        *s = p;
        return t;
    }
    if (*p) *p++ = '\0';
    *s = p;
    return t;
}

static int parse_float(const char *t, float *out) {
    char *end = NULL;
    errno = 0;
    const double x = strtod(t, &end);
    if (end == t || *end || errno == ERANGE || !isfinite(x) || fabs(x) > 3.0e38) return -1;
    *out = (float)x;
    return 0;
}

static int parse_u32(const char *t, uint32_t *out) {
    if (*t < '0' || *t > '9') return -1;
    char *end = NULL;
    errno = 0;
    const unsigned long long x = strtoull(t, &end, 10);
    if (*end || errno == ERANGE || x > UINT32_MAX) return -1;
    *out = (uint32_t)x;
    return 0;
}

static int valid_name(const char *t) {
    if (!((*t >= 'A' && *t <= 'Z') || (*t >= 'a' && *t <= 'z') || *t == '_')) return 0;
    for (++t; *t; ++t)
        if (!((*t >= 'A' && *t <= 'Z') || (*t >= 'a' && *t <= 'z') || (*t >= '0' && *t <= '9') ||
              *t == '_' || *t == '-' || *t == '.'))
            return 0;
    return 1;
}

/* The folder part of path ("." when none), malloc'd. */
static char *dir_of(const char *path) {
    const char *slash = strrchr(path, '/');
    if (!slash) return dup_string(".");
    const size_t n = slash == path ? 1u : (size_t)(slash - path);
    char *d = malloc(n + 1u);
    if (!d) return NULL;
    memcpy(d, path, n);
    d[n] = '\0';
    return d;
}

static pgt_result read_grammar(reader *rd, char *rest, pgt_error *err) {
    char *name = next_token(&rest), *gpath = next_token(&rest);
    if (!name || !gpath || next_token(&rest))
        return pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: expected 'grammar NAME PATH'", rd->path,
                             rd->line);
    if (!valid_name(name))
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s:%u: grammar name '%s' is not a name (letters, digits, _ - .)",
                             rd->path, rd->line, name);
    pgt_facade_file *f = rd->f;
    for (uint32_t k = 0; k < f->grammar_count; ++k)
        if (!strcmp(f->names[k], name))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s:%u: grammar '%s' is already declared", rd->path, rd->line,
                                 name);
    char *full = NULL;
    if (gpath[0] == '/') {
        full = dup_string(gpath);
    } else {
        char *dir = dir_of(rd->path);
        if (dir) {
            const size_t n = strlen(dir) + strlen(gpath) + 2u;
            full = malloc(n);
            if (full) snprintf(full, n, "%s/%s", dir, gpath);
        }
        free(dir);
    }
    if (!full) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    pgt_error sub = {0};
    const pgt_result r = pgt_facade_file_add_grammar(f, name, full, &sub);
    free(full);
    if (r != PGT_OK)
        return pgt_error_set(err, r, "%s:%u: grammar %s: %s", rd->path, rd->line, gpath,
                             sub.message);
    const pgt_grammar *g = &f->grammars[f->grammar_count - 1u];
    if (pgt_grammar_find_param(g, "protrusion") == PGT_NONE ||
        pgt_grammar_find_param(g, "recess") == PGT_NONE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s:%u: grammar %s has no param 'protrusion' or 'recess' (a facade "
                             "grammar declares both: the facade volume, paper 003 sec. 5.2)",
                             rd->path, rd->line, gpath);
    return PGT_OK;
}

static pgt_result read_building(reader *rd, char *rest, pgt_error *err) {
    static const char *form =
        "expected 'building GRAMMAR BASE HEIGHT SEED RRGGBB [PARAM=VALUE ...] : X0 Z0 X1 Z1 ...'";
    pgt_facade_file *f = rd->f;
    pgt_facade_scene *s = &f->scene;
    char *tok[5];
    for (int i = 0; i < 5; ++i)
        if (!(tok[i] = next_token(&rest)))
            return pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: %s", rd->path, rd->line, form);
    uint32_t gi = 0;
    while (gi < f->grammar_count && strcmp(f->names[gi], tok[0])) ++gi;
    if (gi == f->grammar_count)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s:%u: grammar '%s' is not declared (a 'grammar %s PATH' line must "
                             "come first)",
                             rd->path, rd->line, tok[0], tok[0]);
    const pgt_grammar *g = &f->grammars[gi];
    pgt_facade_building b;
    memset(&b, 0, sizeof b);
    b.grammar = gi;
    if (parse_float(tok[1], &b.base))
        return pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: BASE '%s' is not a finite number",
                             rd->path, rd->line, tok[1]);
    if (parse_float(tok[2], &b.height) || !(b.height > 0.0f))
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s:%u: HEIGHT '%s' is not a finite number above 0", rd->path,
                             rd->line, tok[2]);
    if (parse_u32(tok[3], &b.seed))
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s:%u: SEED '%s' is not a whole number in [0, 4294967295]", rd->path,
                             rd->line, tok[3]);
    char *end = NULL;
    const unsigned long colour = strtoul(tok[4], &end, 16);
    /* six hex digits exactly: strtoul also takes a sign, spaces and "0x" */
    if (strlen(tok[4]) != 6 || strspn(tok[4], "0123456789abcdefABCDEF") != 6 || *end)
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s:%u: colour '%s' is not RRGGBB (6 hexadecimal digits)", rd->path,
                             rd->line, tok[4]);
    b.colour = (uint32_t)colour;

    /* params: start from the grammar's values */
    if (s->param_count > UINT32_MAX - g->param_count)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "%s:%u: too many params", rd->path, rd->line);
    if (grow((void **)&s->params, &rd->param_cap, s->param_count + g->param_count, sizeof(float)))
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    b.first_param = s->param_count;
    float *vec = s->params + b.first_param;
    uint8_t *given = calloc(g->param_count ? g->param_count : 1u, 1);
    if (!given) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    if (g->param_count) memcpy(vec, g->param_values, g->param_count * sizeof(float));
    pgt_result r = PGT_OK;
    char *t;
    for (;;) {
        t = next_token(&rest);
        if (!t) {
            r = pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: no ':' before the footprint; %s",
                              rd->path, rd->line, form);
            goto done;
        }
        if (!strcmp(t, ":")) break;
        char *eq = strchr(t, '=');
        if (!eq || eq == t) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s:%u: '%s' is not PARAM=VALUE (or the ':' before the footprint)",
                              rd->path, rd->line, t);
            goto done;
        }
        *eq = '\0';
        const uint32_t k = pgt_grammar_find_param(g, t);
        if (k == PGT_NONE) {
            r = pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                              "%s:%u: grammar '%s' has no param '%s'", rd->path, rd->line,
                              f->names[gi], t);
            goto done;
        }
        if (given[k]) {
            r = pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s:%u: param '%s' given twice",
                              rd->path, rd->line, t);
            goto done;
        }
        if (parse_float(eq + 1, &vec[k])) {
            r = pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: %s=%s: not a finite number", rd->path,
                              rd->line, t, eq + 1);
            goto done;
        }
        given[k] = 1;
    }
    pgt_error sub = {0};
    if (resolve_params(g, vec, given, &sub) != PGT_OK) {
        r = pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s:%u: params: %s", rd->path, rd->line,
                          sub.message);
        goto done;
    }

    /* footprint */
    b.first_corner = s->corner_count;
    uint32_t values = 0;
    while ((t = next_token(&rest))) {
        if (values / 2u >= PGT_FACADE_FILE_MAX_FOOTPRINT ||
            s->corner_count + values / 2u >= PGT_FACADE_FILE_MAX_CORNERS) {
            r = pgt_error_set(err, PGT_ERROR_LIMIT,
                              "%s:%u: more than %u corners in a footprint or %u in the scene",
                              rd->path, rd->line, PGT_FACADE_FILE_MAX_FOOTPRINT,
                              PGT_FACADE_FILE_MAX_CORNERS);
            goto done;
        }
        if (grow((void **)&s->corners, &rd->corner_cap, 2u * s->corner_count + values + 1u,
                 sizeof(float))) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
            goto done;
        }
        if (parse_float(t, &s->corners[2u * s->corner_count + values])) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s:%u: footprint value %u '%s' is not a finite number", rd->path,
                              rd->line, values + 1u, t);
            goto done;
        }
        ++values;
    }
    if (values % 2u || values < 6u) {
        r = pgt_error_set(err, PGT_ERROR_PARSE,
                          "%s:%u: the footprint needs X Z pairs of at least 3 corners, got %u "
                          "value%s",
                          rd->path, rd->line, values, values == 1 ? "" : "s");
        goto done;
    }
    b.corner_count = values / 2u;
    if (s->building_count >= PGT_FACADE_FILE_MAX_BUILDINGS) {
        r = pgt_error_set(err, PGT_ERROR_LIMIT, "%s:%u: more than %u buildings", rd->path, rd->line,
                          PGT_FACADE_FILE_MAX_BUILDINGS);
        goto done;
    }
    if (grow((void **)&s->buildings, &rd->building_cap, s->building_count + 1u, sizeof b) ||
        grow((void **)&rd->lines, &rd->lines_cap, s->building_count + 1u, sizeof(uint32_t))) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
        goto done;
    }
    /* the rest of the checks (orientation, edge lengths, the grammar's axiom) are the core's,
     * on this building alone so that the message names its line */
    s->corner_count += b.corner_count;
    s->param_count += g->param_count;
    s->buildings[s->building_count] = b;
    rd->lines[s->building_count] = rd->line;
    pgt_facade_scene one = *s;
    one.buildings = &s->buildings[s->building_count];
    one.building_count = 1;
    char what[600];
    snprintf(what, sizeof what, "%s:%u", rd->path, rd->line);
    if ((r = pgt_facade_scene_check(&one, what, err)) != PGT_OK) goto done;
    s->building_count++;
done:
    free(given);
    return r;
}

pgt_result pgt_facade_file_read(pgt_facade_file *out, const char *path, pgt_error *err) {
    memset(out, 0, sizeof *out);
    FILE *fp = fopen(path, "rb");
    if (!fp) return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    char *buf = malloc(PGT_FACADE_FILE_MAX_LINE + 2u);
    reader rd;
    memset(&rd, 0, sizeof rd);
    rd.path = path;
    rd.f = out;
    pgt_result r = PGT_OK;
    if (!buf) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
        goto done;
    }
    pgt_text_line got;
    size_t len;
    while ((got = pgt_text_line_read(fp, buf, PGT_FACADE_FILE_MAX_LINE + 1u, &len, rd.line == 0)) !=
           PGT_TEXT_LINE_END) {
        ++rd.line;
        if (got != PGT_TEXT_LINE_OK) { /* too long, or a NUL */
            char msg[PGT_TEXT_LINE_MESSAGE];
            pgt_text_line_message(got, path, rd.line, len, PGT_FACADE_FILE_MAX_LINE, msg,
                                  sizeof msg);
            r = pgt_error_set(err, got == PGT_TEXT_LINE_LONG ? PGT_ERROR_LIMIT : PGT_ERROR_PARSE,
                              "%s", msg);
            goto done;
        }
        char *rest = buf;
        char *word = next_token(&rest);
        if (!word) continue;
        if (!strcmp(word, "grammar")) {
            r = read_grammar(&rd, rest, err);
        } else if (!strcmp(word, "building")) {
            r = read_building(&rd, rest, err);
        } else {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s:%u: unknown statement '%s' (expected 'grammar' or 'building')",
                              path, rd.line, word);
        }
        if (r != PGT_OK) goto done;
    }
    if (ferror(fp)) { /* errno: the failed read's (a folder: EISDIR) */
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", path, strerror(errno));
        goto done;
    }
    if (out->scene.building_count == 0) {
        r = pgt_error_set(err, PGT_ERROR_EMPTY, "%s: no building", path);
        goto done;
    }
    /* the built-in geometry images (Mesh(0) is the oculus, facade.h) */
    if ((r = pgt_facade_add_builtin_gimages(&out->scene, err)) != PGT_OK) goto done;
    /* the whole scene once more: the same checks, nothing new can fail here but indices */
    r = pgt_facade_scene_check(&out->scene, path, err);
    if (r == PGT_OK) out->building_lines = rd.lines, rd.lines = NULL;
done:
    free(buf);
    free(rd.lines);
    fclose(fp);
    if (r != PGT_OK) pgt_facade_file_free(out);
    return r;
}

/* ---- writing ---- */

/* path of target relative to folder dir (both absolute, resolved), into out. */
static void relative_path(const char *dir, const char *target, char *out, size_t size) {
    size_t common = 0, i = 0;
    /* longest common prefix ending at a folder boundary */
    while (dir[i] && target[i] && dir[i] == target[i]) {
        ++i;
        if (target[i] == '/' && (dir[i] == '/' || dir[i] == '\0')) common = i;
    }
    if (dir[i] == '\0' && target[i] == '/') common = i;
    if (!strcmp(dir, "/")) common = 0;
    size_t n = 0;
    out[0] = '\0';
    for (const char *p = dir + common; *p; ++p)
        if (*p == '/' && n + 4u < size) {
            memcpy(out + n, "../", 3);
            n += 3;
            out[n] = '\0';
        }
    const char *rest = target + common + (target[common] == '/' ? 1 : 0);
    snprintf(out + n, size - n, "%s", rest);
}

/* The grammar path as the scene file at scene_path names it (relative to its folder when both
 * resolve) into out; 0 when it cannot be one token of the format (a space, a tab, '#' or a
 * control byte: the reader splits there). */
static int grammar_path_text(const char *scene_path, const char *gpath, char *out, size_t size) {
    char *dir = dir_of(scene_path);
    char rdir[PATH_MAX], rg[PATH_MAX];
    if (dir && realpath(dir, rdir) && realpath(gpath, rg))
        relative_path(rdir, rg, out, size);
    else
        snprintf(out, size, "%s", gpath);
    free(dir);
    for (const char *c = out; *c; ++c)
        if ((unsigned char)*c <= ' ' || *c == '#' || *c == 0x7f) return 0;
    return *out != 0;
}

pgt_result pgt_facade_file_write(const char *path, const char *read_path, const pgt_facade_scene *s,
                                 const char *const *names, const char *const *paths,
                                 const char *comment, pgt_error *err) {
    for (uint32_t k = 0; k < s->grammar_count; ++k) { /* what the reader could not read back */
        char rel[2 * PATH_MAX];
        if (!grammar_path_text(read_path ? read_path : path, paths[k], rel, sizeof rel))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: grammar %s's path '%s' has a space, tab, '#' or control "
                                 "byte, which a scene file cannot hold (its tokens end there)",
                                 path, names[k], rel);
    }
    const size_t tn = strlen(path) + 32u;
    char *tmp = malloc(tn);
    if (!tmp) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    pgt_tmp_name(tmp, tn, path);
    FILE *fp = fopen(tmp, "wb");
    if (!fp) {
        pgt_result r =
            pgt_error_set(err, PGT_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
        free(tmp);
        return r;
    }
    uint32_t max_params = 1;
    for (uint32_t k = 0; k < s->grammar_count; ++k)
        if (s->grammars[k].param_count > max_params) max_params = s->grammars[k].param_count;
    float *sim = malloc(max_params * sizeof(float));
    uint8_t *given = malloc(max_params);
    pgt_result r = PGT_OK;
    if (!sim || !given) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
        goto done;
    }
    if (comment) {
        const char *p = comment;
        while (*p) {
            const char *nl = strchr(p, '\n');
            const size_t n = nl ? (size_t)(nl - p) : strlen(p);
            fprintf(fp, "# %.*s\n", (int)n, p);
            p += n + (nl ? 1u : 0u);
        }
    }
    for (uint32_t k = 0; k < s->grammar_count; ++k) {
        char rel[2 * PATH_MAX];
        grammar_path_text(read_path ? read_path : path, paths[k], rel, sizeof rel);
        fprintf(fp, "grammar %s %s\n", names[k], rel);
    }
    for (uint32_t i = 0; i < s->building_count; ++i) {
        const pgt_facade_building *b = &s->buildings[i];
        const pgt_grammar *g = &s->grammars[b->grammar];
        const float *vec = s->params + b->first_param;
        fprintf(fp, "building %s %.9g %.9g %u %06X", names[b->grammar], (double)b->base,
                (double)b->height, b->seed, b->colour & 0xFFFFFFu);
        /* the params the reader needs: those unlike the grammar's, then any the reader's
         * re-evaluation would still get wrong, until none */
        for (uint32_t k = 0; k < g->param_count; ++k) given[k] = vec[k] != g->param_values[k];
        for (uint32_t pass = 0; pass <= g->param_count; ++pass) {
            for (uint32_t k = 0; k < g->param_count; ++k) sim[k] = given[k] ? vec[k] : 0.0f;
            pgt_error sub = {0};
            int changed = 0;
            if (resolve_params(g, sim, given, &sub) != PGT_OK) {
                for (uint32_t k = 0; k < g->param_count; ++k) given[k] = 1;
                break;
            }
            for (uint32_t k = 0; k < g->param_count; ++k)
                if (!given[k] && sim[k] != vec[k]) given[k] = 1, changed = 1;
            if (!changed) break;
        }
        for (uint32_t k = 0; k < g->param_count; ++k)
            if (given[k]) fprintf(fp, " %s=%.9g", g->names + g->params[k].name, (double)vec[k]);
        fputs(" :", fp);
        for (uint32_t c = 0; c < b->corner_count; ++c) {
            const float *xz = s->corners + 2u * ((size_t)b->first_corner + c);
            fprintf(fp, " %.9g %.9g", (double)xz[0], (double)xz[1]);
        }
        fputc('\n', fp);
    }
done:
    free(sim);
    free(given);
    if (fflush(fp) != 0 || ferror(fp)) {
        if (r == PGT_OK) r = pgt_error_set(err, PGT_ERROR_IO, "%s: write error", path);
    }
    if (fclose(fp) != 0 && r == PGT_OK)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: write error", path);
    if (r == PGT_OK && pgt_replace_file(tmp, path) != 0)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: cannot rename %s: %s", path, tmp,
                          strerror(errno));
    if (r != PGT_OK) remove(tmp);
    free(tmp);
    return r;
}

int pgt_facade_file_bounds(const pgt_facade_scene *s, float lo[3], float hi[3]) {
    for (int k = 0; k < 3; ++k) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t i = 0; i < s->building_count; ++i) {
        const pgt_facade_building *b = &s->buildings[i];
        for (uint32_t c = 0; c < b->corner_count; ++c) {
            const float *xz = s->corners + 2u * ((size_t)b->first_corner + c);
            lo[0] = fminf(lo[0], xz[0]), hi[0] = fmaxf(hi[0], xz[0]);
            lo[2] = fminf(lo[2], xz[1]), hi[2] = fmaxf(hi[2], xz[1]);
        }
        lo[1] = fminf(lo[1], b->base), hi[1] = fmaxf(hi[1], b->base + b->height);
    }
    return s->building_count > 0;
}

/* ---- cities, camera, light ---- */

pgt_result pgt_facade_file_city(pgt_facade_file *out, const char *grammar_path, uint32_t n,
                                uint32_t seed, pgt_error *err) {
    memset(out, 0, sizeof *out);
    /* the grammar's name: its file name without folder and extension */
    const char *base = strrchr(grammar_path, '/');
    base = base ? base + 1 : grammar_path;
    char name[64];
    snprintf(name, sizeof name, "%s", base);
    char *dot = strchr(name, '.');
    if (dot && dot != name) *dot = '\0';
    if (!valid_name(name)) snprintf(name, sizeof name, "g");
    pgt_result r = pgt_facade_file_add_grammar(out, name, grammar_path, err);
    if (r == PGT_OK) {
        pgt_facade_scene city;
        memset(&city, 0, sizeof city);
        r = pgt_gen_city(&city, &out->grammars[0], n, seed, err);
        if (r == PGT_OK) {
            city.grammars = out->grammars;
            city.grammar_count = out->grammar_count;
            out->scene = city;
        }
    }
    if (r != PGT_OK) pgt_facade_file_free(out);
    return r;
}

pgt_result pgt_facade_file_mesh(pgt_facade_file *out, const char *grammar_path, uint32_t seed,
                                const pgt_facade_quads *m, pgt_error *err) {
    memset(out, 0, sizeof *out);
    pgt_result r = pgt_facade_file_add_grammar(out, "mesh", grammar_path, err);
    pgt_facade_scene *s = &out->scene;
    if (r == PGT_OK) {
        const pgt_grammar *g = &out->grammars[0];
        s->buildings = calloc(1, sizeof *s->buildings);
        s->params = malloc((g->param_count ? g->param_count : 1u) * sizeof *s->params);
        if (!s->buildings || !s->params)
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    }
    if (r == PGT_OK) {
        const pgt_grammar *g = &out->grammars[0];
        memcpy(s->params, g->param_values, g->param_count * sizeof *s->params);
        s->param_count = g->param_count;
        float ylo = INFINITY, yhi = -INFINITY;
        for (uint32_t v = 0; v < m->vertex_count; ++v)
            ylo = fminf(ylo, m->positions[3u * v + 1u]),
            yhi = fmaxf(yhi, m->positions[3u * v + 1u]);
        pgt_facade_building *B = &s->buildings[0];
        s->building_count = 1;
        B->first_corner = 0, B->corner_count = 0, B->grammar = 0, B->first_param = 0;
        B->base = isfinite(ylo) ? ylo : 0.0f;
        B->height = isfinite(yhi) && yhi > ylo ? yhi - ylo : 1.0f;
        B->seed = seed, B->colour = PGT_FACADE_MESH_COLOUR;
        /* the built-in geometry images, as for cities and scene files (Mesh(0) is the oculus) */
        r = pgt_facade_add_builtin_gimages(s, err);
    }
    if (r != PGT_OK) pgt_facade_file_free(out);
    return r;
}

void pgt_facade_default_view(const pgt_facade_scene *s, uint32_t width, uint32_t height,
                             float eye[3], float at[3], float up[3], float *fov_deg) {
    float lo[3], hi[3];
    if (!pgt_facade_file_bounds(s, lo, hi))
        for (int k = 0; k < 3; ++k) lo[k] = -1.0f, hi[k] = 1.0f;
    pgt_facade_box_view(lo, hi, width, height, eye, at, up, fov_deg);
}

void pgt_facade_box_view(const float lo[3], const float hi[3], uint32_t width, uint32_t height,
                         float eye[3], float at[3], float up[3], float *fov_deg) {
    double c[3], radius = 0.0;
    for (int k = 0; k < 3; ++k) {
        c[k] = 0.5 * ((double)lo[k] + (double)hi[k]);
        radius += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
    }
    radius = 0.5 * sqrt(radius);
    if (!(radius > 0.0)) radius = 1.0;
    const double deg = 3.14159265358979323846 / 180.0;
    const double az = PGT_FACADE_VIEW_AZIMUTH * deg, el = PGT_FACADE_VIEW_ELEVATION * deg;
    double half = 0.5 * (double)PGT_FACADE_VIEW_FOV * deg;
    const double aspect = (double)width / (double)(height ? height : 1u);
    if (aspect < 1.0) half = atan(aspect * tan(half));
    const double dist = PGT_FACADE_VIEW_MARGIN * radius / sin(half);
    const double dir[3] = {cos(el) * sin(az), sin(el), cos(el) * cos(az)};
    for (int k = 0; k < 3; ++k) {
        at[k] = (float)c[k];
        eye[k] = (float)(c[k] + dist * dir[k]);
        up[k] = k == 1 ? 1.0f : 0.0f;
    }
    *fov_deg = PGT_FACADE_VIEW_FOV;
}

void pgt_facade_default_light(const pgt_facade_scene *s, float light[3]) {
    float lo[3], hi[3];
    if (!pgt_facade_file_bounds(s, lo, hi))
        for (int k = 0; k < 3; ++k) lo[k] = -1.0f, hi[k] = 1.0f;
    pgt_facade_box_light(lo, hi, light);
}

void pgt_facade_box_light(const float lo[3], const float hi[3], float light[3]) {
    double radius = 0.0;
    for (int k = 0; k < 3; ++k) radius += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
    radius = 0.5 * sqrt(radius);
    const double off[3] = {PGT_FACADE_LIGHT_OFFSET_X, PGT_FACADE_LIGHT_OFFSET_Y,
                           PGT_FACADE_LIGHT_OFFSET_Z};
    for (int k = 0; k < 3; ++k)
        light[k] = (float)(0.5 * ((double)lo[k] + (double)hi[k]) + off[k] * radius);
}
