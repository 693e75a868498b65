/*
 * fuzz_card68k.c - libFuzzer target: the firmware as the 68000 EPROM image
 * of the build, on the emulator (Musashi, the bus and device models of
 * mac4sim), while a misbehaving host writes anything into the DPRAM above
 * the vector and boot area ($3000-$FFFF: the axis data, the counters, the
 * queue headers and elements, the stop bits), sends commands through the
 * queue, and puts telegrams and raw bytes on the serial line.
 *
 * Each card boots once in full; every input starts from a copy of the
 * booted card (sim_t and the 68000's registers).
 *
 * Input: byte 0 picks the card (% 3); then operations, opcode % 8:
 *   0 poke8 OFF16 V8    1 poke16 OFF16 V16    2 poke32 OFF16 V32
 *     (OFF into $3000-$FFFF, words and longs even and inside the DPRAM)
 *   3 a command through the queue: axis code parameter (as fuzz_card.h: axis
 *     byte, bit 7 set: any byte, else & 3; code byte < $F0: one of
 *     commands.def, else the next u16; parameter u32)
 *   4 raw serial bytes: count-1 (% 24), bytes   5 a telegram: axis code param
 *   6 time: (1 + b) x 250 us   7 b & 3: 0 /STOP := next & 1, 1 stop bits :=
 *     next u16, 2 J11 := next & 1, 3 the host stops/starts reading responses
 * Every operation is followed by 250 us; an input has at most 1 s.
 *
 * Properties: the emulator sees no fault (an unmapped access, a write to
 * the EPROM, an address error, an illegal instruction, a double bus fault:
 * sim_t.faults), the card never stops with an error on its display, and at
 * the end, once the host has repaired the queue headers, stopped the axes
 * and released /STOP, VER is answered with the card's version word within
 * the bound of fuzz_card.h (the commands held behind off-fly moves first).
 */
#include "fuzz_emu.h"
#include "m68k.h"
#include "serial_host.h"
#include "periph.h"

#define PASS_CYC US_TO_CYC(250)
#define MAX_CYC MS_TO_CYC(1000)
#define FZ_STOP_PASSES 2000
#define HOLD_MAX 16                  /* CMD_HOLD_MAX, firmware/cmd.h */

static const uint16_t codes[] = {
#define GEN(mn, code, cards, kind, desc) code,
#define MODESEL(mn, code, cards, mode, desc) code,
#define DIAG(mn, code, cards, units, desc) code,
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) wcode, (wcode) + 1,
#include "commands.def"
};
#define NCODES (sizeof codes / sizeof codes[0])

static sim_t booted[3];
static void *cpu_ctx[3];
static uint32_t ver_word[3];

static uint16_t pick_code(fz_in_t *in)
{
    uint8_t b = fz_u8(in);
    return b < 0xF0 ? codes[((unsigned)b << 8 | fz_u8(in)) % NCODES] : fz_u16(in);
}
static uint8_t pick_axis(fz_in_t *in)
{
    uint8_t a = fz_u8(in);
    return a & 0x80 ? a : (uint8_t)(a & 3);
}

static void check_card(const char *when)
{
    FZ_CHECK(S.faults == 0, "the emulator saw a fault %s", when);
    FZ_CHECK(!sim_halted, "the 68000 halted %s", when);
    FZ_CHECK(!((S.sys.display & SYS_DISPLAY_DP) && S.sys.display != 0xFF), "the card stopped at %X. %s",
             S.sys.display & 0xF, when);
}

static void pass(void)
{
    sim_run(&S, PASS_CYC);
    check_card("while the host misbehaved");
}

static uint32_t rd32(uint32_t a) { return dp_rd32(&S, a); }

/* The host's repair of a queue header (as fuzz_card.h): its constant words
 * again, and both indices at the card's one, so the queue is empty. */
static void repair(uint32_t q)
{
    dp_wr32(&S, q + QH_BASE, Q_HEADER_SIZE);
    dp_wr32(&S, q + QH_WIDTH, Q_WIDTH);
    dp_wr32(&S, q + QH_NEL, Q_NEL);
    uint32_t idx = rd32(q + (q == DP_CMD_QUEUE ? QH_REAR : QH_FRONT));
    if (idx >= Q_NEL)
        idx = 0;
    dp_wr32(&S, q + QH_FRONT, idx);
    dp_wr32(&S, q + QH_REAR, idx);
}

/* VER asked once after the repair; answered after at most HOLD_MAX other
 * answers (fz_final_ver_vme in fuzz_card.h says why; the serial line's
 * commands are answered on the line). */
static int ask_ver(uint32_t *answer)
{
    S.host_reads = 0;
    for (int ms = 0; ms < 2000 && S.sys.display != 5; ms++)   /* after a watchdog reset: the boot */
        sim_run(&S, MS_TO_CYC(1));
    repair(DP_CMD_QUEUE);
    repair(DP_RSP_QUEUE);
    FZ_CHECK(host_send(&S, 0, 7, 0, MSG_SRC_VME) == 1, "VER could not be queued after the repair");
    uint64_t resets0 = S.resets;
    unsigned others = 0;
    for (int passes = 0; passes <= FZ_STOP_PASSES + HOLD_MAX + 2 && S.resets == resets0;) {
        uint32_t f = rd32(DP_RSP_QUEUE + QH_FRONT), r = rd32(DP_RSP_QUEUE + QH_REAR);
        if (f != r && r < Q_NEL) {
            uint32_t e = DP_RSP_QUEUE + Q_HEADER_SIZE + r * Q_WIDTH;
            uint8_t axis = S.dpram[e + MSG_AXIS];
            uint16_t code = dp_rd16(&S, e + MSG_CODE);
            uint32_t param = rd32(e + MSG_PARAM);
            dp_wr32(&S, DP_RSP_QUEUE + QH_REAR, (r + 1) % Q_NEL);
            if (code == 7 && axis == 0) {
                *answer = param;
                return 1;
            }
            others++;
            FZ_CHECK(others <= HOLD_MAX, "%u answers before VER's", others);
            continue;
        }
        sim_run(&S, PASS_CYC);
        passes++;
        check_card("after the repair");
    }
    return S.resets != resets0 ? 0 : -1;   /* 0: a watchdog reset, ask again */
}

static void boot(int card)
{
    uint8_t img[EPROM_SIZE];
    memset(img, 0xFF, sizeof img);
    size_t n = fz_card_image(card, img);
    sim_init(&S, card);
    S.out = fz_null_out();
    memcpy(S.eprom, img, n);
    sim_attach_cpu(&S, &cpu_m68k);
    for (int ms = 0; ms < 2000 && S.sys.display != 5; ms++)
        sim_run(&S, MS_TO_CYC(1));
    FZ_CHECK(S.sys.display == 5 && S.faults == 0, "the build's image did not boot");
    sim_run(&S, MS_TO_CYC(5));
    booted[card] = S;
    cpu_ctx[card] = malloc(m68k_context_size());
    m68k_get_context(cpu_ctx[card]);
    uint32_t v = 0;
    FZ_CHECK(ask_ver(&v) == 1, "the booted card does not answer VER");
    ver_word[card] = v;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    for (int c = 0; c < 3; c++)
        boot(c);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    fz_in_t in = {data, size, 1};
    int card = data[0] % 3;
    S = booted[card];
    m68k_set_context(cpu_ctx[card]);
    sim_halted = 0;
    estop_irq_ack(&S);
    cyc_t t0 = sim_now(&S);
    while (fz_more(&in) && sim_now(&S) - t0 < MAX_CYC) {
        uint8_t op = fz_u8(&in);
        switch (op % 8) {
        case 0: case 1: case 2: {
            int w = op % 8 == 0 ? 1 : op % 8 == 1 ? 2 : 4;
            uint32_t off = 0x3000u + fz_u16(&in) % (DPRAM_SIZE - 0x3000u - (unsigned)w + 1u);
            if (w > 1)
                off &= ~1u;
            uint32_t v = w == 1 ? fz_u8(&in) : w == 2 ? fz_u16(&in) : fz_u32(&in);
            if (w == 1)
                S.dpram[off] = (uint8_t)v;
            else if (w == 2)
                dp_wr16(&S, off, (uint16_t)v);
            else
                dp_wr32(&S, off, v);
            break;
        }
        case 3: {
            uint8_t a = pick_axis(&in);
            uint16_t c = pick_code(&in);
            host_send(&S, a, c, fz_u32(&in), MSG_SRC_VME);   /* full or unusable: the host's business */
            break;
        }
        case 4: {
            uint8_t b[24];
            unsigned k = 1u + fz_u8(&in) % 24u;
            for (unsigned i = 0; i < k; i++)
                b[i] = fz_u8(&in);
            uart_feed(&S, b, k);
            break;
        }
        case 5: {
            uint8_t buf[18];
            uint8_t a = pick_axis(&in);
            uint16_t c = pick_code(&in);
            unsigned k = serial_host_encode(a, c, fz_u32(&in), buf);
            uart_feed(&S, buf, k);
            break;
        }
        case 6:
            sim_run(&S, PASS_CYC * (1u + fz_u8(&in)));
            break;
        default: {
            uint8_t b = fz_u8(&in);
            if ((b & 3) == 0) {
                estop_set(&S, fz_u8(&in) & 1);
                sim_update_irq(&S);
            } else if ((b & 3) == 1) {
                dp_wr16(&S, DP_STOP_BITS, fz_u16(&in));
            } else if ((b & 3) == 2) {
                S.wdg.j11 = fz_u8(&in) & 1;
            } else {
                S.host_reads = !S.host_reads;
            }
            break;
        }
        }
        pass();
    }
    /* the host wants its card back */
    estop_set(&S, 0);
    sim_update_irq(&S);
    S.wdg.j11 = 1;
    dp_wr16(&S, DP_STOP_BITS, 0x00AA);
    uint32_t v = 0;
    int r = 0;
    for (int asked = 0; asked < 4 && r == 0; asked++)
        r = ask_ver(&v);
    FZ_CHECK(r == 1, "the card no longer answers VER (command front %u rear %u, response front %u rear %u)",
             (unsigned)rd32(DP_CMD_QUEUE + QH_FRONT), (unsigned)rd32(DP_CMD_QUEUE + QH_REAR),
             (unsigned)rd32(DP_RSP_QUEUE + QH_FRONT), (unsigned)rd32(DP_RSP_QUEUE + QH_REAR));
    FZ_CHECK(v == ver_word[card], "VER answered $%08X, not $%08X", (unsigned)v, (unsigned)ver_word[card]);
    return 0;
}
