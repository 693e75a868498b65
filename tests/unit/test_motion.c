/* The protective stop that waits for the mechanics at rest (motion.c,
 * motion_supervise.c, 4.8.2): the end of the tick's brake ramp sets its time
 * bound whichever of the supervision and the profile generator sees it first,
 * and the bound ends a stop whose mechanics do not come to rest. */
#include "unit_support.h"
#include "card.h"
#include "motion.h"
#include "params.h"

/* Axis 0 initialised and moving in mode speed at 10 counts per tick, the
 * following error 64, when a stop that disables begins. */
static axis_t *moving_then_stopped(void)
{
    card_setup();
    card_reset();
    axis_t *x = &axes[0];
    x->ustat |= UB(INIT);
    axis_set_mode(0, M_SPEED);
    x->mf = 2000;
    x->meas = 936;
    x->setpoint = 1000;
    x->ferr = 64;
    x->vel = 10;
    x->sp_vel = (int32_t)Q(40);                   /* 40 counts per SP: 10 per tick */
    motion_emergency(0, STOP_DISABLE);
    assert_true(x->braking && x->stop_settle && x->stop_then == STOP_DISABLE);
    return x;
}

/* The tick's ramp has ended (brake_step down to 0); the mechanics still
 * move under closed-loop control. */
static void ramp_ended(axis_t *x)
{
    x->br_v = 0;
}

static void supervise_moving(axis_t *x)
{
    x->vel = 10;
    x->ferr = 54;
    motion_supervise(0);
}

static void profile_first_then_supervision(void **st)
{
    (void)st;
    axis_t *x = moving_then_stopped();
    ramp_ended(x);
    motion_profile_tick(0);                       /* the profile generator sees the end first */
    assert_false(x->braking);
    supervise_moving(x);
    assert_false(x->ustat & UB(FERR_F));          /* no following error: the loop still brakes */
    assert_int_not_equal(x->mode, M_DISABLE);     /* /EN stays closed */
    assert_true(x->stop_settle);
}

static void supervision_first(void **st)
{
    (void)st;
    axis_t *x = moving_then_stopped();
    ramp_ended(x);
    supervise_moving(x);
    assert_false(x->braking);
    assert_false(x->ustat & UB(FERR_F));
    assert_int_not_equal(x->mode, M_DISABLE);
}

/* Mechanics that never come to rest: the bound (2 x the ramp's ticks +
 * STOP_SETTLE_TICKS) ends the stop with ferr_f and /EN open. */
static void the_bound_ends_a_stop_that_never_rests(void **st)
{
    (void)st;
    axis_t *x = moving_then_stopped();
    ramp_ended(x);
    motion_profile_tick(0);
    unsigned ticks = 0;
    while (x->mode != M_DISABLE && ticks < 1000u) {
        supervise_moving(x);
        ticks++;
    }
    assert_int_equal(x->mode, M_DISABLE);
    assert_true(x->ustat & UB(FERR_F));
    assert_int_equal(ticks, STOP_SETTLE_TICKS + 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(profile_first_then_supervision),
        cmocka_unit_test(supervision_first),
        cmocka_unit_test(the_bound_ends_a_stop_that_never_rests),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
