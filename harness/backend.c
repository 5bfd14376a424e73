/* pgt harness: the backend dispatcher (see backend.h). */
#include "backend.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#if PGT_HAVE_CL
#include "pgt_cl.h"
#endif
#if PGT_HAVE_VK
#include "pgt_vk.h"
#endif

const char *pgt_backend_kind_name(pgt_backend_kind kind) {
    return kind == PGT_BACKEND_CL ? "cl" : kind == PGT_BACKEND_VK ? "vk" : "cpu";
}

int pgt_backend_parse(const char *verb, const char *text, pgt_backend_kind *out) {
    if (!strcmp(text, "cpu")) {
        *out = PGT_BACKEND_CPU;
    } else if (!strcmp(text, "cl")) {
        *out = PGT_BACKEND_CL;
    } else if (!strcmp(text, "vk")) {
        *out = PGT_BACKEND_VK;
    } else {
        pgt_cli_fail(verb, "--backend: expected cpu, cl or vk, got '%s'", text);
        return 1;
    }
    return 0;
}

int pgt_backend_flags(const char *verb, int argc, char **argv, int *i, pgt_backend_kind *kind,
                      uint32_t *device) {
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--backend")) {
        if (!(v = pgt_cli_value(verb, argc, argv, i)) || pgt_backend_parse(verb, v, kind))
            return -1;
        return 1;
    }
    if (!strcmp(a, "--device")) {
        if (!(v = pgt_cli_value(verb, argc, argv, i)) || pgt_cli_uint(verb, a, v, 0, 1024, device))
            return -1;
        return 1;
    }
    return 0;
}

int pgt_backend_parse_list(const char *verb, const char *text, int asked[2]) {
    asked[0] = asked[1] = 0;
    if (!strcmp(text, "both") || !strcmp(text, "cl,vk") || !strcmp(text, "vk,cl"))
        asked[0] = asked[1] = 1;
    else if (!strcmp(text, "cl"))
        asked[0] = 1;
    else if (!strcmp(text, "vk"))
        asked[1] = 1;
    else if (strcmp(text, "none") != 0)
        return pgt_cli_fail(verb, "--backends: expected cl, vk, both or none, got '%s'", text);
    return 0;
}

int pgt_backend_open_asked(const char *verb, pgt_backend gpu[2], const int asked[2],
                           uint32_t device, int must) {
    memset(gpu, 0, 2 * sizeof(*gpu)); /* kind CPU: not open */
    for (int g = 0; g < 2; ++g) {
        if (!asked[g]) continue;
        const pgt_backend_kind kind = g ? PGT_BACKEND_VK : PGT_BACKEND_CL;
        pgt_error err = {0};
        if (pgt_backend_open(&gpu[g], kind, device, 1, &err) != PGT_OK) {
            if (must) {
                pgt_backend_close(&gpu[0]), pgt_backend_close(&gpu[1]);
                return pgt_cli_fail(verb, "%s", err.message);
            }
            fprintf(stderr, "pgt %s: no %s timing (%s)\n", verb, pgt_backend_kind_name(kind),
                    err.message);
            pgt_backend_close(&gpu[g]);
        }
    }
    return 0;
}

pgt_result pgt_backend_list(pgt_backend_kind kind, pgt_gpu_device_list *out, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    (void)err, (void)kind;
#if PGT_HAVE_CL
    if (kind == PGT_BACKEND_CL) return pgt_cl_list_devices(out, err);
#endif
#if PGT_HAVE_VK
    if (kind == PGT_BACKEND_VK) return pgt_vk_list_devices(out, err);
#endif
    return PGT_OK;
}

pgt_result pgt_backend_open(pgt_backend *b, pgt_backend_kind kind, uint32_t device, int profiling,
                            pgt_error *err) {
    memset(b, 0, sizeof(*b));
    b->kind = kind, b->device = device, b->profiling = profiling;
    pgt_gpu_profile *prof = profiling ? &b->profile : NULL;
    if (kind == PGT_BACKEND_CPU) {
        snprintf(b->name, sizeof(b->name), "cpu (reference)");
        return PGT_OK;
    }
    if ((kind == PGT_BACKEND_CL && !PGT_HAVE_CL) || (kind == PGT_BACKEND_VK && !PGT_HAVE_VK))
        return pgt_error_set(
            err, PGT_ERROR_UNSUPPORTED, "--backend %s: this build of pgt has no %s backend",
            pgt_backend_kind_name(kind), kind == PGT_BACKEND_CL ? "OpenCL" : "Vulkan");
    pgt_gpu_device_list list;
    pgt_result r = pgt_backend_list(kind, &list, err);
    if (r != PGT_OK) return r;
    if (device >= list.count)
        return pgt_error_set(err, PGT_ERROR_BACKEND,
                             "--backend %s --device %u: no such device (%u %s device%s found; "
                             "see pgt devices)",
                             pgt_backend_kind_name(kind), device, list.count,
                             kind == PGT_BACKEND_CL ? "OpenCL" : "Vulkan",
                             list.count == 1 ? "" : "s");
    (void)prof;
#if PGT_HAVE_CL
    if (kind == PGT_BACKEND_CL) {
        r = pgt_cl_create(&b->cl, device, prof, err);
        if (r == PGT_OK)
            snprintf(b->name, sizeof(b->name), "cl %u: %s", device, pgt_cl_device_name(b->cl));
    }
#endif
#if PGT_HAVE_VK
    if (kind == PGT_BACKEND_VK) {
        const char *v = getenv("PGT_VK_VALIDATION");
        r = pgt_vk_create(&b->vk, device, prof, v && !strcmp(v, "1"), err);
        if (r == PGT_OK)
            snprintf(b->name, sizeof(b->name), "vk %u: %s", device, pgt_vk_device_name(b->vk));
    }
#endif
    return r;
}

void pgt_backend_close(pgt_backend *b) {
    if (!b) return;
#if PGT_HAVE_CL
    if (b->cl) pgt_cl_destroy(b->cl);
#endif
#if PGT_HAVE_VK
    if (b->vk) pgt_vk_destroy(b->vk);
#endif
    pgt_gpu_profile_free(&b->profile);
    memset(b, 0, sizeof(*b));
}

pgt_result pgt_backend_sqrt3(pgt_backend *b, pgt_mesh *out, const pgt_mesh *in,
                             const pgt_sqrt3_options *opts, pgt_gpu_times *times, pgt_error *err) {
    if (times) memset(times, 0, sizeof(*times));
    (void)b;
#if PGT_HAVE_CL
    if (b->kind == PGT_BACKEND_CL) return pgt_cl_sqrt3(b->cl, out, in, opts, times, err);
#endif
#if PGT_HAVE_VK
    if (b->kind == PGT_BACKEND_VK) return pgt_vk_sqrt3(b->vk, out, in, opts, times, err);
#endif
    return pgt_sqrt3_subdivide(out, in, opts, err);
}

pgt_result pgt_backend_march(pgt_backend *b, const pgt_march_atlas *a, const pgt_march_options *o,
                             float length, uint32_t steps, uint32_t count, pgt_march_state *states,
                             pgt_march_state *rec_states, uint32_t *rec_events, uint32_t *out_taken,
                             pgt_gpu_times *times, pgt_error *err) {
    if (times) memset(times, 0, sizeof(*times));
#if PGT_HAVE_CL
    if (b->kind == PGT_BACKEND_CL)
        return pgt_cl_march(b->cl, a, o, length, steps, count, states, rec_states, rec_events,
                            out_taken, times, err);
#endif
#if PGT_HAVE_VK
    if (b->kind == PGT_BACKEND_VK)
        return pgt_vk_march(b->vk, a, o, length, steps, count, states, rec_states, rec_events,
                            out_taken, times, err);
#endif
    if (!(length > 0.0f && length <= PGT_MARCH_MAX_LENGTH))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "step length %g is outside (0, %g] texels", (double)length,
                             (double)PGT_MARCH_MAX_LENGTH);
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t k = 0;
        for (; k < steps; ++k) {
            pgt_march_info info;
            const pgt_march_event ev = pgt_march_step(a, o, &states[i], length, 0.0f, &info);
            if (rec_states) {
                const size_t r = (size_t)i * steps + k;
                rec_states[r] = states[i];
                rec_events[r] = PGT_MARCH_EVENT_WORD(ev, info.stop, info.jumps);
            }
            if (ev == PGT_MARCH_STOP) break;
        }
        if (out_taken) out_taken[i] = k;
        if (rec_states)
            for (uint32_t j = k + 1; j < steps; ++j) {
                rec_states[(size_t)i * steps + j] = states[i];
                rec_events[(size_t)i * steps + j] = rec_events[(size_t)i * steps + k];
            }
    }
    return PGT_OK;
}

int pgt_backend_march_record_valid(const pgt_march_atlas *a, const pgt_march_state *s,
                                   uint32_t word) {
    if (PGT_MARCH_EVENT_OF(word) > PGT_MARCH_STOP ||
        PGT_MARCH_STOP_OF(word) > PGT_MARCH_STOP_BOUNCE)
        return 0;
    if (!(isfinite(s->dx) && isfinite(s->dy) && isfinite(s->in_dx) && isfinite(s->in_dy))) return 0;
    if (!(s->x >= 0.0f && s->y >= 0.0f && s->x < (float)a->width && s->y < (float)a->height))
        return 0;
    const uint32_t t = (uint32_t)s->y * a->width + (uint32_t)s->x;
    return s->chart < a->chart_count && a->codes[t] == PGT_MARCH_CODE(PGT_TEXEL_INNER, s->chart);
}

typedef struct kernel_row {
    const char *name;
    uint32_t launches;
    double total;
    double *ms;
} kernel_row;

void pgt_backend_print_profile(const pgt_backend *b, FILE *f) {
    const pgt_gpu_profile *p = &b->profile;
    if (b->kind == PGT_BACKEND_CPU) return;
    fprintf(f, "profile: %s (device time per kernel, %u launches)\n", b->name, p->count);
    if (p->count == 0) return;
    kernel_row *rows = calloc(p->count, sizeof(*rows));
    double *all = malloc(p->count * sizeof(double));
    if (!rows || !all) {
        free(rows), free(all);
        fprintf(f, "profile: out of memory\n");
        return;
    }
    uint32_t n = 0, used = 0;
    double sum = 0.0;
    for (uint32_t i = 0; i < p->count; ++i) { /* kernels in order of first launch */
        uint32_t r = 0;
        while (r < n && strcmp(rows[r].name, p->events[i].name)) ++r;
        if (r == n) rows[n++].name = p->events[i].name;
    }
    fprintf(f, "  %-28s %9s %12s %12s\n", "kernel", "launches", "total ms", "median ms");
    for (uint32_t r = 0; r < n; ++r) {
        rows[r].ms = all + used;
        for (uint32_t i = 0; i < p->count; ++i)
            if (!strcmp(rows[r].name, p->events[i].name)) {
                rows[r].ms[rows[r].launches++] = p->events[i].ms;
                rows[r].total += p->events[i].ms;
            }
        used += rows[r].launches;
        sum += rows[r].total;
        fprintf(f, "  %-28s %9u %12.3f %12.4f\n", rows[r].name, rows[r].launches, rows[r].total,
                pgt_cli_median(rows[r].ms, rows[r].launches));
    }
    fprintf(f, "  %-28s %9u %12.3f\n", "all kernels", p->count, sum);
    free(rows), free(all);
}
