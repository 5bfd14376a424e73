/* pgt harness: shared command-line helpers (flag values, timing, JSON, machine facts).
 * Every verb reports bad flags the same way: one line on stderr, exit code 2. */
#ifndef PGT_CLI_H
#define PGT_CLI_H

#include <stdint.h>
#include <stdio.h>

#include "pgt/grammar.h"
#include "pgt/mesh.h"
#include "pgt/result.h"

struct pgt_mesh_origin; /* pgt/mesh_io.h */

#define PGT_EXIT_OK 0
#define PGT_EXIT_FAIL 1  /* the work ran and found a problem (e.g. a diff outside tolerance) */
#define PGT_EXIT_USAGE 2 /* bad flag, bad value, bad input file, or an error while working */

/* Prints "pgt VERB: message" on stderr and returns PGT_EXIT_USAGE. */
int pgt_cli_fail(const char *verb, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Parses a whole number in [lo, hi] from a flag value; on failure prints the flag and value. */
int pgt_cli_uint(const char *verb, const char *flag, const char *text, uint32_t lo, uint32_t hi,
                 uint32_t *out);
/* The same in 64 bits. */
int pgt_cli_u64(const char *verb, const char *flag, const char *text, uint64_t lo, uint64_t hi,
                uint64_t *out);
int pgt_cli_int(const char *verb, const char *flag, const char *text, int32_t *out);

/* Value of flag argv[*i] (advancing *i), or NULL after printing "FLAG needs a value". */
const char *pgt_cli_value(const char *verb, int argc, char **argv, int *i);

/* Monotonic milliseconds. */
double pgt_cli_now_ms(void);

/* Number of online CPUs (at least 1). */
uint32_t pgt_cli_cpu_count(void);

/* Writes s as a JSON string (quoted, escaped). */
void pgt_cli_json_string(FILE *f, const char *s);

/* "CPU model, N cores, M GiB" of this machine; "git short hash[-dirty]" of the source tree or
 * "unknown" (-dirty: a tracked file differs from HEAD; results/ and paper_figs/out/, which the
 * main job rewrites, do not count); UTC date-time in ISO 8601. Each writes into buf. */
void pgt_cli_machine(char *buf, size_t size);
/* Bytes of physical memory (sysconf), 0 when unknown. */
uint64_t pgt_cli_memory_bytes(void);

/* The memory a new allocation can have without swapping (MemAvailable of /proc/meminfo: free
 * memory plus the page cache the kernel can drop), or pgt_cli_memory_bytes where that file
 * does not tell; less when the process's cgroup (v2 memory.max, v1 memory.limit_in_bytes)
 * leaves less below its limit. What a guard against overcommit compares with: RAM that other
 * programs hold is not there for the taking. The environment variable PGT_MEMORY_AVAILABLE (a
 * whole number of bytes) replaces the reading: a smaller budget on a shared machine, and the
 * tests' fixed one. */
uint64_t pgt_cli_available_bytes(void);

/* 0 unless PGT_MEMORY_AVAILABLE is set, not empty and not a whole number of bytes > 0 (it was
 * ignored then, the machine's reading used instead); else one line naming it, PGT_EXIT_USAGE.
 * The verbs that take a budget from it (ivy, woven, facade) call it with their flags. */
int pgt_cli_memory_env_check(const char *verb);
/* "95 MiB" below 1 GiB, else "22.4 GiB": a size for messages (buf of 32 bytes). */
const char *pgt_cli_bytes_text(char *buf, size_t size, uint64_t bytes);
void pgt_cli_commit(char *buf, size_t size);
void pgt_cli_date(char *buf, size_t size);

/* Nonzero when a and b name the same existing file (device and inode). */
int pgt_cli_same_file(const char *a, const char *b);

/* Nonzero when two output paths would write one file: the same text, the same existing file,
 * or (files not written yet) the same name in the same existing folder ("o.ply", "./o.ply"). */
int pgt_cli_same_output(const char *a, const char *b);

/* Before the work: 0 when each of the n output paths (NULL entries skipped) can be written
 * as far as can be told now (an existing regular file, or a new name in an existing folder
 * this process may write to); else one line "pgt VERB: cannot write PATH: why" (the words the
 * final write would use) and PGT_EXIT_USAGE, so that a long run does not end on a typo in -o.
 * The final write still checks (the file system may change meanwhile). */
int pgt_cli_check_outputs(const char *verb, const char *const *paths, int n);

/* 0 when none of the n_out outputs is one of the n_in inputs and no two outputs are the same
 * (NULL entries are skipped); else prints "pgt VERB: OUTPUT is an input file; pgt never
 * overwrites an input" (or "OUTPUT is named for two outputs") and returns PGT_EXIT_USAGE. */
int pgt_cli_refuse_overwrite(const char *verb, const char *const *inputs, int n_in,
                             const char *const *outputs, int n_out);

/* Median and minimum of n values (sorts a copy). */
double pgt_cli_median(const double *v, uint32_t n);
double pgt_cli_min(const double *v, uint32_t n);

/* Parses a comma-separated list of at most max whole numbers in [lo, hi] into out (*n values);
 * on failure prints a one-line error naming verb and flag and returns nonzero. */
int pgt_cli_uint_list(const char *verb, const char *flag, const char *text, uint32_t lo,
                      uint32_t hi, uint32_t *out, uint32_t max, uint32_t *n);

/* An output written atomically: opens path.tmp.PID (its name in tmp) for writing; NULL (errno
 * set) when it cannot be opened. pgt_cli_table_close finishes it. */
FILE *pgt_cli_tmp_open(const char *path, char *tmp, size_t tmp_size);

/* A results table (its folder made by pgt_cli_quick_out): opens it with pgt_cli_tmp_open and
 * writes "# title" and the "# machine:", "# commit:", "# date:" lines every table starts with.
 * NULL (errno set) when the file cannot be opened. */
FILE *pgt_cli_table_open(const char *path, const char *title, char *tmp, size_t tmp_size);

/* Closes a file of pgt_cli_tmp_open or pgt_cli_table_open and renames it over path; on failure
 * removes it, prints a one-line error for verb and returns nonzero. */
int pgt_cli_table_close(FILE *f, const char *tmp, const char *path, const char *verb);

/* A benchmark's table: pgt_cli_table_close when the run had no failures; else the rows go to
 * PATH.failed and PATH is left as it was (a run that lost meshes or columns does not replace a
 * whole table, e.g. the main job's results/), with a note on stderr. Nonzero when the file
 * cannot be written. */
int pgt_cli_bench_close(FILE *f, const char *tmp, const char *path, const char *verb, int failures);

/* A bench's outputs, checked before the benchmark runs: --quick with a default output (out[k] ==
 * def[k], the same pointer: flag[k] not given) is refused (the default is results/NAME.csv, the
 * committed table), and so is an output that cannot be written (pgt_cli_check_outputs: a
 * device, a folder). Their folders are made when missing, one level (every bench calls this
 * before pgt_cli_table_open), and removed again when an output is refused, so a refused run
 * leaves no empty folder. 0 otherwise. */
int pgt_cli_quick_outs(const char *verb, int quick, const char *const *out, const char *const *def,
                       const char *const *flag, int n);

/* pgt_cli_quick_outs of one output, flag --out. */
int pgt_cli_quick_out(const char *verb, int quick, const char *out, const char *def);

/* Outputs of one command that appear together or not at all: each output is written under its
 * staging name (pgt_cli_stage_add: FOLDER/.pgt-stage.PID/NAME for FOLDER/NAME, a folder of this
 * process beside the output, so the name is as long as the output's and the rename stays in one
 * file system), and pgt_cli_stage_commit renames them all over their paths once every one is
 * written, after checking that each path is a regular file or nothing (a folder would fail the
 * rename, and a device such as /dev/null would be replaced by a regular file when run as root);
 * a command that fails first calls pgt_cli_stage_abort, which removes the staged files and the
 * staging folders, so a failed run leaves no output and every older file as it was. While a
 * stage holds names, pgt_cli_fail prints each staging name as its output's path. A stage is
 * initialised with its counts zero. */
#define PGT_CLI_STAGE_MAX 8
typedef struct pgt_cli_stage {
    uint32_t count, dir_count;
    const char *path[PGT_CLI_STAGE_MAX];
    char tmp[PGT_CLI_STAGE_MAX][4400];
    char dir[PGT_CLI_STAGE_MAX][4200]; /* the staging folders */
    int made[PGT_CLI_STAGE_MAX];       /* made by this stage (removed at the end) */
} pgt_cli_stage;

/* The name to write output `path` under (NULL when PGT_CLI_STAGE_MAX are staged already). */
const char *pgt_cli_stage_add(pgt_cli_stage *s, const char *path);
/* In msg (size bytes, NUL-terminated), each staging name and a writer's temporary name of it
 * (pgt_tmp_name) back to its output's path, the longest name first where several begin at one
 * place: what pgt_cli_fail prints while a stage holds names. */
void pgt_cli_stage_unname(const pgt_cli_stage *s, char *msg, size_t size);
/* Renames the staged files over their paths; on failure prints a one-line error for verb,
 * removes what is left staged and returns nonzero. The stage is empty afterwards. */
int pgt_cli_stage_commit(pgt_cli_stage *s, const char *verb);
/* Removes the staged files; the stage is empty afterwards. */
void pgt_cli_stage_abort(pgt_cli_stage *s);

/* The meshes of ../shared/datasets/meshes the project's defaults use (all 2-manifold), and that
 * folder as configured at build time. */
extern const char *const pgt_cli_shared_meshes[];
extern const uint32_t pgt_cli_shared_mesh_count;
#define PGT_CLI_SHARED_MESH_DIR PGT_SHARED_DIR "/datasets/meshes"

/* Appends the comma-separated names of `text` (a flag's value) to out[*n ...], at most max in
 * all: copies text into buf (which the names then point into; it must outlive them). A clear
 * error naming `flag` (returns PGT_EXIT_USAGE) for an empty list, an empty item ("a,,b", a
 * leading or trailing comma), too many names or a text that does not fit buf, else 0. */
int pgt_cli_name_list(const char *verb, const char *flag, const char *text, char *buf,
                      size_t buf_size, const char **out, uint32_t max, uint32_t *n);

/* A mesh name as a table shows it: the file name of a path (what follows the last '/'), the
 * name itself otherwise. Benchmark CSVs compare across machines, whose folders differ. */
const char *pgt_cli_mesh_label(const char *name);

/* Writes s to f inside a '#' comment line of a table: control bytes (a line end would start a
 * line that is not a comment) as '?'. */
void pgt_cli_comment_text(FILE *f, const char *s);

/* Writes s to f as one CSV field (RFC 4180): as it is, or between double quotes with every '"'
 * doubled when it holds a comma, a double quote or a line end, so that a mesh named "a,b" stays
 * one column of a benchmark table. */
void pgt_cli_csv_field(FILE *f, const char *s);

/* Loads a mesh named on a command line: a generated default dataset (pgt_datasets --list), an
 * existing file, or a file name inside shared_dir. UVs are kept, so are labels. */
pgt_result pgt_cli_load_named(const char *name, const char *shared_dir, pgt_mesh *out,
                              pgt_error *err);

/* pgt_cli_load_named, with the places of the file's records in *origin (pgt/mesh_io.h; zeroed
 * for a generated mesh or on failure) so that a later error can name a line. */
pgt_result pgt_cli_load_named_origin(const char *name, const char *shared_dir, pgt_mesh *out,
                                     struct pgt_mesh_origin *origin, pgt_error *err);

/* A benchmark's line for a mesh it skips: "pgt VERB: skipping NAME: MSG", or without "NAME: "
 * when MSG already begins with the name (the readers and builders name their input). */
void pgt_cli_skip_mesh(const char *verb, const char *name, const char *msg);

/* Loads the mesh an atlas is built of (pgt atlas, pgt ivy): pgt_cli_load_named, then refuses a
 * mesh without UVs (`hint` ends that message) and one with repeated faces
 * (pgt_mesh_repeated_faces: their charts lie at one place in 3D, and every pointer search
 * tests them all; 150,000 copies of one triangle, a 2 MB OBJ, ran for minutes). origin (may be
 * NULL) gets the vertices' places (pgt_cli_load_named_origin, then
 * pgt_mesh_origin_keep_vertices: the build names vertices only) for pgt_atlas_options.origin. 0,
 * or PGT_EXIT_USAGE after one error line (*out and *origin then zeroed). */
int pgt_cli_load_atlas_mesh(const char *verb, const char *path, const char *hint, pgt_mesh *out,
                            struct pgt_mesh_origin *origin);

/* 0 unless out (given by `flag`) is the file of one of the n mesh names (pgt_cli_load_named's
 * rule); else prints "pgt VERB: FLAG OUT is the input mesh NAME; ..." and returns
 * PGT_EXIT_USAGE (a benchmark's table or pgt ivy's outputs must not replace their input). */
int pgt_cli_refuse_named_inputs(const char *verb, const char *const *names, uint32_t n,
                                const char *shared_dir, const char *flag, const char *out);

/* Parses exactly n comma-separated finite floats ("A,B,C") into out; a single number > lo_excl
 * and <= hi. On failure both print one line naming verb, flag and text and return nonzero. */
int pgt_cli_floats(const char *verb, const char *flag, const char *text, uint32_t n, float *out);
int pgt_cli_float(const char *verb, const char *flag, const char *text, float lo_excl, float hi,
                  float *out);

/* Nonzero when s ends with suffix, ignoring ASCII case (".PNG" is ".png"). */
int pgt_cli_ends_with_ci(const char *s, const char *suffix);

/* Prints x to stdout in the shortest %g form that reads back as the same float (for printed
 * --camera values a user can paste back). */
void pgt_cli_print_float(float x);

/* Reads an external-context image (a mask, a density) of w x h pixels into w * h floats
 * (malloc'd): PNG, the first channel (gray, or red), 0..255 as 0..1; EXR, the channel named
 * `channel` ("mask", "density"), else 'Y', else 'R', else the only one; every value must be
 * finite (an EXR may hold NaN or infinity). On failure prints "pgt VERB: FLAG PATH: ..." (a wrong
 * size names both sizes, a non-finite value its pixel) and returns nonzero. */
int pgt_cli_read_context(const char *verb, const char *flag, const char *path, const char *channel,
                         uint32_t w, uint32_t h, float **out);

/* Most --param flags of one command: more than any grammar's params would need on one line. */
#define PGT_CLI_MAX_PARAM_FLAGS 256u

/* Appends `value` of a repeatable flag to list[*count]: 0, or "FLAG given more than MAX times"
 * and PGT_EXIT_USAGE when the list holds `max` already. */
int pgt_cli_push(const char *verb, const char *flag, const char *value, const char **list,
                 uint32_t *count, uint32_t max);

/* Sets grammar params from `count` overrides "NAME=VALUE" (--param): 0 on success, else prints
 * "pgt VERB: --param NAME=VALUE: why" and returns nonzero. */
int pgt_cli_grammar_params(const char *verb, pgt_grammar *g, const char *const *overrides,
                           uint32_t count);

/* Verbs. */
int pgt_cmd_subdiv(int argc, char **argv);
int pgt_cmd_bench(int argc, char **argv);
int pgt_cmd_diff(int argc, char **argv);
int pgt_cmd_devices(int argc, char **argv);
int pgt_cmd_atlas(int argc, char **argv);
int pgt_cmd_march(int argc, char **argv);
int pgt_cmd_grammar(int argc, char **argv);
int pgt_cmd_ivy(int argc, char **argv);
int pgt_cmd_woven(int argc, char **argv);
int pgt_cmd_bench_ivy(int argc, char **argv); /* argv[0] = "bench", argv[1] = "ivy" */
int pgt_cmd_render(int argc, char **argv);
int pgt_cmd_bench_atlas(int argc, char **argv); /* argv[0] = "atlas" */
int pgt_cmd_bench_march(int argc, char **argv); /* argv[0] = "bench", argv[1] = "march" */
int pgt_cmd_bench_woven(int argc, char **argv); /* argv[0] = "bench", argv[1] = "woven" */
int pgt_cmd_facade(int argc, char **argv);
int pgt_cmd_bench_facade(int argc, char **argv); /* argv[0] = "bench", argv[1] = "facade" */

#endif
