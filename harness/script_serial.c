/*
 * script_serial.c - host-script commands of the serial line
 * (docs/host-script.md, docs/serial.md):
 *   tx HEX...                 bytes to the card over the line, as given
 *   tx-msg AXIS CODE [PARAM]  a correctly encoded telegram
 *   serial-stats              the card's serial statistics words
 * What the card sends back prints as `rx ...` (serial_host.c).
 */
#include <ctype.h>
#include <string.h>
#include "script.h"
#include "serial_host.h"

static int hexval(int c) { return isdigit(c) ? c - '0' : tolower(c) - 'a' + 10; }

/* "10", "2", "1002000046" -> bytes; returns the count or -1. */
static int parse_hex(const char *t, uint8_t *out, int room)
{
    size_t len = strlen(t);
    for (size_t i = 0; i < len; i++)
        if (!isxdigit((unsigned char)t[i]))
            return -1;
    if (len == 1) {
        if (room < 1)
            return -1;
        out[0] = (uint8_t)hexval(t[0]);
        return 1;
    }
    if (len % 2 || (int)(len / 2) > room)
        return -1;
    for (size_t i = 0; i < len; i += 2)
        out[i / 2] = (uint8_t)(hexval(t[i]) << 4 | hexval(t[i + 1]));
    return (int)(len / 2);
}

static int cmd_tx(script_t *sc, sim_t *s, char **tok, int n)
{
    uint8_t bytes[1024];
    int cnt = 0;
    if (n < 2)
        return script_err(sc, "usage: %s HEXBYTES...", tok[0]);
    for (int i = 1; i < n; i++) {
        int k = parse_hex(tok[i], bytes + cnt, (int)sizeof bytes - cnt);
        if (k < 0)
            return script_err(sc, "bad hex bytes '%s' (e.g. 10 02 00 or 100200)", tok[i]);
        cnt += k;
    }
    if (serial_host_tx(s, bytes, (unsigned)cnt))
        return script_err(sc, "%s: the emulator's serial line buffer is full, nothing sent", tok[0]);
    return 0;
}

static int cmd_tx_msg(script_t *sc, sim_t *s, char **tok, int n)
{
    long long axis, param = 0;
    if (n < 3 || n > 4)
        return script_err(sc, "usage: %s AXIS CODE [PARAM]", tok[0]);
    if (script_parse_num(tok[1], &axis) || axis < 0 || axis > 255)
        return script_err(sc, "bad axis '%s' (0..255)", tok[1]);
    long code = script_code(tok[2]);
    if (code < 0)
        return script_err(sc, "unknown code or mnemonic '%s'", tok[2]);
    if (n == 4 && (script_parse_num(tok[3], &param) || param < -2147483648LL || param > 0xFFFFFFFFLL))
        return script_err(sc, "bad parameter '%s' (32 bits)", tok[3]);
    uint8_t buf[18];
    unsigned len = serial_host_encode((uint8_t)axis, (uint16_t)code, (uint32_t)param, buf);
    if (serial_host_tx(s, buf, len))
        return script_err(sc, "%s: the emulator's serial line buffer is full, nothing sent", tok[0]);
    return 0;
}

static int cmd_stats(sim_t *s)
{
    sim_printf(s, "serial-stats rx_ok=%u naks=%u garbage=%u overruns=%u framing=%u cmd_lost=%u "
               "tx_ok=%u tx_lost=%u\n",
               dp_rd32(s, DPC_SERIAL_RX_OK), dp_rd32(s, DPC_SERIAL_NAKS), dp_rd32(s, DPC_SERIAL_GARBAGE),
               dp_rd32(s, DPC_SERIAL_OVERRUNS), dp_rd32(s, DPC_SERIAL_FRAMING),
               dp_rd32(s, DPC_SERIAL_CMD_LOST), dp_rd32(s, DPC_SERIAL_TX_OK), dp_rd32(s, DPC_SERIAL_TX_LOST));
    return 0;
}

int script_serial(script_t *sc, sim_t *s, char **tok, int n)
{
    if (!strcmp(tok[0], "tx"))
        return cmd_tx(sc, s, tok, n);
    if (!strcmp(tok[0], "tx-msg"))
        return cmd_tx_msg(sc, s, tok, n);
    if (!strcmp(tok[0], "serial-stats")) {
        if (n != 1)
            return script_err(sc, "usage: %s", tok[0]);
        return cmd_stats(s);
    }
    return SCRIPT_NOT_MINE;
}
