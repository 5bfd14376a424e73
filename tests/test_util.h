/* pgt tests: a tiny table-driven test runner (meshoptimizer demo/tests.cpp style).
 *
 * Each test program lists its cases as { "name", function } and calls pgt_test_main(). A case
 * fails when any CHECK in it fails; failures print file:line and the expression. The program
 * prints one line per case and a closing "N passed, N failed" line, and exits 1 on any failure.
 * Run one case with `test_x NAME`. */
#ifndef PGT_TEST_UTIL_H
#define PGT_TEST_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct pgt_test_case {
    const char *name;
    void (*fn)(void);
} pgt_test_case;

static int pgt_test_failures_in_case;

#define CHECK(cond)                                                                            \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            fprintf(stderr, "  %s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);         \
            pgt_test_failures_in_case++;                                                       \
        }                                                                                      \
    } while (0)

#define CHECK_MSG(cond, ...)                                                                   \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            fprintf(stderr, "  %s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);         \
            fprintf(stderr, __VA_ARGS__);                                                      \
            fputc('\n', stderr);                                                               \
            pgt_test_failures_in_case++;                                                       \
        }                                                                                      \
    } while (0)

/* For preconditions of a case: stop the case on failure. */
#define REQUIRE(cond)                                                                          \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            fprintf(stderr, "  %s:%d: REQUIRE failed: %s\n", __FILE__, __LINE__, #cond);       \
            pgt_test_failures_in_case++;                                                       \
            return;                                                                            \
        }                                                                                      \
    } while (0)

/* The ':'-separated paths of environment variable `var` (tests/meshlab_atlas_check.sh passes the
 * meshes it makes to test_atlas and test_march in PGT_TEST_MESHES): copied into buf, at most max
 * of them stored in out (pointing into buf); returns how many: 0 when unset, empty or longer
 * than buf (the caller then does what it does without a list). */
static inline unsigned pgt_test_env_paths(const char *var, char *buf, size_t size, char **out,
                                          unsigned max) {
    const char *env = getenv(var);
    unsigned n = 0;
    if (!env || !*env || strlen(env) >= size) return 0;
    memcpy(buf, env, strlen(env) + 1);
    for (char *p = buf; *p && n < max;) {
        out[n++] = p;
        char *colon = strchr(p, ':');
        if (!colon) break;
        *colon = '\0';
        p = colon + 1;
    }
    return n;
}

static inline int pgt_test_main(int argc, char **argv, const pgt_test_case *cases, int count) {
    int passed = 0, failed = 0;
    for (int i = 0; i < count; ++i) {
        if (argc > 1 && strcmp(argv[1], cases[i].name) != 0) continue;
        pgt_test_failures_in_case = 0;
        cases[i].fn();
        if (pgt_test_failures_in_case == 0) {
            printf("PASS %s\n", cases[i].name);
            passed++;
        } else {
            printf("FAIL %s (%d checks)\n", cases[i].name, pgt_test_failures_in_case);
            failed++;
        }
        fflush(stdout);
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 && passed > 0 ? 0 : 1;
}

#define PGT_TEST_MAIN(table)                                                                   \
    int main(int argc, char **argv) {                                                          \
        return pgt_test_main(argc, argv, table, (int)(sizeof(table) / sizeof(table[0])));      \
    }

#endif
