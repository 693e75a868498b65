/*
 * fuzz_queue.c - the VME command queue (manual 3.2, 7.3.2) under a host that
 * writes anything: well-formed commands, arbitrary element bytes, arbitrary
 * header words (indices out of range, wrong base/width/nel), a response
 * queue it stops reading or wrecks, stop bits, emergency stop, MR.
 *
 * Input: a sequence of operations (tests/fuzz/README.md has the format).
 * Checked on every main-loop pass, against the host's own view of the
 * DPRAM before and after it:
 *   - the card takes at most one command per pass, and exactly one while
 *     the header is sane, the queue holds one and no MR is pending, but in
 *     the pass that first finds the header sane again after a corrupt one
 *     (trusted from the next pass: docs/interpretations.md);
 *   - a corrupt header is never read through: the card touches neither the
 *     indices nor anything else of that queue, and counts the corruption
 *     once (DPC_QUEUE_ERRORS);
 *   - off-fly (5.15): a command taken and not answered is held for its axis
 *     (its move runs off-fly, or older commands of it wait); a pass that
 *     answers without taking answers the oldest held command of one axis;
 *     the card's list of held commands (cmd_held) changes only so;
 *   - every command taken is answered exactly once: one response element in
 *     the response queue (same axis, its code or an error 160-165, source 0,
 *     reserved bytes 0), or, when the response queue is full or its header
 *     corrupt, one count in DPC_RSP_LOST; nothing is answered that was not
 *     taken; DPC_COMMANDS counts it;
 *   - fuzz_hal.c: no odd word access, no write to DPRAM the card does not own,
 *     no emulator fault, no firmware stop; ASan/UBSan: no memory error, no UB.
 * At the end the host repairs the queues and the card answers VER.
 */
#include "fuzz_card.h"
#include "motion.h"

#define PASS_CYC US_TO_CYC(250)
#define MAX_PASSES 6000

static int host_reads;
static int queue_bad;              /* our model of cmd.c's "corrupt header seen" */
static unsigned passes;

static void on_reset(void)
{
    queue_bad = 0;
}

/* The card's held commands (cmd_held), copied. */
typedef struct {
    unsigned n;
    mac4_msg_t m[CMD_HOLD_MAX];
} held_t;

static void held_get(held_t *h)
{
    const mac4_msg_t *l;
    h->n = cmd_held(&l);
    FZ_CHECK(h->n <= CMD_HOLD_MAX, "%u commands held", h->n);
    for (unsigned i = 0; i < h->n; i++)
        h->m[i] = l[i];
}

static int same_msg(const mac4_msg_t *a, const mac4_msg_t *b)
{
    return a->axis == b->axis && a->code == b->code && a->param == b->param;
}

static int held_equal(const held_t *a, const held_t *b, unsigned skip)
{
    unsigned j = 0;
    for (unsigned i = 0; i < a->n; i++) {
        if (i == skip)
            continue;
        if (j >= b->n || !same_msg(&a->m[i], &b->m[j]))
            return 0;
        j++;
    }
    return j == b->n;
}

static void check_response(const fz_elem_t *cmd, const fz_elem_t *rsp)
{
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "  %6u us: axis %u code %u param %d -> %u $%08X\n",
                (unsigned)(S.slice_base / MAC4_CYCLES_PER_US), cmd->axis, cmd->code, (int)cmd->param, rsp->code,
                (unsigned)rsp->param);
    FZ_CHECK(rsp->axis == cmd->axis, "response axis %u for a command to axis %u", rsp->axis, cmd->axis);
    FZ_CHECK(rsp->pad1 == 0 && rsp->pad2 == 0, "reserved response bytes not 0");
    FZ_CHECK(rsp->source == MSG_SRC_VME, "response source %u", rsp->source);
    FZ_CHECK(rsp->code == cmd->code || fz_is_error(rsp->code), "response code %u to command %u",
             rsp->code, cmd->code);
    if (cmd->axis >= MAC4_NAXES)
        FZ_CHECK(rsp->code == ERR_AXIS, "axis %u answered %u, not 160", cmd->axis, rsp->code);
    if (cmd->code == 7 && rsp->code == 7)
        FZ_CHECK(rsp->param == FW_VER_WORD, "VER answered $%08X", (unsigned)rsp->param);
}

/* One main-loop pass, and every property of it. */
static void pass(void)
{
    if (passes >= MAX_PASSES)
        return;
    passes++;
    int cmd_ok = fz_hdr_ok(DP_CMD_QUEUE), rsp_ok = fz_hdr_ok(DP_RSP_QUEUE);
    uint32_t c_front = fz_rd32(DP_CMD_QUEUE + QH_FRONT), c_rear = fz_rd32(DP_CMD_QUEUE + QH_REAR);
    uint32_t r_front = fz_rd32(DP_RSP_QUEUE + QH_FRONT), r_rear = fz_rd32(DP_RSP_QUEUE + QH_REAR);
    fz_elem_t cmd = {0, 0, 0, 0, 0, 0};
    if (cmd_ok && c_front != c_rear)
        cmd = fz_elem(DP_CMD_QUEUE, c_rear);
    uint32_t lost0 = fz_rd32(DPC_RSP_LOST), cmds0 = fz_rd32(DPC_COMMANDS);
    uint32_t qerr0 = fz_rd32(DPC_QUEUE_ERRORS);
    int mr0 = cmd_mr_pending();
    held_t h0, h1;
    held_get(&h0);
    unsigned resets0 = fz_resets;

    fz_pass(PASS_CYC);

    if (fz_resets != resets0)
        return;                    /* the watchdog reset the card: queues created anew */
    held_get(&h1);
    uint32_t c_rear1 = fz_rd32(DP_CMD_QUEUE + QH_REAR), r_front1 = fz_rd32(DP_RSP_QUEUE + QH_FRONT);
    int waiting = cmd_ok && c_front != c_rear;
    int taken = c_rear1 != c_rear;
    /* at most one answer per pass: into the response queue, or counted lost */
    uint32_t lost = fz_rd32(DPC_RSP_LOST) - lost0;
    uint32_t done = fz_rd32(DPC_COMMANDS) - cmds0;
    int written = r_front1 != r_front;
    int answered = written + (int)lost;
    FZ_CHECK(answered <= 1 && done == (uint32_t)answered, "%d written, %u lost, DPC_COMMANDS +%u in one pass",
             written, (unsigned)lost, (unsigned)done);
    /* a pass that answers without taking answers a held command (5.15) */
    int released = answered && !taken;
    if (released) {
        FZ_CHECK(h0.n > 0, "an answer without a command");
    } else if (!cmd_ok || mr0 || !waiting || h0.n >= CMD_HOLD_MAX || queue_bad) {
        FZ_CHECK(!taken, "rear moved %u -> %u (header %s%s, MR %d, %u commands held, queue %s)",
                 (unsigned)c_rear, (unsigned)c_rear1, cmd_ok ? "sane" : "corrupt",
                 cmd_ok && queue_bad ? " again" : "", mr0, h0.n, waiting ? "not empty" : "empty");
    } else {
        FZ_CHECK(c_rear1 == q_next(c_rear, Q_NEL), "a command waits (front %u rear %u) but rear -> %u",
                 (unsigned)c_front, (unsigned)c_rear, (unsigned)c_rear1);
    }
    /* the corruption is counted once per episode (when the card looked) */
    if (!mr0 && !released && h0.n < CMD_HOLD_MAX) {
        uint32_t qerr1 = fz_rd32(DPC_QUEUE_ERRORS);
        uint32_t want = qerr0 + (!cmd_ok && !queue_bad ? 1u : 0u);
        FZ_CHECK(qerr1 == want, "DPC_QUEUE_ERRORS %u, expected %u", (unsigned)qerr1, (unsigned)want);
        queue_bad = !cmd_ok;
    }
    if (answered) {
        if (rsp_ok && q_next(r_front, Q_NEL) != r_rear) {
            FZ_CHECK(written && r_front1 == q_next(r_front, Q_NEL),
                     "response lost or misplaced with room in the queue (front %u -> %u)", (unsigned)r_front,
                     (unsigned)r_front1);
        } else {
            FZ_CHECK(lost == 1, "a response written into a full or corrupt queue");
        }
    }
    fz_elem_t answer_to = cmd;
    if (released) {
        /* off-fly (5.15): the oldest held command of one axis, whose move
         * has ended; the others stay in their order */
        unsigned k = h0.n;
        for (unsigned i = 0; i < h0.n && k == h0.n; i++)
            if (held_equal(&h0, &h1, i))
                k = i;
        FZ_CHECK(k < h0.n, "a held command answered, but the held list changed otherwise (%u -> %u)", h0.n,
                 h1.n);
        for (unsigned i = 0; i < k; i++)
            FZ_CHECK(h0.m[i].axis != h0.m[k].axis, "a held command of axis %u overtook an older one",
                     h0.m[k].axis);
        answer_to = (fz_elem_t){h0.m[k].axis, MSG_SRC_VME, 0, 0, h0.m[k].code, h0.m[k].param};
    } else if (taken && !answered) {
        int axis_waits = 0;
        for (unsigned i = 0; i < h0.n; i++)
            axis_waits |= cmd.axis < MAC4_NAXES && h0.m[i].axis == cmd.axis;
        FZ_CHECK(cmd.axis < MAC4_NAXES &&
                     (axis_waits || (!(axes[cmd.axis].ustat & UB(ON_FLY)) && motion_busy(cmd.axis))),
                 "command %u to axis %u taken, neither answered nor held (off-fly)", cmd.code, cmd.axis);
        FZ_CHECK(cmd.code != 4 && cmd.code != 7 && cmd.code != 125, "C, VER or RBS held (%u): they always answer",
                 cmd.code);
        mac4_msg_t m = {cmd.axis, cmd.code, cmd.param, MSG_SRC_VME};
        held_t h1_old = h1;
        h1_old.n = h0.n;                       /* h1 without its last entry */
        FZ_CHECK(h1.n == h0.n + 1 && held_equal(&h0, &h1_old, h0.n) && same_msg(&h1.m[h0.n], &m),
                 "command %u to axis %u not held last (%u -> %u held)", cmd.code, cmd.axis, h0.n, h1.n);
    } else {
        FZ_CHECK(h1.n == h0.n && held_equal(&h0, &h1, h0.n), "the held commands changed (%u -> %u)", h0.n, h1.n);
        FZ_CHECK(!answered || taken, "an answer without a command");
    }
    if (answered && written) {
        fz_elem_t rsp = fz_elem(DP_RSP_QUEUE, r_front);
        check_response(&answer_to, &rsp);
    }
    if (host_reads) {
        fz_host_drain();
        if (fz_hdr_ok(DP_RSP_QUEUE))
            FZ_CHECK(fz_rd32(DP_RSP_QUEUE + QH_FRONT) == fz_rd32(DP_RSP_QUEUE + QH_REAR), "drain");
    }
}

static void send(uint8_t axis, uint16_t code, uint32_t param, uint8_t source)
{
    host_send(&S, axis, code, param, source);
}

/* Poke a header word: mostly an index near the range, sometimes anything. */
static void poke_header(fz_in_t *in, uint32_t q)
{
    static const uint32_t word[] = {QH_BASE, QH_FRONT, QH_REAR, QH_FREE, QH_WIDTH, QH_NEL};
    uint8_t b = fz_u8(in);
    uint32_t off = word[b % 6];
    uint32_t v = (b & 0x80) ? fz_u32(in) : (uint32_t)(fz_u8(in) % 16);
    fz_wr32(q + off, v);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_init_once();
    FZ_FW_GUARD();
    fz_on_reset = on_reset;
    fz_power_on();
    host_reads = 1;
    queue_bad = 0;
    passes = 0;
    fz_in_t in = {data, size, 0};
    while (fz_more(&in) && passes < MAX_PASSES) {
        uint8_t op = fz_u8(&in);
        switch (op % 12) {
        case 0: {                                  /* a well-formed command */
            uint8_t a = fz_u8(&in);
            uint8_t axis = (a & 0x80) ? a : (uint8_t)(a & 3u);
            uint16_t code = fz_code(&in);
            send(axis, code, fz_param(&in), 0);
            pass();
            break;
        }
        case 1:                                    /* main-loop passes */
            for (int n = 1 + fz_u8(&in) % 16; n > 0; n--)
                pass();
            break;
        case 2: poke_header(&in, DP_CMD_QUEUE); break;
        case 3: {                                  /* element bytes */
            uint32_t off = fz_u8(&in) % (Q_NEL * Q_WIDTH);
            for (int n = 1 + fz_u8(&in) % 10; n > 0; n--, off = (off + 1) % (Q_NEL * Q_WIDTH))
                S.dpram[DP_CMD_QUEUE + Q_HEADER_SIZE + off] = fz_u8(&in);
            break;
        }
        case 4: poke_header(&in, DP_RSP_QUEUE); break;
        case 5:
            fz_hdr_repair(DP_CMD_QUEUE);
            fz_hdr_repair(DP_RSP_QUEUE);
            break;
        case 6: host_reads = !host_reads; break;
        case 7:                                    /* idle: up to 250 ms */
            for (int n = 4 * (1 + fz_u8(&in)); n > 0; n--)
                pass();
            break;
        case 8: dp_wr16(&S, DP_STOP_BITS, fz_u16(&in)); break;
        case 9: estop_set(&S, fz_u8(&in) & 1); break;
        case 10: S.wdg.j11 = fz_u8(&in) & 1; break;
        case 11: {                                 /* fill the queue with one command */
            uint8_t axis = fz_u8(&in) & 3u;
            uint16_t code = fz_code(&in);
            uint32_t param = fz_param(&in);
            for (int n = 0; n < (int)Q_NEL; n++)
                send(axis, code, param, (uint8_t)(n & 1));
            break;
        }
        }
    }
    fz_final_ver_vme(PASS_CYC);
    fz_check_card("the final VER");
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "queue: %u passes, %u commands, %u responses lost, %u corrupt headers, resets %u\n",
                passes, (unsigned)fz_rd32(DPC_COMMANDS), (unsigned)fz_rd32(DPC_RSP_LOST),
                (unsigned)fz_rd32(DPC_QUEUE_ERRORS), fz_resets);
    return 0;
}
