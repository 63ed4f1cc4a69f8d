/*
 * The source instrument's attitude algorithm, in plain C (float, C99):
 * strapdown direction-cosine matrix from the Poisson equation integrated by
 * left rectangles, corrected by the complementary filter
 *     C_out = (1 - k) * C + k * C_a,   k = 0.05
 * (Sapegin & Strokach, "Micromechanical inclinometer", eqs 3-5).
 *
 * Conventions (clino's DESIGN.md): C rotates body vectors into the navigation
 * frame (ENU, z up), v_n = C v_b; C = Rz(yaw) Ry(pitch) Rx(roll) (aerospace
 * z-y-x); accelerometers read specific force, (0, 0, +g) level at rest.
 * The paper writes dC^SP/dt = -Omega C^SP for the nav-to-body matrix; for its
 * transpose C this is dC/dt = C [w x], and left rectangles give
 *     C_{i+1} = C_i (I + [w_i x] h).
 * C_a is the matrix whose roll and pitch come from the accelerometers and
 * whose yaw is that of C (accelerometers say nothing about yaw):
 * roll_a = atan2(f_y, f_z), pitch_a = atan2(-f_x, sqrt(f_y^2 + f_z^2)).
 * After the blend, C is re-orthonormalised (rows 1, 2 symmetric, row 3 their
 * cross product) so that it stays a rotation.
 *
 * No trigonometric call is needed per update except in filter_angles(): C_a is
 * built from the unit specific-force vector and the yaw column of C directly.
 */
#ifndef CLINO_FILTER_H
#define CLINO_FILTER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The source's gain (chosen there as the best trade between the sensors). */
#define FILTER_K_SOURCE 0.05f

typedef struct {
    float C[3][3]; /* body -> navigation DCM */
    float k;       /* complementary gain, 0 = gyro only, 1 = accelerometer only */
    uint8_t aligned;
    uint16_t skipped; /* updates whose accelerometer vector was unusable */
} clino_filter_t;

void filter_init(clino_filter_t *f, float k);
/*
 * Initial alignment from one accelerometer vector (m/s^2): roll and pitch
 * from gravity, yaw 0. Returns 0, or -1 if the vector is too short to level on
 * (|f| < 1 m/s^2); the filter then stays unaligned.
 */
int filter_align(clino_filter_t *f, const float acc[3]);
/*
 * One update with body rate gyr (rad/s) and specific force acc (m/s^2)
 * over step h (s). Aligns on the first call if not aligned yet.
 */
void filter_update(clino_filter_t *f, const float gyr[3], const float acc[3], float h);
/*
 * The instrument steps its filter at no more than FILTER_MAX_HZ: at a sample
 * rate of 200 Hz or more it averages n = rate / 100 samples (the mean rate over
 * the step is the rectangle rule's best single value) and steps with
 * h = n / rate, so k = 0.05 keeps the source's meaning (the accelerometer
 * weight per 10 ms, time constant h / k = 0.2 s) whatever the stream's rate.
 * Samples n*j .. n*j + n - 1 (by seq) form one step.
 */
#define FILTER_MAX_HZ 100u
static inline uint8_t filter_decimation(uint16_t rate_hz)
{
    return rate_hz >= 2u * FILTER_MAX_HZ ? (uint8_t)(rate_hz / FILTER_MAX_HZ) : 1u;
}

/* Aerospace roll and pitch (rad) of the current C. */
void filter_angles(const clino_filter_t *f, float *roll, float *pitch);

#ifdef __cplusplus
}
#endif

#endif
