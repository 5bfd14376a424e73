/* pgt tests: the grammar language, rule compiler and expression evaluator (ref_cpu/src/grammar_*.c;
 * paper 000 sections 5, 7 and 8; grammars/README.md).
 *
 * Known answers: the listing of a small grammar equals a hand-written text; expressions equal
 * hand-computed values (precedence, associativity) and libm in double (every function); rand is
 * in range, a pure function of (seed, stream, counter) and advances the counter once per draw;
 * the context callback receives texCoord. Every compiled grammar is checked against the layout
 * contract of grammar.h by an independent walk (indices in range, each expression's stack depth
 * re-simulated). The bad corpus (tests/data/grammars/bad) states code, place and message in its
 * header; limits are generated here; mutation fuzzing from fixed seeds must give PGT_OK or a
 * FILE:LINE:COL: message (the Sanitize build runs it under ASan+UBSan). */
#include <ctype.h>
#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cli.h>
#include <pgt/grammar.h>
#include <pgt/rng.h>

#include "test_util.h"

#define GOOD_DIR PGT_TEST_DATA_DIR "/grammars/good"
#define BAD_DIR PGT_TEST_DATA_DIR "/grammars/bad"
#define IVY_PATH PGT_SOURCE_DIR "/grammars/ivy.grammar"

/* A float32 function against libm in double, relative to max(|exact|, 1e-6): glibc documents
 * its float functions within 1-2 ulp ("Errors in Math Functions"); 4 ulp leaves room for other
 * libms. The arguments are exact in float32, so the reference sees the same input. */
#define FN_REL_TOL (4.0 * FLT_EPSILON)
/* Mutated grammars per seed file in the fuzz test (5 files: about 6000 cases). */
#define FUZZ_CASES_PER_FILE 1200u
/* The bad corpus must hold at least this many files (the brief's minimum). */
#define BAD_CORPUS_MIN 40

/* ---- helpers ---- */

static char *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc(n > 0 ? (size_t)n + 1 : 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf) buf[n] = '\0';
    *size = (size_t)n;
    return buf;
}

static int compare_names(const void *a, const void *b) { return strcmp(a, b); }

/* Sorted *.grammar file names of a folder; returns the count (at most max). */
static int list_grammars(const char *dir, char names[][128], int max) {
    DIR *d = opendir(dir);
    int n = 0;
    if (!d) return 0;
    for (struct dirent *e; (e = readdir(d)) && n < max;) {
        const size_t l = strlen(e->d_name);
        if (l > 8 && l < 128 && !strcmp(e->d_name + l - 8, ".grammar"))
            memcpy(names[n++], e->d_name, l + 1);
    }
    closedir(d);
    qsort(names, (size_t)n, 128, compare_names);
    return n;
}

static pgt_result compile(pgt_grammar *g, const char *text, pgt_error *err) {
    pgt_error_clear(err);
    return pgt_grammar_compile(g, text, strlen(text), "t.grammar", err);
}

/* The layout contract of grammar.h, walked independently of the compiler. Returns the number of
 * violations (printed). */
static int check_layout(const pgt_grammar *g) {
    int bad = 0;
#define LAYOUT(cond)                                                                               \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            if (bad++ < 5) fprintf(stderr, "  layout: %s\n", #cond);                               \
        }                                                                                          \
    } while (0)
    LAYOUT(g->rule_count >= 1 && g->rules[0].param_count == 0);
    LAYOUT(g->file_name < g->names_size);
    for (uint32_t r = 0; r < g->rule_count; ++r) {
        const pgt_grammar_rule *rl = &g->rules[r];
        LAYOUT(rl->name < g->names_size && rl->case_count >= 1);
        LAYOUT(rl->first_case + rl->case_count <= g->case_count);
        LAYOUT(rl->first_param + rl->param_count <= g->rule_param_count);
        LAYOUT(rl->param_count <= PGT_GRAMMAR_MAX_RULE_PARAMS);
        for (uint32_t c = 0; c < rl->case_count && rl->first_case + c < g->case_count; ++c) {
            const pgt_grammar_case *cs = &g->cases[rl->first_case + c];
            /* only the last case may be unconditional */
            LAYOUT((cs->condition == PGT_NONE) == (c + 1 == rl->case_count));
            LAYOUT(cs->condition == PGT_NONE || cs->condition < g->expr_count);
            LAYOUT(cs->sequence < g->sequence_count);
        }
    }
    for (uint32_t s = 0; s < g->sequence_count; ++s)
        LAYOUT(g->sequences[s].first_item + g->sequences[s].item_count <= g->item_count);
    for (uint32_t i = 0; i < g->item_count; ++i) {
        const pgt_grammar_item *it = &g->items[i];
        LAYOUT(it->first_arg + it->arg_count <= g->arg_count);
        switch (it->kind) {
        case PGT_GRAMMAR_ITEM_CALL:
            LAYOUT(it->target < g->rule_count);
            LAYOUT(it->target >= g->rule_count ||
                   g->rules[it->target].param_count == it->arg_count);
            break;
        case PGT_GRAMMAR_ITEM_MARCHING:
            LAYOUT(it->arg_count == 3 && it->sub_count == 2);
            break;
        case PGT_GRAMMAR_ITEM_BRANCH:
            LAYOUT(it->arg_count == 1 && it->sub_count >= 1);
            break;
        case PGT_GRAMMAR_ITEM_TERMINAL:
            LAYOUT(it->target < PGT_GRAMMAR_TERMINAL_COUNT && it->arg_count == 2);
            break;
        case PGT_GRAMMAR_ITEM_SPLIT:
            LAYOUT(it->target < 3 && it->sub_count >= 1);
            LAYOUT(it->first_sub + it->sub_count <= g->part_count);
            break;
        default:
            LAYOUT(!"item kind");
        }
        if (it->kind == PGT_GRAMMAR_ITEM_MARCHING || it->kind == PGT_GRAMMAR_ITEM_BRANCH) {
            LAYOUT(it->first_sub + it->sub_count <= g->sub_count);
            for (uint32_t k = 0; k < it->sub_count && it->first_sub + k < g->sub_count; ++k)
                LAYOUT(g->subs[it->first_sub + k] < g->sequence_count);
        }
    }
    for (uint32_t k = 0; k < g->arg_count; ++k) LAYOUT(g->args[k] < g->expr_count);
    for (uint32_t k = 0; k < g->part_count; ++k) {
        const pgt_grammar_part *pt = &g->parts[k];
        if (pt->kind == PGT_GRAMMAR_PART_REPEAT) {
            LAYOUT(pt->size == PGT_NONE && pt->sequence == PGT_NONE && pt->part_count >= 1);
            LAYOUT(pt->first_part + pt->part_count <= g->part_count);
            for (uint32_t j = 0; j < pt->part_count && pt->first_part + j < g->part_count; ++j)
                LAYOUT(g->parts[pt->first_part + j].kind != PGT_GRAMMAR_PART_REPEAT);
        } else {
            LAYOUT(pt->kind <= PGT_GRAMMAR_PART_FLOATING);
            LAYOUT(pt->size < g->expr_count && pt->sequence < g->sequence_count);
        }
    }
    for (uint32_t e = 0; e < g->expr_count; ++e) {
        const pgt_grammar_expr *x = &g->exprs[e];
        LAYOUT(x->first_code + x->code_count <= g->code_count && x->code_count >= 1);
        LAYOUT(x->max_stack <= PGT_GRAMMAR_VM_STACK);
        int depth = 0, max = 0, ok = 1;
        for (uint32_t k = 0; k < x->code_count && x->first_code + k < g->code_count; ++k) {
            const uint32_t ins = g->code[x->first_code + k];
            const uint32_t op = ins & PGT_GRAMMAR_OP_MASK, arg = ins >> PGT_GRAMMAR_OP_BITS;
            LAYOUT(op < PGT_GRAMMAR_OP_COUNT);
            if (op == PGT_GRAMMAR_OP_CONST) LAYOUT(arg < g->const_count);
            if (op == PGT_GRAMMAR_OP_PARAM) LAYOUT(arg < g->param_count);
            if (op == PGT_GRAMMAR_OP_ARG) LAYOUT(arg < PGT_GRAMMAR_MAX_RULE_PARAMS);
            if (op == PGT_GRAMMAR_OP_CONTEXT) LAYOUT(arg < PGT_GRAMMAR_CONTEXT_COUNT);
            /* stack effects by hand: pushes, unary, ternary clamp, the rest binary */
            int pops = 2;
            if (op <= PGT_GRAMMAR_OP_ARG || op == PGT_GRAMMAR_OP_CONTEXT) pops = 0;
            if (op == PGT_GRAMMAR_OP_NEG || op == PGT_GRAMMAR_OP_NOT ||
                (op >= PGT_GRAMMAR_OP_SIN && op <= PGT_GRAMMAR_OP_LOG &&
                 op != PGT_GRAMMAR_OP_ATAN2 && op != PGT_GRAMMAR_OP_MIN &&
                 op != PGT_GRAMMAR_OP_MAX && op != PGT_GRAMMAR_OP_POW))
                pops = 1;
            if (op == PGT_GRAMMAR_OP_CLAMP) pops = 3;
            if (depth < pops) ok = 0;
            depth += 1 - pops;
            if (depth > max) max = depth;
        }
        LAYOUT(ok && depth == 1 && (uint32_t)max == x->max_stack);
    }
    for (uint32_t k = 0; k < g->param_count; ++k) {
        LAYOUT(g->params[k].name < g->names_size && g->params[k].expr < g->expr_count);
        LAYOUT(isfinite(g->param_values[k]));
    }
    for (uint32_t k = 0; k < g->rule_param_count; ++k) LAYOUT(g->rule_params[k] < g->names_size);
    LAYOUT(g->names_size >= 1 && g->names[g->names_size - 1] == '\0');
#undef LAYOUT
    return bad;
}

/* The listing of g, malloc'd. */
static char *dump_text(const pgt_grammar *g) {
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    if (!f) return NULL;
    pgt_grammar_dump(g, f);
    fclose(f);
    return buf;
}

/* Removes "#" comments (indices and positions) from a listing, in place. */
static void strip_comments(char *s) {
    char *w = s;
    for (char *r = s; *r;) {
        if (*r == '#') {
            while (w > s && w[-1] == ' ') w--;
            while (*r && *r != '\n') r++;
        } else {
            *w++ = *r++;
        }
    }
    *w = '\0';
}

/* ---- compile and list ---- */

/* Every good grammar compiles, satisfies the layout, and its listing compiles again to the same
 * listing (comments aside: positions move). */
static void check_good(const char *path) {
    pgt_grammar g, h;
    pgt_error err = {0};
    if (pgt_grammar_load(&g, path, &err) != PGT_OK) {
        CHECK_MSG(0, "%s: %s", path, err.message);
        return;
    }
    CHECK_MSG(check_layout(&g) == 0, "%s", path);
    char *a = dump_text(&g);
    REQUIRE(a);
    CHECK_MSG(compile(&h, a, &err) == PGT_OK, "%s listing: %s", path, err.message);
    char *b = dump_text(&h);
    REQUIRE(b);
    strip_comments(a);
    strip_comments(b);
    CHECK_MSG(!strcmp(a, b), "%s: the listing does not round-trip:\n%s\n---\n%s", path, a, b);
    free(a);
    free(b);
    pgt_grammar_destroy(&h);
    pgt_grammar_destroy(&g);
}

static void test_good_grammars(void) {
    char names[64][128];
    const int n = list_grammars(GOOD_DIR, names, 64);
    CHECK(n >= 4);
    char path[512];
    for (int k = 0; k < n; ++k) {
        snprintf(path, sizeof path, "%s/%s", GOOD_DIR, names[k]);
        check_good(path);
    }
    check_good(IVY_PATH);
}

static const char small_grammar[] =
    "param a = 2\n"
    "attr b = a * (1 + 3)\n"
    "S --> R(b) Bark(a, C0)\n"
    "R(x) --> case x > 1 && !0 : Marching(x, -x, context.mask(texCoord) < 0.5) { NIL | R(x - 1) }\n"
    "         else : split(x) { 1 : NIL | { 'x : S }* }\n";

/* Written by hand from the language reference: items, sequences, parts and expressions are
 * numbered in the order they are completed (inner before outer). */
static const char small_listing[] =
    "# grammar t.grammar: 2 rules, 3 cases, 7 sequences, 6 items, 3 split parts, 12 expressions, "
    "26 instructions, 9 consts, 2 params\n"
    "param a = 2;  # param 0 = 2, 1:7\n"
    "param b = a * (1 + 3);  # param 1 = 8, 2:6\n"
    "\n"
    "# rule 0 (axiom), 3:1\n"
    "S -->\n"
    "    R(b)  # item 0, 3:7\n"
    "    Bark(a, C0)  # item 1, 3:12\n"
    ";\n"
    "\n"
    "# rule 1, 4:1\n"
    "R(x) -->\n"
    "  case x > 1 && !0 :\n"
    "    Marching(x, -x, context.mask(texCoord) < 0.5) {  # item 3, 4:29\n"
    "        NIL  # sequence 1\n"
    "      ,\n"
    "        R(x - 1)  # item 2, 4:83\n"
    "    }\n"
    "  else :\n"
    "    split(x) {  # item 5, 5:17\n"
    "        1 :  # part 1, 5:28\n"
    "            NIL  # sequence 4\n"
    "      |\n"
    "        {  # part 2, repeat group, 5:38\n"
    "            'x :  # part 0, 5:40\n"
    "                S  # item 4, 5:45\n"
    "        }*\n"
    "    }\n"
    ";\n";

static void test_listing(void) {
    pgt_grammar g;
    pgt_error err;
    REQUIRE(compile(&g, small_grammar, &err) == PGT_OK);
    char *s = dump_text(&g);
    REQUIRE(s);
    CHECK_MSG(!strcmp(s, small_listing), "listing:\n%s", s);
    free(s);
    pgt_grammar_destroy(&g);
}

/* The ivy grammar's compiled form is the paper's section 8 grammar. */
static void test_ivy_structure(void) {
    pgt_grammar g;
    pgt_error err = {0};
    REQUIRE(pgt_grammar_load(&g, IVY_PATH, &err) == PGT_OK);
    const char *order[] = {"Ivy", "IvyMainBranch", "IvyBranching", "IvySecBranch", "IvyGeometries"};
    for (uint32_t r = 0; r < 5; ++r) CHECK(pgt_grammar_find_rule(&g, order[r]) == r);
    CHECK(pgt_grammar_find_rule(&g, "Nope") == PGT_NONE);
    CHECK(g.rule_count == 5 && g.rules[0].param_count == 0);
    /* IvyMainBranch(n) --> Marching(...) {IvyBranching(n), IvyGeometries} */
    const pgt_grammar_rule *main_rule = &g.rules[1];
    CHECK(main_rule->param_count == 1 && main_rule->case_count == 1);
    const pgt_grammar_sequence *s = &g.sequences[g.cases[main_rule->first_case].sequence];
    REQUIRE(s->item_count == 1);
    const pgt_grammar_item *m = &g.items[s->first_item];
    CHECK(m->kind == PGT_GRAMMAR_ITEM_MARCHING && m->arg_count == 3 && m->sub_count == 2);
    const pgt_grammar_expr *cond = &g.exprs[g.args[m->first_arg + 2]];
    CHECK((cond->flags & PGT_GRAMMAR_EXPR_CONTEXT) && (cond->flags & PGT_GRAMMAR_EXPR_ARGS));
    const pgt_grammar_sequence *top = &g.sequences[g.subs[m->first_sub]];
    REQUIRE(top->item_count == 1);
    CHECK(g.items[top->first_item].kind == PGT_GRAMMAR_ITEM_CALL &&
          g.items[top->first_item].target == 2);
    /* IvyBranching: Branch(2) with two sequences */
    s = &g.sequences[g.cases[g.rules[2].first_case].sequence];
    REQUIRE(s->item_count == 1);
    CHECK(g.items[s->first_item].kind == PGT_GRAMMAR_ITEM_BRANCH &&
          g.items[s->first_item].sub_count == 2);
    /* IvySecBranch's angle draws a random number */
    s = &g.sequences[g.cases[g.rules[3].first_case].sequence];
    REQUIRE(s->item_count == 1);
    CHECK(g.exprs[g.args[g.items[s->first_item].first_arg + 1]].flags & PGT_GRAMMAR_EXPR_RAND);
    /* IvyGeometries: Bark(barkRadius, C1) Leaves(...) */
    s = &g.sequences[g.cases[g.rules[4].first_case].sequence];
    REQUIRE(s->item_count == 2);
    const pgt_grammar_item *bark = &g.items[s->first_item];
    CHECK(bark->kind == PGT_GRAMMAR_ITEM_TERMINAL && bark->target == PGT_GRAMMAR_TERMINAL_BARK);
    float v = -1.0f;
    CHECK(pgt_grammar_eval(&g, g.args[bark->first_arg + 1], NULL, 0, NULL, &v, &err) == PGT_OK &&
          v == (float)PGT_GRAMMAR_C1);
    CHECK(g.items[s->first_item + 1].target == PGT_GRAMMAR_TERMINAL_LEAVES);
    pgt_grammar_destroy(&g);
}

/* The split data issue 6 needs: axis, per part kind, size and successors, repeat groups. */
static void test_split_structure(void) {
    pgt_grammar g;
    pgt_error err = {0};
    REQUIRE(pgt_grammar_load(&g, GOOD_DIR "/facade_split.grammar", &err) == PGT_OK);
    /* F --> split(y) { groundFloorHeight : GF | { ~floorHeight : FL }* } */
    const pgt_grammar_sequence *s = &g.sequences[g.cases[g.rules[0].first_case].sequence];
    REQUIRE(s->item_count == 1);
    const pgt_grammar_item *it = &g.items[s->first_item];
    CHECK(it->kind == PGT_GRAMMAR_ITEM_SPLIT && it->target == 1 && it->sub_count == 2);
    const pgt_grammar_part *p0 = &g.parts[it->first_sub], *p1 = &g.parts[it->first_sub + 1];
    CHECK(p0->kind == PGT_GRAMMAR_PART_ABSOLUTE);
    float v = 0.0f;
    CHECK(pgt_grammar_eval(&g, p0->size, NULL, 0, NULL, &v, &err) == PGT_OK && v == 4.2f);
    REQUIRE(g.sequences[p0->sequence].item_count == 1);
    CHECK(g.items[g.sequences[p0->sequence].first_item].target == pgt_grammar_find_rule(&g, "GF"));
    REQUIRE(p1->kind == PGT_GRAMMAR_PART_REPEAT && p1->part_count == 1);
    CHECK(g.parts[p1->first_part].kind == PGT_GRAMMAR_PART_FLOATING);
    pgt_grammar_destroy(&g);
    /* split(z) { ... }* repeats all its parts: one repeat group holding them */
    REQUIRE(compile(&g, "param x = 1\nA --> split(z) { 'x : NIL | ~2 : NIL }*\n", &err) == PGT_OK);
    s = &g.sequences[g.cases[0].sequence];
    REQUIRE(s->item_count == 1);
    it = &g.items[s->first_item];
    CHECK(it->kind == PGT_GRAMMAR_ITEM_SPLIT && it->target == 2 && it->sub_count == 1);
    const pgt_grammar_part *group = &g.parts[it->first_sub];
    REQUIRE(group->kind == PGT_GRAMMAR_PART_REPEAT && group->part_count == 2);
    CHECK(g.parts[group->first_part].kind == PGT_GRAMMAR_PART_RELATIVE);
    CHECK(g.parts[group->first_part + 1].kind == PGT_GRAMMAR_PART_FLOATING);
    pgt_grammar_destroy(&g);
}

/* ---- expressions ---- */

/* Compiles `R(a, b, c) --> B(EXPR)` and evaluates EXPR with args; *code is the result. */
static float eval_expr(const char *expr, const float *args, const pgt_grammar_env *env,
                       pgt_result *code, pgt_error *err) {
    char text[1024];
    snprintf(text, sizeof text, "A --> NIL\nR(a, b, c) --> B(%s)\nB(x) --> NIL\n", expr);
    pgt_grammar g;
    float v = NAN;
    *code = compile(&g, text, err);
    if (*code == PGT_OK) {
        const pgt_grammar_sequence *s = &g.sequences[g.cases[g.rules[1].first_case].sequence];
        *code =
            pgt_grammar_eval(&g, g.args[g.items[s->first_item].first_arg], args, 3, env, &v, err);
    }
    pgt_grammar_destroy(&g);
    return v;
}

static void test_precedence(void) {
    static const struct {
        const char *expr;
        float value;
    } cases[] = {
        {"1 + 2 * 3", 7.0f},
        {"(1 + 2) * 3", 9.0f},
        {"10 - 4 - 3", 3.0f},
        {"8 / 4 / 2", 1.0f},
        {"2 * 3 % 4", 2.0f},
        {"7 % 3", 1.0f},
        {"-7 % 3", -1.0f},
        {"2 - -3", 5.0f},
        {"- - 3", 3.0f},
        {"-2 * -3", 6.0f},
        {"!0 + 1", 2.0f},
        {"!5", 0.0f},
        {"3 > 2 > 1", 0.0f},
        {"1 < 2 == 1", 1.0f},
        {"1 + 2 < 4 == 1", 1.0f},
        {"1 || 0 && 0", 1.0f},
        {"0 && 1 || 1", 1.0f},
        {"(1 || 0) && 0", 0.0f},
        {"2 != 2 || 3 >= 3", 1.0f},
        {"2 <= 1", 0.0f},
        {"1 == 1 != 0", 1.0f},
        {"a + b * c", 7.0f},
        {"(a + b) * c", 9.0f},
        {"a - b - c", -4.0f},
        {"c / b / a", 1.5f},
        {"-a * b", -2.0f},
        {".5 + 1e1 + 2.", 12.5f},
        {"1e-3 * 1000", 1.0f},
        {"0.5 * 4 + 3 * 2 - 1", 7.0f},
    };
    const float args[3] = {1.0f, 2.0f, 3.0f};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        pgt_error err = {0};
        pgt_result code;
        const float v = eval_expr(cases[k].expr, args, NULL, &code, &err);
        CHECK_MSG(code == PGT_OK && v == cases[k].value, "%s = %g, expected %g (%s)", cases[k].expr,
                  (double)v, (double)cases[k].value, err.message);
    }
    pgt_error err = {0};
    pgt_result code;
    CHECK(eval_expr("PI", args, NULL, &code, &err) == 3.14159265358979323846f);
}

static void test_functions(void) {
    static const struct {
        const char *expr;
        double value;
    } cases[] = {
        {"sin(0.5)", 0},       {"cos(0.5)", 0},        {"tan(1.25)", 0},         {"asin(0.25)", 0},
        {"acos(0.25)", 0},     {"atan(3)", 0},         {"atan2(1, -2)", 0},      {"sqrt(2)", 0},
        {"abs(-2.5)", 0},      {"floor(-2.5)", 0},     {"ceil(-2.5)", 0},        {"min(3, -1)", 0},
        {"max(3, -1)", 0},     {"pow(2, 0.5)", 0},     {"exp(1.5)", 0},          {"log(10)", 0},
        {"clamp(5, 0, 1)", 0}, {"clamp(-5, 0, 1)", 0}, {"clamp(0.25, 0, 1)", 0},
    };
    const double ref[] = {sin(0.5),   cos(0.5),     tan(1.25),   asin(0.25),  acos(0.25),
                          atan(3.0),  atan2(1, -2), sqrt(2.0),   fabs(-2.5),  floor(-2.5),
                          ceil(-2.5), fmin(3, -1),  fmax(3, -1), pow(2, 0.5), exp(1.5),
                          log(10.0),  1.0,          0.0,         0.25};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        pgt_error err = {0};
        pgt_result code;
        const float v = eval_expr(cases[k].expr, NULL, NULL, &code, &err);
        const double tol = FN_REL_TOL * fmax(fabs(ref[k]), 1e-6);
        CHECK_MSG(code == PGT_OK && fabs((double)v - ref[k]) <= tol, "%s = %.9g, libm %.9g (%s)",
                  cases[k].expr, (double)v, ref[k], err.message);
    }
}

static float test_context_fn(void *ctx, uint32_t context_id, float u, float v) {
    float *seen = ctx;
    seen[0] = (float)context_id, seen[1] = u, seen[2] = v;
    return context_id == PGT_GRAMMAR_CONTEXT_MASK ? 0.25f : 0.75f;
}

static void test_rand(void) {
    uint64_t counter = 7;
    pgt_grammar_env env = {42, 3, &counter, 0, 0, NULL, NULL, NULL};
    pgt_error err = {0};
    pgt_result code;
    /* in range, and exactly a + (b - a) * pgt_rng_float(seed, stream, counter) */
    for (int k = 0; k < 200; ++k) {
        const uint64_t before = counter;
        const float v = eval_expr("rand(-2, 5)", NULL, &env, &code, &err);
        CHECK(code == PGT_OK && v >= -2.0f && v < 5.0f);
        CHECK(counter == before + 1);
        CHECK(v == -2.0f + 7.0f * pgt_rng_float(42, 3, before));
    }
    /* same (seed, stream, counter), same value; two draws advance twice */
    counter = 100;
    const float a = eval_expr("rand(0, 1)", NULL, &env, &code, &err);
    counter = 100;
    const float b = eval_expr("rand(0, 1)", NULL, &env, &code, &err);
    CHECK(a == b);
    counter = 100;
    const float c = eval_expr("rand(0, 1) + 10 * rand(0, 1)", NULL, &env, &code, &err);
    CHECK(counter == 102);
    CHECK(c == pgt_rng_float(42, 3, 100) + 10.0f * pgt_rng_float(42, 3, 101));
    /* another seed or stream gives another value */
    counter = 100;
    env.seed = 43;
    CHECK(eval_expr("rand(0, 1)", NULL, &env, &code, &err) != a);
    /* an empty range gives its bound */
    CHECK(eval_expr("rand(2, 2)", NULL, &env, &code, &err) == 2.0f);
    /* no counter: an error, not a crash */
    env.counter = NULL;
    eval_expr("rand(0, 1)", NULL, &env, &code, &err);
    CHECK(code == PGT_ERROR_INVALID_ARGUMENT && strstr(err.message, "t.grammar:2:"));
}

static void test_context(void) {
    float seen[3] = {-1, -1, -1};
    pgt_grammar_env env = {1, 0, NULL, 0.125f, 0.875f, test_context_fn, seen, NULL};
    pgt_error err = {0};
    pgt_result code;
    float v = eval_expr("context.mask(texCoord) < 0.5", NULL, &env, &code, &err);
    CHECK(code == PGT_OK && v == 1.0f);
    CHECK(seen[0] == (float)PGT_GRAMMAR_CONTEXT_MASK && seen[1] == 0.125f && seen[2] == 0.875f);
    v = eval_expr("2 * context.density(texCoord)", NULL, &env, &code, &err);
    CHECK(code == PGT_OK && v == 1.5f && seen[0] == (float)PGT_GRAMMAR_CONTEXT_DENSITY);
    env.context = NULL;
    eval_expr("context.mask(texCoord)", NULL, &env, &code, &err);
    CHECK(code == PGT_ERROR_INVALID_ARGUMENT);
}

/* Does expression text fail as not finite with a message starting with `where` and holding
 * `detail` (NULL: any)? The message is printed when not. */
static int not_finite_at(const char *text, const float *args, const pgt_grammar_env *env,
                         const char *where, const char *detail) {
    pgt_error err = {0};
    pgt_result code;
    eval_expr(text, args, env, &code, &err);
    const int ok = code == PGT_ERROR_NOT_FINITE && strstr(err.message, where) == err.message &&
                   (!detail || strstr(err.message, detail));
    if (!ok) printf("  %s: %s\n", text, err.message);
    return ok;
}

/* Runtime errors name FILE:LINE:COL of the operator the value that is not finite came from
 * (the expressions sit in "R(a, b, c) --> B(...)", line 2, from column 18). */
static void test_runtime_errors(void) {
    const float args[3] = {0.0f, -1.0f, 1e30f};
    pgt_error err = {0};
    pgt_result code;
    eval_expr("1 / a", args, NULL, &code, &err);
    CHECK_MSG(code == PGT_ERROR_NOT_FINITE &&
                  !strcmp(err.message, "t.grammar:2:20: the expression evaluates to infinity "
                                       "('/' gives inf here)"),
              "%s", err.message);
    eval_expr("-sqrt(b) + 1", args, NULL, &code, &err);
    CHECK_MSG(code == PGT_ERROR_NOT_FINITE &&
                  !strcmp(err.message, "t.grammar:2:19: the expression evaluates to NaN (sqrt "
                                       "gives NaN here)"),
              "%s", err.message);
    /* an infinity passed on through later operators keeps its origin */
    CHECK(not_finite_at("c * c - 1", args, NULL, "t.grammar:2:20: ", "('*' gives inf here)"));
    /* max drops the NaN of 0 / a: the infinity of 1 / a is the one that stays */
    CHECK(
        not_finite_at("max(0 / a, 1 / a)", args, NULL, "t.grammar:2:31: ", "('/' gives inf here)"));
    /* two infinities make a NaN: the operator that made it */
    CHECK(not_finite_at("c * c - c * c", args, NULL, "t.grammar:2:24: ", "('-' gives NaN here)"));
    /* one a comparison made finite is forgotten: the second '*' overflows */
    CHECK(not_finite_at("(1 / a > 0) * c * c", args, NULL, "t.grammar:2:34: ", NULL));
    /* the search for the origin draws the same numbers again and leaves the counter as the
     * failed run left it: one draw */
    uint64_t counter = 7;
    pgt_grammar_env env = {5, 2, &counter, 0, 0, NULL, NULL, NULL};
    CHECK(not_finite_at("rand(0, 1) / a", args, &env, "t.grammar:2:29: ", NULL) && counter == 8);
    /* ... the same numbers: at a counter whose draw is >= 0.5 and whose next draw is not,
     * 1 / (rand(0, 1) < 0.5) divides by zero; a search drawing the next number would find a
     * finite value and no operator (the message would point at the expression's start, 2:18) */
    uint64_t c0 = 0;
    while (c0 < 1000u && !(pgt_rng_float(5, 2, c0) >= 0.5f && pgt_rng_float(5, 2, c0 + 1u) < 0.5f))
        ++c0;
    REQUIRE(c0 < 1000u);
    counter = c0;
    CHECK(not_finite_at("1 / (rand(0, 1) < 0.5)", args, &env, "t.grammar:2:20: ", NULL) &&
          counter == c0 + 1u);
    /* infinity in between is fine when the result is finite */
    CHECK(eval_expr("1 / a > 0", args, NULL, &code, &err) == 1.0f && code == PGT_OK);
    /* fewer arguments than the rule has: an error, not a read past the array */
    pgt_grammar g;
    REQUIRE(compile(&g, "A --> NIL\nR(a, b) --> B(b)\nB(x) --> NIL\n", &err) == PGT_OK);
    const pgt_grammar_sequence *s = &g.sequences[g.cases[g.rules[1].first_case].sequence];
    float v;
    CHECK(pgt_grammar_eval(&g, g.args[g.items[s->first_item].first_arg], args, 1, NULL, &v, &err) ==
          PGT_ERROR_INVALID_ARGUMENT);
    pgt_grammar_destroy(&g);
}

/* ---- params ---- */

static void test_params(void) {
    pgt_grammar g;
    pgt_error err = {0};
    REQUIRE(compile(&g,
                    "param a = 2\nparam b = a * 3\nattr c = b + a\nparam d = 1 / (a - 1)\n"
                    "param n = 2\nA --> Branch(n) {NIL, NIL}\n",
                    &err) == PGT_OK);
    const uint32_t a = pgt_grammar_find_param(&g, "a"), b = pgt_grammar_find_param(&g, "b"),
                   c = pgt_grammar_find_param(&g, "c"), d = pgt_grammar_find_param(&g, "d");
    REQUIRE(a == 0 && b == 1 && c == 2 && d == 3);
    CHECK(pgt_grammar_find_param(&g, "zz") == PGT_NONE);
    CHECK(g.param_values[a] == 2 && g.param_values[b] == 6 && g.param_values[c] == 8 &&
          g.param_values[d] == 1);
    /* overriding a re-evaluates b, c and d */
    CHECK(pgt_grammar_set_param(&g, "a", 3, &err) == PGT_OK);
    CHECK(g.param_values[a] == 3 && g.param_values[b] == 9 && g.param_values[c] == 12 &&
          g.param_values[d] == 0.5f);
    /* an overridden param keeps its value when an earlier one changes */
    CHECK(pgt_grammar_set_param(&g, "b", 100, &err) == PGT_OK);
    CHECK(pgt_grammar_set_param(&g, "a", 5, &err) == PGT_OK);
    CHECK(g.param_values[b] == 100 && g.param_values[c] == 105 && g.param_values[d] == 0.25f);
    /* a dependent division by zero is refused and changes nothing */
    pgt_error_clear(&err);
    CHECK(pgt_grammar_set_param(&g, "a", 1, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, "t.grammar:4:13: with a = 1, param 'd' divides by zero") != NULL);
    CHECK(g.param_values[a] == 5 && g.param_values[d] == 0.25f && g.params[a].overridden == 1);
    /* unknown name, non-finite value */
    pgt_error_clear(&err);
    CHECK(pgt_grammar_set_param(&g, "nope", 1, &err) == PGT_ERROR_INVALID_ARGUMENT &&
          strstr(err.message, "no param 'nope'"));
    pgt_error_clear(&err);
    CHECK(pgt_grammar_set_param(&g, "c", INFINITY, &err) == PGT_ERROR_INVALID_ARGUMENT);
    /* a Branch count must keep matching its sequences */
    pgt_error_clear(&err);
    CHECK(pgt_grammar_set_param(&g, "n", 3, &err) == PGT_ERROR_INVALID_ARGUMENT &&
          strstr(err.message, "Branch asks for 3 sequences, it has 2"));
    CHECK(g.param_values[4] == 2 && !g.params[4].overridden);
    /* rule expressions read the current values */
    CHECK(pgt_grammar_set_param(&g, "n", 2, &err) == PGT_OK);
    pgt_grammar_destroy(&g);
    pgt_grammar_destroy(NULL);
    /* a Branch count that no longer evaluates names its operator, not a count of 0 */
    REQUIRE(compile(&g, "param a = 2\nA --> Branch(4 / (a - 1) - 2) {NIL, NIL}\n", &err) == PGT_OK);
    CHECK_MSG(pgt_grammar_set_param(&g, "a", 1, &err) == PGT_ERROR_INVALID_ARGUMENT &&
                  !strcmp(err.message, "t.grammar:2:16: with a = 1, the count of Branch divides "
                                       "by zero"),
              "%s", err.message);
    pgt_grammar_destroy(&g);
    pgt_grammar_destroy(&g); /* a destroyed grammar is zeroed: destroying again is harmless */
}

/* ---- the bad corpus ---- */

/* Reads "# error: CODE", "# at: L:C", "# message: TEXT" from the first three lines. */
static int bad_header(const char *text, char *code, size_t code_size, unsigned *line, unsigned *col,
                      char *msg, size_t msg_size) {
    const char *l2 = strchr(text, '\n');
    const char *l3 = l2 ? strchr(l2 + 1, '\n') : NULL;
    const char *end = l3 ? strchr(l3 + 1, '\n') : NULL;
    if (!end || strncmp(text, "# error: ", 9) || strncmp(l2 + 1, "# at: ", 6) ||
        strncmp(l3 + 1, "# message: ", 11))
        return 0;
    snprintf(code, code_size, "%.*s", (int)(l2 - text - 9), text + 9);
    if (sscanf(l2 + 7, "%u:%u", line, col) != 2) return 0;
    snprintf(msg, msg_size, "%.*s", (int)(end - l3 - 12), l3 + 12);
    return 1;
}

static void test_bad_corpus(void) {
    static char names[256][128];
    const int n = list_grammars(BAD_DIR, names, 256);
    CHECK_MSG(n >= BAD_CORPUS_MIN, "%d bad grammars", n);
    for (int k = 0; k < n; ++k) {
        char path[512], code[64], msg[PGT_ERROR_MESSAGE_SIZE], where[192];
        unsigned line = 0, col = 0;
        snprintf(path, sizeof path, "%s/%s", BAD_DIR, names[k]);
        size_t size = 0;
        char *text = read_file(path, &size);
        REQUIRE(text);
        if (!bad_header(text, code, sizeof code, &line, &col, msg, sizeof msg)) {
            CHECK_MSG(0, "%s: no '# error/at/message' header", names[k]);
            free(text);
            continue;
        }
        pgt_grammar g;
        pgt_error err = {0};
        const pgt_result r = pgt_grammar_compile(&g, text, size, names[k], &err);
        snprintf(where, sizeof where, "%s:%u:%u: ", names[k], line, col);
        CHECK_MSG(r != PGT_OK && !strcmp(pgt_result_name(r), code), "%s: %s, expected %s (%s)",
                  names[k], pgt_result_name(r), code, err.message);
        CHECK_MSG(!strncmp(err.message, where, strlen(where)), "%s: '%s' does not start with '%s'",
                  names[k], err.message, where);
        CHECK_MSG(strstr(err.message, msg) != NULL, "%s: '%s' does not hold '%s'", names[k],
                  err.message, msg);
        CHECK(g.rule_count == 0 && g.rules == NULL); /* a failed compile leaves nothing */
        pgt_grammar_destroy(&g);
        free(text);
    }
}

/* ---- limits, generated ---- */

typedef struct text_buf {
    char *s;
    size_t n, cap;
} text_buf;

static void put(text_buf *b, const char *s) {
    const size_t l = strlen(s);
    if (b->n + l + 1 > b->cap) {
        b->cap = 2 * (b->n + l + 1);
        b->s = realloc(b->s, b->cap);
    }
    memcpy(b->s + b->n, s, l + 1);
    b->n += l;
}

static void put_repeat(text_buf *b, const char *s, uint32_t times) {
    for (uint32_t k = 0; k < times; ++k) put(b, s);
}

/* Compiles b and expects PGT_ERROR_LIMIT naming `name` (and where, when given). */
static void expect_limit(text_buf *b, const char *name, const char *where) {
    pgt_grammar g;
    pgt_error err = {0};
    const pgt_result r = pgt_grammar_compile(&g, b->s, b->n, "big.grammar", &err);
    CHECK_MSG(r == PGT_ERROR_LIMIT && strstr(err.message, name), "%s: %s %s", name,
              pgt_result_name(r), err.message);
    if (where)
        CHECK_MSG(!strncmp(err.message, where, strlen(where)), "%s: '%s', expected at '%s'", name,
                  err.message, where);
    pgt_grammar_destroy(&g);
    free(b->s);
    *b = (text_buf){0};
}

/* "FMT" with k = 0 .. count - 1 (numbered names). */
static void put_numbered(text_buf *b, const char *fmt, uint32_t count) {
    char line[64];
    for (uint32_t k = 0; k < count; ++k) {
        snprintf(line, sizeof line, fmt, k);
        put(b, line);
    }
}

/* Grammars of the form prefix + unit x times + suffix that cross one limit each. */
static const struct {
    const char *prefix, *unit;
    uint32_t times;
    const char *suffix, *limit, *where;
} limit_cases[] = {
    {"A --> B(0", ", 0", PGT_GRAMMAR_MAX_RULE_PARAMS, ")\nB --> NIL\n",
     "PGT_GRAMMAR_MAX_RULE_PARAMS", "big.grammar:1:57: "},
    /* one sequence of too many calls */
    {"A --> ", "B ", PGT_GRAMMAR_MAX_ITEMS + 1, "\nB --> NIL\n", "PGT_GRAMMAR_MAX_ITEMS", NULL},
    /* empty Branch sequences cost no item */
    {"A --> Branch(1) {NIL}\nB --> ", "Branch(4) {,,,} ", PGT_GRAMMAR_MAX_SEQUENCES / 4 + 1, "",
     "PGT_GRAMMAR_MAX_SEQUENCES", NULL},
    /* calls of 16 arguments, params so that the consts do not run out first */
    {"param one = 1\nA --> ", "B(one,one,one,one,one,one,one,one,one,one,one,one,one,one,one,one) ",
     PGT_GRAMMAR_MAX_EXPRS / 16 + 1, "\nB(a,b,c,d,e,f,g,h,i,j,k,l,m,n,o,p) --> NIL\n",
     "PGT_GRAMMAR_MAX_EXPRS", NULL},
    /* a long flat sum of params */
    {"param one = 1\nparam sum = one", "+one", PGT_GRAMMAR_MAX_CODE / 2 + 1, "\nA --> NIL\n",
     "PGT_GRAMMAR_MAX_CODE", NULL},
    {"param sum = 1", "+1", PGT_GRAMMAR_MAX_CONSTS, "\nA --> NIL\n", "PGT_GRAMMAR_MAX_CONSTS",
     NULL},
    /* nesting through split parts (the corpus nests Branch): the error comes before the
     * missing '}' would */
    {"A --> ", "split(x) { 1 : ", PGT_GRAMMAR_MAX_NESTING, "", "PGT_GRAMMAR_MAX_NESTING",
     "big.grammar:1:"},
    /* expression depth through unary minus (the corpus uses parentheses) */
    {"param a = ", "-", PGT_GRAMMAR_MAX_EXPR_DEPTH, "1\nA --> NIL\n", "PGT_GRAMMAR_MAX_EXPR_DEPTH",
     NULL},
    /* the VM stack through right operands: the error comes before the missing ')' would */
    {"param a = 1", " + (1", PGT_GRAMMAR_VM_STACK, "", "PGT_GRAMMAR_VM_STACK", NULL},
    {"param a = ", "0", PGT_GRAMMAR_MAX_NAME_CHARS + 1, "\nA --> NIL\n",
     "PGT_GRAMMAR_MAX_NAME_CHARS", "big.grammar:1:11: "},
};

static void test_limits(void) {
    text_buf b = {0};
    for (size_t k = 0; k < sizeof limit_cases / sizeof limit_cases[0]; ++k) {
        put(&b, limit_cases[k].prefix);
        put_repeat(&b, limit_cases[k].unit, limit_cases[k].times);
        put(&b, limit_cases[k].suffix);
        expect_limit(&b, limit_cases[k].limit, limit_cases[k].where);
    }
    /* the file: 1 MiB of comment lines plus a bit */
    put(&b, "A --> NIL\n");
    while (b.n <= PGT_GRAMMAR_MAX_FILE_BYTES)
        put(&b, "# padding padding padding padding padding\n");
    expect_limit(&b, "PGT_GRAMMAR_MAX_FILE_BYTES", NULL);
    /* rules R0 .. R4096, one too many, the last on line 4097 */
    char where[192];
    put_numbered(&b, "R%u --> NIL\n", PGT_GRAMMAR_MAX_RULES + 1);
    snprintf(where, sizeof where, "big.grammar:%u:1: ", PGT_GRAMMAR_MAX_RULES + 1);
    expect_limit(&b, "PGT_GRAMMAR_MAX_RULES", where);
    put_numbered(&b, "param p%u = 1\n", PGT_GRAMMAR_MAX_PARAMS + 1);
    put(&b, "A --> NIL\n");
    snprintf(where, sizeof where, "big.grammar:%u:7: ", PGT_GRAMMAR_MAX_PARAMS + 1);
    expect_limit(&b, "PGT_GRAMMAR_MAX_PARAMS", where);
    put(&b, "A --> NIL\nR(");
    put_numbered(&b, "p%u, ", PGT_GRAMMAR_MAX_RULE_PARAMS + 1);
    put(&b, "q) --> NIL\n");
    expect_limit(&b, "PGT_GRAMMAR_MAX_RULE_PARAMS", "big.grammar:2:");
    /* a left-leaning chain stays shallow: one operand per precedence level below || plus the
     * || operand, 7 entries, whatever its length */
    put(&b, "param a = 1");
    put_repeat(&b, " || 1 && 1 == 1 < 1 + 1 * -1", 10 * PGT_GRAMMAR_VM_STACK);
    put(&b, "\nA --> NIL\n");
    pgt_grammar g;
    pgt_error err = {0};
    CHECK(pgt_grammar_compile(&g, b.s, b.n, "big.grammar", &err) == PGT_OK);
    CHECK(g.expr_count == 1 && g.exprs[0].max_stack == 7);
    pgt_grammar_destroy(&g);
    free(b.s);
}

/* ---- robustness ---- */

/* Byte flips, deletions, insertions (random bytes or language tokens), truncations and
 * duplicated chunks of a good grammar, from fixed seeds. Each must compile or fail with
 * "FILE:LINE:COL: "; a compiled one must satisfy the layout, list and evaluate without crash. */
static void fuzz_file(const char *path, uint32_t seed, uint32_t cases_count) {
    static const char *const tokens[] = {"(",
                                         ")",
                                         "{",
                                         "}",
                                         ",",
                                         "|",
                                         ":",
                                         ";",
                                         "-->",
                                         "->",
                                         "\xE2\x86\x92",
                                         "'",
                                         "~",
                                         "*",
                                         "/",
                                         "/*",
                                         "*/",
                                         "#",
                                         "\"",
                                         "\\",
                                         "Marching",
                                         "Branch",
                                         "split",
                                         "case",
                                         "else",
                                         "NIL",
                                         "rand",
                                         "context.",
                                         "texCoord",
                                         "PI",
                                         "1e39",
                                         "0",
                                         ".",
                                         "param",
                                         "\n",
                                         " ",
                                         "\0",
                                         "Bark",
                                         "C1",
                                         "!",
                                         "&&",
                                         "1e-45"};
    size_t size = 0;
    char *text = read_file(path, &size);
    REQUIRE(text);
    char *buf = malloc(2 * size + 64);
    REQUIRE(buf);
    uint32_t compiled = 0;
    for (uint32_t c = 0; c < cases_count; ++c) {
        memcpy(buf, text, size);
        size_t n = size;
        uint64_t draw = 0;
#define RND(m) ((uint32_t)(pgt_rng_u64(seed, c, draw++) % (uint64_t)(m)))
        const uint32_t edits = 1 + RND(4);
        for (uint32_t e = 0; e < edits && n > 0; ++e) {
            const size_t at = RND(n);
            switch (RND(6)) {
            case 0:
                buf[at] ^= (char)(1u << RND(8));
                break;
            case 1: {
                const size_t len = 1 + RND(n - at < 16 ? n - at : 16);
                memmove(buf + at, buf + at + len, n - at - len);
                n -= len;
                break;
            }
            case 2:
                memmove(buf + at + 1, buf + at, n - at);
                buf[at] = (char)RND(256);
                n++;
                break;
            case 3: {
                const char *t = tokens[RND(sizeof tokens / sizeof tokens[0])];
                const size_t len = t[0] ? strlen(t) : 1;
                if (n + len > 2 * size + 32) break;
                memmove(buf + at + len, buf + at, n - at);
                memcpy(buf + at, t, len);
                n += len;
                break;
            }
            case 4:
                n = at;
                break;
            default: {
                const size_t len = RND(n - at < 64 ? n - at : 64);
                if (n + len > 2 * size + 32) break;
                memmove(buf + at + len, buf + at, n - at);
                n += len;
                break;
            }
            }
        }
#undef RND
        /* the compiler gets exactly n bytes in a buffer of n bytes, so ASan sees any over-read */
        char *exact = malloc(n ? n : 1);
        REQUIRE(exact);
        memcpy(exact, buf, n);
        pgt_grammar g;
        pgt_error err = {0};
        const pgt_result r = pgt_grammar_compile(&g, exact, n, "fuzz.grammar", &err);
        if (r != PGT_OK) {
            unsigned line = 0, col = 0;
            char colon = 0;
            CHECK_MSG(sscanf(err.message, "fuzz.grammar:%u:%u%c", &line, &col, &colon) == 3 &&
                          colon == ':' && line >= 1 && col >= 1,
                      "case %u of %s: '%s'", c, path, err.message);
        } else {
            compiled++;
            CHECK_MSG(check_layout(&g) == 0, "case %u of %s", c, path);
            char *d = dump_text(&g);
            CHECK(d != NULL);
            free(d);
            float args[PGT_GRAMMAR_MAX_RULE_PARAMS] = {0}, seen[3], v;
            uint64_t counter = 0;
            pgt_grammar_env env = {seed, c, &counter, 0.5f, 0.5f, test_context_fn, seen, NULL};
            for (uint32_t e = 0; e < g.expr_count; ++e)
                pgt_grammar_eval(&g, e, args, PGT_GRAMMAR_MAX_RULE_PARAMS, &env, &v, &err);
        }
        pgt_grammar_destroy(&g);
        free(exact);
    }
    /* the mutations must not all break the grammar, or the compiled side goes untested */
    CHECK_MSG(compiled > cases_count / 20, "%s: only %u of %u mutants compiled", path, compiled,
              cases_count);
    free(buf);
    free(text);
}

static void test_fuzz(void) {
    char names[64][128], path[512];
    const int n = list_grammars(GOOD_DIR, names, 64);
    fuzz_file(IVY_PATH, 0x1F1Eu, FUZZ_CASES_PER_FILE);
    for (int k = 0; k < n; ++k) {
        snprintf(path, sizeof path, "%s/%s", GOOD_DIR, names[k]);
        fuzz_file(path, 0x6A3Du + (uint32_t)k, FUZZ_CASES_PER_FILE);
    }
    /* every truncation of the ivy grammar */
    size_t size = 0;
    char *text = read_file(IVY_PATH, &size);
    REQUIRE(text);
    for (size_t cut = 0; cut < size; ++cut) {
        char *exact = malloc(cut ? cut : 1);
        REQUIRE(exact);
        memcpy(exact, text, cut);
        pgt_grammar g;
        pgt_error err = {0};
        if (pgt_grammar_compile(&g, exact, cut, "cut.grammar", &err) != PGT_OK)
            CHECK_MSG(!strncmp(err.message, "cut.grammar:", 12), "cut %zu: %s", cut, err.message);
        pgt_grammar_destroy(&g);
        free(exact);
    }
    free(text);
}

/* load: a missing file is an I/O error naming it. */
static void test_load_errors(void) {
    pgt_grammar g;
    pgt_error err = {0};
    CHECK(pgt_grammar_load(&g, "/nonexistent/x.grammar", &err) == PGT_ERROR_IO &&
          strstr(err.message, "/nonexistent/x.grammar"));
    pgt_grammar_destroy(&g);
    /* all three arrows, and a file name NULL */
    pgt_error_clear(&err);
    const char *arrows = "A --> B\nB -> C\nC \xE2\x86\x92 NIL";
    CHECK(pgt_grammar_compile(&g, arrows, strlen(arrows), NULL, &err) == PGT_OK);
    CHECK(g.rule_count == 3 && !strcmp(g.names + g.file_name, "<grammar>"));
    pgt_grammar_destroy(&g);
    /* a UTF-8 byte order mark is skipped and not counted as a column */
    CHECK(compile(&g,
                  "\xEF\xBB\xBF"
                  "A --> NIL",
                  &err) == PGT_OK);
    pgt_grammar_destroy(&g);
    CHECK(compile(&g,
                  "\xEF\xBB\xBF"
                  "}",
                  &err) == PGT_ERROR_PARSE &&
          !strncmp(err.message, "t.grammar:1:1: ", 15));
    pgt_grammar_destroy(&g);
}

/* pgt grammar, through its C function (the CLI test script belongs to the lead). */
/* pgt_cmd_grammar(argc, argv) with stdout captured into a temporary file: its exit code in *rc
 * and what it printed (malloc'd; NULL when the capture could not be set up). */
static char *cmd_grammar_output(int argc, char **argv, int *rc) {
    fflush(stdout);
    FILE *captured = tmpfile();
    const int saved = captured ? dup(1) : -1;
    if (saved < 0 || dup2(fileno(captured), 1) < 0) {
        if (saved >= 0) close(saved);
        if (captured) fclose(captured);
        return NULL;
    }
    *rc = pgt_cmd_grammar(argc, argv);
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    const long n = ftell(captured);
    char *text = calloc((size_t)(n > 0 ? n : 0) + 1u, 1);
    rewind(captured);
    if (text && n > 0 && fread(text, 1, (size_t)n, captured) != (size_t)n) text[0] = '\0';
    fclose(captured);
    return text;
}

/* Exit codes of the verb, and what it prints for ivy.grammar: the summary lists the params with
 * their values (stepLength = 4 in the file), and --dump --param stepLength=2 lists the param at
 * its new value, marked overridden (grammar_dump.c's "param NAME = VALUE;  # ... (overridden;
 * was OLD)"), where the dump without the override has the file's value. */
static void test_cli(void) {
    char *ok[] = {"grammar", IVY_PATH, NULL};
    int rc = -1;
    char *text = cmd_grammar_output(2, ok, &rc);
    REQUIRE(text != NULL);
    CHECK(rc == PGT_EXIT_OK);
    CHECK_MSG(strstr(text, " 8 params (stepLength=4, ") != NULL, "summary: %s", text);
    free(text);
    char *dump[] = {"grammar", IVY_PATH, "--dump", "--param", "stepLength=2", NULL};
    text = cmd_grammar_output(5, dump, &rc);
    REQUIRE(text != NULL);
    CHECK(rc == PGT_EXIT_OK);
    CHECK_MSG(strstr(text, "\nparam stepLength = 2;  # param 0 = 2 (overridden; was 4)") != NULL,
              "dump with stepLength=2 does not list it:\n%s", text);
    CHECK(strstr(text, "param stepLength = 4;") == NULL);
    free(text);
    char *plain[] = {"grammar", IVY_PATH, "--dump", NULL};
    text = cmd_grammar_output(3, plain, &rc);
    REQUIRE(text != NULL);
    CHECK(rc == PGT_EXIT_OK);
    CHECK_MSG(strstr(text, "\nparam stepLength = 4;") != NULL && !strstr(text, "overridden"),
              "dump without overrides:\n%s", text);
    free(text);
    char *help[] = {"grammar", "--help", NULL};
    CHECK(pgt_cmd_grammar(2, help) == PGT_EXIT_OK);
    char *bad_file[] = {"grammar", BAD_DIR "/marching_one_sequence.grammar", NULL};
    CHECK(pgt_cmd_grammar(2, bad_file) == PGT_EXIT_USAGE);
    char *bad_param[] = {"grammar", IVY_PATH, "--param", "nope=1", NULL};
    CHECK(pgt_cmd_grammar(4, bad_param) == PGT_EXIT_USAGE);
    char *bad_value[] = {"grammar", IVY_PATH, "--param", "stepLength=x", NULL};
    CHECK(pgt_cmd_grammar(4, bad_value) == PGT_EXIT_USAGE);
    char *no_value[] = {"grammar", IVY_PATH, "--param", NULL};
    CHECK(pgt_cmd_grammar(3, no_value) == PGT_EXIT_USAGE);
    char *bad_flag[] = {"grammar", IVY_PATH, "--frobnicate", NULL};
    CHECK(pgt_cmd_grammar(3, bad_flag) == PGT_EXIT_USAGE);
    char *no_file[] = {"grammar", NULL};
    CHECK(pgt_cmd_grammar(1, no_file) == PGT_EXIT_USAGE);
    char *missing[] = {"grammar", "/nonexistent.grammar", NULL};
    CHECK(pgt_cmd_grammar(2, missing) == PGT_EXIT_USAGE);
}

/* Line ends: LF, CRLF and CR alone (a file saved with old Mac line ends) count lines alike, and a
 * '#' comment ends at any of them (with CR alone it swallowed the rest of the file, and every
 * error was on line 1). */
static void test_line_ends(void) {
    static const char *const ends[3] = {"\n", "\r\n", "\r"};
    for (int k = 0; k < 3; ++k) {
        char text[256];
        const char *e = ends[k];
        snprintf(text, sizeof text, "param p = 3%s# a comment%sA --> B(p)%sB(n) --> Q%s", e, e, e,
                 e);
        pgt_grammar g;
        pgt_error err = {0};
        CHECK(pgt_grammar_compile(&g, text, strlen(text), "ends.grammar", &err) != PGT_OK);
        CHECK_MSG(strstr(err.message, "ends.grammar:4:") != NULL, "line end %d: %s", k,
                  err.message);
        snprintf(text, sizeof text, "param p = 3%s# a comment%sA --> B(p)%sB(n) --> NIL%s", e, e, e,
                 e);
        pgt_error_clear(&err);
        CHECK_MSG(pgt_grammar_compile(&g, text, strlen(text), "ends.grammar", &err) == PGT_OK,
                  "line end %d: %s", k, err.message);
        if (err.code == PGT_OK) {
            CHECK(g.param_count == 1);
            pgt_grammar_destroy(&g);
        }
    }
    /* the file-size error's place too: LF and CR files of one byte a line end agree */
    char msg[2][PGT_ERROR_MESSAGE_SIZE];
    for (int k = 0; k < 2; ++k) {
        const size_t size = PGT_GRAMMAR_MAX_FILE_BYTES + 64u;
        char *big = malloc(size);
        REQUIRE(big != NULL);
        for (size_t i = 0; i < size; ++i) big[i] = i % 10u == 9u ? (k ? '\r' : '\n') : '#';
        pgt_grammar g;
        pgt_error err = {0};
        CHECK(pgt_grammar_compile(&g, big, size, "big.grammar", &err) == PGT_ERROR_LIMIT);
        snprintf(msg[k], sizeof msg[k], "%s", err.message);
        free(big);
    }
    CHECK_MSG(strcmp(msg[0], msg[1]) == 0 && strstr(msg[0], "big.grammar:104858:7:"),
              "LF: %s; CR: %s", msg[0], msg[1]);
}

static const pgt_test_case cases[] = {
    {"good_grammars", test_good_grammars},
    {"line_ends", test_line_ends},
    {"listing", test_listing},
    {"ivy_structure", test_ivy_structure},
    {"split_structure", test_split_structure},
    {"precedence", test_precedence},
    {"functions", test_functions},
    {"rand", test_rand},
    {"context", test_context},
    {"runtime_errors", test_runtime_errors},
    {"params", test_params},
    {"bad_corpus", test_bad_corpus},
    {"limits", test_limits},
    {"fuzz", test_fuzz},
    {"load_errors", test_load_errors},
    {"cli", test_cli},
};

PGT_TEST_MAIN(cases)
