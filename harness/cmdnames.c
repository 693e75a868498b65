/*
 * cmdnames.c - mnemonic -> code for the host script, straight from
 * firmware/commands.def (the one table).
 */
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "script.h"

#define PFX_W_MODE "W"
#define PFX_W_SYS "UW"
#define PFX_R_MODE "R"
#define PFX_R_SYS "UR"

typedef struct {
    const char *name;
    long code;
} cmdname_t;

static const cmdname_t names[] = {
#define GEN(mn, code, cards, kind, desc) {#mn, code},
#define MODESEL(mn, code, cards, mode, desc) {#mn, code},
#define DIAG(mn, code, cards, units, desc) {#mn, code},
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) \
    {PFX_W_##kind #mn, wcode}, {PFX_R_##kind #mn, (wcode) + 1},
#define CARDSEL(i, s, p) 0
#include "commands.def"
};

static const struct { const char *alias, *of; } aliases[] = {
#define ALIAS(mn, of) {#mn, #of},
#include "commands.def"
};

static long lookup(const char *tok)
{
    for (unsigned i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcasecmp(names[i].name, tok))
            return names[i].code;
    return -1;
}

long script_code(const char *tok)
{
    long long v;
    if (script_parse_num(tok, &v) == 0)      /* decimal, 0x or $ hex */
        return (v >= 0 && v <= 0xFFFF) ? (long)v : -1;
    long c = lookup(tok);
    if (c >= 0)
        return c;
    for (unsigned i = 0; i < sizeof aliases / sizeof aliases[0]; i++)
        if (!strcasecmp(aliases[i].alias, tok))
            return lookup(aliases[i].of);
    return -1;
}
