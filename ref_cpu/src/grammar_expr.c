/* pgt: the grammar's expression stack machine, and params overridden after compilation (paper
 * 000 sec. 7: the rule expander evaluates the compiled rule map per seed; sec. 8: rand and the
 * external contexts of the ivy grammar).
 *
 * One expression is a postfix program over float32 with an explicit stack of
 * PGT_GRAMMAR_VM_STACK floats and no recursion, so a GPU kernel can run the same loop. Every
 * random draw is pgt_rng_float(seed, stream, counter++) (rng.h): deterministic per seed whatever
 * the evaluation order of the seeds. */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grammar_internal.h"
#include "pgt/rng.h"

const pgt_grammar_fn pgt_grammar_fns[] = {
    {"sin", PGT_GRAMMAR_OP_SIN, 1},     {"cos", PGT_GRAMMAR_OP_COS, 1},
    {"tan", PGT_GRAMMAR_OP_TAN, 1},     {"asin", PGT_GRAMMAR_OP_ASIN, 1},
    {"acos", PGT_GRAMMAR_OP_ACOS, 1},   {"atan", PGT_GRAMMAR_OP_ATAN, 1},
    {"atan2", PGT_GRAMMAR_OP_ATAN2, 2}, {"sqrt", PGT_GRAMMAR_OP_SQRT, 1},
    {"abs", PGT_GRAMMAR_OP_ABS, 1},     {"floor", PGT_GRAMMAR_OP_FLOOR, 1},
    {"ceil", PGT_GRAMMAR_OP_CEIL, 1},   {"min", PGT_GRAMMAR_OP_MIN, 2},
    {"max", PGT_GRAMMAR_OP_MAX, 2},     {"pow", PGT_GRAMMAR_OP_POW, 2},
    {"exp", PGT_GRAMMAR_OP_EXP, 1},     {"log", PGT_GRAMMAR_OP_LOG, 1},
    {"clamp", PGT_GRAMMAR_OP_CLAMP, 3}, {"rand", PGT_GRAMMAR_OP_RAND, 2},
};
const uint32_t pgt_grammar_fn_count = sizeof pgt_grammar_fns / sizeof pgt_grammar_fns[0];

static const char *const op_names[PGT_GRAMMAR_OP_COUNT] = {
    "const", "param", "arg", "neg",  "!",    "+",    "-",     "*",    "/",    "%",
    "<",     "<=",    ">",   ">=",   "==",   "!=",   "&&",    "||",   "rand", "context",
    "sin",   "cos",   "tan", "asin", "acos", "atan", "atan2", "sqrt", "abs",  "floor",
    "ceil",  "min",   "max", "pow",  "exp",  "log",  "clamp",
};

const char *pgt_grammar_op_name(uint32_t op) {
    return op < PGT_GRAMMAR_OP_COUNT ? op_names[op] : "?";
}

const char *pgt_grammar_terminal_name(uint32_t terminal) {
    static const char *const names[PGT_GRAMMAR_TERMINAL_COUNT] = {
        "Bark", "Leaves", "Wall", "Window", "Door", "Ledge", "Balcony", "Mesh"};
    return terminal < PGT_GRAMMAR_TERMINAL_COUNT ? names[terminal] : "?";
}

const char *pgt_grammar_context_name(uint32_t context_id) {
    static const char *const names[PGT_GRAMMAR_CONTEXT_COUNT] = {"mask", "density"};
    return context_id < PGT_GRAMMAR_CONTEXT_COUNT ? names[context_id] : "?";
}

const char *pgt_grammar_smoothness_name(uint32_t smoothness) {
    static const char *const names[] = {"discontinuous", "C0", "C1"};
    return smoothness < 3 ? names[smoothness] : "?";
}

int pgt_grammar_op_effect(uint32_t op) {
    switch (op) {
    case PGT_GRAMMAR_OP_CONST:
    case PGT_GRAMMAR_OP_PARAM:
    case PGT_GRAMMAR_OP_ARG:
    case PGT_GRAMMAR_OP_CONTEXT:
        return 1;
    case PGT_GRAMMAR_OP_NEG:
    case PGT_GRAMMAR_OP_NOT:
        return 0;
    default:
        break;
    }
    if (op >= PGT_GRAMMAR_OP_ADD && op <= PGT_GRAMMAR_OP_OR) return -1; /* binary operators */
    for (uint32_t k = 0; k < pgt_grammar_fn_count; ++k)
        if (pgt_grammar_fns[k].op == op) return 1 - (int)pgt_grammar_fns[k].arity;
    return -1; /* the binary operators */
}

static float unary_fn(uint32_t op, float a) {
    switch (op) {
    case PGT_GRAMMAR_OP_NEG:
        return -a;
    case PGT_GRAMMAR_OP_NOT:
        return a == 0.0f ? 1.0f : 0.0f;
    case PGT_GRAMMAR_OP_SIN:
        return sinf(a);
    case PGT_GRAMMAR_OP_COS:
        return cosf(a);
    case PGT_GRAMMAR_OP_TAN:
        return tanf(a);
    case PGT_GRAMMAR_OP_ASIN:
        return asinf(a);
    case PGT_GRAMMAR_OP_ACOS:
        return acosf(a);
    case PGT_GRAMMAR_OP_ATAN:
        return atanf(a);
    case PGT_GRAMMAR_OP_SQRT:
        return sqrtf(a);
    case PGT_GRAMMAR_OP_ABS:
        return fabsf(a);
    case PGT_GRAMMAR_OP_FLOOR:
        return floorf(a);
    case PGT_GRAMMAR_OP_CEIL:
        return ceilf(a);
    case PGT_GRAMMAR_OP_EXP:
        return expf(a);
    default:
        assert(op == PGT_GRAMMAR_OP_LOG);
        return logf(a);
    }
}

static float binary_fn(uint32_t op, float a, float b) {
    switch (op) {
    case PGT_GRAMMAR_OP_ADD:
        return a + b;
    case PGT_GRAMMAR_OP_SUB:
        return a - b;
    case PGT_GRAMMAR_OP_MUL:
        return a * b;
    case PGT_GRAMMAR_OP_DIV:
        return a / b;
    case PGT_GRAMMAR_OP_MOD:
        return fmodf(a, b);
    case PGT_GRAMMAR_OP_LT:
        return (float)(a < b);
    case PGT_GRAMMAR_OP_LE:
        return (float)(a <= b);
    case PGT_GRAMMAR_OP_GT:
        return (float)(a > b);
    case PGT_GRAMMAR_OP_GE:
        return (float)(a >= b);
    case PGT_GRAMMAR_OP_EQ:
        return (float)(a == b);
    case PGT_GRAMMAR_OP_NE:
        return (float)(a != b);
    case PGT_GRAMMAR_OP_AND:
        return (float)(a != 0.0f && b != 0.0f);
    case PGT_GRAMMAR_OP_OR:
        return (float)(a != 0.0f || b != 0.0f);
    case PGT_GRAMMAR_OP_ATAN2:
        return atan2f(a, b);
    case PGT_GRAMMAR_OP_MIN:
        return fminf(a, b);
    case PGT_GRAMMAR_OP_MAX:
        return fmaxf(a, b);
    default:
        assert(op == PGT_GRAMMAR_OP_POW);
        return powf(a, b);
    }
}

/* The machine. With diag it also follows where a value that is not finite came from: origin[i]
 * is the instruction that made stack[i] NaN or infinite. A result that is not finite takes the
 * origin of its first operand of the same kind (NaN, or an infinity of either sign: inf * -1
 * passes the infinity on, max(NaN, inf) the infinity, not the NaN fmaxf dropped), else the
 * operator is the origin (1 / 0, inf - inf, sqrt(-inf)); a value a comparison turns finite is
 * forgotten. So a failure names the operator at fault. Only the failure path runs with diag. */
static pgt_result run(const pgt_grammar *g, uint32_t expr, const float *args, uint32_t arg_count,
                      const pgt_grammar_env *env, int strict, int diag, float *out,
                      pgt_grammar_fault *fault) {
    assert(expr < g->expr_count);
    const pgt_grammar_expr *e = &g->exprs[expr];
    assert(e->max_stack <= PGT_GRAMMAR_VM_STACK);
    float stack[PGT_GRAMMAR_VM_STACK];
    uint32_t origin[PGT_GRAMMAR_VM_STACK];
    float origin_value[PGT_GRAMMAR_VM_STACK];
    uint32_t sp = 0;
    const float *params = env && env->params ? env->params : g->param_values;
    for (uint32_t k = 0; k < e->code_count; ++k) {
        const uint32_t at = e->first_code + k;
        const uint32_t ins = g->code[at];
        const uint32_t op = ins & PGT_GRAMMAR_OP_MASK, arg = ins >> PGT_GRAMMAR_OP_BITS;
        /* diag: where the operands are, and their NaN and infinity flags before the op */
        uint32_t base = 0;
        uint32_t operand_nan = 0, operand_inf = 0; /* bit i - base */
        if (diag) {
            base = sp + (uint32_t)pgt_grammar_op_effect(op) - 1u;
            for (uint32_t i = base; i < sp; ++i) {
                operand_nan |= (uint32_t)(isnan(stack[i]) != 0) << (i - base);
                operand_inf |= (uint32_t)(isinf(stack[i]) != 0) << (i - base);
            }
        }
        switch (op) {
        case PGT_GRAMMAR_OP_CONST:
            assert(arg < g->const_count);
            stack[sp++] = g->consts[arg];
            break;
        case PGT_GRAMMAR_OP_PARAM:
            assert(arg < g->param_count);
            stack[sp++] = params[arg];
            break;
        case PGT_GRAMMAR_OP_ARG:
            if (arg >= arg_count || !args) {
                fault->why = "reads a rule argument that was not given", fault->at = at;
                return PGT_ERROR_INVALID_ARGUMENT;
            }
            stack[sp++] = args[arg];
            break;
        case PGT_GRAMMAR_OP_CONTEXT:
            if (!env || !env->context) {
                fault->why = "reads a context but no context callback was given", fault->at = at;
                return PGT_ERROR_INVALID_ARGUMENT;
            }
            stack[sp++] = env->context(env->context_data, arg, env->u, env->v);
            break;
        case PGT_GRAMMAR_OP_RAND: {
            if (!env || !env->counter) {
                fault->why = "draws a random number but no draw counter was given";
                fault->at = at;
                return PGT_ERROR_INVALID_ARGUMENT;
            }
            const float a = stack[sp - 2], b = stack[sp - 1];
            float x = a + (b - a) * pgt_rng_float(env->seed, env->stream, (*env->counter)++);
            /* rounding may land on b; the language promises [a, b) */
            if (a < b && x >= b) x = nextafterf(b, a);
            stack[--sp - 1] = x;
            break;
        }
        case PGT_GRAMMAR_OP_CLAMP: {
            const float x = stack[sp - 3], lo = stack[sp - 2], hi = stack[sp - 1];
            sp -= 2;
            stack[sp - 1] = fminf(fmaxf(x, lo), hi);
            break;
        }
        default:
            if (pgt_grammar_op_effect(op) == 0) {
                stack[sp - 1] = unary_fn(op, stack[sp - 1]);
            } else {
                const float a = stack[sp - 2], b = stack[sp - 1];
                if (strict && (op == PGT_GRAMMAR_OP_DIV || op == PGT_GRAMMAR_OP_MOD) && b == 0.0f) {
                    fault->why = "divides by zero", fault->at = at;
                    return PGT_ERROR_INVALID_ARGUMENT;
                }
                stack[--sp - 1] = binary_fn(op, a, b);
            }
            break;
        }
        if (diag) {
            assert(base == sp - 1u);
            const float v = stack[base];
            const uint32_t same = isnan(v) ? operand_nan : isinf(v) ? operand_inf : 0u;
            if (isfinite(v)) {
                origin[base] = PGT_NONE;
            } else if (same) {
                /* the first operand of the same kind (origin[] still holds the operands': the
                 * result overwrote only stack[base]) */
                uint32_t i = base;
                while (!(same >> (i - base) & 1u)) ++i;
                origin[base] = origin[i], origin_value[base] = origin_value[i];
            } else {
                origin[base] = at, origin_value[base] = v;
            }
        }
    }
    assert(sp == 1);
    *out = stack[0];
    if (!isfinite(stack[0])) {
        fault->why = isnan(stack[0]) ? "evaluates to NaN" : "evaluates to infinity";
        if (diag) fault->at = origin[0], fault->value = origin_value[0];
        return PGT_ERROR_NOT_FINITE;
    }
    return PGT_OK;
}

pgt_result pgt_grammar_run(const pgt_grammar *g, uint32_t expr, const float *args,
                           uint32_t arg_count, const pgt_grammar_env *env, int strict, float *out,
                           pgt_grammar_fault *fault) {
    const uint64_t drawn = env && env->counter ? *env->counter : 0u;
    *fault = (pgt_grammar_fault){"", PGT_NONE, 0.0f};
    const pgt_result r = run(g, expr, args, arg_count, env, strict, 0, out, fault);
    if (r != PGT_ERROR_NOT_FINITE) return r;
    /* once more, drawing the same numbers (the caller's counter stays where the first run left
     * it), to find the operator the value that is not finite came from */
    pgt_grammar_env again;
    uint64_t counter = drawn;
    if (env) {
        again = *env;
        if (env->counter) again.counter = &counter;
    }
    float value = 0.0f;
    (void)run(g, expr, args, arg_count, env ? &again : NULL, strict, 1, &value, fault);
    return r;
}

/* How a message shows an instruction: binary and unary operators quoted, functions by name. */
static void op_label(uint32_t op, char *buf, size_t size) {
    if (op == PGT_GRAMMAR_OP_NEG)
        snprintf(buf, size, "unary '-'");
    else if (op >= PGT_GRAMMAR_OP_NOT && op <= PGT_GRAMMAR_OP_OR)
        snprintf(buf, size, "'%s'", op_names[op]);
    else if (op == PGT_GRAMMAR_OP_CONTEXT)
        snprintf(buf, size, "the context lookup");
    else if (op == PGT_GRAMMAR_OP_ARG)
        snprintf(buf, size, "the rule argument");
    else
        snprintf(buf, size, "%s", pgt_grammar_op_name(op));
}

void pgt_grammar_fault_place(const pgt_grammar *g, uint32_t expr, const pgt_grammar_fault *fault,
                             uint32_t *line, uint32_t *col, char *detail, size_t detail_size) {
    *line = g->exprs[expr].line, *col = g->exprs[expr].col;
    if (detail_size) detail[0] = '\0';
    if (fault->at == PGT_NONE || !g->code_pos) return;
    *line = g->code_pos[fault->at].line, *col = g->code_pos[fault->at].col;
    if (isfinite(fault->value) || !detail_size) return;
    char what[32];
    op_label(g->code[fault->at] & PGT_GRAMMAR_OP_MASK, what, sizeof what);
    snprintf(detail, detail_size, " (%s gives %s here)", what,
             isnan(fault->value)   ? "NaN"
             : fault->value > 0.0f ? "inf"
                                   : "-inf");
}

pgt_result pgt_grammar_eval(const pgt_grammar *g, uint32_t expr, const float *args,
                            uint32_t arg_count, const pgt_grammar_env *env, float *out,
                            pgt_error *err) {
    pgt_grammar_fault fault;
    const pgt_result r = pgt_grammar_run(g, expr, args, arg_count, env, 0, out, &fault);
    if (r != PGT_OK) {
        uint32_t line, col;
        char detail[64];
        pgt_grammar_fault_place(g, expr, &fault, &line, &col, detail, sizeof detail);
        pgt_error_set(err, r, "%s:%u:%u: the expression %s%s", g->names + g->file_name, line, col,
                      fault.why, detail);
    }
    return r;
}

uint32_t pgt_grammar_find_param(const pgt_grammar *g, const char *name) {
    for (uint32_t k = 0; g && name && k < g->param_count; ++k)
        if (!strcmp(g->names + g->params[k].name, name)) return k;
    return PGT_NONE;
}

pgt_result pgt_grammar_set_param(pgt_grammar *g, const char *name, float value, pgt_error *err) {
    const uint32_t k = pgt_grammar_find_param(g, name);
    if (k == PGT_NONE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: no param '%s' in the grammar",
                             g->names + g->file_name, name ? name : "");
    if (!isfinite(value))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: param '%s' must be finite",
                             g->names + g->file_name, name);
    float *saved = malloc((size_t)g->param_count * sizeof *saved);
    if (!saved)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory",
                             g->names + g->file_name);
    memcpy(saved, g->param_values, (size_t)g->param_count * sizeof *saved);
    g->param_values[k] = value;
    pgt_result r = PGT_OK;
    pgt_grammar_fault fault;
    /* params only read earlier ones, so one pass in definition order settles every value */
    for (uint32_t j = k + 1; j < g->param_count && r == PGT_OK; ++j) {
        if (g->params[j].overridden) continue;
        r = pgt_grammar_run(g, g->params[j].expr, NULL, 0, NULL, 1, &g->param_values[j], &fault);
        if (r != PGT_OK) {
            uint32_t line, col;
            char detail[64];
            pgt_grammar_fault_place(g, g->params[j].expr, &fault, &line, &col, detail,
                                    sizeof detail);
            pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                          "%s:%u:%u: with %s = %g, param '%s' %s%s", g->names + g->file_name, line,
                          col, name, (double)value, g->names + g->params[j].name, fault.why,
                          detail);
        }
    }
    /* a Branch count is a constant of the params and must still equal its sequences */
    for (uint32_t i = 0; i < g->item_count && r == PGT_OK; ++i) {
        const pgt_grammar_item *it = &g->items[i];
        if (it->kind != PGT_GRAMMAR_ITEM_BRANCH) continue;
        float n = 0.0f;
        const uint32_t e = g->args[it->first_arg];
        r = pgt_grammar_run(g, e, NULL, 0, NULL, 1, &n, &fault);
        if (r != PGT_OK) { /* the count itself fails: where and why, as for a param */
            uint32_t line, col;
            char detail[64];
            pgt_grammar_fault_place(g, e, &fault, &line, &col, detail, sizeof detail);
            r = PGT_ERROR_INVALID_ARGUMENT;
            pgt_error_set(err, r, "%s:%u:%u: with %s = %g, the count of Branch %s%s",
                          g->names + g->file_name, line, col, name, (double)value, fault.why,
                          detail);
        } else if (n != (float)it->sub_count) {
            r = PGT_ERROR_INVALID_ARGUMENT;
            pgt_error_set(err, r, "%s:%u:%u: with %s = %g, Branch asks for %g sequences, it has %u",
                          g->names + g->file_name, it->line, it->col, name, (double)value,
                          (double)n, it->sub_count);
        }
    }
    if (r != PGT_OK) {
        memcpy(g->param_values, saved, (size_t)g->param_count * sizeof *saved);
    } else {
        g->params[k].overridden = 1;
    }
    free(saved);
    return r;
}
