/* Calibration eqs 1-2 of the source; see calibration.h. */
#include "calibration.h"

#include <math.h>

#define DEG 0.017453292519943295f
/* Nominal at the reference ranges: 8192 LSB/g, 65.5 LSB/(deg/s). */
#define KA (8192.0f / CALIB_G0)
#define KG (65.5f / DEG)

#ifndef CLINO_CALIB_SIM
const clino_calib_matrices_t CLINO_CALIB = {
    .K = {{KA, 0, 0}, {0, KA, 0}, {0, 0, KA}},
    .Ua0 = {0, 0, 0},
    .R = {{KG, 0, 0}, {0, KG, 0}, {0, 0, KG}},
    .U0 = {0, 0, 0},
};
#else
/* The simulated unit of firmware/simavr (its mpu6050 model uses these). */
const clino_calib_matrices_t CLINO_CALIB = {
    .K = {{1.012f * KA, 0.004f * KA, -0.006f * KA},
          {-0.003f * KA, 0.991f * KA, 0.005f * KA},
          {0.007f * KA, -0.002f * KA, 1.004f * KA}},
    .Ua0 = {153.0f, -97.0f, 241.0f},
    .R = {{0.985f * KG, 0.006f * KG, 0.002f * KG},
          {-0.004f * KG, 1.013f * KG, -0.007f * KG},
          {0.003f * KG, 0.005f * KG, 0.996f * KG}},
    .U0 = {-41.0f, 27.0f, 12.0f},
};
#endif

int calib_inv3(const float m[3][3], float o[3][3])
{
    float c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    float c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    float c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    float det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    float scale = fabsf(m[0][0]) + fabsf(m[1][1]) + fabsf(m[2][2]);
    if (!(fabsf(det) > 1e-9f * scale * scale * scale))
        return -1;
    float id = 1.0f / det;
    o[0][0] = c00 * id;
    o[1][0] = c01 * id;
    o[2][0] = c02 * id;
    o[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
    o[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
    o[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
    o[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
    o[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
    o[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
    return 0;
}

float mpu_accel_lsb_per_g(uint8_t fs_g)
{
    switch (fs_g) {
    case 2:
        return 16384.0f;
    case 4:
        return 8192.0f;
    case 8:
        return 4096.0f;
    default:
        return 2048.0f;
    }
}

float mpu_gyro_lsb_per_dps(uint16_t fs_dps)
{
    switch (fs_dps) {
    case 250:
        return 131.0f;
    case 500:
        return 65.5f;
    case 1000:
        return 32.8f;
    default:
        return 16.4f;
    }
}

int calib_init(clino_calib_t *c, const clino_calib_matrices_t *m)
{
    if (calib_inv3(m->K, c->Kinv) != 0 || calib_inv3(m->R, c->Rinv) != 0)
        return -1;
    for (int i = 0; i < 3; i++) {
        c->Ua0[i] = m->Ua0[i];
        c->U0[i] = m->U0[i];
    }
    calib_set_ranges(c, CALIB_ACCEL_FS_G, CALIB_GYRO_FS_DPS);
    return 0;
}

void calib_set_ranges(clino_calib_t *c, uint8_t accel_fs_g, uint16_t gyro_fs_dps)
{
    c->acc_scale = mpu_accel_lsb_per_g(CALIB_ACCEL_FS_G) / mpu_accel_lsb_per_g(accel_fs_g);
    c->gyr_scale = mpu_gyro_lsb_per_dps(CALIB_GYRO_FS_DPS) / mpu_gyro_lsb_per_dps(gyro_fs_dps);
}

static void apply(const float M[3][3], const float off[3], float s, const float u[3],
                  float out[3])
{
    float d0 = u[0] * s - off[0];
    float d1 = u[1] * s - off[1];
    float d2 = u[2] * s - off[2];
    for (int i = 0; i < 3; i++)
        out[i] = M[i][0] * d0 + M[i][1] * d1 + M[i][2] * d2;
}

void calib_acc(const clino_calib_t *c, const float u[3], float out[3])
{
    apply(c->Kinv, c->Ua0, c->acc_scale, u, out);
}

void calib_gyr(const clino_calib_t *c, const float u[3], float out[3])
{
    apply(c->Rinv, c->U0, c->gyr_scale, u, out);
}
