#include "unit_support.h"

static void check_value(void **st)
{
    (void)st;
    /* CRC-16/CCITT-FALSE check value of "123456789" */
    const char *s = "123456789";
    uint16_t a = CRC16_INIT, b = CRC16_INIT;
    crc16_init_table();
    for (const char *p = s; *p; p++) {
        a = crc16_update(a, (uint8_t)*p);
        b = crc16_bitwise(b, (uint8_t)*p);
    }
    assert_int_equal(a, 0x29B1);
    assert_int_equal(b, 0x29B1);
}

static void table_matches_bitwise(void **st)
{
    (void)st;
    crc16_init_table();
    uint16_t a = CRC16_INIT, b = CRC16_INIT;
    for (unsigned i = 0; i < 70000; i++) {
        uint8_t byte = (uint8_t)(i * 2654435761u >> 13);
        a = crc16_update(a, byte);
        b = crc16_bitwise(b, byte);
        assert_int_equal(a, b);
    }
}

static void single_byte_change_detected(void **st)
{
    (void)st;
    crc16_init_table();
    static uint8_t img[4096];
    for (unsigned i = 0; i < sizeof img; i++)
        img[i] = (uint8_t)(i ^ (i >> 3));
    uint16_t ref = CRC16_INIT;
    for (unsigned i = 0; i < sizeof img; i++)
        ref = crc16_update(ref, img[i]);
    for (unsigned pos = 0; pos < sizeof img; pos += 97) {
        for (unsigned bit = 0; bit < 8; bit++) {
            img[pos] ^= (uint8_t)(1u << bit);
            uint16_t c = CRC16_INIT;
            for (unsigned i = 0; i < sizeof img; i++)
                c = crc16_update(c, img[i]);
            assert_int_not_equal(c, ref);
            img[pos] ^= (uint8_t)(1u << bit);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(check_value),
        cmocka_unit_test(table_matches_bitwise),
        cmocka_unit_test(single_byte_change_detected),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
