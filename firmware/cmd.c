/*
 * cmd.c - command processing: queue or serial line -> decoder -> command
 * table (commands.def) -> parameter store / mode change -> response.
 *
 * Order of the checks for a command (manual 3.4, 6.3):
 *   1. axis number 4..255            -> 160, overall status, nothing else happens
 *   2. code unknown on this card     -> 161
 *   3. read commands always run      -> the value, even with an error waiting (6.3)
 *   4. an error waits to be reported -> that code (163/164/165) in place of the
 *                                       answer of this non-read, which is not
 *                                       executed - but C, which acknowledges it
 *   5. C acknowledges errors
 *   6. an unacknowledged error       -> 163 (6.3.7)
 *   7. the command itself            -> its code and the user status, or 162/163
 */
#include <stddef.h>
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "params.h"
#include "serial.h"
#include "motion.h"
#include "measure.h"
#include "ext.h"
#if MAC4_CARD == MAC4_CARD_STP
#include "stepper.h"
#endif

/* ---- the command table -------------------------------------------------- */
/* Reads last: kind >= CK_READ_ is a read. */
enum { CK_NONE, CK_GEN_, CK_MODE, CK_WPAR, CK_READ_, CK_RPAR, CK_DIAG, CK_FIELD };
#define CK_GEN CK_GEN_
#define CK_READ CK_READ_

/* the command indices CI_*: cmd.h */
_Static_assert(NCMDS <= 256 && NPARAMS <= 256, "cmd_t.arg is a byte");

/* Code -> what it is, in one look-up indexed by the code: the kind
 * (CK_NONE for codes that do not exist or not on this card) and its
 * argument: the mode (CK_MODE), the parameter (CK_WPAR/CK_RPAR) or the
 * command's CI_ index.  A duplicate code in commands.def overrides an
 * initialiser: -Woverride-init (-Wextra) makes that a compile error. */
typedef struct {
    uint8_t kind;
    uint8_t arg;
} cmd_t;

/* How each diagnosis value is read: a 32-bit field of axis_t (CK_FIELD and
 * its offset: one move), or computed by read_value() (CK_DIAG). */
#define DIAG_FIELD(f) CK_FIELD, offsetof(axis_t, f)
#define DIAG_RCP  DIAG_FIELD(pos)
#if MAC4_CARD == MAC4_CARD_STP
#define DIAG_RCPI CK_DIAG, CI_RCPI          /* encoder increments since INIT */
#define DIAG_ROUT CK_DIAG, CI_ROUT          /* step frequency, Steps/SP (table 6.2) */
#else
#define DIAG_RCPI DIAG_FIELD(counter)
#define DIAG_ROUT CK_DIAG, CI_ROUT          /* the DAC word, sign-extended */
#endif
#define DIAG_RCT  DIAG_FIELD(counter)
#define DIAG_RED  DIAG_FIELD(raw)
#define DIAG_RFE  DIAG_FIELD(ferr)
#define DIAG_RPS  CK_DIAG, CI_RPS           /* command velocity per SP, from Q16 */
#define DIAG_RAV  DIAG_FIELD(vel)
#define DIAG_RAS  CK_DIAG, CI_RAS           /* card-wide */
#define DIAG_RBS  DIAG_FIELD(ustat)
#define DIAG_RSS  DIAG_FIELD(sstat)
_Static_assert(offsetof(axis_t, ferr) < 256 && offsetof(axis_t, vel) < 256, "CK_FIELD offsets are bytes");

#define CMD_ON(cards, kind, arg) {ON_THIS_CARD(cards) ? (kind) : CK_NONE, (arg)}
#define CMD_ON_(...) CMD_ON(__VA_ARGS__)
static const cmd_t cmds[] = {   /* as long as the highest code + 1 */
#define GEN(mn, code, cards, kind, desc) [code] = CMD_ON(cards, kind, CI_##mn),
#define MODESEL(mn, code, cards, mode, desc) [code] = CMD_ON(cards, CK_MODE, (mode)),
#define DIAG(mn, code, cards, units, desc) [code] = CMD_ON_(cards, DIAG_##mn),
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) \
    [wcode] = CMD_ON(cards, CK_WPAR, P_##id), [(wcode) + 1] = CMD_ON(cards, CK_RPAR, P_##id),
#include "commands.def"
};

#define NCODES (sizeof cmds / sizeof cmds[0])

static inline __attribute__((always_inline)) cmd_t cmd_of(uint16_t code)
{
    static const cmd_t none = {CK_NONE, 0};
    return code < NCODES ? cmds[code] : none;
}

/* &axes[a] in one load: axis_at[] (card.h). */

/* Reads answer a value and change nothing (6.3: "read commands always run"). */
static inline int kind_is_read(uint8_t kind) { return kind >= CK_READ; }

/* ---- state -------------------------------------------------------------- */
static uint8_t queue_bad;       /* 1 while the command queue header is corrupt */
static uint8_t last_valid_axis; /* for interrupt 2 of a false axis number (6.3.1) */
uint8_t cmd_mr;                 /* MR accepted: stop retriggering the watchdog (cmd.h) */
static uint32_t wd_last_us;     /* time of the last command, for <wd> (kept while <wd> > 0) */
static uint8_t wd_fired;
static uint8_t turn;            /* which interface is asked first this pass */
/* Bit 0: some axis has an interrupt-1 vector, bit 1: an interrupt-2 vector
 * (4.6; both 0 by default): the command path looks a vector up only then. */
static uint8_t irq12;
/* Diagnostic counts, kept here and published to the card data block at
 * every change and every tick (cmd_publish): a host write to the DPRAM
 * cannot corrupt them. */
static uint32_t n_commands, n_rsp_lost, n_queue_errors;

void cmd_publish(void)
{
    hal_wr32(DPC_COMMANDS, n_commands);
    hal_wr32(DPC_RSP_LOST, n_rsp_lost);
    hal_wr32(DPC_QUEUE_ERRORS, n_queue_errors);
}

static void irq12_update(void)
{
    uint8_t f = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        if (PAR(n, IRQ1))
            f |= 1u;
        if (PAR(n, IRQ2))
            f |= 2u;
    }
    irq12 = f;
}

/* Off-fly (5.15, docs/interpretations.md): commands for an axis whose move
 * runs off-fly wait here, in the order they came, until the move ends;
 * reads and C are answered at once, other axes are not held up. */
#define HOLD_MAX CMD_HOLD_MAX
static mac4_msg_t held[HOLD_MAX];
static uint8_t n_held;
static uint8_t held_axes;       /* bit n: a command for axis n waits in held[] */

void cmd_reset(void)
{
    queue_bad = 0;
    last_valid_axis = 0;
    cmd_mr = 0;
    wd_fired = 0;
    wd_last_us = 0;
    n_commands = n_rsp_lost = n_queue_errors = 0;
    n_held = 0;
    held_axes = 0;
    irq12_update();
}


unsigned cmd_held(const mac4_msg_t **list)
{
    *list = held;
    return n_held;
}

static inline __attribute__((always_inline)) uint32_t now_us(void)
{
    uint32_t hi = hal_rd16(TMR_FREE_HI);   /* latches the low word */
    return (hi << 16) | hal_rd16(TMR_FREE_LO);
}

/* ---- helpers ------------------------------------------------------------ */
static int absolute_encoder(unsigned a)
{
    int32_t et = PAR(a, ET);
    return et == 2 || et == 4;
}

/* Is a target position reachable on this axis (6.3.3)?  Uses the system
 * parameters in force. */
static int target_ok(unsigned a, int32_t t)
{
    int32_t sh = PAR(a, SH);
    if (sh == 1) {
        if (t < PAR(a, LN) || t > PAR(a, LP))
            return 0;
    } else if (t < 0 || t >= PAR(a, CR)) {
        return 0;
    }
    if (absolute_encoder(a) && axis_initialised(a)) {
        int64_t raw = (int64_t)t - PAR(a, AO);
        int32_t ec = PAR(a, EC);
        if (raw < 0 || (ec > 0 && raw >= ec))
            return 0;
    }
    return 1;
}

/* Which encoder types each card has (table 4.2/4.3). */
static int et_ok(int32_t et)
{
    switch (MAC4_CARD) {
    case MAC4_CARD_INC: return et == 1 || et == 3 || et == 4;
    case MAC4_CARD_SSI: return et >= 1 && et <= 4;
    default: return et == 0 || et == 1 || et == 3 || et == 4;
    }
}

static int system_change_allowed(unsigned a)
{
    return !axis_initialised(a) || axes[a].mode == M_DISABLE;
}

/* Commands run in the main loop only, at level 0: execute_and_respond masks
 * them and restores level 0 after.  A part of a command that the tick does
 * not read may run with interrupts enabled between these two. */
static inline void cmd_unmask(void) { hal_irq_enable_all(); }
static inline void cmd_remask(void) { (void)hal_irq_save(); }

/* ---- parameter writes ---------------------------------------------------- */
static int write_param_checked(unsigned a, unsigned p, int32_t v)
{
    if (pdesc[p].kind == PK_SYS && !system_change_allowed(a))
        return ERR_LOGICAL;
    if (v < pdesc[p].min || v > pdesc[p].max)
        return ERR_LIMIT;
    switch (p) {
    case P_ET:
        if (!et_ok(v))
            return ERR_LIMIT;
        break;
    case P_EA:
        if (v != 0 && !measure_ea_ok((uint32_t)v, 0))
            return ERR_LIMIT;     /* odd, or DPRAM outside the host's part (0: not set yet) */
        break;
    case P_EC: {
        int32_t sh = PAR_W(a, SH), et = PAR_W(a, ET);
        if (sh != 1 && (et == 2 || et == 4))
            return ERR_LOGICAL;   /* 6.3.7: not on circular axes with an absolute encoder */
        break;
    }
    case P_AP:
    case P_AT:                    /* 6.3.3: every target, the tracking one too */
        if (!target_ok(a, v))
            return ERR_LIMIT;
        break;
    case P_LV:
        if (MAC4_CARD == MAC4_CARD_STP && v > PAR_W(a, SSF))
            return ERR_LIMIT;     /* 4.8.3: not above the start/stop frequency */
        break;
    case P_WD:
        wd_last_us = now_us();    /* the watchdog counts from here (only kept while <wd> > 0) */
        break;
    case P_ZP:
        /* against the measured position and the mode: masked (write_param) */
        cmd_remask();
        if (!axis_standstill(a))
            return ERR_LOGICAL;   /* 6.3.7: position set only at stand-still */
        if (axis_initialised(a)) {
            /* <ao> such that the actual position becomes v (4.3.2) */
            int32_t ao = pos_sub(v, axes[a].meas);
            par_w[P_AO][a] = par_a[P_AO][a] = ao;
            axis_set_pos(a);
        }
        axes[a].zp_value = v;
        cmd_unmask();
        break;
    default:
        break;
    }
    params_write(a, p, v);                        /* (in range: checked above) */
    if (p == P_IRQ1 || p == P_IRQ2)
        irq12_update();
    if (p == P_SSF && PAR_W(a, LV) > v) {   /* 4.8.3: <lv> follows a lower <ssf> */
        par_w[P_LV][a] = v;
        par_a[P_LV][a] = v;
        par_gen[a]++;
    }
    return 0;
}

/* A parameter write touches what the main loop reads (par_w, par_a, the
 * watchdog's start, the vector flags): the tick reads no parameter but
 * <da>'s word in test mode, and an interrupt reads a parameter with one
 * move, so the checks and the write run with interrupts enabled - but
 * <zp>'s, which sets <ao> against the measured position and the position. */
static int write_param(unsigned a, unsigned p, int32_t v)
{
    cmd_unmask();
    int r = write_param_checked(a, p, v);
    cmd_remask();
    return r;
}

/* ---- mode changes (E) ---------------------------------------------------- */
static int mode_change_check(unsigned a, uint8_t target)
{
    uint8_t cur = axes[a].mode;
    if (target != M_DISABLE && !axis_initialised(a))
        return ERR_LOGICAL;                       /* operation starts after INIT (4) */
    if (axes[a].stop_then >= STOP_DISABLE && target != M_DISABLE && target != M_RESET)
        return ERR_LOGICAL;                       /* being stopped to disable it (4.8, 4.9) */
    switch (target) {
    case M_DISABLE:
    case M_RESET:
        return 0;
    case M_ENABLE:
        return (cur == M_DISABLE || cur == M_ENABLE || cur == M_BRAKE || cur == M_TEST) ? 0 : ERR_LOGICAL;
    case M_UE:
        return (cur == M_DISABLE || cur == M_TEST || cur == M_RESET) ? ERR_LOGICAL : 0;
    case M_BRAKE:
        return cur == M_DISABLE ? ERR_LOGICAL : 0;
    case M_TEST:
        return (cur == M_DISABLE || cur == M_ENABLE || cur == M_TEST) ? 0 : ERR_LOGICAL;
    default:
        break;
    }
    /* motion modes: only from enable or brake (6.3.7), or a new target on-fly */
    if (!(cur == M_ENABLE || cur == M_BRAKE || cur == target))
        return ERR_LOGICAL;
    switch (target) {
    case M_SEARCH_IDX_C:
    case M_SEARCH_IDX:
    case M_HOME:
        if (PAR(a, ET) != 1)
            return ERR_LOGICAL;                   /* index needs the incremental encoder at P2 */
        if (target == M_HOME && PAR(a, RS) == 0)
            return ERR_LOGICAL;                   /* reference switch declared OFF */
        break;
    case M_FIND_EDGE: {
        int32_t dl = PAR_W(a, DL);
        int32_t cfg = dl == 0 ? PAR(a, RS) : dl == 1 ? PAR(a, NS) : PAR(a, PS);
        if (cfg == 0)
            return ERR_LOGICAL;                   /* that switch is declared OFF */
        if (dl != 0 && PAR(a, SH) != 1)
            return ERR_LOGICAL;                   /* circular axes: reference switch only */
        break;
    }
    case M_POSITIONING:
        if (!target_ok(a, PAR_W(a, AP)))
            return ERR_LIMIT;
        break;
    case M_POS_TRACK:             /* the limits may have changed since WAT (INIT) */
        if (!target_ok(a, PAR(a, AT)))
            return ERR_LIMIT;
        break;
    default:
        break;
    }
    return 0;
}

static __attribute__((noinline)) int do_execute(unsigned a)
{
    uint8_t target = axes[a].next_mode;
    if (target == NO_MODE)
        target = axes[a].mode;
    else if (target == M_BRAKE && axes[a].mode == M_TEST)
        target = M_DISABLE;                       /* 3.5.1: test mode stops by disabling */
    /* the checks read the mode, the status and the parameters, which only
     * the main loop writes: unmasked */
    cmd_unmask();
    int r = mode_change_check(a, target);
    cmd_remask();
    if (r)
        return r;
    uint8_t mode = target == M_UE ? M_ENABLE : target;
    motion_plan_t plan;
    motion_plan_target(a, mode, &plan);           /* masked: a circular axis's from the tick's position */
    /* The activation, <mf> and the gains are read by the main loop only (the
     * tick reads no mode parameter but <da> in test mode, one word): they
     * run with interrupts enabled, between the checks and the commit, which
     * are masked. */
    int init = axis_initialised(a);
    cmd_unmask();
    params_activate(a, PK_MODE);
    if (init)
        axis_prepare_mode(a);                     /* the system parameters' part is INIT's */
    if (mode != M_DISABLE)
        motion_plan(a, &plan);
    cmd_remask();
    /* The one thing an interrupt does to an axis' state: a tick that failed
     * to measure it raised encoder_f and disabled it (6.3.8,
     * measure_encoder_error).  Met while unmasked, it counts as come first:
     * the error is not acknowledged (6.3.7), the axis stays disabled. */
    if (mode != M_DISABLE && (axes[a].ustat & US_ERRORS))
        return ERR_LOGICAL;
    if (!init)
        axis_prepare(a);
    axes[a].next_mode = NO_MODE;
    /* pos_end, jus_end and LED P are cleared only by the next E (5.6) */
    axes[a].ustat &= ~(UB(POS_END) | UB(JUS_END));
    axes[a].sstat &= ~SB(IN_POS);
    uint8_t from = axes[a].mode;
    if (mode == M_DISABLE || (mode == M_RESET && (from == M_DISABLE || from == M_TEST))) {
        axis_disable(a);                          /* (reset: nothing moves to stop) */
    } else {
        axis_set_mode(a, mode);
        motion_start(a, mode, from, &plan);
    }
    return 0;
}

/* ---- general instructions ---------------------------------------------- */
static int do_init(unsigned a)
{
    if (axes[a].mode != M_DISABLE)
        return ERR_LOGICAL;
    if (PAR_W(a, SH) == 1 && PAR_W(a, LP) <= PAR_W(a, LN))
        return ERR_LIMIT;                         /* 4.3.1.1: <lp> > <ln> */
    if (!et_ok(PAR_W(a, ET)))
        return ERR_LIMIT;
    if (PAR_W(a, ET) >= 3 && !measure_ea_ok((uint32_t)PAR_W(a, EA), PAR_W(a, EB)))
        return ERR_LIMIT;                         /* external encoder: no usable <ea> for this <eb> */
#if MAC4_CARD != MAC4_CARD_STP
    /* INIT needs the axis disabled: the tick drives 0 V there and, with its
     * measurement of the axis held off until the supervision after INIT
     * (mk_tick), reads nothing INIT writes - so the bulk of INIT runs with
     * interrupts enabled (the other axes' ticks are not held off by it). */
    axes[a].mk_tick = MK_NONE;
    cmd_unmask();
    params_activate(a, PK_SYS);
    params_activate(a, PK_MODE);
    axis_init_measurement(a);
    cmd_remask();
#else
    /* The STP's tick works on a disabled axis' step output and step count
     * too (stp_t, which the measurement's set-up rewrites): that part stays
     * masked.  The parameters' activation only copies the axis' written
     * values, which no interrupt reads on a disabled axis but one at a time
     * in a single move (<irq6>, <irq5>): unmasked. */
    cmd_unmask();
    params_activate(a, PK_SYS);
    params_activate(a, PK_MODE);
    cmd_remask();
    axis_init_measurement(a);
#endif
    axes[a].ustat |= UB(INIT);
    axes[a].next_mode = NO_MODE;
    return 0;
}

static int do_general(int ci, unsigned a, uint32_t p)
{
    switch (ci) {
    case CI_INIT:
        return do_init(a);
    case CI_E:
        return do_execute(a);
    case CI_DEINIT:                               /* 4.9: stop, disable, deinitialise */
        if (axis_standstill(a) || axes[a].mode == M_TEST) {
            axis_disable(a);
            axes[a].ustat &= ~UB(INIT);
        } else {
            motion_emergency(a, STOP_DEINIT);
        }
        axes[a].next_mode = NO_MODE;
        return 0;
    case CI_MR:
        if (!(hal_rd16(SYS_STATUS) & SYS_ST_J11))
            return ERR_LOGICAL;                   /* 2.1.3: MR works only with J11 in */
        cmd_mr = 1;
        for (unsigned n = 0; n < MAC4_NAXES; n++)
            axes[n].sstat &= ~SB(M_RDY);          /* no more commands until the reset */
        return 0;
    case CI_FLYON:
        axes[a].ustat |= UB(ON_FLY);
        return 0;
    case CI_FLYOFF:
        axes[a].ustat &= ~UB(ON_FLY);
        return 0;
    case CI_USR:
    case CI_USN:
        if (!system_change_allowed(a))
            return ERR_LOGICAL;
        if (ci == CI_USR)
            axes[a].ustat |= UB(REV_O);
        else
            axes[a].ustat &= ~UB(REV_O);
        return 0;
    case CI_TURBO:
        if (p > 1)
            return ERR_LIMIT;
        if (!axis_standstill(a))
            return ERR_LOGICAL;
        if (p)
            axes[a].sstat |= SB(TURBO);
        else
            axes[a].sstat &= ~SB(TURBO);
        return 0;
    case CI_WAP_R: {
        int64_t t = (int64_t)PAR_W(a, AP) + (int32_t)p;
        if (t < INT32_MIN || t > INT32_MAX)
            return ERR_LIMIT;
        return write_param(a, P_AP, (int32_t)t);
    }
    default:
        return ext_general(ci, a, p);             /* the extensions (ext.h), else 161 */
    }
}

static uint32_t read_value(cmd_t c, unsigned a)
{
    const axis_t *x = axis_at[a];
    if (c.kind == CK_FIELD)
        return *(const uint32_t *)(const void *)((const uint8_t *)x + c.arg);
    if (c.kind == CK_RPAR) {
        if (c.arg == P_ZP)
            return (uint32_t)x->zp_value;
        return (uint32_t)par_written(a, c.arg);
    }
    switch (c.arg) {
    case CI_VER: return FW_VER_WORD;
#if MAC4_CARD == MAC4_CARD_STP
    case CI_RCPI: return (uint32_t)stp_counts(a);
    case CI_ROUT: return (uint32_t)stp_out_steps_sp(a);
#else
    case CI_ROUT: return (uint32_t)(int32_t)x->out;
#endif
    case CI_RPS: return (uint32_t)(int32_t)(x->prof.vel >> 16);
    case CI_RAS: return card_ostat;
    default: return ext_read(c.arg, a);
    }
}

/* ---- one command --------------------------------------------------------- */
static void error_bits(unsigned a, uint16_t code)
{
    switch (code) {
    case ERR_SYNTAX: axes[a].ustat |= UB(SYN_F); break;
    case ERR_LIMIT: axes[a].ustat |= UB(LIMIT_F); break;
    case ERR_LOGICAL: axes[a].ustat |= UB(LOGO_F); break;
    default: break;
    }
}

static int is_card_error(uint16_t code)
{
    return code == ERR_AXIS || code == ERR_WATCHDOG || code == ERR_HSTOP;
}

/* Everything but the reads (cmd_execute's common case): C, and the commands
 * that need every error acknowledged first (6.3.7). */
static __attribute__((noinline)) uint16_t execute_other(cmd_t c, unsigned a, uint32_t param)
{
    axis_t *x = axis_at[a];
    if (c.kind == CK_GEN && c.arg == CI_C) {
        x->ustat &= ~US_ERRORS;
        card_ostat &= ~(OB(AXIS_F) | OB(WATCH_F));
        if (!(hal_rd16(SYS_STATUS) & SYS_ST_STOP))
            card_ostat &= ~OB(H_STOP);
        return 0;
    }
    if ((x->ustat & US_ERRORS) || (card_ostat & (OB(AXIS_F) | OB(WATCH_F) | OB(H_STOP))))
        return ERR_LOGICAL;                       /* 6.3.7: error not acknowledged */
    if (c.kind == CK_MODE) {
        x->next_mode = c.arg;
        return 0;
    }
    if (c.kind == CK_WPAR)
        return (uint16_t)write_param(a, c.arg, (int32_t)param);
    return (uint16_t)do_general(c.arg, a, param);
}

/* Everything but a read without an error to report: the checks in the
 * order of the file's head comment. */
static __attribute__((noinline)) void execute_slow(const mac4_msg_t *in, mac4_msg_t *out)
{
    if (in->axis >= MAC4_NAXES) {                 /* 6.3.1 */
        card_ostat |= OB(AXIS_F);
        out->code = ERR_AXIS;
        out->param = card_ostat;
        return;
    }
    unsigned a = in->axis;
    axis_t *x = axis_at[a];
    cmd_t c = cmd_of(in->code);
    uint16_t err;

    if (c.kind == CK_NONE) {
        err = ERR_SYNTAX;
    } else if (kind_is_read(c.kind)) {
        out->param = read_value(c, a);            /* 6.3: reads are always executed */
        return;
    } else if (card_err_report || x->err_report) {
        /* 6.3.4-6.3.6: "the error message is given as the response to the
         * next instruction" (a read excepted, 6.3); the instruction itself is
         * not executed - but a C, which acknowledges the error it reports,
         * so that a host never needs two.  The status as at the report. */
        uint16_t code = card_err_report ? card_err_report : x->err_report;
        if (card_err_report)
            card_err_report = 0;
        else
            x->err_report = 0;
        out->code = code;
        out->param = is_card_error(code) ? card_ostat : x->ustat;
        if (c.kind == CK_GEN && c.arg == CI_C) {
            x->err_report = 0;                    /* both of this axis' reports: one C */
            (void)execute_other(c, a, in->param);
        }
        return;
    } else {
        err = execute_other(c, a, in->param);
    }
    if (err) {
        error_bits(a, err);
        out->code = err;
    }
    out->param = x->ustat;
}

void cmd_execute(const mac4_msg_t *in, mac4_msg_t *out)
{
    unsigned a = in->axis;
    uint16_t code = in->code;
    out->axis = in->axis;
    out->source = in->source;
    out->code = code;
    if (PAR(0, WD) > 0)
        wd_last_us = now_us();                    /* otherwise WWD sets it (write_param) */
    wd_fired = 0;
    if (a < MAC4_NAXES) {
        last_valid_axis = (uint8_t)a;
        /* the common case first: a read (executed even with an error waiting, 6.3) */
        cmd_t c = cmd_of(code);
        const axis_t *x = axis_at[a];
        if (kind_is_read(c.kind)) {
            if (c.kind == CK_FIELD)
                out->param = *(const uint32_t *)(const void *)((const uint8_t *)x + c.arg);
            else
                out->param = read_value(c, a);
            return;
        }
    }
    execute_slow(in, out);
}

/* ---- the interfaces ------------------------------------------------------ */
static inline __attribute__((always_inline)) void respond(const mac4_msg_t *out)
{
    if (out->source == MSG_SRC_SERIAL) {
        serial_send(out);
        return;
    }
    /* the VME response queue: source 0 (only the serial driver marks source 1) */
    if (q_put_at(DP_RSP_QUEUE, out->axis, out->code, out->param, MSG_SRC_VME) != Q_OK) {
        /* 4.6: a full output queue loses the response, no interrupt 2 */
        hal_wr32(DPC_RSP_LOST, ++n_rsp_lost);
        return;
    }
    if (irq12 & 2u) {
        unsigned a = out->axis < MAC4_NAXES ? out->axis : last_valid_axis;
        uint8_t v = (uint8_t)PAR(a, IRQ2);
        if (v)
            vme_irq(v);
    }
}

static inline __attribute__((always_inline)) void execute_and_respond(const mac4_msg_t *in)
{
    mac4_msg_t out;
    /* A command always follows the supervision of the ticks before it, and
     * the tick sees it whole or not at all: masked, once no tick is left to
     * supervise - the supervision itself runs unmasked (it masks per axis),
     * so the mask holds off the next tick for the command alone. */
    unsigned prev = hal_irq_save();
    while (card_supervise_due()) {
        hal_irq_restore(prev);
        card_supervise_tick();
        prev = hal_irq_save();
    }
    cmd_execute(in, &out);   /* (perf track counts a pass with a cmd_execute as a command pass) */
    hal_irq_restore(prev);
    hal_wr32(DPC_COMMANDS, ++n_commands);   /* (a diagnostic count: after the mask) */
    /* what only the main loop reads, after the mask: the profile
     * generator's velocities of a move the command started (motion.c) */
    motion_after_command();
    respond(&out);
}

static __attribute__((noinline)) void watchdog_fire(void)
{
    /* 4.7, 6.3.6: all axes stop (emergency ramp; test mode without) */
    wd_fired = 1;
    unsigned prev = hal_irq_save();
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        motion_emergency(n, STOP_DISABLE);
    card_ostat |= OB(WATCH_F);
    card_err_report = ERR_WATCHDOG;
    hal_irq_restore(prev);
}

static void watchdog_check(void)
{
    int32_t wd = PAR(0, WD);
    if (wd <= 0 || wd_fired)
        return;
    uint32_t elapsed = now_us() - wd_last_us;
    if (elapsed / 1000u >= (uint32_t)wd)
        watchdog_fire();
}

/* ---- off-fly: commands in series per axis (5.15) -------------------------- */
/* The axis' move runs off-fly: its commands wait for the end of it. */
static inline __attribute__((always_inline)) int axis_in_series(unsigned a)
{
    return !(axis_at[a]->ustat & UB(ON_FLY)) && motion_busy(a);
}

/* Does this command wait behind its axis' off-fly move or behind commands
 * of its axis that wait already?  Reads and C never do. */
static int must_wait(const mac4_msg_t *m)
{
    unsigned a = m->axis;
    if (a >= MAC4_NAXES || (!(held_axes & (1u << a)) && !axis_in_series(a)))
        return 0;
    cmd_t c = cmd_of(m->code);
    return !(kind_is_read(c.kind) || (c.kind == CK_GEN && c.arg == CI_C));
}

static __attribute__((noinline)) void hold(const mac4_msg_t *m)
{
    held[n_held++] = *m;
    held_axes |= (uint8_t)(1u << m->axis);
    if (PAR(0, WD) > 0)
        wd_last_us = now_us();      /* a held command counts for the watchdog when it comes */
}

/* The oldest held command whose axis is free now, executed: 1; or 0. */
static __attribute__((noinline)) int release_held(void)
{
    unsigned blocked = 0;
    for (unsigned i = 0; i < n_held; i++) {
        unsigned a = held[i].axis, bit = 1u << a;
        if (blocked & bit)
            continue;               /* an older command of this axis waits */
        if (axis_in_series(a)) {
            blocked |= bit;
            continue;
        }
        mac4_msg_t m = held[i];
        unsigned mask = 0;
        for (unsigned k = 0; k + 1u < n_held; k++) {
            if (k >= i)
                held[k] = held[k + 1u];
            mask |= 1u << held[k].axis;
        }
        n_held--;
        held_axes = (uint8_t)mask;
        execute_and_respond(&m);
        return 1;
    }
    return 0;
}

/* ---- the main loop's part ------------------------------------------------- */
/* One pass: at most one command.  (An idle pass split off as an inline test
 * in front of this would save ~240 cycles per idle pass but cost ~190 more
 * per command: a command pass is this function's prologue either way.) */
void cmd_poll(void)
{
    mac4_msg_t in;
    serial_poll();
    watchdog_check();
    if (cmd_mr)
        return;             /* the watchdog resets the card soon */
    if (n_held) {
        if (release_held())
            return;
        if (n_held == HOLD_MAX)
            return;         /* no room to hold another: the interfaces wait */
    }
    /* One command per pass, alternating between the two interfaces so
     * neither can starve the other. */
    uint8_t t = turn ^= 1u;
    int have = 0;
    if (t && serial_pending())
        have = serial_get(&in);
    if (!have) {
        int r = q_get_at(DP_CMD_QUEUE, &in, 0);
        if (r == Q_CORRUPT) {
            if (!queue_bad)
                hal_wr32(DPC_QUEUE_ERRORS, ++n_queue_errors);
            queue_bad = 1;
        } else {
            queue_bad = 0;
            have = r;       /* Q_OK 1, Q_EMPTY 0 */
            if (have) {
                in.source = MSG_SRC_VME;   /* a VME command is answered on the VMEbus */
                /* interrupt 1: a command was read from the VME queue (4.6) */
                if ((irq12 & 1u) && in.axis < MAC4_NAXES) {
                    uint8_t v = (uint8_t)PAR(in.axis, IRQ1);
                    if (v)
                        vme_irq(v);
                }
            }
        }
    }
    if (!have && !t && serial_pending())
        have = serial_get(&in);
    if (!have)
        return;
    if (must_wait(&in)) {
        hold(&in);          /* off-fly: strictly in series for its axis (5.15) */
        return;
    }
    execute_and_respond(&in);
}
