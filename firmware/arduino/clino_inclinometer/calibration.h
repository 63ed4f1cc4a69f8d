/*
 * The source instrument's sensor calibration (Sapegin & Strokach,
 * "Micromechanical inclinometer", eqs 1-2):
 *     A = K^-1 (U_a - U_a0)      accelerometers, m/s^2
 *     W = R^-1 (U - U0)          gyroscopes, rad/s
 * K (counts per m/s^2) and R (counts per rad/s) are 3x3 scale-factor and
 * misalignment matrices, U_a0 and U0 the zero offsets (counts). They are
 * given at the calibration's reference ranges CALIB_ACCEL_FS_G and
 * CALIB_GYRO_FS_DPS; at another range the raw counts are first brought to the
 * reference range by the ratio of the datasheet sensitivities.
 *
 * The paper's own matrices did not survive its text, so two sets are built in:
 *  - default: the MPU6050 datasheet's nominal sensitivities, zero offsets,
 *    no misalignment: replace them by your unit's (e.g. from a six-position
 *    test and a rate table, or `clino calibrate`) in calibration.c;
 *  - CLINO_CALIB_SIM: the simulated sensor the simavr harness plays (offsets,
 *    scale errors and cross-axis terms), so the harness checks that the
 *    firmware applies eqs 1-2 and not just the nominal scale.
 */
#ifndef CLINO_CALIBRATION_H
#define CLINO_CALIBRATION_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CALIB_ACCEL_FS_G 4u
#define CALIB_GYRO_FS_DPS 500u
#define CALIB_G0 9.80665f

typedef struct {
    float K[3][3];  /* counts per m/s^2 */
    float Ua0[3];   /* counts */
    float R[3][3];  /* counts per rad/s */
    float U0[3];    /* counts */
} clino_calib_matrices_t;

/* The built-in set (see above). */
extern const clino_calib_matrices_t CLINO_CALIB;

typedef struct {
    float Kinv[3][3], Rinv[3][3];
    float Ua0[3], U0[3];
    float acc_scale, gyr_scale; /* raw counts -> reference-range counts */
} clino_calib_t;

/* Invert K and R; returns -1 if either is singular. */
int calib_init(clino_calib_t *c, const clino_calib_matrices_t *m);
/* Set the count rescaling for the ranges in use (datasheet sensitivities). */
void calib_set_ranges(clino_calib_t *c, uint8_t accel_fs_g, uint16_t gyro_fs_dps);
/* u: raw counts (or a mean of raw counts) at the ranges in use. */
void calib_acc(const clino_calib_t *c, const float u[3], float out[3]);
void calib_gyr(const clino_calib_t *c, const float u[3], float out[3]);

/* MPU6050 datasheet sensitivities (rev 3.4): LSB per g, LSB per deg/s. */
float mpu_accel_lsb_per_g(uint8_t fs_g);
float mpu_gyro_lsb_per_dps(uint16_t fs_dps);

/* 3x3 inverse; returns -1 if |det| is tiny. */
int calib_inv3(const float m[3][3], float out[3][3]);

#ifdef __cplusplus
}
#endif

#endif
