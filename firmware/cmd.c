/*
 * cmd.c - the command dispatcher: queue or serial line -> decoder -> command
 * table (commands.def) -> the group's handler (cmd_table.h) -> response;
 * the poll loop and the watchdog <wd> (4.7); the commands held behind an
 * off-fly move (5.15) wait in cmd_offfly.c.
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
#include "inline.h"
#include <stddef.h>
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "axis.h"
#include "cmd.h"
#include "params.h"
#include "serial.h"
#include "motion.h"
#include "measure.h"
#include "ext.h"
#include "cmd_table.h"
#include "card_variant.h"

/* ---- the command table -------------------------------------------------- */
/* the command indices CI_*: cmd.h */
_Static_assert(NCMDS <= 256 && NPARAMS <= 256, "cmd_t.arg is a byte");

/* Code -> what it is, in one look-up indexed by the code: the kind
 * (CK_NONE for codes that do not exist or not on this card) and its
 * argument: the mode (CK_MODE), the parameter (CK_WPAR/CK_RPAR) or the
 * command's CI_ index.  A duplicate code in commands.def overrides an
 * initialiser: -Woverride-init (-Wextra) makes that a compile error.
 * (cmd_t: cmd_table.h) */

/* How each diagnosis value is read: a field of axis_t (CK_FIELD, 32 bits,
 * or CK_FIELD16, a signed word, and its offset: one move), from the card's
 * own stages (CK_CARD, cmd_read_card), or computed by cmd_read_value()
 * (CK_DIAG, cmd_read.c). */
#define DIAG_FIELD(f) CK_FIELD, offsetof(axis_t, f)
#define DIAG_RCP  DIAG_FIELD(pos)
#define DIAG_RCPI CK_CARD, CI_RCPI          /* STP only: encoder increments since INIT */
/* the DAC word the output stage wrote; STP: Steps/SP (table 6.2), from the rate */
#define DIAG_ROUT CARDSEL(CK_FIELD16, CK_FIELD16, CK_CARD), \
                  CARDSEL(offsetof(axis_t, out), offsetof(axis_t, out), CI_ROUT)
#define DIAG_RCT  DIAG_FIELD(counter)
#define DIAG_RED  DIAG_FIELD(raw)
#define DIAG_RFE  DIAG_FIELD(ferr)
#define DIAG_RPS  CK_DIAG, CI_RPS           /* command velocity per SP, from Q16 */
#define DIAG_RAV  DIAG_FIELD(vel)
#define DIAG_RAS  CK_DIAG, CI_RAS           /* card-wide */
#define DIAG_RBS  DIAG_FIELD(ustat)
#define DIAG_RSS  DIAG_FIELD(sstat)
_Static_assert(offsetof(axis_t, ferr) < 256 && offsetof(axis_t, vel) < 256 && offsetof(axis_t, out) < 256,
               "CK_FIELD offsets are bytes");

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

FW_INLINE cmd_t cmd_of(uint16_t code)
{
    static const cmd_t none = {CK_NONE, 0};
    return code < NCODES ? cmds[code] : none;
}

/* &axes[a] in one load: axis_at[] (card.h). */

/* ---- state -------------------------------------------------------------- */
static uint8_t queue_bad;       /* 1 while the command queue header is corrupt */
static uint8_t last_valid_axis; /* for interrupt 2 of a false axis number (6.3.1) */
uint8_t cmd_mr;                 /* MR accepted: stop retriggering the watchdog (cmd.h) */
uint32_t cmd_wd_last_us;        /* time of the last command, for <wd> (cmd_table.h) */
static uint8_t wd_fired;
/* Some axis has an interrupt-1 vector, an interrupt-2 vector (4.6; both 0
 * by default): the command path looks a vector up only then.  A byte each,
 * one TST. */
static uint8_t irq1_on, irq2_on;
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

void cmd_irq12_update(void)
{
    uint8_t f1 = 0, f2 = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        if (PAR(n, IRQ1))
            f1 = 1;
        if (PAR(n, IRQ2))
            f2 = 1;
    }
    irq1_on = f1;
    irq2_on = f2;
}

void cmd_reset(void)
{
    queue_bad = 0;
    last_valid_axis = 0;
    cmd_mr = 0;
    wd_fired = 0;
    cmd_wd_last_us = 0;
    n_commands = n_rsp_lost = n_queue_errors = 0;
    cmd_offfly_reset();
    cmd_irq12_update();
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

/* A read's value (6.3: executed even with an error waiting): a field of
 * the axis in one move, the card's stages' (ROUT, the STP's RCPI:
 * card_variant.h card_read), or worked out (cmd_read.c). */
FW_INLINE uint32_t read_value(cmd_t c, unsigned a)
{
    const uint8_t *x = (const uint8_t *)axis_at[a];
    if (c.kind == CK_FIELD)
        return *(const uint32_t *)(const void *)(x + c.arg);
    if (c.kind == CK_FIELD16)
        return (uint32_t)(int32_t)*(const int16_t *)(const void *)(x + c.arg);
    if (c.kind == CK_CARD)
        return card_read(c.arg, a);
    return cmd_read_value(c.kind, c.arg, a);
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
        out->param = read_value(c, a);                /* 6.3: reads are always executed */
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
            axis_error_reported(x);
        out->code = code;
        out->param = is_card_error(code) ? card_ostat : x->ustat;
        if (c.kind == CK_GEN && c.arg == CI_C) {
            axis_error_reported(x);               /* both of this axis' reports: one C */
            (void)cmd_execute_other(c, a, in->param);
        }
        return;
    } else {
        err = cmd_execute_other(c, a, in->param);
    }
    if (err) {
        error_bits(a, err);
        out->code = err;
    }
    out->param = x->ustat;
}

/* What every command does first, a read or not: <wd> counts from it (4.7). */
FW_INLINE void command_begins(unsigned a, int32_t wd)
{
    if (wd > 0)
        cmd_wd_last_us = now_us();                    /* otherwise WWD sets it (write_param) */
    wd_fired = 0;
    if (a < MAC4_NAXES)
        last_valid_axis = (uint8_t)a;
}

void cmd_execute(const mac4_msg_t *in, mac4_msg_t *out)
{
    unsigned a = in->axis;
    out->axis = in->axis;
    out->source = in->source;
    out->code = in->code;
    command_begins(a, PAR(0, WD));
    if (a < MAC4_NAXES) {
        /* the common case first: a read */
        cmd_t c = cmd_of(in->code);
        if (kind_is_read(c.kind)) {
            out->param = read_value(c, a);
            return;
        }
    }
    execute_slow(in, out);
}

/* ---- the interfaces ------------------------------------------------------ */
/* A command always follows the supervision of the ticks before it, and the
 * tick sees it whole or not at all: masked, once no tick is left to
 * supervise - the supervision itself runs unmasked (it masks per axis), so
 * the mask holds off the next tick for the command alone.  The mask to
 * restore after the command. */
static __attribute__((noinline)) uint16_t supervise_then_mask(uint16_t prev)
{
    do {
        hal_irq_restore(prev);
        card_supervise_tick();
        prev = (uint16_t)hal_irq_save();
    } while (card_supervise_due());
    return prev;
}

FW_INLINE uint16_t mask_supervised(void)
{
    uint16_t prev = (uint16_t)hal_irq_save();
    if (card_supervise_due())
        prev = supervise_then_mask(prev);   /* out of line: the rare case */
    return prev;
}

/* After every command executed, read or not, unmasked: the count (a
 * diagnostic), and what only the main loop reads - the profile generator's
 * velocities of a move the command started (motion.c).  Out of line: a
 * pass that calls it is a command pass (perf track, docs/performance.md). */
static __attribute__((noinline)) void cmd_done(void)
{
    hal_wr32(DPC_COMMANDS, ++n_commands);
    motion_after_command();
}

/* The answer of a VME command, written into the response queue's element
 * directly: source 0 (only the serial driver marks source 1). */
FW_INLINE void respond_vme(uint8_t axis, uint16_t code, uint32_t param)
{
    if (q_put_at(DP_RSP_QUEUE, axis, code, param, MSG_SRC_VME) != Q_OK) {
        /* 4.6: a full output queue loses the response, no interrupt 2 */
        hal_wr32(DPC_RSP_LOST, ++n_rsp_lost);
        return;
    }
    if (irq2_on) {
        unsigned a = axis < MAC4_NAXES ? axis : last_valid_axis;
        uint8_t v = (uint8_t)PAR(a, IRQ2);
        if (v)
            vme_irq(v);
    }
}

FW_INLINE void execute_and_respond(const mac4_msg_t *in)
{
    mac4_msg_t out;
    uint16_t prev = mask_supervised();
    cmd_execute(in, &out);
    hal_irq_restore(prev);
    cmd_done();
    if (out.source == MSG_SRC_SERIAL)
        serial_send(&out);
    else
        respond_vme(out.axis, out.code, out.param);
}

static __attribute__((noinline)) void watchdog_fire(void)
{
    /* 4.7, 6.3.6: all axes stop (emergency ramp; test mode without), each
     * in a masked section of its own, as the supervision's reactions are:
     * the tick sees an axis' stop whole, and waits for one axis' set-up,
     * not four */
    wd_fired = 1;
    unsigned prev;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        prev = hal_irq_save();
        motion_emergency(n, STOP_DISABLE);
        hal_irq_restore(prev);
    }
    prev = hal_irq_save();
    card_ostat |= OB(WATCH_F);
    card_err_report = ERR_WATCHDOG;
    hal_irq_restore(prev);
}

static void watchdog_check(int32_t wd)
{
    if (wd <= 0 || wd_fired)
        return;
    uint32_t elapsed = now_us() - cmd_wd_last_us;
    if (elapsed / 1000u >= (uint32_t)wd)
        watchdog_fire();
}

/* ---- off-fly: commands in series per axis (5.15, cmd_offfly.c) ---------- */
/* Does this command wait behind its axis' off-fly move or behind commands
 * of its axis that wait already?  Reads and C never do. */
static int must_wait(const mac4_msg_t *m)
{
    if (!cmd_offfly_busy(m->axis))
        return 0;
    cmd_t c = cmd_of(m->code);
    return !(kind_is_read(c.kind) || (c.kind == CK_GEN && c.arg == CI_C));
}

/* The oldest held command whose axis is free now, executed: 1; or 0. */
static __attribute__((noinline)) int release_held(void)
{
    mac4_msg_t m;
    if (!cmd_offfly_next(&m))
        return 0;
    execute_and_respond(&m);
    return 1;
}

/* ---- the main loop's part ------------------------------------------------- */
/* A command taken from either interface: held behind its axis' off-fly
 * move, or executed and answered. */
static __attribute__((noinline)) void dispatch(const mac4_msg_t *in)
{
    if (must_wait(in)) {
        cmd_offfly_hold(in);    /* off-fly: strictly in series for its axis (5.15) */
        return;
    }
    execute_and_respond(in);
}

/* The VME host's reads (RBS, RCP, RFE, ROUT, ...: the common command):
 * straight from the queue element to the response element, the kind and
 * the field from the table, the same steps as execute_and_respond's. */
FW_INLINE void vme_read(unsigned a, uint16_t code, cmd_t c, int32_t wd)
{
    uint16_t prev = mask_supervised();
    command_begins(a, wd);
    uint32_t v = read_value(c, a);
    hal_irq_restore(prev);
    cmd_done();
    respond_vme((uint8_t)a, code, v);
}

/* The VME command at the rear of the queue (its header checked, not empty). */
FW_INLINE void vme_command(uint32_t rear, int32_t wd)
{
    uint32_t e = DP_CMD_QUEUE + q_elem_off(rear);
    IN_ADDR_REG(e);
    uint8_t a = hal_rd8(e + MSG_AXIS);
    uint16_t code = hal_rd16(e + MSG_CODE);
    cmd_t c = cmd_of(code);
    /* a read of a valid axis never waits (off-fly) and needs no parameter */
    if (a < MAC4_NAXES && kind_is_read(c.kind) && !irq1_on) {
        q_rear_on(DP_CMD_QUEUE, rear);
        vme_read(a, code, c, wd);
        return;
    }
    mac4_msg_t in;
    in.axis = a;
    in.code = code;
    in.param = hal_rd32(e + MSG_PARAM);
    q_rear_on(DP_CMD_QUEUE, rear);
    in.source = MSG_SRC_VME;                /* a VME command is answered on the VMEbus */
    /* interrupt 1: a command was read from the VME queue (4.6) */
    if (irq1_on && a < MAC4_NAXES) {
        uint8_t v = (uint8_t)PAR(a, IRQ1);
        if (v)
            vme_irq(v);
    }
    dispatch(&in);
}

static __attribute__((noinline)) void serial_command(void)
{
    mac4_msg_t in;
    if (serial_get(&in))
        dispatch(&in);
}

/* One pass: a held command that can go now, or else at most one command of
 * each interface, the VME queue's first.  Both each pass, so that neither
 * starves the other, and a VME command waits for one serial command at
 * most, never for a pass of its own behind it (the 2 ms command latency
 * with both hosts busy, docs/performance.md). */
void cmd_poll(void)
{
    serial_poll();
    /* <wd> as this pass found it: no command before the VME read changes it */
    int32_t wd = PAR(0, WD);
    watchdog_check(wd);
    if (cmd_mr)
        return;             /* the watchdog resets the card soon */
    if (cmd_n_held) {
        if (release_held())
            return;
        if (cmd_n_held == CMD_HOLD_MAX)
            return;         /* no room to hold another: the interfaces wait */
    }
    uint32_t front, rear;
    if (q_header_at(DP_CMD_QUEUE, &front, &rear)) {
        if (!queue_bad)
            hal_wr32(DPC_QUEUE_ERRORS, ++n_queue_errors);
        queue_bad = 1;
    } else if (queue_bad) {
        /* A header found valid again is trusted from the next pass on: the
         * host repairs it with several writes, and a read between them can
         * pair its old front with its new rear (docs/interpretations.md). */
        queue_bad = 0;
    } else if (front != rear) {
        vme_command(rear, wd);
    }
    if (serial_pending() && !cmd_mr && cmd_n_held < CMD_HOLD_MAX)
        serial_command();
}
