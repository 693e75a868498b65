/*
 * gen_commands.c - writes build/commands.json from firmware/commands.def
 * and firmware/status.def, the firmware's own table, evaluated for each
 * card exactly as the firmware compiles it.  tools/commands_md.py turns the
 * JSON into docs/commands.md; host tools read the JSON.
 */
#include <limits.h>
#include <stdio.h>
#include <string.h>

#define MAC4_CARD 0 /* status.h wants one; CARDSEL is redefined below */
#include "status.h"
#undef CARDSEL
static int card;   /* the card being evaluated */
#define CARDSEL(inc, ssi, stp) (card == 0 ? (inc) : card == 1 ? (ssi) : (stp))

static const char *const card_names[3] = {"inc", "ssi", "stp"};

static void jstr(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            putchar('\\');
        putchar(*s);
    }
    putchar('"');
}

static void cards_list(unsigned mask)
{
    printf("\"cards\": [");
    int first = 1;
    for (int c = 0; c < 3; c++)
        if (mask & (1u << c)) {
            printf("%s\"%s\"", first ? "" : ", ", card_names[c]);
            first = 0;
        }
    printf("]");
}

/* Every mnemonic names one command: a second use of one (a parameter's
 * W../R.. name, a mode, an alias) is an error of commands.def, found here
 * rather than by a host that looks the wrong command up. */
#define MAX_MNEMONICS 512
static char seen[MAX_MNEMONICS][24];
static int nseen, dup_errors;
static void unique(const char *mn)
{
    for (int i = 0; i < nseen; i++)
        if (!strcmp(seen[i], mn)) {
            fprintf(stderr, "gen_commands: mnemonic %s defined twice in commands.def\n", mn);
            dup_errors++;
            return;
        }
    if (nseen < MAX_MNEMONICS)
        snprintf(seen[nseen++], sizeof seen[0], "%s", mn);
}

/* General instructions that take a parameter (the others ignore it). */
static int takes_parameter(const char *mn)
{
    static const char *const with[] = {"TURBO", "WAP_R", "CENT", "CPTR", "CON", "PCON", "FBX", "FBS", "FBW1", "FBW2"};
    for (unsigned i = 0; i < sizeof with / sizeof with[0]; i++)
        if (!strcmp(with[i], mn))
            return 1;
    return 0;
}

static int nout;
static void begin(const char *mn, long code, const char *kind, unsigned cards, const char *desc)
{
    unique(mn);
    printf("%s\n    {\"mnemonic\": ", nout++ ? "," : "");
    jstr(mn);
    printf(", \"code\": %ld, \"kind\": \"%s\", ", code, kind);
    cards_list(cards);
    printf(", \"description\": ");
    jstr(desc);
}

/* Per-card numbers of a parameter: range, default, units. */
#define PER_CARD(cards, expr_fmt, ...)                                   \
    do {                                                                 \
        int first_ = 1;                                                  \
        printf("{");                                                     \
        for (card = 0; card < 3; card++)                                 \
            if ((cards) & (1u << card)) {                                \
                printf("%s\"%s\": ", first_ ? "" : ", ", card_names[card]); \
                printf(expr_fmt, __VA_ARGS__);                           \
                first_ = 0;                                              \
            }                                                            \
        printf("}");                                                     \
    } while (0)

static void param(const char *id, const char *mn, int sys, long wcode, unsigned cards, unsigned flags,
                  const char *desc, int which)
{
    char name[32];
    snprintf(name, sizeof name, "%s%s%s", sys ? "U" : "", which ? "R" : "W", mn);
    begin(name, wcode + which, which ? (sys ? "read-system" : "read-mode") : (sys ? "write-system" : "write-mode"),
          cards, desc);
    printf(", \"parameter\": \"%s\", \"system\": %s, \"immediate\": %s, \"card_wide\": %s", id,
           sys ? "true" : "false", (flags & PF_IMM) ? "true" : "false", (flags & PF_CARD) ? "true" : "false");
}

int main(void)
{
    printf("{\n  \"generated_from\": \"firmware/commands.def, firmware/status.def\",\n");
    printf("  \"cards\": {\"inc\": 0, \"ssi\": 1, \"stp\": 2},\n");
    printf("  \"not_implemented\": 1,\n");
    printf("  \"commands\": [");

#define GEN(mn, code, cards, kind, desc)                                        \
    begin(#mn, code, (kind) == CK_READ ? "read" : "general", cards, desc);       \
    if (takes_parameter(#mn))                                                    \
        printf(", \"takes_parameter\": true");                                   \
    printf("}");
#define CK_GEN 0
#define CK_READ 1
#define MODESEL(mn, code, cards, mode, desc)                                    \
    begin(#mn, code, "mode", cards, desc);                                       \
    printf(", \"mode\": %d}", (mode) == M_UE ? M_ENABLE : (mode));
#define DIAG(mn, code, cards, units, desc)                                      \
    begin(#mn, code, "diagnosis", cards, desc);                                  \
    printf(", \"units\": ");                                                     \
    PER_CARD(cards, "\"%s\"", (units));                                          \
    printf("}");
#define PK_MODE 0
#define PK_SYS 1
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc)    \
    for (int w_ = 0; w_ < 2; w_++) {                                             \
        param(#id, #mn, PK_##kind, wcode, cards, flags, desc, w_);               \
        printf(", \"range\": ");                                                 \
        PER_CARD(cards, "[%ld, %ld]", (long)(min), (long)(max));                 \
        printf(", \"default\": ");                                               \
        PER_CARD(cards, "%ld", (long)(def));                                     \
        printf(", \"units\": ");                                                 \
        PER_CARD(cards, "\"%s\"", (units));                                      \
        printf("}");                                                             \
    }
#include "commands.def"
    printf("\n  ],\n  \"aliases\": {");
    nout = 0;
#define ALIAS(mn, of) unique(#mn); printf("%s\"%s\": \"%s\"", nout++ ? ", " : "", #mn, #of);
#include "commands.def"
    printf("},\n  \"errors\": [");
    nout = 0;
#define ERROR(code, id, bit, name, desc)                                               \
    printf("%s\n    {\"code\": %d, \"status_bit\": \"%s\", \"description\": ", nout++ ? "," : "", \
           code, name);                                                                 \
    jstr(desc);                                                                         \
    printf(", \"status_word\": \"%s\"}", #bit[0] == 'O' ? "overall" : "user");
#include "commands.def"
    /* The user status bits that mean an error (status.h US_ERRORS): a host
     * waiting for an event stops at any of them. */
    printf("\n  ],\n  \"user_error_bits\": [");
    nout = 0;
#define USTAT(id, bit, name, desc) \
    if (UB(id) & US_ERRORS) printf("%s\"%s\"", nout++ ? ", " : "", name);
#include "status.def"
    printf("],\n  \"status\": {\n");
    const char *sep;
    sep = "";
    printf("    \"user\": [");
    printf("{\"bit\": 0, \"width\": 8, \"name\": \"mode\", \"description\": \"mode code\"}");
#define USTAT(id, bit, name, desc) printf(", {\"bit\": %d, \"name\": \"%s\", \"description\": ", bit, name); jstr(desc); printf("}");
#include "status.def"
    printf("],\n    \"system\": [");
#define SSTAT(id, bit, name, desc) printf("%s{\"bit\": %d, \"name\": \"%s\", \"description\": ", sep, bit, name); jstr(desc); printf("}"); sep = ", ";
#include "status.def"
    sep = "";
    printf("],\n    \"overall\": [");
#define OSTAT(id, bit, name, desc) printf("%s{\"bit\": %d, \"name\": \"%s\", \"description\": ", sep, bit, name); jstr(desc); printf("}"); sep = ", ";
#include "status.def"
    sep = "";
    printf("],\n    \"modes\": [");
#define MODE(id, code, name) printf("%s{\"code\": %d, \"name\": \"%s\"}", sep, code, name); sep = ", ";
#include "status.def"
    printf("]\n  }\n}\n");
    return dup_errors ? 1 : 0;
}
