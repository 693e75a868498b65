/* status.h - status bits, mode codes, card masks and error codes, all
 * derived from status.def and commands.def. */
#ifndef STATUS_H
#define STATUS_H
#include <stdint.h>
#include "mac4_map.h"

enum {
#define USTAT(id, bit, name, desc) US_##id = bit,
#include "status.def"
};
enum {
#define SSTAT(id, bit, name, desc) SS_##id = bit,
#include "status.def"
};
enum {
#define OSTAT(id, bit, name, desc) OS_##id = bit,
#include "status.def"
};
enum {
#define MODE(id, code, name) M_##id = code,
#include "status.def"
};
/* UE selects "enable" from an enabled mode, unlike ME from "disable". */
#define M_UE 0x80

#define UB(id) ((uint32_t)1 << US_##id)
#define SB(id) ((uint32_t)1 << SS_##id)
#define OB(id) ((uint32_t)1 << OS_##id)
#define US_MODE_MASK 0xFFu
#define US_ERRORS (UB(SYN_F) | UB(LIMIT_F) | UB(LOGO_F) | UB(ENCODER_F) | UB(DR_F) | UB(FERR_F))

/* Which cards a command or parameter exists on. */
#define C_INC     (1u << MAC4_CARD_INC)
#define C_SSI     (1u << MAC4_CARD_SSI)
#define C_STP     (1u << MAC4_CARD_STP)
#define C_SERVO   (C_INC | C_SSI)
#define C_INC_STP (C_INC | C_STP)
#define C_ALL     (C_INC | C_SSI | C_STP)
#define CARDSEL(inc, ssi, stp) \
    (MAC4_CARD == MAC4_CARD_INC ? (inc) : MAC4_CARD == MAC4_CARD_SSI ? (ssi) : (stp))
#define ON_THIS_CARD(cards) (((cards) >> MAC4_CARD) & 1u)

/* Error codes (6.3). */
enum {
#define ERROR(code, id, bit, name, desc) ERR_##id = code,
#include "commands.def"
};

/* Parameter kinds and flags of commands.def. */
#define PF_IMM  0x01
#define PF_CARD 0x02

#endif
