/* pgt harness: shared command-line helpers. */
#include "cli.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "gen.h"
#include "pgt/image.h"
#include "pgt/mesh_io.h"
#include "png_io.h"
#include "progress_line.h"
#include "signal_cleanup.h"

/* The stage whose names pgt_cli_fail turns back into the outputs' paths (pgt_cli_stage_add
 * sets it; a verb stages its outputs in one place). */
static const pgt_cli_stage *cli_active_stage;

int pgt_cli_fail(const char *verb, const char *fmt, ...) {
    char msg[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    /* a writer names the staging file it was given: the user's path instead */
    if (cli_active_stage) pgt_cli_stage_unname(cli_active_stage, msg, sizeof msg);
    pgt_cli_progress_silence(); /* the error is stderr's last line */
    fprintf(stderr, "pgt %s: %s\n", verb, msg);
    return PGT_EXIT_USAGE;
}

int pgt_cli_u64(const char *verb, const char *flag, const char *text, uint64_t lo, uint64_t hi,
                uint64_t *out) {
    char *end = NULL;
    errno = 0;
    if (!text || !(*text >= '0' && *text <= '9')) goto bad; /* no spaces, no sign */
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || *end || v < lo || v > hi) goto bad;
    *out = (uint64_t)v;
    return 0;
bad:
    pgt_cli_fail(verb, "%s: expected a whole number from %llu to %llu, got '%s'", flag,
                 (unsigned long long)lo, (unsigned long long)hi, text ? text : "");
    return -1;
}

int pgt_cli_uint(const char *verb, const char *flag, const char *text, uint32_t lo, uint32_t hi,
                 uint32_t *out) {
    uint64_t v = 0;
    if (pgt_cli_u64(verb, flag, text, lo, hi, &v)) return -1;
    *out = (uint32_t)v;
    return 0;
}

int pgt_cli_int(const char *verb, const char *flag, const char *text, int32_t *out) {
    char *end = NULL;
    errno = 0;
    /* a digit or a minus sign first: strtoll would skip spaces and take '+' */
    const int starts = text && ((*text >= '0' && *text <= '9') || *text == '-');
    long long v = starts ? strtoll(text, &end, 10) : 0;
    if (!starts || errno || *end || v < INT32_MIN || v > INT32_MAX) {
        pgt_cli_fail(verb, "%s: expected a 32-bit integer, got '%s'", flag, text ? text : "");
        return -1;
    }
    *out = (int32_t)v;
    return 0;
}

const char *pgt_cli_value(const char *verb, int argc, char **argv, int *i) {
    if (*i + 1 >= argc) {
        pgt_cli_fail(verb, "%s needs a value (see pgt %s --help)", argv[*i], verb);
        return NULL;
    }
    return argv[++*i];
}

int pgt_cli_push(const char *verb, const char *flag, const char *value, const char **list,
                 uint32_t *count, uint32_t max) {
    if (*count >= max) return pgt_cli_fail(verb, "%s given more than %u times", flag, max);
    list[(*count)++] = value;
    return 0;
}

double pgt_cli_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

uint32_t pgt_cli_cpu_count(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (uint32_t)n : 1u;
}

void pgt_cli_json_string(FILE *f, const char *s) {
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; ++p) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

void pgt_cli_machine(char *buf, size_t size) {
    char model[256] = "unknown CPU";
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f)) {
            if (strncmp(line, "model name", 10) == 0) {
                char *c = strchr(line, ':');
                if (c) {
                    c++;
                    while (*c == ' ' || *c == '\t') c++;
                    c[strcspn(c, "\n")] = 0;
                    snprintf(model, sizeof model, "%s", c);
                }
                break;
            }
        }
        fclose(f);
    }
    const double gib = (double)pgt_cli_memory_bytes() / 1073741824.0;
    snprintf(buf, size, "%s, %u cores, %.0f GiB", model, pgt_cli_cpu_count(), gib);
}

uint64_t pgt_cli_memory_bytes(void) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? (uint64_t)pages * (uint64_t)page : 0u;
}

/* The first number of a file, after its line starting with key (NULL: the first line); 0 when
 * the file, the key or a number is missing. */
static uint64_t file_number(const char *path, const char *key) {
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[256];
    uint64_t v = 0;
    while (fgets(line, sizeof line, f)) {
        if (key && strncmp(line, key, strlen(key))) continue;
        const char *p = line + (key ? strlen(key) : 0);
        while (*p == ' ' || *p == '\t') ++p;
        if (*p >= '0' && *p <= '9') v = strtoull(p, NULL, 10);
        break;
    }
    fclose(f);
    return v;
}

/* PGT_MEMORY_AVAILABLE as a whole number of bytes > 0, or 0 (unset, empty or malformed). */
static uint64_t memory_env(const char **text) {
    const char *env = getenv("PGT_MEMORY_AVAILABLE");
    *text = env;
    if (!env || !(*env >= '0' && *env <= '9')) return 0; /* no blanks, no sign */
    char *end = NULL;
    errno = 0;
    const unsigned long long v = strtoull(env, &end, 10);
    return !errno && *end == 0 ? (uint64_t)v : 0;
}

int pgt_cli_memory_env_check(const char *verb) {
    const char *env = NULL;
    if (memory_env(&env) || !env || !*env) return 0;
    return pgt_cli_fail(verb,
                        "the environment variable PGT_MEMORY_AVAILABLE is '%s': give a whole "
                        "number of bytes > 0, or unset it (the machine's reading)",
                        env);
}

uint64_t pgt_cli_available_bytes(void) {
    const char *env = NULL;
    const uint64_t given = memory_env(&env);
    if (given) return given; /* malformed: pgt_cli_memory_env_check refused it */
    uint64_t avail = file_number("/proc/meminfo", "MemAvailable:") * 1024u;
    if (avail == 0) avail = pgt_cli_memory_bytes();
    /* the cgroup's limit, usage and its page cache the kernel can drop (as docker stats counts) */
    static const char *const limit[2][4] = {
        {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current", "/sys/fs/cgroup/memory.stat",
         "inactive_file "},
        {"/sys/fs/cgroup/memory/memory.limit_in_bytes",
         "/sys/fs/cgroup/memory/memory.usage_in_bytes", "/sys/fs/cgroup/memory/memory.stat",
         "total_inactive_file "}};
    for (int k = 0; k < 2; ++k) {
        const uint64_t max = file_number(limit[k][0], NULL), usage = file_number(limit[k][1], NULL);
        if (max == 0 || usage == 0) continue; /* "max" (no limit) or not this cgroup version */
        const uint64_t cache = file_number(limit[k][2], limit[k][3]);
        const uint64_t used = usage > cache ? usage - cache : 0;
        const uint64_t left = max > used ? max - used : 0;
        if (avail == 0 || left < avail) avail = left ? left : 1u; /* 0 says "unknown" */
    }
    return avail;
}

const char *pgt_cli_bytes_text(char *buf, size_t size, uint64_t bytes) {
    const double mib = (double)bytes / (1024.0 * 1024.0);
    if (mib < 1024.0)
        snprintf(buf, size, "%.0f MiB", mib);
    else
        snprintf(buf, size, "%.1f GiB", mib / 1024.0);
    return buf;
}

void pgt_cli_commit(char *buf, size_t size) {
    snprintf(buf, size, "unknown");
#ifdef PGT_SOURCE_DIR
    FILE *p = popen("git -C '" PGT_SOURCE_DIR "' rev-parse --short=12 HEAD 2>/dev/null", "r");
    if (!p) return;
    char line[64] = "";
    if (fgets(line, sizeof line, p)) {
        line[strcspn(line, "\n")] = 0;
        if (*line) snprintf(buf, size, "%s", line);
    }
    pclose(p);
    /* "-dirty": a tracked file differs from HEAD, other than the tables and figures the main
     * job writes as it goes (results/, paper_figs/out/), which would mark every later table */
    p = popen("git -C '" PGT_SOURCE_DIR "' status --porcelain --untracked-files=no -- . "
              "':(exclude)results' ':(exclude)paper_figs/out' 2>/dev/null",
              "r");
    if (!p) return;
    if (fgets(line, sizeof line, p) && strcmp(buf, "unknown") != 0) {
        size_t n = strlen(buf);
        if (n + 7 < size) memcpy(buf + n, "-dirty", 7);
    }
    pclose(p);
#endif
}

void pgt_cli_date(char *buf, size_t size) {
    time_t t = time(NULL);
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(buf, size, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

int pgt_cli_same_file(const char *a, const char *b) {
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int pgt_cli_same_output(const char *a, const char *b) {
    if (!strcmp(a, b) || pgt_cli_same_file(a, b)) return 1;
    /* files that do not exist yet ("o.ply" and "./o.ply"): one name in one folder */
    const char *na = strrchr(a, '/'), *nb = strrchr(b, '/');
    if (strcmp(na ? na + 1 : a, nb ? nb + 1 : b)) return 0;
    char da[4096], db[4096];
    if (pgt_path_folder(a, da, sizeof da) || pgt_path_folder(b, db, sizeof db))
        return 0; /* a folder name past PATH_MAX: neither can be written */
    return pgt_cli_same_file(da, db);
}

int pgt_cli_check_outputs(const char *verb, const char *const *paths, int n) {
    for (int k = 0; k < n; ++k) {
        const char *path = paths[k];
        if (!path) continue;
        pgt_cli_cleanup_add(path, PGT_CLI_CLEANUP_TMP_OF); /* its writer's PATH.tmp.PID */
        char why[128];
        if (pgt_output_check(path, why, sizeof why))
            return pgt_cli_fail(verb, "cannot write %s: %s", path, why);
    }
    return 0;
}

int pgt_cli_refuse_overwrite(const char *verb, const char *const *inputs, int n_in,
                             const char *const *outputs, int n_out) {
    for (int o = 0; o < n_out; ++o) {
        for (int k = 0; k < n_in; ++k)
            if (outputs[o] && inputs[k] && pgt_cli_same_file(inputs[k], outputs[o]))
                return pgt_cli_fail(verb, "%s is an input file; pgt never overwrites an input",
                                    outputs[o]);
        for (int k = 0; k < o; ++k) /* one would replace the other */
            if (outputs[o] && outputs[k] && pgt_cli_same_output(outputs[o], outputs[k]))
                return pgt_cli_fail(verb, "%s is named for two outputs", outputs[o]);
    }
    return 0;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double pgt_cli_median(const double *v, uint32_t n) {
    if (n == 0) return 0.0;
    double *c = malloc(n * sizeof(double));
    if (!c) return v[0];
    memcpy(c, v, n * sizeof(double));
    qsort(c, n, sizeof(double), cmp_double);
    double m = n % 2 ? c[n / 2] : 0.5 * (c[n / 2 - 1] + c[n / 2]);
    free(c);
    return m;
}

double pgt_cli_min(const double *v, uint32_t n) {
    double m = n ? v[0] : 0.0;
    for (uint32_t i = 1; i < n; ++i)
        if (v[i] < m) m = v[i];
    return m;
}

const char *const pgt_cli_shared_meshes[] = {
    "spot.obj",  "bob_tri.obj",          "ogre_bs_rest.obj", "human_neutral.obj",
    "pizza.obj", "nefertiti-lowres.obj", "mountain.obj"};
const uint32_t pgt_cli_shared_mesh_count =
    sizeof pgt_cli_shared_meshes / sizeof *pgt_cli_shared_meshes;

int pgt_cli_name_list(const char *verb, const char *flag, const char *text, char *buf,
                      size_t buf_size, const char **out, uint32_t max, uint32_t *n) {
    const size_t len = strlen(text);
    if (len >= buf_size)
        return pgt_cli_fail(verb, "%s: list longer than %zu characters", flag, buf_size - 1u);
    if (strspn(text, ",") == len) return pgt_cli_fail(verb, "%s: empty list", flag);
    memcpy(buf, text, len + 1u);
    /* split by hand: strtok would merge "a,,b" into two items and hide the typo */
    for (char *item = buf;;) {
        char *comma = strchr(item, ',');
        if (comma) *comma = '\0';
        if (!*item) return pgt_cli_fail(verb, "%s %s: an empty item in the list", flag, text);
        if (*n >= max) return pgt_cli_fail(verb, "%s: at most %u items in all", flag, max);
        out[(*n)++] = item;
        if (!comma) return 0;
        item = comma + 1;
    }
}

const char *pgt_cli_mesh_label(const char *name) { return pgt_path_name(name); }

void pgt_cli_comment_text(FILE *f, const char *s) {
    for (; *s; ++s) fputc((unsigned char)*s < 0x20u || *s == 0x7F ? '?' : *s, f);
}

void pgt_cli_csv_field(FILE *f, const char *s) {
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"') fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* The file a mesh name stands for (pgt_cli_load_named's rule), or NULL for a generated one. */
static const char *named_path(const char *name, const char *shared_dir, char *buf, size_t size) {
    if (pgt_gen_default_find(name) != PGT_NONE) return NULL;
    struct stat st;
    if (stat(name, &st) == 0 || strchr(name, '/')) return name;
    snprintf(buf, size, "%s/%s", shared_dir, name);
    return buf;
}

pgt_result pgt_cli_load_named(const char *name, const char *shared_dir, pgt_mesh *out,
                              pgt_error *err) {
    return pgt_cli_load_named_origin(name, shared_dir, out, NULL, err);
}

pgt_result pgt_cli_load_named_origin(const char *name, const char *shared_dir, pgt_mesh *out,
                                     pgt_mesh_origin *origin, pgt_error *err) {
    if (origin) memset(origin, 0, sizeof *origin);
    if (!name || !*name) /* not the shared folder's path, which an empty name would join to */
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "no mesh named (an empty name)");
    char buf[4096];
    const char *path = named_path(name, shared_dir, buf, sizeof buf);
    if (!path) return pgt_gen_default(pgt_gen_default_find(name), out, err);
    struct stat st;
    if (path == buf &&
        stat(path, &st) != 0) /* a bare name found nowhere: say where it was looked for */
        return pgt_error_set(err, PGT_ERROR_IO,
                             "%s: not a generated dataset (pgt_datasets --list), not a file in "
                             "this folder, not in %s",
                             name, shared_dir);
    pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, origin};
    return pgt_mesh_read(out, path, &ro, err);
}

int pgt_cli_refuse_named_inputs(const char *verb, const char *const *names, uint32_t n,
                                const char *shared_dir, const char *flag, const char *out) {
    for (uint32_t k = 0; k < n; ++k) {
        char buf[4096];
        const char *path = named_path(names[k], shared_dir, buf, sizeof buf);
        if (path && pgt_cli_same_file(path, out))
            return pgt_cli_fail(verb, "%s %s is the input mesh %s; pgt never overwrites an input",
                                flag, out, names[k]);
    }
    return 0;
}

int pgt_cli_uint_list(const char *verb, const char *flag, const char *text, uint32_t lo,
                      uint32_t hi, uint32_t *out, uint32_t max, uint32_t *n) {
    char buf[1024];
    const char *items[256];
    uint32_t count = 0;
    if (pgt_cli_name_list(verb, flag, text, buf, sizeof buf, items, max < 256u ? max : 256u,
                          &count))
        return PGT_EXIT_USAGE;
    for (*n = 0; *n < count; ++*n)
        if (pgt_cli_uint(verb, flag, items[*n], lo, hi, &out[*n])) return PGT_EXIT_USAGE;
    return 0;
}

FILE *pgt_cli_tmp_open(const char *path, char *tmp, size_t tmp_size) {
    pgt_cli_cleanup_add(path, PGT_CLI_CLEANUP_TMP_OF);
    pgt_tmp_name(tmp, tmp_size, path);
    return fopen(tmp, "w");
}

FILE *pgt_cli_table_open(const char *path, const char *title, char *tmp, size_t tmp_size) {
    FILE *f = pgt_cli_tmp_open(path, tmp, tmp_size); /* the folder: pgt_cli_quick_out made it */
    if (!f) return NULL;
    char machine[512], commit[64], date[64];
    pgt_cli_machine(machine, sizeof machine);
    pgt_cli_commit(commit, sizeof commit);
    pgt_cli_date(date, sizeof date);
    fprintf(f, "# %s\n# machine: %s\n# commit: %s\n# date: %s\n", title, machine, commit, date);
    return f;
}

int pgt_cli_table_close(FILE *f, const char *tmp, const char *path, const char *verb) {
    const int bad = ferror(f);
    if (fclose(f) != 0 || bad || pgt_replace_file(tmp, path) != 0) {
        remove(tmp);
        return pgt_cli_fail(verb, "cannot write %s: %s", path, strerror(errno));
    }
    return 0;
}

int pgt_cli_quick_outs(const char *verb, int quick, const char *const *out, const char *const *def,
                       const char *const *flag, int n) {
    for (int k = 0; k < n; ++k)
        if (quick && out[k] == def[k])
            return pgt_cli_fail(verb,
                                "--quick without %s would replace %s, the committed table, "
                                "with a smoke run's numbers: give %s FILE",
                                flag[k], def[k], flag[k]);
    for (int k = 0; k < n; ++k) /* pgt_cli_bench_close's OUT.failed must fit too */
        if (strlen(pgt_path_name(out[k])) + strlen(".failed") > PGT_NAME_MAX)
            return pgt_cli_fail(verb,
                                "%s %s: a file name of at most %d bytes (a run with failures "
                                "writes its rows to NAME.failed beside it)",
                                flag[k], out[k], PGT_NAME_MAX - (int)strlen(".failed"));
    enum { MAX_OUTS = 8 };
    if (n > MAX_OUTS || pgt_cli_refuse_overwrite(verb, NULL, 0, out, n))
        return n > MAX_OUTS ? pgt_cli_fail(verb, "%d outputs (at most %d)", n, (int)MAX_OUTS)
                            : PGT_EXIT_USAGE;
    /* the folders are made when missing (results/ may not exist yet; one level: a folder
     * whose parent existed before this call, whatever the flags' order) and the ones made here
     * removed when a check fails */
    char dir[MAX_OUTS][4096], parent[4096];
    int made[MAX_OUTS] = {0}, may[MAX_OUTS] = {0};
    struct stat st;
    for (int k = 0; k < n; ++k) {
        pgt_path_folder(out[k], dir[k], sizeof dir[k]);
        pgt_path_folder(dir[k], parent, sizeof parent);
        may[k] = stat(parent, &st) == 0 && S_ISDIR(st.st_mode);
    }
    for (int k = 0; k < n; ++k) made[k] = may[k] && mkdir(dir[k], 0777) == 0;
    const int r = pgt_cli_check_outputs(verb, out, n);
    for (int k = n - 1; k >= 0 && r; --k)
        if (made[k]) rmdir(dir[k]);
    return r;
}

int pgt_cli_quick_out(const char *verb, int quick, const char *out, const char *def) {
    static const char *const flag = "--out";
    return pgt_cli_quick_outs(verb, quick, &out, &def, &flag, 1);
}

int pgt_cli_bench_close(FILE *f, const char *tmp, const char *path, const char *verb,
                        int failures) {
    if (!failures) return pgt_cli_table_close(f, tmp, path, verb);
    char failed[4200];
    snprintf(failed, sizeof failed, "%s.failed", path);
    if (pgt_cli_table_close(f, tmp, failed, verb)) return -1;
    fprintf(stderr, "pgt %s: %d failure%s: %s left as it was; this run's rows are in %s\n", verb,
            failures, failures == 1 ? "" : "s", path, failed);
    return 0;
}

const char *pgt_cli_stage_add(pgt_cli_stage *s, const char *path) {
    if (s->count == PGT_CLI_STAGE_MAX) return NULL;
    /* the staging folder inside path's folder */
    char folder[4096], dir[4200];
    pgt_path_folder(path, folder, sizeof folder);
    snprintf(dir, sizeof dir, "%s/.pgt-stage.%ld", folder, (long)getpid());
    uint32_t d = 0;
    while (d < s->dir_count && strcmp(s->dir[d], dir)) ++d;
    if (d == s->dir_count) {
        snprintf(s->dir[d], sizeof s->dir[0], "%s", dir);
        /* only a folder made here is removed at the end; when it cannot be made (the output's
         * folder is missing or read-only) the writer fails on the name below and says why */
        pgt_cli_cleanup_add(dir, PGT_CLI_CLEANUP_DIR); /* first: no moment made but unregistered */
        s->made[d] = mkdir(dir, 0700) == 0;
        s->dir_count++;
    }
    char *tmp = s->tmp[s->count];
    snprintf(tmp, sizeof s->tmp[0], "%s/%s", dir, pgt_path_name(path));
    pgt_cli_cleanup_add(tmp, PGT_CLI_CLEANUP_FILE);
    s->path[s->count++] = path;
    cli_active_stage = s;
    return tmp;
}

void pgt_cli_stage_unname(const pgt_cli_stage *s, char *msg, size_t size) {
    /* one pass: at each place the longest of the names (one staged name may begin another:
     * -o x.ply --curves x.ply.csv), replaced in place, the rest of the message moved */
    char tmp[PGT_CLI_STAGE_MAX][4400]; /* pgt_tmp_name of each staged name */
    for (uint32_t k = 0; k < s->count; ++k)
        if (pgt_tmp_name(tmp[k], sizeof tmp[k], s->tmp[k]) != 0) tmp[k][0] = '\0';
    size_t len = strlen(msg);
    for (size_t at = 0; at < len;) {
        const char *to = NULL;
        size_t nf = 0;
        for (uint32_t k = 0; k < s->count; ++k)
            for (int t = 0; t < 2; ++t) {
                const char *from = t ? tmp[k] : s->tmp[k];
                const size_t n = strlen(from);
                if (n > nf && !strncmp(msg + at, from, n)) nf = n, to = s->path[k];
            }
        if (!to) {
            ++at;
            continue;
        }
        size_t nt = strlen(to);
        if (at + nt >= size) nt = size - 1u - at; /* cut at the buffer's end */
        size_t tail = len - (at + nf);
        if (at + nt + tail >= size) tail = size - 1u - at - nt;
        memmove(msg + at + nt, msg + at + nf, tail);
        memcpy(msg + at, to, nt);
        len = at + nt + tail;
        msg[len] = '\0';
        at += nt;
    }
}

/* Removes the staged files from the from-th on (unlink: never a user's folder of that name) and
 * the staging folders made here (rmdir: only when empty); the stage is empty afterwards. */
static void stage_clear(pgt_cli_stage *s, uint32_t from) {
    for (uint32_t k = from; k < s->count; ++k) unlink(s->tmp[k]);
    for (uint32_t d = 0; d < s->dir_count; ++d)
        if (s->made[d]) rmdir(s->dir[d]);
    s->count = s->dir_count = 0;
    if (cli_active_stage == s) cli_active_stage = NULL;
}

void pgt_cli_stage_abort(pgt_cli_stage *s) { stage_clear(s, 0); }

int pgt_cli_stage_commit(pgt_cli_stage *s, const char *verb) {
    /* every path checked before the first rename, so that none is made when one would fail (a
     * rename would also replace a device such as /dev/null or a fifo by a regular file) */
    if (pgt_cli_check_outputs(verb, s->path, (int)s->count)) {
        stage_clear(s, 0);
        return -1;
    }
    for (uint32_t k = 0; k < s->count; ++k)
        if (pgt_replace_file(s->tmp[k], s->path[k]) != 0) {
            const int e = errno;
            stage_clear(s, k);
            pgt_cli_fail(verb, "cannot write %s: %s", s->path[k], strerror(e));
            return -1;
        }
    stage_clear(s, s->count);
    return 0;
}

int pgt_cli_floats(const char *verb, const char *flag, const char *text, uint32_t n, float *out) {
    const char *p = text;
    for (uint32_t k = 0; k < n; ++k) {
        char *end = NULL;
        /* no errno test: an overflow gives inf (refused), an underflow a denormal or zero, which
         * is what the number is in float32 (the caller's own checks judge it) */
        const float v = strtof(p, &end);
        if (end == p || !isfinite(v) || *end != (k + 1 < n ? ',' : '\0')) {
            pgt_cli_fail(verb, "%s: expected %u finite numbers separated by commas, got '%s'", flag,
                         n, text);
            return -1;
        }
        out[k] = v;
        p = end + 1;
    }
    return 0;
}

int pgt_cli_float(const char *verb, const char *flag, const char *text, float lo_excl, float hi,
                  float *out) {
    char *end = NULL;
    const float v = strtof(text, &end); /* underflow: see pgt_cli_floats */
    if (end == text || *end || !isfinite(v) || !(v > lo_excl) || v > hi) {
        pgt_cli_fail(verb, "%s: expected a number > %g and <= %g, got '%s'", flag, (double)lo_excl,
                     (double)hi, text);
        return -1;
    }
    *out = v;
    return 0;
}

int pgt_cli_ends_with_ci(const char *s, const char *suffix) {
    const size_t n = strlen(s), m = strlen(suffix);
    if (n < m) return 0;
    for (size_t i = 0; i < m; ++i)
        if (tolower((unsigned char)s[n - m + i]) != tolower((unsigned char)suffix[i])) return 0;
    return 1;
}

int pgt_cli_read_context(const char *verb, const char *flag, const char *path, const char *channel,
                         uint32_t w, uint32_t h, float **out) {
    pgt_error err = {0};
    *out = NULL;
    uint32_t iw = 0, ih = 0;
    float *m = NULL;
    if (pgt_cli_ends_with_ci(path, ".png")) {
        uint32_t pc;
        uint8_t *px = NULL;
        if (pgt_png_read(path, &iw, &ih, &pc, &px, &err) != PGT_OK)
            return pgt_cli_fail(verb, "%s %s", flag, err.message), -1;
        if (iw == w && ih == h && (m = malloc((size_t)w * h * sizeof(float))))
            for (size_t i = 0; i < (size_t)w * h; ++i) m[i] = (float)px[i * pc] / 255.0f;
        free(px);
    } else {
        pgt_image img = {0};
        if (pgt_image_read_exr_threads(&img, path, pgt_cli_cpu_count(), &err) != PGT_OK)
            return pgt_cli_fail(verb, "%s %s", flag, err.message), -1;
        int32_t c = pgt_image_find_channel(&img, channel);
        if (c < 0) c = pgt_image_find_channel(&img, "Y");
        if (c < 0) c = pgt_image_find_channel(&img, "R");
        if (c < 0 && img.channel_count == 1) c = 0;
        if (c < 0) {
            pgt_image_destroy(&img);
            return pgt_cli_fail(verb,
                                "%s %s: no channel '%s', 'Y' or 'R' (and more than one channel)",
                                flag, path, channel),
                   -1;
        }
        iw = img.width, ih = img.height;
        const float *plane = pgt_image_plane(&img, (uint32_t)c);
        for (size_t i = 0; iw == w && ih == h && i < (size_t)w * h; ++i)
            if (!isfinite(plane[i])) { /* a PNG's values are finite by construction */
                pgt_cli_fail(verb, "%s %s: pixel (%u, %u) is %g, not a finite number", flag, path,
                             (uint32_t)(i % w), (uint32_t)(i / w), (double)plane[i]);
                pgt_image_destroy(&img);
                return -1;
            }
        if (iw == w && ih == h && (m = malloc((size_t)w * h * sizeof(float))))
            memcpy(m, plane, (size_t)w * h * sizeof(float));
        pgt_image_destroy(&img);
    }
    if (iw != w || ih != h)
        return pgt_cli_fail(verb, "%s %s: %u x %u pixels, the atlas is %u x %u", flag, path, iw, ih,
                            w, h),
               -1;
    if (!m) return pgt_cli_fail(verb, "out of memory"), -1;
    *out = m;
    return 0;
}

/* Whether s is a decimal number as a grammar file writes one: an optional sign, digits with an
 * optional fraction (or a fraction alone), an optional exponent; no blanks, hex, inf or nan
 * (which strtof would take). */
static int decimal_number(const char *s) {
    if (*s == '+' || *s == '-') ++s;
    int digits = 0;
    while (*s >= '0' && *s <= '9') ++s, ++digits;
    if (*s == '.')
        for (++s; *s >= '0' && *s <= '9'; ++s) ++digits;
    if (!digits) return 0;
    if (*s == 'e' || *s == 'E') {
        ++s;
        if (*s == '+' || *s == '-') ++s;
        if (!(*s >= '0' && *s <= '9')) return 0;
        while (*s >= '0' && *s <= '9') ++s;
    }
    return *s == '\0';
}

int pgt_cli_grammar_params(const char *verb, pgt_grammar *g, const char *const *overrides,
                           uint32_t count) {
    pgt_error err = {0};
    for (uint32_t k = 0; k < count; ++k) {
        const char *o = overrides[k], *eq = strchr(o, '=');
        char name[PGT_GRAMMAR_MAX_NAME_CHARS + 1];
        char *end = NULL;
        const float value = eq ? strtof(eq + 1, &end) : 0.0f;
        if (!eq || eq == o || (size_t)(eq - o) > PGT_GRAMMAR_MAX_NAME_CHARS || end == eq + 1 ||
            *end != '\0' || !isfinite(value) || !decimal_number(eq + 1))
            return pgt_cli_fail(verb,
                                "--param %s: expected NAME=VALUE with a finite decimal number", o);
        memcpy(name, o, (size_t)(eq - o));
        name[eq - o] = '\0';
        if (pgt_grammar_set_param(g, name, value, &err) != PGT_OK)
            return pgt_cli_fail(verb, "--param %s: %s", o, err.message);
    }
    return 0;
}

void pgt_cli_print_float(float x) {
    char buf[32];
    for (int digits = 6; digits <= 9; ++digits) {
        snprintf(buf, sizeof buf, "%.*g", digits, (double)x);
        if (strtof(buf, NULL) == x) break;
    }
    fputs(buf, stdout);
}

void pgt_cli_skip_mesh(const char *verb, const char *name, const char *msg) {
    const size_t n = strlen(name);
    if (!strncmp(msg, name, n) && msg[n] == ':')
        fprintf(stderr, "pgt %s: skipping %s\n", verb, msg);
    else
        fprintf(stderr, "pgt %s: skipping %s: %s\n", verb, name, msg);
}

int pgt_cli_load_atlas_mesh(const char *verb, const char *path, const char *hint, pgt_mesh *out,
                            pgt_mesh_origin *origin) {
    pgt_error err = {0};
    if (pgt_cli_load_named_origin(path, PGT_CLI_SHARED_MESH_DIR, out, origin, &err) != PGT_OK)
        return pgt_cli_fail(verb, "%s", err.message);
    if (!out->uvs) {
        pgt_mesh_destroy(out);
        pgt_mesh_origin_destroy(origin);
        return pgt_cli_fail(verb,
                            "%s: no UVs: run a parametrization first (datasets_gen gives UV-less "
                            "meshes an atlas with MeshLab's Voronoi Atlas)%s",
                            path, hint ? hint : "");
    }
    uint32_t first = 0, face = 0;
    const uint32_t n = pgt_mesh_repeated_faces(out, &first, &face);
    if (n) {
        char place[4200];
        pgt_mesh_origin_where(origin, path, face, place, sizeof place);
        pgt_mesh_destroy(out);
        pgt_mesh_origin_destroy(origin);
        return pgt_cli_fail(verb,
                            "%s: face %u (0-based) repeats face %u, the same three vertices in "
                            "the same order (%u such faces): their charts would lie at one place",
                            place, face, first, n);
    }
    pgt_mesh_origin_keep_vertices(origin); /* the build names vertices only */
    return 0;
}
