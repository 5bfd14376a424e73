/* pgt: a human-readable listing of a compiled grammar (paper 000 sec. 7: what the rule compiler
 * produced), written as grammar text so that it compiles again to the same listing; indices and
 * source positions go into comments. Expressions are decompiled from their postfix code into
 * infix with the fewest parentheses C's precedence needs. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "grammar_internal.h"

/* Precedence of a decompiled piece: binary operators as in the parser (1 || .. 6 * / %). */
#define PREC_UNARY 7
#define PREC_ATOM 8

static char *format(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

static char *format(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (!s) return NULL;
    va_start(ap, fmt);
    vsnprintf(s, (size_t)n + 1, fmt, ap);
    va_end(ap);
    return s;
}

/* The shortest %g spelling of v that reads back as the same float (so 0.004, not
 * 0.00400000019); 9 significant digits always do. */
static void put_float(char *buf, size_t size, float v) {
    for (int digits = 6; digits <= 9; ++digits) {
        snprintf(buf, size, "%.*g", digits, (double)v);
        if (strtof(buf, NULL) == v) return;
    }
}

static int binary_prec(uint32_t op) {
    switch (op) {
    case PGT_GRAMMAR_OP_OR:
        return 1;
    case PGT_GRAMMAR_OP_AND:
        return 2;
    case PGT_GRAMMAR_OP_EQ:
    case PGT_GRAMMAR_OP_NE:
        return 3;
    case PGT_GRAMMAR_OP_LT:
    case PGT_GRAMMAR_OP_LE:
    case PGT_GRAMMAR_OP_GT:
    case PGT_GRAMMAR_OP_GE:
        return 4;
    case PGT_GRAMMAR_OP_ADD:
    case PGT_GRAMMAR_OP_SUB:
        return 5;
    case PGT_GRAMMAR_OP_MUL:
    case PGT_GRAMMAR_OP_DIV:
    case PGT_GRAMMAR_OP_MOD:
        return 6;
    default:
        return 0;
    }
}

/* s, in parentheses when its precedence is below min. */
static char *wrap(const char *s, int prec, int min) {
    return prec < min ? format("(%s)", s) : format("%s", s);
}

/* Expression e of rule `rule` (PGT_NONE for a param) in infix; malloc'd, NULL when out of
 * memory. */
static char *infix(const pgt_grammar *g, uint32_t e, uint32_t rule) {
    const pgt_grammar_expr *x = &g->exprs[e];
    char *s[PGT_GRAMMAR_VM_STACK] = {0};
    int prec[PGT_GRAMMAR_VM_STACK] = {0};
    uint32_t sp = 0;
    int ok = 1;
    for (uint32_t k = 0; k < x->code_count && ok; ++k) {
        const uint32_t ins = g->code[x->first_code + k];
        const uint32_t op = ins & PGT_GRAMMAR_OP_MASK, arg = ins >> PGT_GRAMMAR_OP_BITS;
        const int effect = pgt_grammar_op_effect(op), bp = binary_prec(op);
        char *r = NULL;
        int rp = PREC_ATOM;
        if (op == PGT_GRAMMAR_OP_CONST) {
            char num[32];
            put_float(num, sizeof num, g->consts[arg]);
            r = format("%s", num);
        } else if (op == PGT_GRAMMAR_OP_PARAM) {
            r = format("%s", g->names + g->params[arg].name);
        } else if (op == PGT_GRAMMAR_OP_ARG) {
            r = rule == PGT_NONE
                    ? format("arg%u", arg)
                    : format("%s", g->names + g->rule_params[g->rules[rule].first_param + arg]);
        } else if (op == PGT_GRAMMAR_OP_CONTEXT) {
            r = format("context.%s(texCoord)", pgt_grammar_context_name(arg));
        } else if (op == PGT_GRAMMAR_OP_NEG || op == PGT_GRAMMAR_OP_NOT) {
            char *a = wrap(s[sp - 1], prec[sp - 1], PREC_UNARY);
            r = a ? format("%s%s", op == PGT_GRAMMAR_OP_NEG ? "-" : "!", a) : NULL;
            free(a);
            rp = PREC_UNARY;
        } else if (bp > 0) {
            /* left-associative: a right operand of the same precedence needs parentheses */
            char *a = wrap(s[sp - 2], prec[sp - 2], bp), *b = wrap(s[sp - 1], prec[sp - 1], bp + 1);
            r = a && b ? format("%s %s %s", a, pgt_grammar_op_name(op), b) : NULL;
            free(a);
            free(b);
            rp = bp;
        } else {
            /* a function of 1 - effect arguments */
            const uint32_t n = (uint32_t)(1 - effect);
            r = format("%s(", pgt_grammar_op_name(op));
            for (uint32_t j = 0; j < n && r; ++j) {
                char *t = format("%s%s%s", r, s[sp - n + j], j + 1 < n ? ", " : ")");
                free(r);
                r = t;
            }
        }
        /* pop the operands, push the result */
        const uint32_t pops = (uint32_t)(effect <= 0 ? 1 - effect : 0);
        for (uint32_t j = 0; j < pops; ++j) free(s[--sp]);
        s[sp] = r;
        prec[sp++] = rp;
        ok = r != NULL;
    }
    char *result = ok && sp == 1 ? s[0] : NULL;
    for (uint32_t j = result ? 1 : 0; j < sp; ++j) free(s[j]);
    return result;
}

static void put_expr(const pgt_grammar *g, uint32_t e, uint32_t rule, FILE *f) {
    char *s = infix(g, e, rule);
    fputs(s ? s : "<out of memory>", f);
    free(s);
}

/* "(a, b, c)" of an item's arguments; a smoothness argument by its name. */
static void put_args(const pgt_grammar *g, const pgt_grammar_item *it, uint32_t rule, FILE *f) {
    /* a terminal takes its parentheses even without arguments (the parser requires them) */
    if (it->arg_count == 0) {
        if (it->kind == PGT_GRAMMAR_ITEM_TERMINAL) fputs("()", f);
        return;
    }
    fputc('(', f);
    for (uint32_t a = 0; a < it->arg_count; ++a) {
        if (a) fputs(", ", f);
        const uint32_t e = g->args[it->first_arg + a];
        if (it->kind == PGT_GRAMMAR_ITEM_TERMINAL && it->target == PGT_GRAMMAR_TERMINAL_BARK &&
            a == 1)
            fputs(pgt_grammar_smoothness_name(
                      (uint32_t)g->consts[g->code[g->exprs[e].first_code] >> PGT_GRAMMAR_OP_BITS]),
                  f);
        else
            put_expr(g, e, rule, f);
    }
    fputc(')', f);
}

static void put_sequence(const pgt_grammar *g, uint32_t s, uint32_t rule, int depth, FILE *f);

static void put_parts(const pgt_grammar *g, uint32_t first, uint32_t count, uint32_t rule,
                      int depth, FILE *f) {
    for (uint32_t k = 0; k < count; ++k) {
        const pgt_grammar_part *pt = &g->parts[first + k];
        if (k) fprintf(f, "%*s|\n", 4 * depth - 2, "");
        if (pt->kind == PGT_GRAMMAR_PART_REPEAT) {
            fprintf(f, "%*s{  # part %u, repeat group, %u:%u\n", 4 * depth, "", first + k, pt->line,
                    pt->col);
            put_parts(g, pt->first_part, pt->part_count, rule, depth + 1, f);
            fprintf(f, "%*s}*\n", 4 * depth, "");
            continue;
        }
        static const char *const prefix[] = {"", "'", "~"};
        fprintf(f, "%*s%s", 4 * depth, "", prefix[pt->kind]);
        put_expr(g, pt->size, rule, f);
        fprintf(f, " :  # part %u, %u:%u\n", first + k, pt->line, pt->col);
        put_sequence(g, pt->sequence, rule, depth + 1, f);
    }
}

static void put_item(const pgt_grammar *g, uint32_t i, uint32_t rule, int depth, FILE *f) {
    const pgt_grammar_item *it = &g->items[i];
    fprintf(f, "%*s", 4 * depth, "");
    switch (it->kind) {
    case PGT_GRAMMAR_ITEM_CALL:
        fputs(g->names + g->rules[it->target].name, f);
        break;
    case PGT_GRAMMAR_ITEM_MARCHING:
        fputs("Marching", f);
        break;
    case PGT_GRAMMAR_ITEM_BRANCH:
        fputs("Branch", f);
        break;
    case PGT_GRAMMAR_ITEM_TERMINAL:
        fputs(pgt_grammar_terminal_name(it->target), f);
        break;
    default:
        fprintf(f, "split(%c)", "xyz"[it->target]);
        break;
    }
    put_args(g, it, rule, f);
    if (it->kind != PGT_GRAMMAR_ITEM_MARCHING && it->kind != PGT_GRAMMAR_ITEM_BRANCH &&
        it->kind != PGT_GRAMMAR_ITEM_SPLIT) {
        fprintf(f, "  # item %u, %u:%u\n", i, it->line, it->col);
        return;
    }
    fprintf(f, " {  # item %u, %u:%u\n", i, it->line, it->col);
    if (it->kind == PGT_GRAMMAR_ITEM_SPLIT) {
        put_parts(g, it->first_sub, it->sub_count, rule, depth + 1, f);
    } else {
        for (uint32_t k = 0; k < it->sub_count; ++k) {
            if (k) fprintf(f, "%*s,\n", 4 * depth + 2, "");
            put_sequence(g, g->subs[it->first_sub + k], rule, depth + 1, f);
        }
    }
    fprintf(f, "%*s}\n", 4 * depth, "");
}

static void put_sequence(const pgt_grammar *g, uint32_t s, uint32_t rule, int depth, FILE *f) {
    const pgt_grammar_sequence *q = &g->sequences[s];
    if (q->item_count == 0) fprintf(f, "%*sNIL  # sequence %u\n", 4 * depth, "", s);
    for (uint32_t k = 0; k < q->item_count; ++k) put_item(g, q->first_item + k, rule, depth, f);
}

void pgt_grammar_dump(const pgt_grammar *g, FILE *f) {
    fprintf(f,
            "# grammar %s: %u rules, %u cases, %u sequences, %u items, %u split parts, %u "
            "expressions, %u instructions, %u consts, %u params\n",
            g->names + g->file_name, g->rule_count, g->case_count, g->sequence_count, g->item_count,
            g->part_count, g->expr_count, g->code_count, g->const_count, g->param_count);
    for (uint32_t k = 0; k < g->param_count; ++k) {
        const pgt_grammar_param *pm = &g->params[k];
        char num[32];
        put_float(num, sizeof num, g->param_values[k]);
        fprintf(f, "param %s = ", g->names + pm->name);
        /* an overridden param is its value (the params after it were re-evaluated from it, as
         * they will be from the dump); its expression goes into the comment */
        if (pm->overridden)
            fputs(num, f);
        else
            put_expr(g, pm->expr, PGT_NONE, f);
        fprintf(f, ";  # param %u = %s", k, num);
        if (pm->overridden) {
            fputs(" (overridden; was ", f);
            put_expr(g, pm->expr, PGT_NONE, f);
            fputc(')', f);
        }
        fprintf(f, ", %u:%u\n", pm->line, pm->col);
    }
    for (uint32_t r = 0; r < g->rule_count; ++r) {
        const pgt_grammar_rule *rl = &g->rules[r];
        fprintf(f, "\n# rule %u%s, %u:%u\n%s", r, r == 0 ? " (axiom)" : "", rl->line, rl->col,
                g->names + rl->name);
        for (uint32_t k = 0; k < rl->param_count; ++k)
            fprintf(f, "%s%s", k ? ", " : "(", g->names + g->rule_params[rl->first_param + k]);
        fputs(rl->param_count ? ") -->\n" : " -->\n", f);
        for (uint32_t c = 0; c < rl->case_count; ++c) {
            const pgt_grammar_case *cs = &g->cases[rl->first_case + c];
            const int plain = rl->case_count == 1;
            if (!plain && cs->condition != PGT_NONE) {
                fputs("  case ", f);
                put_expr(g, cs->condition, r, f);
                fputs(" :\n", f);
            } else if (!plain) {
                fputs("  else :\n", f);
            }
            put_sequence(g, cs->sequence, r, 1, f);
        }
        fputs(";\n", f);
    }
}
