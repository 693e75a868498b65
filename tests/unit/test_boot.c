#include "unit_support.h"
#include "fw.h"
#include "queue.h"

/* Run both boot stages; returns 1 if the firmware stopped the card. */
static int boot(void)
{
    jmp_buf jb;
    hal_native_stop_jmp = &jb;
    if (setjmp(jb)) {
        hal_native_stop_jmp = NULL;
        fflush(events_f);
        return 1;
    }
    fw_boot_stage1();
    fw_init();
    hal_native_stop_jmp = NULL;
    fflush(events_f);
    return 0;
}

static void sequence_and_queues(void **st)
{
    (void)st;
    card_setup();
    assert_int_equal(boot(), 0);
    assert_string_equal(events, "display 1\ndisplay 2\ndisplay 3\ndisplay 5\n");
    assert_int_equal(dp_rd32(&card, DPC_BOOT_ERROR), 0);
    assert_int_equal(dp_rd32(&card, DPC_BOOT_STATE), 5);
    for (uint32_t q = DP_CMD_QUEUE; q <= DP_RSP_QUEUE; q += 0x100) {
        assert_int_equal(dp_rd32(&card, q + QH_BASE), 0x18);
        assert_int_equal(dp_rd32(&card, q + QH_FRONT), 0);
        assert_int_equal(dp_rd32(&card, q + QH_REAR), 0);
        assert_int_equal(dp_rd32(&card, q + QH_WIDTH), 10);
        assert_int_equal(dp_rd32(&card, q + QH_NEL), 10);
    }
    assert_memory_equal(&card.dpram[0x4818], "MACCON \xA9" "1993", 13);
    assert_int_equal(dp_rd32(&card, DPC_VERSION), 0x00440402u);
}

static void outputs_in_reset_state(void **st)
{
    (void)st;
    card_setup();
    for (int n = 0; n < 4; n++) {   /* whatever was there before */
        card.ax[n].ctrl = AX_CTRL_EN;
        card.ax[n].dac = 1234;
    }
    assert_int_equal(boot(), 0);
    for (int n = 0; n < 4; n++) {
        assert_int_equal(card.ax[n].ctrl & AX_CTRL_EN, 0);
        assert_int_equal(card.ax[n].dac, 0);
    }
    assert_int_equal(card.tmr.period_us, SERVO_PERIOD_US_SERVO);
    assert_true(card.tmr.ctrl & TMR_CTRL_RUN);
    assert_true(card.tmr.ctrl & TMR_CTRL_IE);
}

static void checksum_mismatch_stops_at_3(void **st)
{
    (void)st;
    card_setup();
    card.eprom[0x1234] ^= 0x40;
    assert_int_equal(boot(), 1);
    assert_string_equal(events, "display 1\ndisplay 2\ndisplay 3\ndisplay 3.\n");
    assert_int_equal(dp_rd32(&card, DPC_BOOT_ERROR), DPC_ERR_CHECKSUM);
    assert_int_not_equal(dp_rd32(&card, DPC_CRC_EXPECTED), dp_rd32(&card, DPC_CRC_COMPUTED));
    /* no queues: host software keeps waiting for the banner */
    assert_int_not_equal(dp_rd32(&card, DP_CMD_QUEUE + QH_NEL), 10);
}

static void stored_complement_is_checked(void **st)
{
    (void)st;
    card_setup();
    card.eprom[EPROM_CRC_OFFSET + 3] ^= 0x01;
    assert_int_equal(boot(), 1);
    assert_int_equal(dp_rd32(&card, DPC_BOOT_ERROR), DPC_ERR_CHECKSUM);
}

static void ram_fault_stops_at_2(void **st)
{
    (void)st;
    card_setup();
    card.sram_fault_addr = 0x1230;
    card.sram_fault_mask = 0x0100;
    assert_int_equal(boot(), 1);
    assert_string_equal(events, "display 1\ndisplay 2\ndisplay 2.\n");
    assert_int_equal(dp_rd32(&card, DPC_BOOT_ERROR), DPC_ERR_RAM);
    assert_int_equal(dp_rd32(&card, DPC_RAM_BAD_ADDR), SRAM_BASE + 0x1230);
}

static void ram_fault_in_a_low_word_is_found_there(void **st)
{
    (void)st;
    card_setup();
    card.sram_fault_addr = 0x7FFE;      /* the last word: the low half of the last long */
    card.sram_fault_mask = 0x0001;
    assert_int_equal(boot(), 1);
    assert_int_equal(dp_rd32(&card, DPC_BOOT_ERROR), DPC_ERR_RAM);
    assert_int_equal(dp_rd32(&card, DPC_RAM_BAD_ADDR), SRAM_BASE + 0x7FFE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sequence_and_queues),
        cmocka_unit_test(outputs_in_reset_state),
        cmocka_unit_test(checksum_mismatch_stops_at_3),
        cmocka_unit_test(stored_complement_is_checked),
        cmocka_unit_test(ram_fault_stops_at_2),
        cmocka_unit_test(ram_fault_in_a_low_word_is_found_there),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
