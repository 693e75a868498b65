#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "serial.h"

static uint8_t queue_bad;   /* 1 while the command queue header is corrupt */

void cmd_reset(void) { queue_bad = 0; }

void cmd_execute(const mac4_msg_t *in, mac4_msg_t *out)
{
    /* The command table arrives with the command-interface issue; until then
     * every code is a syntax error (161, manual 6.3.2). */
    out->axis = in->axis;
    out->source = in->source;
    out->code = 161;
    out->param = (in->axis < MAC4_NAXES ? axes[in->axis].ustat : 0) | (1ul << 13);
}

static void respond(const mac4_msg_t *out)
{
    if (out->source == MSG_SRC_SERIAL) {
        serial_send(out);
        return;
    }
    if (q_put(DP_RSP_QUEUE, out) != Q_OK)
        hal_wr32(DPC_RSP_LOST, hal_rd32(DPC_RSP_LOST) + 1);
}

void cmd_poll(void)
{
    mac4_msg_t in, out;
    serial_poll();
    /* One command per pass, alternating between the two interfaces so
     * neither can starve the other. */
    static uint8_t turn;
    turn ^= 1u;
    int have = 0;
    if (turn)
        have = serial_get(&in);
    if (!have) {
        int r = q_get(DP_CMD_QUEUE, &in);
        if (r == Q_CORRUPT) {
            if (!queue_bad)
                hal_wr32(DPC_QUEUE_ERRORS, hal_rd32(DPC_QUEUE_ERRORS) + 1);
            queue_bad = 1;
        } else {
            queue_bad = 0;
            have = (r == Q_OK);
            if (have)
                in.source = MSG_SRC_VME;   /* a VME command is answered on the VMEbus */
        }
    }
    if (!have && !turn)
        have = serial_get(&in);
    if (!have)
        return;
    cmd_execute(&in, &out);
    respond(&out);
}
