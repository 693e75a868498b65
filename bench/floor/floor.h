/*
 * floor.h - the memory of the floor routines (bench/floor/README.md): where
 * build/floor/floorrun-CARD puts a routine's inputs and finds its outputs,
 * and the offsets the routines address them by.  Included by the routines
 * (.S, through cpp) and by the runner (C); never by the firmware.
 *
 * The map is the card's (hal/mac4_map.h): a routine runs from the EPROM
 * (1 wait state per fetch), its data in the SRAM (0), the vector of level 6
 * in the DPRAM (1), the axis registers on the axis board (3), the encoders
 * on the VMEbus (12): the firmware's regions, under the same bus model.
 * The layout inside the SRAM is the routines' own: each axis one record,
 * the fields the tick reads and writes, a 16-bit displacement apart.  The
 * values in it are the firmware's (card.h axis_t, servo.h servo_gains_t and
 * servo_state_t, measure.h meas_cfg_t); the few a routine takes derived
 * beyond what the firmware derives are marked "floor" and computed by the
 * runner where the firmware's main loop would (once per E or INIT).
 */
#ifndef FLOOR_H
#define FLOOR_H
#include "mac4_map.h"

#define FLOOR_CODE      EPROM_BASE                  /* the routine, entered from the vector */
#define FLOOR_IDLE      (EPROM_BASE + 0xFF00)       /* bra.s * : where the CPU waits for the interrupt */
#define FLOOR_CARD      (SRAM_BASE + 0x0100)        /* the card's words (CD_*) */
#define FLOOR_AX0       (SRAM_BASE + 0x0200)        /* axis n at FLOOR_AX0 + n * FLOOR_AX_SIZE */
#define FLOOR_AX_SIZE   0x100
#define FLOOR_AX(n)     (FLOOR_AX0 + (n) * FLOOR_AX_SIZE)
#define FLOOR_STACK_TOP (SRAM_BASE + SRAM_SIZE)     /* the supervisor stack, as the firmware's */

/* ---- the card (FLOOR_CARD + ...) ---------------------------------------- */
#define CD_TICKS        0x00    /* l  card_ticks */
#define CD_LATE         0x04    /* w  card_profile_late */
#define CD_DUE          0x06    /* b  card_profile_due */
#define CD_GENERAL      0x07    /* b  card_servo_general (INC/SSI) */
#define CD_STPCONV      0x08    /* b  stp_conv (STP): bit n, axis n counts increments */
/* the supervision's (card_supervise_tick) */
#define CD_ESTOP        0x09    /* b  estop_seen */
#define CD_EXTON        0x0A    /* b  ext_on (the extensions, ext.h) */
#define CD_VIRQWAIT     0x0B    /* b  vme_irq_waiting */
#define CD_SUPLATE      0x0C    /* w  card_supervise_late */
#define CD_SUPERVISED   0x10    /* l  card_supervised */
#define CD_OSTAT        0x14    /* l  card_ostat */
#define CD_VIRQLOST     0x18    /* l  virq_lost */
#define CD_NCMD         0x1C    /* l  cmd.c n_commands      (cmd_publish's, in this order) */
#define CD_RSPLOST      0x20    /* l  cmd.c n_rsp_lost */
#define CD_QERR         0x24    /* l  cmd.c n_queue_errors */
#define CD_SERSTATS     0x28    /* 8 l serial.c stats[] (serial_publish's) */
/* the command path's (cmd.c cmd_poll) */
#define CD_SERWORK      0x48    /* b  serial_rx_work */
#define CD_FIFOCNT      0x49    /* b  serial_fifo_count */
#define CD_WDFIRED      0x4A    /* b  wd_fired */
#define CD_MR           0x4B    /* b  cmd_mr */
#define CD_NHELD        0x4C    /* b  n_held */
#define CD_QBAD         0x4E    /* b  queue_bad */
#define CD_LASTAX       0x4F    /* b  last_valid_axis */
#define CD_IRQ12        0x50    /* b  irq12 */
#define CD_VQDUE        0x51    /* b  motion_vq_due */
#define CD_NCODES       0x52    /* w  the command table's length */
#define CD_WD           0x54    /* l  PAR(0, WD) */
#define CD_CIROUT       0x58    /* b  the command index CI_ROUT (cmd.h) */
#define FLOOR_CMDTAB    (SRAM_BASE + 0x0800)    /* cmd.c cmds[]: kind, arg per code (CK_FIELD: the
                                                 * record's offset, floor) */

/* ---- an INC/SSI axis (FLOOR_AX(n) + ...) ---------------------------------- */
#define SV_USTAT        0x00    /* l  ustat */
#define SV_MK           0x04    /* b  mk_tick */
#define SV_MODE         0x05    /* b  mode */
#define SV_BRAKING      0x06    /* b  braking */
#define SV_NXREADY      0x07    /* b  nx_ready */
#define SV_LINEAR       0x08    /* b  linear */
#define SV_FULL         0x09    /* b  gains.full */
#define SV_KISC         0x0A    /* b  gains.kisc */
#define SV_SC           0x0B    /* b  meas_cfg.sc */
#define SV_OUT          0x0C    /* w  out */
#define SV_DA           0x0E    /* w  PAR(n, DA) (test mode, 5.13) */
#define SV_RAW          0x10    /* l  raw        (raw .. pos in this order: MOVEM) */
#define SV_COUNTER      0x14    /* l  counter */
#define SV_MEAS         0x18    /* l  meas */
#define SV_POS          0x1C    /* l  pos */
#define SV_CR           0x20    /* l  cr */
#define SV_SPNOW        0x24    /* l  sp_now (an address of SV_ROWS) */
#define SV_SPNEXT       0x28    /* l  sp_next */
#define SV_SPVEL        0x2C    /* l  sp_vel */
#define SV_SPVELNX      0x30    /* l  sp_vel_next */
#define SV_BRPOSH       0x34    /* 8  br_posh, int64 big-endian (bits 16-47 at +2) */
#define SV_BRV          0x3C    /* l  br_v */
#define SV_BRDEC        0x40    /* l  br_dec */
/* servo_gains_t */
#define SV_GA           0x44    /* w  ga */
#define SV_ZE           0x46    /* w  ze */
#define SV_PO           0x48    /* w  po */
#define SV_KI           0x4A    /* w  ki */
#define SV_GZH          0x4C    /* w  gzh */
#define SV_GZL          0x4E    /* w  gzl */
#define SV_KIMASK       0x50    /* w  ki_mask */
#define SV_OUTHI        0x52    /* w  out_hi */
#define SV_OUTLO        0x54    /* w  out_lo */
#define SV_ELIM         0x56    /* w  e_lim */
#define SV_U2HI         0x58    /* l  u2_hi */
#define SV_U2LO         0x5C    /* l  u2_lo */
#define SV_ELIML        0x60    /* l  floor: e_lim as a long */
#define SV_ELIM2        0x64    /* l  floor: 2 e_lim */
/* servo_state_t */
#define SV_U1           0x68    /* l  u1 */
#define SV_U2           0x6C    /* l  u2 */
#define SV_U2RES        0x70    /* l  u2_res */
#define SV_EPREV        0x74    /* w  e_prev */
/* the rest of axis_t the encoder error touches (measure_encoder_error) */
#define SV_CTRL         0x76    /* w  ctrl */
#define SV_ERR          0x78    /* w  err_report */
#define SV_STOPTHEN     0x7A    /* b  stop_then */
#define SV_STOPSETTLE   0x7B    /* b  stop_settle */
#define SV_NEXTMODE     0x7C    /* b  next_mode */
/* meas_cfg_t */
#define SV_PATH         0x7D    /* b  path */
#define SV_ABS          0x7E    /* b  abs */
#define SV_FAILED       0x7F    /* b  failed */
#define SV_MASK         0x80    /* l  mask */
#define SV_LIM          0x84    /* l  lim */
#define SV_RANGE        0x88    /* l  range */
#define SV_HALF         0x8C    /* l  half */
#define SV_SIGN         0x90    /* l  sign */
#define SV_EADDR        0x94    /* l  addr: the window address of the MSW */
#define SV_PAGE         0x98    /* w  page */
#define SV_DKIND        0x9A    /* b  floor: measure_delta's case, from abs and linear
                                 *    (INIT): 0 absolute linear, 1 absolute circular,
                                 *    2 relative */
#define SV_OUTLOL       0x9C    /* l  floor: out_lo as a long (the gains) */
#define SV_ROWS         0xA0    /* 32 sp_rows[2][PROFILE_DIVIDER] */
#define SV_OUTSPAN      0xC0    /* l  floor: out_hi - out_lo (the gains) */
/* the rest of axis_t the supervision (card_supervise_tick) reads and writes */
#define SV_SSTAT        0xC4    /* l  sstat */
#define SV_VEL          0xC8    /* l  vel */
#define SV_SETPOINT     0xCC    /* l  setpoint */
#define SV_FERR         0xD0    /* l  ferr */
#define SV_MEASSUP      0xD4    /* l  meas_sup */
#define SV_MF           0xD8    /* l  mf */
#define SV_LP           0xDC    /* l  lp */
#define SV_LN           0xE0    /* l  ln */
#define SV_IN           0xE4    /* w  in */
#define SV_SWEN         0xE6    /* w  sw_en */
#define SV_SWINV        0xE8    /* w  sw_inv */
#define SV_MKSUP        0xEA    /* b  mk (what mk_tick becomes once initialised) */
#define SV_INEVAL       0xEB    /* b  in_eval */
#define SV_IDXSEEN      0xEC    /* b  idx_seen */
#define SV_DF           0xED    /* b  PAR(n, DF): 0 off, 1 low, 2 high active */
#define SV_END          0xEE

/* ---- a MAC4-STP axis (FLOOR_AX(n) + ...): axis_t and its stp_t ---------- */
#define ST_USTAT        0x00    /* l  ustat */
#define ST_MK           0x04    /* b  mk_tick */
#define ST_MODE         0x05    /* b  mode */
#define ST_BRAKING      0x06    /* b  braking */
#define ST_NXREADY      0x07    /* b  nx_ready */
#define ST_LINEAR       0x08    /* b  linear */
#define ST_DIR          0x09    /* b  stp dir (-1, 0, 1) */
#define ST_CREEP        0x0A    /* b  stp creep */
#define ST_ACTIVE       0x0B    /* b  stp active */
#define ST_CTRL         0x0C    /* w  ctrl */
#define ST_OUT          0x0E    /* w  out */
#define ST_RAW          0x10    /* l  raw        (raw .. pos in this order: MOVEM) */
#define ST_COUNTER      0x14    /* l  counter */
#define ST_MEAS         0x18    /* l  meas */
#define ST_POS          0x1C    /* l  pos */
#define ST_SETPOINT     0x20    /* l  setpoint */
#define ST_FERR         0x24    /* l  ferr */
#define ST_SPI          0x28    /* l  sp_i */
#define ST_SPF          0x2C    /* w  sp_f */
#define ST_STARTI       0x30    /* l  start_i    (the segment in force: MOVEM order, */
#define ST_STI          0x34    /* l  st_i        as the next one's) */
#define ST_ENDI         0x38    /* l  end_i */
#define ST_STARTF       0x3C    /* w  start_f */
#define ST_STF          0x3E    /* w  st_f */
#define ST_ENDF         0x40    /* w  end_f */
#define ST_NXSTARTI     0x44    /* l  nx_start_i */
#define ST_NXSTI        0x48    /* l  nx_st_i */
#define ST_NXENDI       0x4C    /* l  nx_end_i */
#define ST_NXSTARTF     0x50    /* w  nx_start_f */
#define ST_NXSTF        0x52    /* w  nx_st_f */
#define ST_NXENDF       0x54    /* w  nx_end_f */
#define ST_BOOST        0x56    /* b  stp boost */
#define ST_BOOSTEN      0x57    /* b  stp boost_en */
#define ST_BRPOSH       0x58    /* 8  br_posh */
#define ST_BRV          0x60    /* l  br_v */
#define ST_BRDEC        0x64    /* l  br_dec */
#define ST_BRSSF        0x68    /* l  br_ssf */
#define ST_CR           0x6C    /* l  cr */
#define ST_PROFVEL      0x70    /* 8  prof.vel */
#define ST_INC          0x78    /* l  stp inc */
#define ST_CONV         0x7C    /* l  stp conv */
#define ST_RATIO        0xB8    /* l  stp ratio */
#define ST_RATE         0x80    /* w  stp rate */
#define ST_OBITS        0x82    /* w  stp obits */
#define ST_CLOCKS       0x84    /* w  stp clocks */
#define ST_LVRATE       0x86    /* w  stp lv_rate */
#define ST_LIM          0x88    /* l  stp lim */
#define ST_CARRY        0x8C    /* l  stp carry */
#define ST_DA           0x90    /* l  PAR(n, DA): Hz in test mode (5.13) */
#define ST_ERR          0x94    /* w  err_report */
#define ST_STOPTHEN     0x96    /* b  stop_then */
#define ST_STOPSETTLE   0x97    /* b  stop_settle */
#define ST_NEXTMODE     0x98    /* b  next_mode */
#define ST_PATH         0x99    /* b  meas_cfg: path */
#define ST_ABS          0x9A    /* b  abs */
#define ST_FAILED       0x9B    /* b  failed */
#define ST_MASK         0x9C    /* l  mask */
#define ST_MLIM         0xA0    /* l  lim */
#define ST_RANGE        0xA4    /* l  range */
#define ST_HALF         0xA8    /* l  half */
#define ST_SIGN         0xAC    /* l  sign */
#define ST_EADDR        0xB0    /* l  addr */
#define ST_PAGE         0xB4    /* w  page */
#define ST_DKIND        0xB6    /* b  floor: measure_delta's case (as SV_DKIND) */
/* the creep phase (stp_rate.c creep_tick, creep_begin, creep_stop; motion_hold) */
#define ST_TARGET       0xBC    /* 8  target (Q16; bits 16-47 at +2) */
#define ST_CREEPBASE    0xC4    /* l  stp creep_base */
#define ST_CREEPN       0xC8    /* w  stp creep_n */
#define ST_COUNTED      0xCA    /* w  stp counted */
#define ST_HWDONE       0xCC    /* b  stp hw_done */
#define ST_CREEPDIR     0xCD    /* b  stp creep_dir */
#define ST_CREEPIRQ     0xCE    /* b  stp creep_irq */
#define ST_MKSUP        0xCF    /* b  mk */
#define ST_IN           0xD0    /* w  in (the supervision's last AX_IN) */
#define ST_PROFPOS      0xD4    /* 8  prof.pos */
/* the rest of axis_t the supervision (card_supervise_tick) reads and writes */
#define ST_SSTAT        0xDC    /* l  sstat */
#define ST_VEL          0xE0    /* l  vel */
#define ST_MEASSUP      0xE4    /* l  meas_sup */
#define ST_MF           0xE8    /* l  mf */
#define ST_LP           0xEC    /* l  lp */
#define ST_LN           0xF0    /* l  ln */
#define ST_SWEN         0xF4    /* w  sw_en */
#define ST_SWINV        0xF6    /* w  sw_inv */
#define ST_INEVAL       0xF8    /* b  in_eval */
#define ST_IDXSEEN      0xF9    /* b  idx_seen */
#define ST_DF           0xFA    /* b  PAR(n, DF) */
#define ST_END          0xFB

/* ---- the firmware's constants the routines need, as numbers (the C
 * runner asserts each against its definition: ref_servo.c) ------------- */
#define FL_M_DISABLE    0       /* status.def MODE(DISABLE) */
#define FL_M_TEST       10
#define FL_MK_COUNTER   0       /* card.h MK_* */
#define FL_MK_OTHER     1
#define FL_MK_NONE      2
#define FL_MK_SSI       3
#define FL_MK_SSI_ABS   4
#define FL_EXT_VME32    3       /* measure.h EXT_* */
#define FL_NO_MODE      0xFF
#define FL_US_DR_EN     8       /* status.def USTAT bit numbers */
#define FL_US_REV_O     9
#define FL_US_LOGO_F    15
#define FL_US_ENCODER_F 16
#define FL_US_GRAY      27
#define FL_ERR_LOGICAL  163     /* commands.def ERROR(163, LOGICAL) */
#define FL_U1_MAX       0x7FFFFF    /* servo.h SERVO_U1_MAX */
#define FL_OUT_MAX      2047
#define FL_OUT_MIN      (-2048)
#define FL_M_POSITIONING 8
#define FL_CREEP_IDLE   0       /* stp_card.h CREEP_* */
#define FL_CREEP_REQ    1
#define FL_CREEP_WAIT   2
#define FL_CREEP_RUN    3
#define FL_CREEP_DONE   4
#define FL_CREEP_TRIM   5
#define FL_PULSE_IRQ_MAX_RATE 1311      /* stp_rate.c PULSE_IRQ_MAX_RATE, _TURBO */
#define FL_PULSE_IRQ_MAX_RATE_TURBO 131
#define FL_STP_TICK_CLOCKS 400          /* stepper.h STP_TICK_CLOCKS, _TURBO */
#define FL_STP_TICK_CLOCKS_TURBO 4000
#define FL_TRIM_MAX     3       /* stp_rate.c TRIM_MAX */
#define FL_M_SEARCH_IDX_C 2
#define FL_M_HOME       4
#define FL_US_POS_END   10
#define FL_US_INIT      12
#define FL_US_DR_F      17
#define FL_US_HWL_N     19
#define FL_US_HWL_P     20
#define FL_US_SWL_N     21
#define FL_US_SWL_P     22
#define FL_US_REF       23
#define FL_US_ERRORS    ((1 << 13) + (1 << 14) + (1 << 15) + (1 << 16) + (1 << 17) + (1 << 18))   /* status.h US_ERRORS */
#define FL_OS_FCODE0    3       /* status.def OSTAT(FCODE0) */
#define FL_CK_READ      4       /* cmd_table.h CK_*: kind >= CK_READ is a read */
#define FL_CK_DIAG      6
#define FL_CK_FIELD     7
#define FL_STP_OBITS    (AX_CTRL_DIR + AX_CTRL_BOOST + AX_CTRL_TURBO)   /* stepper.h STP_OBITS */

#endif
