/*
 * fuzz_cmd.c - the command executor and the parameter store (cmd_execute,
 * commands.def, params.c) fed arbitrary axis/code/parameter triples in any
 * state of the card: axes initialised or not, in any mode, with time passing
 * (ticks, profile generator, servo), switches, drive faults, emergency stop,
 * stop bits, encoder faults and jumps, external encoder values, J11.
 *
 * Checked after every command (and ASan/UBSan/fuzz_hal.c throughout):
 *   - the response names the command's axis and source, and carries its code
 *     or an error 160-165; axis 4..255 gets 160 with the overall status;
 *   - VER answers the version word;
 *   - a parameter write that succeeded reads back the value written;
 *   - every parameter of every axis, written and in force, stays inside the
 *     limits of commands.def;
 *   - every axis is in a mode of manual 7.1.1 and its user status shows it.
 * At the end the card answers VER through the VME queue.
 */
#include "fuzz_card.h"

#define PASS_CYC US_TO_CYC(250)
#define MAX_PASSES 12000

static unsigned passes;

static void run_passes(unsigned n)
{
    for (; n > 0 && passes < MAX_PASSES; n--, passes++) {
        fz_pass(PASS_CYC);
        fz_host_drain();
    }
}

static int find_param(uint16_t code)
{
    for (unsigned p = 0; p < NPARAMS; p++)
        if (pdesc[p].avail && pdesc[p].wcode == code)
            return (int)p;
    return -1;
}

static void check_invariants(void)
{
    for (unsigned p = 0; p < NPARAMS; p++)
        for (unsigned a = 0; a < MAC4_NAXES; a++) {
            FZ_CHECK(par_w[p][a] >= pdesc[p].min && par_w[p][a] <= pdesc[p].max,
                     "parameter %u (code %u) axis %u written value %d outside %d..%d", p, pdesc[p].wcode, a,
                     (int)par_w[p][a], (int)pdesc[p].min, (int)pdesc[p].max);
            FZ_CHECK(par_a[p][a] >= pdesc[p].min && par_a[p][a] <= pdesc[p].max,
                     "parameter %u (code %u) axis %u value in force %d outside %d..%d", p, pdesc[p].wcode, a,
                     (int)par_a[p][a], (int)pdesc[p].min, (int)pdesc[p].max);
        }
    for (unsigned a = 0; a < MAC4_NAXES; a++) {
        FZ_CHECK(axes[a].mode <= M_RESET, "axis %u in mode %u", a, axes[a].mode);
        FZ_CHECK((axes[a].ustat & US_MODE_MASK) == axes[a].mode, "axis %u: mode %u, user status $%08X", a,
                 axes[a].mode, (unsigned)axes[a].ustat);
    }
}

static void execute(uint8_t axis, uint16_t code, uint32_t param, mac4_msg_t *out)
{
    mac4_msg_t in = {axis, code, param, (uint8_t)(code & 1)};
    unsigned prev = hal_irq_save();          /* as cmd_poll does */
    cmd_execute(&in, out);
    hal_irq_restore(prev);
    fz_check_card("cmd_execute");
    FZ_CHECK(out->axis == in.axis && out->source == in.source, "response axis/source");
    FZ_CHECK(out->code == in.code || fz_is_error(out->code), "code %u answered %u", in.code, out->code);
    if (in.axis >= MAC4_NAXES)
        FZ_CHECK(out->code == ERR_AXIS && out->param == card_ostat, "axis %u: %u", in.axis, out->code);
    if (in.code == 7 && out->code == 7)
        FZ_CHECK(out->param == FW_VER_WORD, "VER answered $%08X", (unsigned)out->param);
}

static void command(uint8_t axis, uint16_t code, uint32_t param)
{
    mac4_msg_t out;
    execute(axis, code, param, &out);
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "  %6u us: axis %u code %u param %d -> %u $%08X\n",
                (unsigned)(S.slice_base / MAC4_CYCLES_PER_US), axis, code, (int)param, out.code,
                (unsigned)out.param);
    int p = find_param(code);
    if (p >= 0 && out.code == code && axis < MAC4_NAXES) {
        mac4_msg_t back;
        execute(axis, (uint16_t)(code + 1), 0, &back);
        FZ_CHECK(back.code == code + 1 && back.param == param,
                 "wrote %d with code %u on axis %u, reads back %d (code %u)", (int)param, code, axis,
                 (int)back.param, back.code);
    }
    check_invariants();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_init_once();
    FZ_FW_GUARD();
    fz_on_reset = NULL;
    fz_power_on();
    passes = 0;
    fz_in_t in = {data, size, 0};
    while (fz_more(&in) && passes < MAX_PASSES) {
        uint8_t op = fz_u8(&in);
        switch (op % 12) {
        default: {                                 /* 0-3: a command */
            uint8_t a = fz_u8(&in);
            uint8_t axis = (a & 0x80) ? a : (uint8_t)(a & 3u);
            uint16_t code = fz_code(&in);
            command(axis, code, fz_param(&in));
            break;
        }
        case 4:                                    /* time passes: 0.25 .. 64 ms */
            run_passes(1u + fz_u8(&in));
            break;
        case 5: {                                  /* switch inputs (1 = at 0 V) */
            uint8_t b = fz_u8(&in);
            S.ax[b & 3u].in = (uint16_t)((b >> 2) & (AX_IN_IESP | AX_IN_IESN | AX_IN_RS | AX_IN_DF));
            break;
        }
        case 6: estop_set(&S, fz_u8(&in) & 1); break;
        case 7: dp_wr16(&S, DP_STOP_BITS, fz_u16(&in)); break;
        case 8: {                                  /* the encoder misbehaves */
            uint8_t b = fz_u8(&in);
            int n = b & 3;
            if (b & 0x80)
                plant_enc_jump(&S, n, (int32_t)fz_u32(&in));
            else
                plant_set_enc_fault(&S, n, (b >> 2) % 4);
            break;
        }
        case 9: {                                  /* an external encoder value in the DPRAM */
            uint8_t n = fz_u8(&in) & 3u;
            dp_wr32(&S, DP_EXT_POS(n), fz_u32(&in));
            dp_wr16(&S, DP_EXT_FLAG(n), 0x8000);
            break;
        }
        case 10: {                                 /* axis n: INIT, mode, E in one go */
            uint8_t b = fz_u8(&in);
            uint8_t n = b & 3u;
            command(n, 4, 0);                      /* C */
            command(n, 2, 0);                      /* INIT */
            command(n, 52, 0);                     /* ME */
            command(n, 3, 0);                      /* E */
            command(n, (uint16_t)(50 + (b >> 2) % 14), 0);   /* UE .. MRE */
            command(n, 3, 0);                      /* E */
            break;
        }
        case 11: {
            uint8_t b = fz_u8(&in);
            S.wdg.j11 = b & 1;
            S.sys.fc = (uint8_t)((b >> 1) & 7u);
            S.ax[(b >> 4) & 3u].gray = (b >> 6) & 1;
            break;
        }
        }
    }
    run_passes(8);
    check_invariants();
    fz_final_ver_vme(PASS_CYC);
    fz_check_card("the final VER");
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "cmd: %u passes, %u commands, resets %u\n", passes, (unsigned)fz_rd32(DPC_COMMANDS),
                fz_resets);
    return 0;
}
