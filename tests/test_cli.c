/* Tests of the harness's text helpers that no command line reaches reliably: the staging names
 * a writer's error holds translated back to the outputs' paths (a writer fails inside a stage
 * only on a full disk or a vanished folder), and the CSV and comment fields of the tables. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "pgt/result.h"
#include "test_util.h"

/* A stage of n outputs named paths[k], staged under DIR/.pgt-stage.7/ (as pgt_cli_stage_add
 * names them; no folder is made). */
static void fake_stage(pgt_cli_stage *s, const char *const *paths, uint32_t n) {
    memset(s, 0, sizeof *s);
    for (uint32_t k = 0; k < n; ++k) {
        const char *slash = strrchr(paths[k], '/');
        snprintf(s->tmp[k], sizeof s->tmp[k], "out/.pgt-stage.7/%s", slash ? slash + 1 : paths[k]);
        s->path[k] = paths[k];
    }
    s->count = n;
}

/* The longest name wins where one staged name begins another (-o x.ply --curves x.ply.csv),
 * a writer's temporary name (pgt_tmp_name, cut for a long name) goes back to its output too,
 * and a message's tail of any length after a name is kept. */
static void stage_unname(void) {
    char longname[300];
    memset(longname, 'n', 250);
    memcpy(longname + 250, ".ply", 5);
    char longpath[320];
    snprintf(longpath, sizeof longpath, "out/%s", longname);
    const char *paths[3] = {"out/x.ply", "out/x.ply.csv", longpath};
    pgt_cli_stage s;
    fake_stage(&s, paths, 3);

    char msg[9000], tmp[4400];
    snprintf(msg, sizeof msg, "%s: cannot write; then %s: ok", s.tmp[1], s.tmp[0]);
    pgt_cli_stage_unname(&s, msg, sizeof msg);
    CHECK_MSG(!strcmp(msg, "out/x.ply.csv: cannot write; then out/x.ply: ok"), "%s", msg);

    REQUIRE(pgt_tmp_name(tmp, sizeof tmp, s.tmp[1]) == 0);
    snprintf(msg, sizeof msg, "%s: No space left on device", tmp);
    pgt_cli_stage_unname(&s, msg, sizeof msg);
    CHECK_MSG(!strcmp(msg, "out/x.ply.csv: No space left on device"), "%s", msg);

    REQUIRE(pgt_tmp_name(tmp, sizeof tmp, s.tmp[2]) == 0 && strchr(tmp, '~')); /* cut */
    snprintf(msg, sizeof msg, "cannot create %s", tmp);
    pgt_cli_stage_unname(&s, msg, sizeof msg);
    char want[9000];
    snprintf(want, sizeof want, "cannot create %s", longpath);
    CHECK_MSG(!strcmp(msg, want), "%s", msg);

    /* a 2000-byte tail after the name */
    char tail[2001];
    memset(tail, 't', 2000);
    tail[2000] = '\0';
    snprintf(msg, sizeof msg, "%s:%s", s.tmp[0], tail);
    pgt_cli_stage_unname(&s, msg, sizeof msg);
    snprintf(want, sizeof want, "out/x.ply:%s", tail);
    CHECK_MSG(!strcmp(msg, want), "%zu bytes", strlen(msg));

    /* a message that fills its buffer */
    char small[24];
    REQUIRE(strlen(s.tmp[0]) == 22);
    memcpy(small, s.tmp[0], 22);
    memcpy(small + 22, "!", 2);
    pgt_cli_stage_unname(&s, small, sizeof small);
    CHECK_MSG(!strcmp(small, "out/x.ply!"), "%s", small);

    /* nothing staged, or no name in the message: unchanged */
    snprintf(msg, sizeof msg, "out/.pgt-stage.8/x.ply: another process's");
    pgt_cli_stage_unname(&s, msg, sizeof msg);
    CHECK(!strcmp(msg, "out/.pgt-stage.8/x.ply: another process's"));
}

/* RFC 4180: a field is quoted (its quotes doubled) exactly when it holds a comma, a double quote
 * or a line end; a comment line's control bytes become '?'. */
static void table_fields(void) {
    static const char *const in[] = {"spot.obj", "a,b.obj", "q\"x.obj", "two\nlines", "cr\r"};
    static const char *const out[] = {"spot.obj", "\"a,b.obj\"", "\"q\"\"x.obj\"",
                                      "\"two\nlines\"", "\"cr\r\""};
    char *buf = NULL;
    size_t size = 0;
    for (int k = 0; k < 5; ++k) {
        FILE *f = open_memstream(&buf, &size);
        REQUIRE(f);
        pgt_cli_csv_field(f, in[k]);
        fclose(f);
        CHECK_MSG(!strcmp(buf, out[k]), "%s", buf);
        free(buf);
        buf = NULL;
    }
    FILE *f = open_memstream(&buf, &size);
    REQUIRE(f);
    pgt_cli_comment_text(f, "nl\nfc\t.grammar\x7f");
    fclose(f);
    CHECK_MSG(!strcmp(buf, "nl?fc?.grammar?"), "%s", buf);
    free(buf);
}

static const pgt_test_case cases[] = {
    {"stage_unname", stage_unname},
    {"table_fields", table_fields},
};

PGT_TEST_MAIN(cases)
