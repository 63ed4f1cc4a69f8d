/* The simulated MPU6050; see mpu6050_model.h. */
#include "mpu6050_model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "avr_twi.h"
#include "calibration.h"

#define DEG (M_PI / 180.0)
#define G0 9.80665

/* Smooth step 0..1 over [t0, t1] and its derivative. */
static void ramp(double t, double t0, double t1, double *s, double *ds)
{
    double T = t1 - t0, u = (t - t0) / T;
    *s = 0.5 * (1.0 - cos(M_PI * u));
    *ds = 0.5 * M_PI / T * sin(M_PI * u);
}

motion_t motion_at(double t)
{
    motion_t m = {0, 0, 0, 0};
    const double r1 = 30 * DEG, p1 = -15 * DEG, r2 = -20 * DEG, p2 = 25 * DEG;
    double s, ds;
    if (t < 1.0) {
        /* level */
    } else if (t < 3.0) {
        ramp(t, 1.0, 3.0, &s, &ds);
        m.roll = r1 * s, m.droll = r1 * ds;
        m.pitch = p1 * s, m.dpitch = p1 * ds;
    } else if (t < 5.0) {
        m.roll = r1, m.pitch = p1;
    } else if (t < 8.0) {
        double w1 = 2 * M_PI * 0.5, w2 = 2 * M_PI / 3.0, u = t - 5.0;
        m.roll = r1 + 15 * DEG * sin(w1 * u);
        m.droll = 15 * DEG * w1 * cos(w1 * u);
        m.pitch = p1 + 10 * DEG * sin(w2 * u);
        m.dpitch = 10 * DEG * w2 * cos(w2 * u);
    } else if (t < 10.0) {
        ramp(t, 8.0, 10.0, &s, &ds);
        m.roll = r1 + (r2 - r1) * s, m.droll = (r2 - r1) * ds;
        m.pitch = p1 + (p2 - p1) * s, m.dpitch = (p2 - p1) * ds;
    } else {
        m.roll = r2, m.pitch = p2;
    }
    return m;
}

int mpu_model_accel_fs(const mpu_model_t *m)
{
    return 2 << ((m->reg[0x1C] >> 3) & 3);
}

int mpu_model_gyro_fs(const mpu_model_t *m)
{
    return 250 << ((m->reg[0x1B] >> 3) & 3);
}

static double lsb_g(int fs)
{
    return 32768.0 / fs; /* 16384, 8192, 4096, 2048 */
}

static double lsb_dps(int fs)
{
    switch (fs) {
    case 250:
        return 131.0;
    case 500:
        return 65.5;
    case 1000:
        return 32.8;
    default:
        return 16.4;
    }
}

static int noise(mpu_model_t *m)
{
    m->rng = m->rng * 1664525u + 1013904223u;
    return (int)((m->rng >> 16) % 5u) - 2;
}

static int16_t sat(double v)
{
    v = floor(v + 0.5);
    if (v > 32767)
        return 32767;
    if (v < -32768)
        return -32768;
    return (int16_t)v;
}

static void reset_regs(mpu_model_t *m)
{
    memset(m->reg, 0, sizeof m->reg);
    m->reg[0x6B] = 0x40; /* SLEEP */
    m->reg[0x75] = 0x68;
}

static void latch(mpu_model_t *m)
{
    played_t p;
    p.cycle = m->avr->cycle;
    p.t = (double)m->avr->cycle / (double)m->avr->frequency;
    motion_t mo = motion_at(p.t);
    p.roll = mo.roll;
    p.pitch = mo.pitch;
    double sr = sin(mo.roll), cr = cos(mo.roll), sp = sin(mo.pitch), cp = cos(mo.pitch);
    double f[3] = {-G0 * sp, G0 * sr * cp, G0 * cr * cp};
    double w[3] = {mo.droll, mo.dpitch * cr, -mo.dpitch * sr};
    double as = lsb_g(mpu_model_accel_fs(m)) / lsb_g(CALIB_ACCEL_FS_G);
    double gs = lsb_dps(mpu_model_gyro_fs(m)) / lsb_dps(CALIB_GYRO_FS_DPS);
    const clino_calib_matrices_t *c = &CLINO_CALIB;
    for (int i = 0; i < 3; i++) {
        double a = c->Ua0[i], g = c->U0[i];
        for (int j = 0; j < 3; j++) {
            a += (double)c->K[i][j] * f[j];
            g += (double)c->R[i][j] * w[j];
        }
        p.raw[i] = sat(a * as + noise(m));
        p.raw[4 + i] = sat(g * gs + noise(m));
    }
    double temp = 24.0 + 0.5 * sin(p.t / 10.0);
    p.raw[3] = sat((temp - 36.53) * 340.0);
    if (m->reg[0x6B] & 0x40)
        memset(p.raw, 0, sizeof p.raw);
    for (int i = 0; i < 7; i++) {
        m->reg[0x3B + 2 * i] = (uint8_t)((uint16_t)p.raw[i] >> 8);
        m->reg[0x3C + 2 * i] = (uint8_t)((uint16_t)p.raw[i] & 0xFF);
    }
    if (m->nplayed == m->capplayed) {
        m->capplayed = m->capplayed ? 2 * m->capplayed : 4096;
        m->played = realloc(m->played, m->capplayed * sizeof *m->played);
        if (!m->played) {
            fprintf(stderr, "harness: out of memory\n");
            exit(2);
        }
    }
    m->played[m->nplayed++] = p;
}

static void twi_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    mpu_model_t *m = param;
    avr_twi_msg_irq_t v;
    v.u.v = value;
    if (v.u.twi.msg & TWI_COND_STOP)
        m->selected = 0;
    if (v.u.twi.msg & TWI_COND_START) {
        m->selected = 0;
        if ((v.u.twi.addr >> 1) == 0x68 && !m->absent) {
            m->selected = v.u.twi.addr;
            if (!(v.u.twi.addr & 1))
                m->want_ptr = 1;
            avr_raise_irq(m->irq + TWI_IRQ_INPUT,
                          avr_twi_irq_msg(TWI_COND_ACK, m->selected, 1));
        } else {
            m->naks++;
        }
    }
    if (!m->selected)
        return;
    if (v.u.twi.msg & TWI_COND_WRITE) {
        avr_raise_irq(m->irq + TWI_IRQ_INPUT, avr_twi_irq_msg(TWI_COND_ACK, m->selected, 1));
        if (m->want_ptr) {
            m->ptr = v.u.twi.data & 0x7F;
            m->want_ptr = 0;
        } else {
            m->writes++;
            if (m->ptr == 0x6B && (v.u.twi.data & 0x80))
                reset_regs(m);
            else if (m->ptr != 0x75 && !(m->ptr >= 0x3B && m->ptr <= 0x48))
                m->reg[m->ptr] = v.u.twi.data;
            m->ptr = (m->ptr + 1) & 0x7F;
        }
    }
    if (v.u.twi.msg & TWI_COND_READ) {
        if (m->ptr == 0x3B)
            latch(m);
        m->reads++;
        uint8_t d = m->reg[m->ptr];
        m->ptr = (m->ptr + 1) & 0x7F;
        avr_raise_irq(m->irq + TWI_IRQ_INPUT, avr_twi_irq_msg(TWI_COND_READ, m->selected, d));
    }
}

void mpu_model_init(mpu_model_t *m, avr_t *avr)
{
    static const char *names[2] = {"8<mpu.in", "32>mpu.out"};
    memset(m, 0, sizeof *m);
    m->avr = avr;
    m->rng = 12345u;
    reset_regs(m);
    m->irq = avr_alloc_irq(&avr->irq_pool, 0, 2, names);
    avr_irq_register_notify(m->irq + TWI_IRQ_OUTPUT, twi_hook, m);
    avr_connect_irq(m->irq + TWI_IRQ_INPUT,
                    avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT));
    avr_connect_irq(avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT),
                    m->irq + TWI_IRQ_OUTPUT);
}

void mpu_model_set_present(mpu_model_t *m, int present)
{
    if (present && m->absent)
        reset_regs(m);
    m->absent = !present;
    m->selected = 0;
}
