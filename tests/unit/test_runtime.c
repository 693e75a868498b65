/* The 68000 integer helpers (hal/target/runtime.c) against the host's. */
#include "unit_support.h"
#include "runtime.h"

static const uint32_t edges[] = {0, 1, 2, 3, 0x7FFF, 0x8000, 0xFFFF, 0x10000, 0x7FFFFFFF,
                                 0x80000000u, 0x80000001u, 0xFFFFFFFEu, 0xFFFFFFFFu, 1000, 25000};

static void check_pair(uint32_t a, uint32_t b)
{
    assert_int_equal(rt_mul32(a, b), (uint32_t)(a * b));
    if (b) {
        uint32_t r;
        assert_int_equal(rt_udivmod32(a, b, &r), a / b);
        assert_int_equal(r, a % b);
        int32_t sa = (int32_t)a, sb = (int32_t)b;
        if (!(sa == INT32_MIN && sb == -1)) {
            assert_int_equal(rt_div32(sa, sb), sa / sb);
            assert_int_equal(rt_mod32(sa, sb), sa % sb);
        }
    }
}

static void edges_and_random(void **st)
{
    (void)st;
    for (unsigned i = 0; i < sizeof edges / sizeof edges[0]; i++)
        for (unsigned j = 0; j < sizeof edges / sizeof edges[0]; j++)
            check_pair(edges[i], edges[j]);
    for (int i = 0; i < 200000; i++) {
        uint32_t a = rnd32(), b = rnd32() >> (rnd32() & 31);
        check_pair(a, b);
    }
}

static void shifts_64(void **st)
{
    (void)st;
    for (int i = 0; i < 20000; i++) {
        uint64_t a = (uint64_t)rnd32() << 32 | rnd32();
        unsigned b = rnd32() & 63u;
        assert_true(rt_lshr64(a, b) == a >> b);
        assert_true(rt_shl64(a, b) == a << b);
        assert_true(rt_ashr64((int64_t)a, b) == ((int64_t)a >> b));
    }
}

static void divide_by_zero_does_not_trap(void **st)
{
    (void)st;
    uint32_t r;
    assert_int_equal(rt_udivmod32(1234, 0, &r), 0xFFFFFFFFu);
    assert_int_equal(r, 1234);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(edges_and_random),
        cmocka_unit_test(divide_by_zero_does_not_trap),
        cmocka_unit_test(shifts_64),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
