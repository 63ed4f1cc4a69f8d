/* The source instrument's filter; see filter.h for the equations. */
#include "filter.h"

#include <math.h>
#include <string.h>

void filter_init(clino_filter_t *f, float k)
{
    memset(f, 0, sizeof *f);
    f->C[0][0] = f->C[1][1] = f->C[2][2] = 1.0f;
    f->k = k;
}

/*
 * Rz(psi) Ry(theta) Rx(phi) from the unit up-vector in body axes
 * u = (-sin theta, sin phi cos theta, cos phi cos theta) and (cos psi, sin psi).
 * Returns -1 when cos theta is too small to split u into roll and pitch.
 */
static int dcm_from_up(float out[3][3], const float u[3], float cpsi, float spsi)
{
    float ct = sqrtf(u[1] * u[1] + u[2] * u[2]);
    if (ct < 1e-3f)
        return -1;
    float st = -u[0];
    float sphi = u[1] / ct, cphi = u[2] / ct;
    out[0][0] = cpsi * ct;
    out[0][1] = cpsi * st * sphi - spsi * cphi;
    out[0][2] = cpsi * st * cphi + spsi * sphi;
    out[1][0] = spsi * ct;
    out[1][1] = spsi * st * sphi + cpsi * cphi;
    out[1][2] = spsi * st * cphi - cpsi * sphi;
    out[2][0] = -st;
    out[2][1] = u[1];
    out[2][2] = u[2];
    return 0;
}

static int unit_up(const float acc[3], float u[3])
{
    float n2 = acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2];
    if (!(n2 > 1.0f)) /* also false for NaN */
        return -1;
    float inv = 1.0f / sqrtf(n2);
    u[0] = acc[0] * inv;
    u[1] = acc[1] * inv;
    u[2] = acc[2] * inv;
    return 0;
}

int filter_align(clino_filter_t *f, const float acc[3])
{
    float u[3];
    if (unit_up(acc, u) != 0 || dcm_from_up(f->C, u, 1.0f, 0.0f) != 0)
        return -1;
    f->aligned = 1;
    return 0;
}

/* Rows 0 and 1 made orthogonal symmetrically, unit length, row 2 = r0 x r1. */
static void renormalise(float C[3][3])
{
    float e = C[0][0] * C[1][0] + C[0][1] * C[1][1] + C[0][2] * C[1][2];
    float r0[3], r1[3];
    for (int j = 0; j < 3; j++) {
        r0[j] = C[0][j] - 0.5f * e * C[1][j];
        r1[j] = C[1][j] - 0.5f * e * C[0][j];
    }
    float n0 = 1.0f / sqrtf(r0[0] * r0[0] + r0[1] * r0[1] + r0[2] * r0[2]);
    float n1 = 1.0f / sqrtf(r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2]);
    for (int j = 0; j < 3; j++) {
        C[0][j] = r0[j] * n0;
        C[1][j] = r1[j] * n1;
    }
    C[2][0] = C[0][1] * C[1][2] - C[0][2] * C[1][1];
    C[2][1] = C[0][2] * C[1][0] - C[0][0] * C[1][2];
    C[2][2] = C[0][0] * C[1][1] - C[0][1] * C[1][0];
}

void filter_update(clino_filter_t *f, const float gyr[3], const float acc[3], float h)
{
    if (!f->aligned && filter_align(f, acc) != 0) {
        f->skipped++;
        return;
    }
    /* Poisson equation, left rectangles: C <- C (I + [w x] h). */
    float wx = gyr[0] * h, wy = gyr[1] * h, wz = gyr[2] * h;
    float (*C)[3] = f->C;
    for (int i = 0; i < 3; i++) {
        float c0 = C[i][0], c1 = C[i][1], c2 = C[i][2];
        /* row i of C times (I + [w x]), [w x] = [[0,-wz,wy],[wz,0,-wx],[-wy,wx,0]] */
        C[i][0] = c0 + c1 * wz - c2 * wy;
        C[i][1] = c1 - c0 * wz + c2 * wx;
        C[i][2] = c2 + c0 * wy - c1 * wx;
    }
    /* Complementary filter, eq. 5, with C_a at the yaw of C. */
    float u[3], Ca[3][3];
    float hyaw = sqrtf(C[0][0] * C[0][0] + C[1][0] * C[1][0]);
    if (f->k > 0.0f && hyaw > 1e-3f && unit_up(acc, u) == 0 &&
        dcm_from_up(Ca, u, C[0][0] / hyaw, C[1][0] / hyaw) == 0) {
        float k = f->k, k1 = 1.0f - f->k;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                C[i][j] = k1 * C[i][j] + k * Ca[i][j];
    } else if (f->k > 0.0f) {
        f->skipped++;
    }
    renormalise(C);
}

void filter_angles(const clino_filter_t *f, float *roll, float *pitch)
{
    const float (*C)[3] = f->C;
    *roll = atan2f(C[2][1], C[2][2]);
    *pitch = atan2f(-C[2][0], sqrtf(C[2][1] * C[2][1] + C[2][2] * C[2][2]));
}
