/*
 * Host unit test of the instrument's filter.c and calibration.c against
 * closed forms:
 *  - alignment: roll and pitch of the specific force g(-sin p, sin r cos p,
 *    cos r cos p) come back exactly;
 *  - Poisson rectangles, gyro only (k = 0): a constant rate w about x for T
 *    gives roll = n * atan(w h) (each step is I + [w x] h re-orthonormalised,
 *    a rotation by atan(w h)), i.e. w T to O((w h)^3);
 *  - complementary filter eq 5: after a step change of the accelerometer
 *    tilt the error decays by (1 - k) per step (small angles), and a gyro
 *    bias b gives the steady error e = (1 - k) b h / k;
 *  - calibration eqs 1-2: counts made with K, U_a0, R, U0 come back as the
 *    physical vector; a range change rescales by the datasheet ratio.
 */
#include <math.h>
#include <stdio.h>

#include "calibration.h"
#include "filter.h"

static int fails, checks;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        checks++;                                                                                  \
        if (!(cond)) {                                                                             \
            fails++;                                                                               \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);                                            \
        } else {                                                                                   \
            printf("ok   ");                                                                       \
        }                                                                                          \
        printf(__VA_ARGS__);                                                                       \
        printf("\n");                                                                              \
    } while (0)

#define DEG (3.14159265358979323846 / 180.0)
#define G0 9.80665

static void up(double r, double p, float f[3])
{
    f[0] = (float)(-G0 * sin(p));
    f[1] = (float)(G0 * sin(r) * cos(p));
    f[2] = (float)(G0 * cos(r) * cos(p));
}

static void test_align(void)
{
    const double cases[][2] = {{0, 0}, {30, -15}, {-20, 25}, {170, 10}, {-45, -80}};
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        clino_filter_t f;
        filter_init(&f, FILTER_K_SOURCE);
        float a[3], r, p;
        up(cases[i][0] * DEG, cases[i][1] * DEG, a);
        CHECK(filter_align(&f, a) == 0, "align at roll %.0f pitch %.0f", cases[i][0],
              cases[i][1]);
        filter_angles(&f, &r, &p);
        CHECK(fabs(r / DEG - cases[i][0]) < 1e-4 && fabs(p / DEG - cases[i][1]) < 1e-4,
              "  angles back: %.6f %.6f", r / DEG, p / DEG);
    }
    clino_filter_t f;
    filter_init(&f, FILTER_K_SOURCE);
    float zero[3] = {0, 0, 0.5f};
    CHECK(filter_align(&f, zero) != 0 && !f.aligned, "no alignment on |f| < 1 m/s^2");
    float nan3[3] = {NAN, 0, 9.8f};
    CHECK(filter_align(&f, nan3) != 0, "no alignment on NaN");
}

static void test_gyro_only(void)
{
    clino_filter_t f;
    filter_init(&f, 0.0f);
    float a[3], g[3] = {0.5f, 0, 0}, r, p;
    up(0, 0, a);
    filter_align(&f, a);
    const float h = 0.01f;
    const int n = 200; /* 2 s at 0.5 rad/s = 1 rad */
    for (int i = 0; i < n; i++)
        filter_update(&f, g, a, h);
    filter_angles(&f, &r, &p);
    double want = n * atan(0.5 * 0.01);
    CHECK(fabs(r - want) < 2e-5 && fabs(p) < 1e-5,
          "gyro only, 0.5 rad/s about x for 2 s: roll %.7f rad, n atan(w h) = %.7f, w T = 1",
          r, want);
    /* about y from a rolled attitude: pitch grows, roll holds */
    filter_init(&f, 0.0f);
    up(20 * DEG, 0, a);
    filter_align(&f, a);
    /* body rate for d(pitch)/dt = 0.2 rad/s at roll 20 deg, yaw rate 0 */
    float g2[3] = {0, (float)(0.2 * cos(20 * DEG)), (float)(-0.2 * sin(20 * DEG))};
    for (int i = 0; i < 100; i++)
        filter_update(&f, g2, a, h);
    filter_angles(&f, &r, &p);
    CHECK(fabs(p - 0.2) < 1e-4 && fabs(r - 20 * DEG) < 1e-4,
          "pitch rate 0.2 rad/s for 1 s at roll 20 deg: pitch %.6f, roll %.4f deg", p, r / DEG);
}

static void test_complementary(void)
{
    const float k = FILTER_K_SOURCE, h = 0.01f;
    clino_filter_t f;
    filter_init(&f, k);
    float a0[3], a1[3], g[3] = {0, 0, 0}, r, p;
    up(0, 0, a0);
    filter_align(&f, a0);
    up(2 * DEG, 0, a1); /* the accelerometers now say 2 deg of roll */
    double e_prev = 2 * DEG, worst = 0;
    for (int i = 0; i < 60; i++) {
        filter_update(&f, g, a1, h);
        filter_angles(&f, &r, &p);
        double e = 2 * DEG - r;
        double ratio = e / e_prev;
        if (fabs(ratio - (1 - k)) > worst)
            worst = fabs(ratio - (1 - k));
        e_prev = e;
    }
    CHECK(worst < 2e-3, "step of 2 deg: error ratio per step within %.1e of 1 - k = %.2f",
          worst, 1 - k);
    /* gyro bias: steady error (1 - k) b h / k */
    filter_init(&f, k);
    filter_align(&f, a0);
    float gb[3] = {0.01f, 0, 0};
    for (int i = 0; i < 2000; i++)
        filter_update(&f, gb, a0, h);
    filter_angles(&f, &r, &p);
    double want = (1 - k) * 0.01 * h / k;
    CHECK(fabs(r - want) < 0.01 * want, "bias 0.01 rad/s: steady roll %.6e rad, (1-k) b h/k = %.6e",
          r, want);
    /* the DCM stays orthonormal */
    double worst_o = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = 0;
            for (int m = 0; m < 3; m++)
                d += f.C[i][m] * f.C[j][m];
            d -= i == j;
            if (fabs(d) > worst_o)
                worst_o = fabs(d);
        }
    CHECK(worst_o < 1e-6, "C C^T = I within %.1e after 2000 steps", worst_o);
}

static void test_calibration(void)
{
    const float KA = 8192.0f / 9.80665f, KG = 65.5f / 0.017453292f;
    clino_calib_matrices_t m = {
        .K = {{1.012f * KA, 0.004f * KA, -0.006f * KA},
              {-0.003f * KA, 0.991f * KA, 0.005f * KA},
              {0.007f * KA, -0.002f * KA, 1.004f * KA}},
        .Ua0 = {153, -97, 241},
        .R = {{0.985f * KG, 0.006f * KG, 0.002f * KG},
              {-0.004f * KG, 1.013f * KG, -0.007f * KG},
              {0.003f * KG, 0.005f * KG, 0.996f * KG}},
        .U0 = {-41, 27, 12},
    };
    clino_calib_t c;
    CHECK(calib_init(&c, &m) == 0, "calibration matrices invert");
    double fa[3] = {1.5, -3.0, 9.0}, w[3] = {0.3, -0.2, 0.05};
    float u[3], v[3], out[3], outg[3];
    for (int i = 0; i < 3; i++) {
        u[i] = m.Ua0[i];
        v[i] = m.U0[i];
        for (int j = 0; j < 3; j++) {
            u[i] += (float)(m.K[i][j] * fa[j]);
            v[i] += (float)(m.R[i][j] * w[j]);
        }
    }
    calib_acc(&c, u, out);
    calib_gyr(&c, v, outg);
    double ea = 0, eg = 0;
    for (int i = 0; i < 3; i++) {
        ea = fmax(ea, fabs(out[i] - fa[i]));
        eg = fmax(eg, fabs(outg[i] - w[i]));
    }
    CHECK(ea < 1e-4 && eg < 1e-6, "A = K^-1 (U_a - U_a0), W = R^-1 (U - U0): errors %.1e, %.1e",
          ea, eg);
    /* at +-8 g and +-1000 deg/s the chip gives half (and 32.8/65.5) the counts */
    calib_set_ranges(&c, 8, 1000);
    float u8[3], v8[3];
    for (int i = 0; i < 3; i++) {
        u8[i] = u[i] * 0.5f;
        v8[i] = v[i] * (32.8f / 65.5f);
    }
    calib_acc(&c, u8, out);
    calib_gyr(&c, v8, outg);
    ea = eg = 0;
    for (int i = 0; i < 3; i++) {
        ea = fmax(ea, fabs(out[i] - fa[i]));
        eg = fmax(eg, fabs(outg[i] - w[i]));
    }
    CHECK(ea < 1e-4 && eg < 1e-6, "the same at +-8 g, +-1000 deg/s: errors %.1e, %.1e", ea, eg);
    clino_calib_matrices_t sing = m;
    for (int j = 0; j < 3; j++)
        sing.K[2][j] = sing.K[1][j];
    CHECK(calib_init(&c, &sing) != 0, "a singular K is refused");
    CHECK(mpu_accel_lsb_per_g(2) == 16384 && mpu_accel_lsb_per_g(16) == 2048 &&
              mpu_gyro_lsb_per_dps(250) == 131.0f && mpu_gyro_lsb_per_dps(2000) == 16.4f,
          "datasheet sensitivities");
    CHECK(filter_decimation(100) == 1 && filter_decimation(199) == 1 && filter_decimation(200) == 2 &&
              filter_decimation(400) == 4 && filter_decimation(50) == 1,
          "filter stepped at <= 100 Hz: decimation 1, 1, 2, 4, 1 at 100, 199, 200, 400, 50 Hz");
}

int main(void)
{
    test_align();
    test_gyro_only();
    test_complementary();
    test_calibration();
    printf("test_filter: %d checks, %d failed\n", checks, fails);
    return fails ? 1 : 0;
}
