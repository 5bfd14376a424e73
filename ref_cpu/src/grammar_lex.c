/* pgt: the grammar language's lexer (grammars/README.md, "Tokens").
 *
 * Reads exactly size bytes (no NUL terminator needed, a NUL byte is an error), tracks line and
 * column (columns count UTF-8 code points: every byte but 10xxxxxx continuation bytes), and
 * matches parentheses once so the parser can recognise a rule start `Name(...) -->` in O(1). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grammar_internal.h"

typedef struct lexer {
    const char *text;
    size_t size, pos;
    uint32_t line, col;
    const char *file;
    pgt_error *err;
    gtoken *toks;
    uint32_t count, cap;
} lexer;

static int lex_at(const lexer *L, size_t k) {
    return L->pos + k < L->size ? (unsigned char)L->text[L->pos + k] : -1;
}

/* Moves over n bytes, counting lines and code points. */
static void lex_advance(lexer *L, size_t n) {
    for (; n > 0 && L->pos < L->size; --n, ++L->pos) {
        const unsigned char c = (unsigned char)L->text[L->pos];
        if (pgt_grammar_line_end(L->text, L->size, L->pos)) {
            L->line++;
            L->col = 1;
        } else if ((c & 0xC0u) != 0x80u) {
            L->col++;
        }
    }
}

static pgt_result lex_fail(lexer *L, pgt_result code, uint32_t line, uint32_t col,
                           const char *what) {
    return pgt_error_set(L->err, code, "%s:%u:%u: %s", L->file, line, col, what);
}

static int is_ident_start(int c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
static int is_digit(int c) { return c >= '0' && c <= '9'; }
static int is_ident_char(int c) { return is_ident_start(c) || is_digit(c); }

/* A NUL byte is an error inside comments too (grammars/README.md). */
static pgt_result comment_nul(lexer *L) {
    return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col,
                    "found a NUL byte in a comment, expected grammar text (UTF-8 without NUL)");
}

/* Skips white space and the three comment forms. */
static pgt_result lex_skip(lexer *L) {
    for (;;) {
        const int c = lex_at(L, 0), d = lex_at(L, 1);
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') {
            lex_advance(L, 1);
        } else if (c == '#' || (c == '/' && d == '/')) {
            while (L->pos < L->size && !pgt_grammar_line_end(L->text, L->size, L->pos)) {
                if (L->text[L->pos] == '\0') return comment_nul(L);
                lex_advance(L, 1);
            }
        } else if (c == '/' && d == '*') {
            const uint32_t line = L->line, col = L->col;
            lex_advance(L, 2);
            while (L->pos < L->size && !(lex_at(L, 0) == '*' && lex_at(L, 1) == '/')) {
                if (L->text[L->pos] == '\0') return comment_nul(L);
                lex_advance(L, 1);
            }
            if (L->pos >= L->size)
                return lex_fail(L, PGT_ERROR_PARSE, line, col,
                                "found a '/*' comment that never ends, expected '*/' before the "
                                "end of file");
            lex_advance(L, 2);
        } else {
            return PGT_OK;
        }
    }
}

/* C decimal floating literal without sign: digits [. digits] [e [+-] digits] or . digits [...]. */
static pgt_result lex_number(lexer *L, gtoken *t) {
    size_t n = 0;
    while (is_digit(lex_at(L, n))) n++;
    if (lex_at(L, n) == '.') {
        n++;
        while (is_digit(lex_at(L, n))) n++;
    }
    if (lex_at(L, n) == 'e' || lex_at(L, n) == 'E') {
        size_t e = n + 1;
        if (lex_at(L, e) == '+' || lex_at(L, e) == '-') e++;
        if (!is_digit(lex_at(L, e)))
            return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col,
                            "found a number whose exponent has no digits, expected digits "
                            "after 'e'");
        n = e;
        while (is_digit(lex_at(L, n))) n++;
    }
    if (is_ident_char(lex_at(L, n)) || lex_at(L, n) == '.')
        return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col,
                        "found a letter, digit or '.' glued to a number, expected a number "
                        "like 3, 0.5, .5 or 1e-3 followed by a space or an operator");
    if (n > PGT_GRAMMAR_MAX_NAME_CHARS) {
        char msg[160];
        snprintf(msg, sizeof msg,
                 "found a number of %zu characters, more than PGT_GRAMMAR_MAX_NAME_CHARS (%u)", n,
                 PGT_GRAMMAR_MAX_NAME_CHARS);
        return lex_fail(L, PGT_ERROR_LIMIT, L->line, L->col, msg);
    }
    char buf[PGT_GRAMMAR_MAX_NAME_CHARS + 1];
    memcpy(buf, L->text + L->pos, n);
    buf[n] = '\0';
    const float v = strtof(buf, NULL);
    if (!isfinite(v)) {
        char msg[PGT_GRAMMAR_MAX_NAME_CHARS + 96];
        snprintf(msg, sizeof msg,
                 "found the number %s, expected a number that is finite as float32 (at most "
                 "3.4e38)",
                 buf);
        return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col, msg);
    }
    t->kind = GTOK_NUMBER;
    t->value = v;
    t->length = (uint32_t)n;
    return PGT_OK;
}

static pgt_result lex_string(lexer *L, gtoken *t) {
    size_t n = 1;
    for (;;) {
        const int c = lex_at(L, n);
        if (c < 0 || c == '\n' || c == '\r')
            return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col,
                            "found a string that does not end on its line, expected a closing "
                            "'\"'");
        if (c == '"') break;
        if (c == '\\') {
            const int e = lex_at(L, n + 1);
            if (e != '"' && e != '\\')
                return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col,
                                "found an unknown escape in a string, expected \\\" or \\\\ "
                                "only");
            n++;
        } else if (c == 0) {
            return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col,
                            "found a NUL byte in a string, expected text");
        }
        n++;
    }
    t->kind = GTOK_STRING;
    t->length = (uint32_t)(n + 1);
    return PGT_OK;
}

/* Punctuation, longest first. */
static const struct {
    const char *text;
    uint32_t kind;
} puncts[] = {
    {"-->", GTOK_ARROW},  {"\xE2\x86\x92", GTOK_ARROW},
    {"->", GTOK_ARROW},   {"<=", GTOK_LE},
    {">=", GTOK_GE},      {"==", GTOK_EQ},
    {"!=", GTOK_NE},      {"&&", GTOK_AND},
    {"||", GTOK_OR},      {"(", GTOK_LPAREN},
    {")", GTOK_RPAREN},   {"{", GTOK_LBRACE},
    {"}", GTOK_RBRACE},   {"[", GTOK_LBRACKET},
    {"]", GTOK_RBRACKET}, {",", GTOK_COMMA},
    {":", GTOK_COLON},    {"|", GTOK_BAR},
    {";", GTOK_SEMI},     {"=", GTOK_ASSIGN},
    {"+", GTOK_PLUS},     {"-", GTOK_MINUS},
    {"*", GTOK_STAR},     {"/", GTOK_SLASH},
    {"%", GTOK_PERCENT},  {"<", GTOK_LT},
    {">", GTOK_GT},       {"!", GTOK_NOT},
    {"'", GTOK_QUOTE},    {"~", GTOK_TILDE},
    {".", GTOK_DOT},
};

static pgt_result lex_punct(lexer *L, gtoken *t) {
    for (size_t k = 0; k < sizeof puncts / sizeof puncts[0]; ++k) {
        const size_t n = strlen(puncts[k].text);
        if (L->size - L->pos >= n && memcmp(L->text + L->pos, puncts[k].text, n) == 0) {
            t->kind = puncts[k].kind;
            t->length = (uint32_t)n;
            return PGT_OK;
        }
    }
    const int c = lex_at(L, 0);
    char msg[200];
    if (c == 0)
        snprintf(msg, sizeof msg, "found a NUL byte, expected grammar text (UTF-8 without NUL)");
    else if (c >= 0x80)
        snprintf(msg, sizeof msg,
                 "found byte 0x%02X outside a comment or string, expected ASCII text (the only "
                 "other character allowed there is the arrow U+2192)",
                 (unsigned)c);
    else if (c < 0x20 || c == 0x7F)
        snprintf(msg, sizeof msg, "found control byte 0x%02X, expected a token", (unsigned)c);
    else
        snprintf(msg, sizeof msg, "found '%c', expected a token (see grammars/README.md)", c);
    return lex_fail(L, PGT_ERROR_PARSE, L->line, L->col, msg);
}

static gtoken *lex_push(lexer *L) {
    if (L->count == L->cap) {
        const uint32_t cap = L->cap ? 2 * L->cap : 256;
        gtoken *t = realloc(L->toks, (size_t)cap * sizeof *t);
        if (!t) return NULL;
        L->toks = t;
        L->cap = cap;
    }
    gtoken *t = &L->toks[L->count++];
    memset(t, 0, sizeof *t);
    t->offset = (uint32_t)L->pos;
    t->line = L->line;
    t->col = L->col;
    t->match = PGT_NONE;
    return t;
}

/* Pairs every '(' with its ')' (PGT_NONE when unbalanced), with the tokens as the stack. */
static pgt_result lex_match(lexer *L) {
    uint32_t *stack = malloc((size_t)L->count * sizeof *stack), depth = 0;
    if (!stack) return pgt_error_set(L->err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->file);
    for (uint32_t i = 0; i < L->count; ++i) {
        if (L->toks[i].kind == GTOK_LPAREN) stack[depth++] = i;
        if (L->toks[i].kind == GTOK_RPAREN && depth > 0) L->toks[stack[--depth]].match = i;
    }
    free(stack);
    return PGT_OK;
}

pgt_result pgt_grammar_lex(const char *text, size_t size, const char *file, gtoken **out,
                           uint32_t *count, pgt_error *err) {
    lexer L = {text, size, 0, 1, 1, file, err, NULL, 0, 0};
    /* a UTF-8 byte order mark (some Windows editors write one) is not text */
    if (size >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) L.pos = 3;
    pgt_result r = PGT_OK;
    *out = NULL;
    *count = 0;
    for (;;) {
        if ((r = lex_skip(&L)) != PGT_OK) break;
        gtoken *t = lex_push(&L);
        if (!t) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", file);
            break;
        }
        const int c = lex_at(&L, 0);
        if (c < 0) {
            t->kind = GTOK_EOF;
            r = lex_match(&L);
            break;
        }
        if (is_ident_start(c)) {
            size_t n = 1;
            while (is_ident_char(lex_at(&L, n))) n++;
            if (n > PGT_GRAMMAR_MAX_NAME_CHARS) {
                char msg[160];
                snprintf(msg, sizeof msg,
                         "found a name of %zu characters, more than PGT_GRAMMAR_MAX_NAME_CHARS "
                         "(%u)",
                         n, PGT_GRAMMAR_MAX_NAME_CHARS);
                r = lex_fail(&L, PGT_ERROR_LIMIT, L.line, L.col, msg);
                break;
            }
            t->kind = GTOK_IDENT;
            t->length = (uint32_t)n;
        } else if (is_digit(c) || (c == '.' && is_digit(lex_at(&L, 1)))) {
            r = lex_number(&L, t);
        } else if (c == '"') {
            r = lex_string(&L, t);
        } else {
            r = lex_punct(&L, t);
        }
        if (r != PGT_OK) break;
        lex_advance(&L, t->length);
    }
    if (r != PGT_OK) {
        free(L.toks);
        return r;
    }
    *out = L.toks;
    *count = L.count;
    return PGT_OK;
}

void pgt_grammar_describe(const char *text, const gtoken *t, char *buf, size_t size) {
    /* long names and numbers are cut: the message holds FILE:LINE:COL and the expectation too */
    enum { SHOWN = 40 };
    if (t->kind == GTOK_EOF)
        snprintf(buf, size, "end of file");
    else if (t->kind == GTOK_STRING)
        snprintf(buf, size, "a string");
    else if (t->kind == GTOK_ARROW)
        snprintf(buf, size, "'-->'");
    else
        snprintf(buf, size, "'%.*s%s'", (int)(t->length < SHOWN ? t->length : SHOWN),
                 text + t->offset, t->length > SHOWN ? "..." : "");
}

uint32_t pgt_grammar_distance(const char *a, size_t na, const char *b, size_t nb, uint32_t cap) {
    /* names are at most PGT_GRAMMAR_MAX_NAME_CHARS, so one row fits on the stack */
    uint32_t row[PGT_GRAMMAR_MAX_NAME_CHARS + 1];
    if (na > PGT_GRAMMAR_MAX_NAME_CHARS || nb > PGT_GRAMMAR_MAX_NAME_CHARS) return cap;
    for (size_t j = 0; j <= nb; ++j) row[j] = (uint32_t)j;
    for (size_t i = 1; i <= na; ++i) {
        uint32_t diag = row[0];
        row[0] = (uint32_t)i;
        for (size_t j = 1; j <= nb; ++j) {
            const uint32_t up = row[j];
            uint32_t best = diag + (a[i - 1] != b[j - 1]);
            if (up + 1 < best) best = up + 1;
            if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[nb] < cap ? row[nb] : cap;
}
