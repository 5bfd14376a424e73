/* pgt: what the grammar modules share (grammar_lex.c, grammar_parse.c, grammar_expr.c,
 * grammar_dump.c) and nobody else needs: tokens, the function table, the raw evaluator. */
#ifndef PGT_GRAMMAR_INTERNAL_H
#define PGT_GRAMMAR_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "pgt/grammar.h"

typedef enum gtok_kind {
    GTOK_EOF = 0,
    GTOK_IDENT,
    GTOK_NUMBER,
    GTOK_STRING,
    GTOK_ARROW, /* --> -> and U+2192 */
    GTOK_LPAREN,
    GTOK_RPAREN,
    GTOK_LBRACE,
    GTOK_RBRACE,
    GTOK_LBRACKET,
    GTOK_RBRACKET,
    GTOK_COMMA,
    GTOK_COLON,
    GTOK_BAR,
    GTOK_SEMI,
    GTOK_ASSIGN,
    GTOK_PLUS,
    GTOK_MINUS,
    GTOK_STAR,
    GTOK_SLASH,
    GTOK_PERCENT,
    GTOK_LT,
    GTOK_LE,
    GTOK_GT,
    GTOK_GE,
    GTOK_EQ,
    GTOK_NE,
    GTOK_AND,
    GTOK_OR,
    GTOK_NOT,
    GTOK_QUOTE,
    GTOK_TILDE,
    GTOK_DOT,
    GTOK_COUNT
} gtok_kind;

typedef struct gtoken {
    uint32_t kind;           /* gtok_kind */
    uint32_t offset, length; /* bytes of the source */
    uint32_t line, col;
    uint32_t match; /* '(': index of the matching ')', or PGT_NONE */
    float value;    /* NUMBER */
} gtoken;

/* Splits text into tokens ending with one GTOK_EOF, and matches parentheses. On failure sets err
 * ("FILE:LINE:COL: ...") and returns its code; *out is then freed and NULL. */
pgt_result pgt_grammar_lex(const char *text, size_t size, const char *file, gtoken **out,
                           uint32_t *count, pgt_error *err);

/* The token as a message shows it: "'}'", "'IvyMain'", "'3.5'", "a string", "end of file". */
void pgt_grammar_describe(const char *text, const gtoken *t, char *buf, size_t size);

/* Levenshtein distance of two byte strings, capped at cap (cheap "did you mean"). */
uint32_t pgt_grammar_distance(const char *a, size_t na, const char *b, size_t nb, uint32_t cap);

/* Functions of the language: name, opcode, number of arguments. */
typedef struct pgt_grammar_fn {
    const char *name;
    uint32_t op;
    uint32_t arity;
} pgt_grammar_fn;
extern const pgt_grammar_fn pgt_grammar_fns[];
extern const uint32_t pgt_grammar_fn_count;

/* Stack effect of an opcode (pushes minus pops). */
int pgt_grammar_op_effect(uint32_t op);

/* Why an expression failed: a static phrase ("divides by zero", "evaluates to NaN", ...), the
 * instruction it points at (the division; for a value that is not finite, the first instruction
 * whose result was not, so that the message names the operator, not the expression; PGT_NONE
 * when none) and that first value. */
typedef struct pgt_grammar_fault {
    const char *why;
    uint32_t at; /* index in g->code, or PGT_NONE */
    float value;
} pgt_grammar_fault;

/* Runs expression expr of g (which may still be under construction). strict (compile-time
 * params) also rejects a division or remainder by zero. On failure returns the code and fills
 * *fault. A draw counter in env advances as in a run without failure. */
pgt_result pgt_grammar_run(const pgt_grammar *g, uint32_t expr, const float *args,
                           uint32_t arg_count, const pgt_grammar_env *env, int strict, float *out,
                           pgt_grammar_fault *fault);

/* Where a fault points (its instruction's token, else the expression's start) and what to add to
 * its phrase: " ('/' gives inf here)" for a value that is not finite, else "". */
void pgt_grammar_fault_place(const pgt_grammar *g, uint32_t expr, const pgt_grammar_fault *fault,
                             uint32_t *line, uint32_t *col, char *detail, size_t detail_size);

/* Whether text[pos] (pos < size) ends a line: '\n', or a '\r' not followed by '\n' (a file
 * saved with CR line ends; CRLF ends its line at the '\n'). The lexer and the file-size error
 * count lines by it. */
static inline int pgt_grammar_line_end(const char *text, size_t size, size_t pos) {
    return text[pos] == '\n' || (text[pos] == '\r' && (pos + 1u >= size || text[pos + 1u] != '\n'));
}

#endif
