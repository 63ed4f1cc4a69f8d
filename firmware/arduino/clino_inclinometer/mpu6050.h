/*
 * MPU6050 on the ATmega328P's TWI at 400 kHz, with the project's own
 * interrupt-driven TWI driver: a burst read is started from the sample-clock
 * interrupt and completes in the TWI interrupt, so the sample instant does
 * not depend on what the main loop is doing (the Arduino Wire library blocks
 * the caller for the whole transfer and cannot be used from an interrupt).
 */
#ifndef CLINO_MPU6050_H
#define CLINO_MPU6050_H

#include <stdint.h>

#define MPU_ADDR 0x68u
#define MPU_REG_SMPLRT_DIV 0x19u
#define MPU_REG_CONFIG 0x1Au
#define MPU_REG_GYRO_CONFIG 0x1Bu
#define MPU_REG_ACCEL_CONFIG 0x1Cu
#define MPU_REG_ACCEL_XOUT_H 0x3Bu /* 14 bytes: accel xyz, temp, gyro xyz */
#define MPU_REG_PWR_MGMT_1 0x6Bu
#define MPU_REG_WHO_AM_I 0x75u
#define MPU_WHO_AM_I 0x68u
#define MPU_BURST_LEN 14u

/* TWI at 400 kHz (TWBR = 12, prescaler 1 at 16 MHz). */
void twi_init(void);
/* Blocking register access (set-up only); return 0 or -1 on NACK/timeout. */
int twi_write_reg(uint8_t reg, uint8_t value);
int twi_read_regs(uint8_t reg, uint8_t *buf, uint8_t n);
/*
 * Start a burst read of n bytes from reg into buf without waiting; done(ok)
 * is called from the TWI interrupt when it ends. Returns -1 if busy.
 */
int twi_start_read(uint8_t reg, uint8_t *buf, uint8_t n, void (*done)(uint8_t ok));
uint8_t twi_busy(void);
/* Abandon a transfer that never ends (a slave holding the bus): reset the unit. */
void twi_abort(void);

typedef struct {
    uint8_t accel_fs_g;   /* 2, 4, 8, 16 */
    uint16_t gyro_fs_dps; /* 250, 500, 1000, 2000 */
    uint8_t dlpf_cfg;     /* 0..6 */
} mpu_ranges_t;

/* 1 if the values are ones the chip has. */
uint8_t mpu_ranges_valid(const mpu_ranges_t *r);
/*
 * Wake the chip (PLL on the X gyro), check WHO_AM_I, set sample-rate divider 0
 * (the chip samples at its full rate; the board polls the freshest sample),
 * DLPF and ranges, and read them back. 0 on success, -1 on any failure.
 */
int mpu_init(const mpu_ranges_t *r);
int mpu_set_ranges(const mpu_ranges_t *r);
/* Big-endian burst (ACCEL_XOUT_H..GYRO_ZOUT_L) to seven counts. */
void mpu_unpack(const uint8_t *burst, int16_t out[7]);

#endif
