#include "unit_support.h"
#include "queue.h"

static void index_arithmetic(void **st)
{
    (void)st;
    assert_int_equal(q_next(0, 10), 1);
    assert_int_equal(q_next(9, 10), 0);
    assert_int_equal(q_used(0, 0, 10), 0);
    assert_int_equal(q_used(9, 0, 10), 9);
    assert_int_equal(q_used(0, 1, 10), 9);
    assert_int_equal(q_used(3, 7, 10), 6);
    for (uint32_t f = 0; f < 10; f++)
        for (uint32_t r = 0; r < 10; r++)
            assert_true(q_used(f, r, 10) < 10);
}

static void create_matches_table_7_1(void **st)
{
    (void)st;
    card_setup();
    q_create(DP_CMD_QUEUE);
    assert_int_equal(dp_rd32(&card, 0x4700), 0x18);
    assert_int_equal(dp_rd32(&card, 0x4704), 0);
    assert_int_equal(dp_rd32(&card, 0x4708), 0);
    assert_int_equal(dp_rd32(&card, 0x470C), 0);
    assert_int_equal(dp_rd32(&card, 0x4710), 0xA);
    assert_int_equal(dp_rd32(&card, 0x4714), 0xA);
}

/* The DPRAM keeps the queues across a reset and the host may poll them
 * while the card creates them anew: after every write of q_create the
 * header is either one the host must not use, or one with front == rear
 * (never the new front with the old rear: stale elements as responses). */
static uint32_t watched_q;
static unsigned header_writes, stale_seen;
static void check_header(sim_t *s, uint32_t addr, uint32_t v, int size)
{
    (void)v;
    (void)size;
    if (addr < watched_q || addr >= watched_q + Q_HEADER_SIZE)
        return;
    header_writes++;
    uint32_t base = dp_rd32(s, watched_q + QH_BASE), width = dp_rd32(s, watched_q + QH_WIDTH);
    uint32_t nel = dp_rd32(s, watched_q + QH_NEL);
    uint32_t front = dp_rd32(s, watched_q + QH_FRONT), rear = dp_rd32(s, watched_q + QH_REAR);
    int sane = base == Q_HEADER_SIZE && width == Q_WIDTH && nel == Q_NEL && front < nel && rear < nel;
    if (sane && front != rear)
        stale_seen++;
}

static void create_over_a_live_queue(void **st)
{
    (void)st;
    static const uint32_t q[] = {DP_CMD_QUEUE, DP_RSP_QUEUE};
    static const uint32_t fr[][2] = {{3, 7}, {7, 3}, {0, 5}, {5, 0}, {9, 1}};
    for (unsigned k = 0; k < 2; k++)
        for (unsigned i = 0; i < sizeof fr / sizeof fr[0]; i++) {
            card_setup();
            q_create(q[k]);
            dp_wr32(&card, q[k] + QH_FRONT, fr[i][0]);   /* the host's view before the reset */
            dp_wr32(&card, q[k] + QH_REAR, fr[i][1]);
            watched_q = q[k];
            header_writes = stale_seen = 0;
            card.on_bus_write = check_header;
            q_create(q[k]);
            card.on_bus_write = NULL;
            assert_true(header_writes >= 6);
            assert_int_equal(stale_seen, 0);
            assert_int_equal(dp_rd32(&card, q[k] + QH_BASE), Q_HEADER_SIZE);
            assert_int_equal(dp_rd32(&card, q[k] + QH_FRONT), 0);
            assert_int_equal(dp_rd32(&card, q[k] + QH_REAR), 0);
        }
}

static void host_to_card_round_trip(void **st)
{
    (void)st;
    card_setup();
    q_create(DP_CMD_QUEUE);
    /* nine fit, the tenth does not (nel-1, manual 7.3.2) */
    for (int i = 0; i < 9; i++)
        assert_int_equal(host_send(&card, (uint8_t)i, (uint16_t)(100 + i), 0x01020304u * (uint32_t)i, 0), 1);
    assert_int_equal(host_send(&card, 0, 1, 0, 0), 0);
    /* entry 2 lies at $4722, as table 7.1 shows */
    assert_int_equal(card.dpram[0x4722], 1);
    assert_int_equal(dp_rd16(&card, 0x4724), 101);
    mac4_msg_t m;
    for (int i = 0; i < 9; i++) {
        assert_int_equal(q_get(DP_CMD_QUEUE, &m), Q_OK);
        assert_int_equal(m.axis, i);
        assert_int_equal(m.code, 100 + i);
        assert_int_equal(m.param, 0x01020304u * (uint32_t)i);
        assert_int_equal(m.source, 0);
    }
    assert_int_equal(q_get(DP_CMD_QUEUE, &m), Q_EMPTY);
    /* wrapped around: the rear index is 9 */
    assert_int_equal(dp_rd32(&card, 0x4708), 9);
}

static void card_to_host_full(void **st)
{
    (void)st;
    card_setup();
    q_create(DP_RSP_QUEUE);
    mac4_msg_t m = {0, 70, 0x02000101u, 0};
    for (int i = 0; i < 9; i++)
        assert_int_equal(q_put(DP_RSP_QUEUE, &m), Q_OK);
    assert_int_equal(q_put(DP_RSP_QUEUE, &m), Q_FULL);
    assert_int_equal(dp_rd32(&card, 0x4804), 9);
    /* the element bytes are exactly diagram 3.6 */
    const uint8_t want[10] = {0, 0, 0, 70, 0x02, 0x00, 0x01, 0x01, 0, 0};
    assert_memory_equal(&card.dpram[0x4818], want, 10);
}

static void corrupt_header_touches_nothing(void **st)
{
    (void)st;
    card_setup();
    q_create(DP_CMD_QUEUE);
    q_create(DP_RSP_QUEUE);
    uint8_t before[DPRAM_SIZE];
    const uint32_t bad[][2] = {
        {QH_FRONT, 10}, {QH_FRONT, 0xFFFFFFFFu}, {QH_REAR, 200}, {QH_NEL, 11},
        {QH_WIDTH, 0x100}, {QH_BASE, 0x1000}, {QH_NEL, 0},
    };
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        q_create(DP_CMD_QUEUE);
        q_create(DP_RSP_QUEUE);
        dp_wr32(&card, DP_CMD_QUEUE + bad[i][0], bad[i][1]);
        dp_wr32(&card, DP_RSP_QUEUE + bad[i][0], bad[i][1]);
        memcpy(before, card.dpram, sizeof before);
        mac4_msg_t m = {0, 3, 0, 0};
        assert_int_equal(q_get(DP_CMD_QUEUE, &m), Q_CORRUPT);
        assert_int_equal(q_put(DP_RSP_QUEUE, &m), Q_CORRUPT);
        assert_memory_equal(before, card.dpram, sizeof before);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(index_arithmetic),
        cmocka_unit_test(create_matches_table_7_1),
        cmocka_unit_test(create_over_a_live_queue),
        cmocka_unit_test(host_to_card_round_trip),
        cmocka_unit_test(card_to_host_full),
        cmocka_unit_test(corrupt_header_touches_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
