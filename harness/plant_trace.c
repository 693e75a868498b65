/*
 * plant_trace.c - what the plant shows: the step counts of the STP, the
 * trace file (a CSV row per interval or per timer expiry) and the one-line
 * summary of `plant N` (docs/host-script.md, "Plant").
 */
#include <string.h>
#include "plant_int.h"

void plant_step_counts(sim_t *s, int n, int64_t *generated, int64_t *lost)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    *generated = p->gen;
    *lost = p->gen - p->lost_base - iround(stp_rotor(p, now));
}

static const char *const trace_hdr_servo = "t_ms,dac,volts,en,position,velocity,motor_rpm,counter";
static const char *const trace_hdr_stp = "t_ms,rate,field_hz,en,generated,rotor,rotor_hz,lost,sync,counter";
/* the axis data the card publishes (hal/mac4_map.h DPA_*), as a host reads it */
static const char *const trace_hdr_card = ",card_pos,setpoint,ferr,out,ustat";

void plant_trace_row(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    double ms = (double)t / 16000.0;
    uint32_t cnt = is_ssi(s) ? plant_ssi_value(s, n, t) : axb_counter_at(s, n, t);
    if (is_stp(s)) {
        double rot = stp_rotor(p, t);
        fprintf(p->trace, "%.3f,%u,%.3f,%d,%lld,%.3f,%.3f,%lld,%d,%u", ms, axb_rate(s, n),
                axb_step_hz(s, n), plant_drive_enabled(s, n), (long long)p->gen, rot,
                p->sync ? (plant_drive_enabled(s, n) ? axb_step_hz(s, n) : 0.0) : lerp_v(p, t),
                (long long)(p->gen - p->lost_base - iround(rot)), p->sync, cnt);
    } else {
        fprintf(p->trace, "%.3f,%d,%.4f,%d,%.3f,%.3f,%.2f,%u", ms, axb_dac(s, n), axb_dac_volts(s, n),
                plant_drive_enabled(s, n), plant_units(s, n, t), plant_units_per_s(s, n, t),
                plant_motor_rpm(s, n, t), cnt);
    }
    if (p->trace_card) {
        uint32_t d = DP_AXIS_DATA((uint32_t)n);
        fprintf(p->trace, ",%d,%d,%d,%d,0x%08X", (int32_t)dp_rd32(s, d + DPA_POS),
                (int32_t)dp_rd32(s, d + DPA_SETPOINT), (int32_t)dp_rd32(s, d + DPA_FERR),
                (int32_t)dp_rd32(s, d + DPA_OUT), dp_rd32(s, d + DPA_USTAT));
    }
    fputc('\n', p->trace);
}

int plant_trace_start_ex(sim_t *s, int n, const char *path, cyc_t iv, int tick, int card)
{
    plant_axis_t *p = &s->plant.ax[n];
    plant_trace_stop(s, n);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    p->trace = f;
    p->trace_iv = iv ? iv : 1;
    p->trace_next = now;
    p->trace_tick = tick;
    p->trace_card = card;
    p->trace_tick_seen = s->tmr.last;   /* from the next expiry on */
    fputs(is_stp(s) ? trace_hdr_stp : trace_hdr_servo, f);
    fputs(card ? trace_hdr_card : "", f);
    fputc('\n', f);
    return 0;
}

int plant_trace_start(sim_t *s, int n, const char *path, cyc_t iv)
{
    return plant_trace_start_ex(s, n, path, iv, 0, 0);
}

void plant_trace_stop(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->trace)
        fclose(p->trace);
    p->trace = NULL;
}

void plant_format(sim_t *s, int n, char *buf, size_t len)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    uint16_t in = plant_inputs_word(s, n, now);   /* syncs */
    double u = plant_units(s, n, now);
    const char *unit = is_stp(s) ? "steps" : is_ssi(s) ? "counts" : "inc";
    int sw[PLANT_NSW];
    for (int w = 0; w < PLANT_NSW; w++)
        sw[w] = plant_switch_active(s, n, w, now);
    if (is_stp(s)) {
        int64_t made = iround(u);
        snprintf(buf, len,
                "plant %d pos=%lld %s rev=%.4f vel=%.1f steps/s rate=%u field=%.3fHz en=%d "
                "generated=%lld lost=%lld sync=%d counter=0x%06X "
                "lp=%d ln=%d ref=%d df=%d in=0x%04X",
                n, (long long)made, unit, plant_out_rev(s, n, now), plant_units_per_s(s, n, now),
                axb_rate(s, n), axb_step_hz(s, n), plant_drive_enabled(s, n), (long long)p->gen,
                (long long)(p->gen - p->lost_base - made), p->sync, axb_counter_at(s, n, now), sw[0],
                sw[1], sw[2], p->drive_fault, in);
    } else {
        snprintf(buf, len,
                "plant %d pos=%lld %s rev=%.4f vel=%.1f %s/s rpm=%.1f dac=%d volts=%.3f en=%d "
                "%s=0x%06X lp=%d ln=%d ref=%d df=%d in=0x%04X",
                n, (long long)ifloor(u + 0.5), unit, plant_out_rev(s, n, now), plant_units_per_s(s, n, now),
                unit, plant_motor_rpm(s, n, now), axb_dac(s, n), axb_dac_volts(s, n), plant_drive_enabled(s, n),
                is_ssi(s) ? "ssi" : "counter",
                is_ssi(s) ? plant_ssi_value(s, n, now) : axb_counter_at(s, n, now), sw[0], sw[1], sw[2],
                p->drive_fault, in);
    }
    if (p->lead_amp != 0.0 || p->lead_ppm != 0.0) {   /* a leadscrew with an error: where the load is */
        size_t used = strlen(buf);
        if (used < len)
            snprintf(buf + used, len - used, " load=%.3f", u + plant_lead_error(p, u));
    }
}
