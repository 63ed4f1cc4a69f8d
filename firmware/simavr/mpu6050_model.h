/*
 * A simulated MPU6050 on simavr's TWI bus, played from a scripted motion.
 *
 * Registers: the firmware's writes are kept (SMPLRT_DIV, CONFIG, GYRO_CONFIG,
 * ACCEL_CONFIG, PWR_MGMT_1, with the reset bit honoured), WHO_AM_I reads
 * 0x68, the register pointer auto-increments. A read that starts at
 * ACCEL_XOUT_H (0x3B) latches one sample of the motion at that simulated
 * instant into 0x3B..0x48 (big-endian), the way the chip shadows its data
 * registers during a burst; each latched sample is recorded as "played".
 * While PWR_MGMT_1.SLEEP is set the data registers read zero.
 *
 * The sensor: counts = (K f + U_a0) * LSB(range)/LSB(reference range) for the
 * accelerometers and (R w + U0) * ... for the gyros, with K, U_a0, R, U0 the
 * simulated unit's calibration (calibration.c built with CLINO_CALIB_SIM),
 * plus a deterministic uniform noise of +-2 counts; the temperature is
 * 24 degC + 0.5 sin(t / 10 s). The DLPF is not modelled (latched values are
 * the instantaneous motion).
 */
#ifndef CLINO_MPU6050_MODEL_H
#define CLINO_MPU6050_MODEL_H

#include <stdint.h>
#include <stdio.h>

#include "sim_avr.h"
#include "sim_irq.h"

typedef struct {
    double roll, pitch;   /* rad */
    double droll, dpitch; /* rad/s */
} motion_t;

/* The scripted motion: level, ramp, hold, sway, ramp, hold (see .c). */
motion_t motion_at(double t);

typedef struct {
    uint64_t cycle; /* simulated cycle of the latch */
    double t;       /* s */
    int16_t raw[7]; /* ax ay az temp gx gy gz */
    double roll, pitch; /* truth, rad */
} played_t;

typedef struct {
    avr_t *avr;
    avr_irq_t *irq; /* [TWI_IRQ_INPUT], [TWI_IRQ_OUTPUT] on our side */
    uint8_t reg[128];
    uint8_t ptr;
    uint8_t selected;  /* SLA byte when addressed, else 0 */
    uint8_t want_ptr;  /* next written byte is the register pointer */
    uint32_t rng;
    played_t *played;
    size_t nplayed, capplayed;
    uint32_t writes, reads, naks;
    int absent; /* 1: nobody answers at 0x68 (the sensor unplugged) */
} mpu_model_t;

void mpu_model_init(mpu_model_t *m, avr_t *avr);
int mpu_model_accel_fs(const mpu_model_t *m); /* g */
/* Unplug (present 0: nobody answers) or plug back in (present 1: the chip
 * powers up again, registers at their reset values, asleep). */
void mpu_model_set_present(mpu_model_t *m, int present);
int mpu_model_gyro_fs(const mpu_model_t *m);  /* deg/s */

#endif
