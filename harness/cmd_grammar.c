/* pgt grammar: compiles a grammar file (paper 000 sec. 7, the rule compiler; ref_cpu/src/
 * grammar_*.c) and prints a summary or the listing of the compiled rule table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "pgt/grammar.h"

static const char *grammar_usage =
    "usage: pgt grammar FILE [--dump] [--param NAME=VALUE ...]\n"
    "\n"
    "Compiles a grammar (the language of grammars/README.md: rules, case/else, Marching,\n"
    "Branch, split, terminals, params, expressions) into the flat rule table the expander runs.\n"
    "\n"
    "  FILE                a grammar file, e.g. grammars/ivy.grammar\n"
    "  --dump              print the listing of the compiled grammar (grammar text that compiles\n"
    "                      to the same listing; indices and source positions in comments)\n"
    "  --param NAME=VALUE  override a param after compiling (params defined from it are\n"
    "                      re-evaluated); repeatable, applied in order\n"
    "\n"
    "Prints one line: rules, items, expressions, consts and the params with their values.\n"
    "Exit 0 on success, 2 on a bad flag or grammar (one line FILE:LINE:COL: what was found,\n"
    "what was expected).\n";

int pgt_cmd_grammar(int argc, char **argv) {
    const char *verb = "grammar", *path = NULL;
    const char *overrides[PGT_CLI_MAX_PARAM_FLAGS];
    uint32_t override_count = 0;
    int dump = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(grammar_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--dump")) {
            dump = 1;
        } else if (!strcmp(a, "--param")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_push(verb, a, v, overrides, &override_count, PGT_CLI_MAX_PARAM_FLAGS))
                return PGT_EXIT_USAGE;
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt grammar --help)", a);
        } else if (!path) {
            path = a;
        } else {
            return pgt_cli_fail(verb, "unexpected argument '%s' (one grammar file only)", a);
        }
    }
    if (!path) return pgt_cli_fail(verb, "no grammar file (see pgt grammar --help)");

    pgt_error err = {0};
    pgt_grammar g;
    if (pgt_grammar_load(&g, path, &err) != PGT_OK) {
        pgt_grammar_destroy(&g);
        return pgt_cli_fail(verb, "%s", err.message);
    }
    int rc = PGT_EXIT_USAGE;
    if (pgt_cli_grammar_params(verb, &g, overrides, override_count)) goto done;
    if (dump) {
        pgt_grammar_dump(&g, stdout);
    } else {
        printf("grammar %s: %u rules, %u items, %u expressions, %u consts, %u params", path,
               g.rule_count, g.item_count, g.expr_count, g.const_count, g.param_count);
        for (uint32_t k = 0; k < g.param_count; ++k)
            printf("%s%s=%g", k ? ", " : " (", g.names + g.params[k].name,
                   (double)g.param_values[k]);
        printf("%s\n", g.param_count ? ")" : "");
    }
    rc = PGT_EXIT_OK;
done:
    pgt_grammar_destroy(&g);
    return rc;
}
