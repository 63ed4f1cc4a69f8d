/*
 * simavr test harness for firmware/arduino/clino_inclinometer.
 *
 * Runs the firmware ELF on a simulated ATmega328P at 16 MHz with a simulated
 * MPU6050 on the TWI bus (mpu6050_model.c), captures the UART byte stream and
 * the servo pulses on PB1/PB2 (pins 9/10, OC1A/OC1B), sends host commands and
 * checks:
 *   1. every played sample appears, in order and bit-exact, in the decoded
 *      stream (COBS + CRC decoded here with the firmware's protocol.c), with
 *      seq +1 per sample, except samples played while the host had sent STOP;
 *   2. the sample rate holds: consecutive t_us differ by exactly 1e6/rate
 *      (the stamp is the sample clock's tick), the number of frames in a
 *      window is rate * window within 1, and the board clock keeps step with
 *      the simulated clock;
 *   3. the dials: the 50 Hz period from the simulated OC1A/OC1B pins; each
 *      pulse width (the OCR1x value in force at the period's start, see
 *      pin_servo) equals 1500 us + angle * 500/90 us
 *      (within 0.5 us, one Timer1 tick) for the angle of the source filter
 *      run here over the played samples (filter.c built for the host); during
 *      holds of the motion, the dial angle is within 0.2 deg of the truth;
 *      while the host sends SET_DIALS the dials show those angles;
 *   4. commands: ACK status 0/1/2/3 as the spec says, CONFIG after accepted
 *      SET_* and REQUEST_CONFIG, STOP silences SAMPLE frames, START restarts
 *      seq at 0, SET_RANGES changes the chip's ranges (and the dials stay
 *      right), SET_RATE above 400 Hz is refused;
 *   5. unplugging the sensor for 1 s (it powers up again, asleep, at its
 *      reset ranges): one gap in seq covers the outage, every seq step is
 *      one period of t_us, the firmware sets the chip up again with the
 *      ranges in force and the dials come back to the truth;
 *   6. with no sensor on the bus: CONFIG at boot, no SAMPLE, the firmware
 *      keeps retrying, commands are answered, the dials stay centred.
 * and measures the CPU use per sample in simulated cycles: busy = not asleep
 * (the firmware sleeps in idle mode between interrupts); each interrupt from
 * its vector-table entry to its RETI; the main loop's work on a sample from
 * the D4 (PD4) test point less the interrupts inside it; the filter step from
 * D7 (PD7).
 *
 * Usage: harness FIRMWARE.elf OUTDIR [100hz|400hz|unplug|nosensor|all]
 * Writes OUTDIR/<scenario>_capture.bin (every byte the board sent),
 * <scenario>_played.csv (every sample the simulated chip played),
 * <scenario>_decoded.csv (the decoded samples in clino fuse's raw CSV),
 * <scenario>_pulses.csv. Exit status 0 only if every check passed.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "avr_ioport.h"
#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"

#include "calibration.h"
#include "filter.h"
#include "mpu6050_model.h"
#include "protocol.h"

#define F_CPU 16000000.0
#define US(c) ((double)(c) / 16.0)
#define CYC(t) ((uint64_t)((t) * F_CPU))

static int failures;
static void check(int ok, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    printf("  [%s] ", ok ? "ok" : "FAIL");
    vprintf(fmt, ap);
    printf("\n");
    va_end(ap);
    if (!ok)
        failures++;
}

/* ---------------------------------------------------------------- capture */
typedef struct {
    uint8_t *b;
    uint64_t *cyc;
    size_t n, cap;
} bytes_t;

typedef struct {
    uint64_t rise;
    double width_us;
} pulse_t;

typedef struct {
    pulse_t *p;
    size_t n, cap;
    uint64_t rise;
    int level;
} pulses_t;

typedef struct {
    uint64_t busy_start;
    uint64_t total, count, max;
    int level;
} probe_t;

static avr_t *g_avr;
static bytes_t g_tx;
static pulses_t g_pulse[2]; /* 0: pin 9 roll, 1: pin 10 pitch */
static probe_t g_probe_main, g_probe_filter;
static uint64_t g_idle;

/* Interrupt accounting: a vector is entered when the PC lands on its slot in
 * the vector table and left at its RETI (the firmware does not nest them). */
#define NVEC 26
static uint64_t g_isr_cycles[NVEC], g_isr_count[NVEC], g_isr_in_main;
static const char *const vec_name[NVEC] = {
    [7] = "TIMER2_COMPA (sample clock)", [16] = "TIMER0_OVF (millis)",
    [18] = "USART_RX", [19] = "USART_UDRE (transmit)", [24] = "TWI"};

static void *grow(void *p, size_t *cap, size_t n, size_t elem)
{
    if (n < *cap)
        return p;
    *cap = *cap ? 2 * *cap : 4096;
    p = realloc(p, *cap * elem);
    if (!p) {
        fprintf(stderr, "harness: out of memory\n");
        exit(2);
    }
    return p;
}

static void uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq, (void)param;
    size_t cap = g_tx.cap;
    g_tx.b = grow(g_tx.b, &cap, g_tx.n, 1);
    size_t cap2 = g_tx.cap;
    g_tx.cyc = grow(g_tx.cyc, &cap2, g_tx.n, sizeof(uint64_t));
    g_tx.cap = cap;
    g_tx.b[g_tx.n] = (uint8_t)value;
    g_tx.cyc[g_tx.n] = g_avr->cycle;
    g_tx.n++;
}

/*
 * Servo pulses. The period and the rising edges are the simulated OC1A/OC1B
 * pins. The width is the OCR1A/OCR1B value in force at the rising edge,
 * (OCR + 1) ticks of 0.5 us: in fast PWM the hardware latches OCR1x at BOTTOM
 * (double buffering) and holds the pin high for OCR1x + 1 ticks. simavr 1.6
 * does not re-time the compare match after an OCR write in fast PWM (its pin
 * keeps the width of the first OCR value), so its falling edge cannot be used.
 */
#define OCR1AL 0x88
#define OCR1BL 0x8A
static void pin_servo(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    pulses_t *s = param;
    int v = value != 0;
    if (v == s->level)
        return;
    s->level = v;
    if (v) {
        int a = s == &g_pulse[0] ? OCR1AL : OCR1BL;
        uint16_t ocr = (uint16_t)(g_avr->data[a] | (g_avr->data[a + 1] << 8));
        s->p = grow(s->p, &s->cap, s->n, sizeof *s->p);
        s->p[s->n].rise = g_avr->cycle;
        s->p[s->n].width_us = (ocr + 1) * 0.5;
        s->n++;
    }
}

static void pin_probe(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    probe_t *p = param;
    int v = value != 0;
    if (v == p->level)
        return;
    p->level = v;
    if (v) {
        p->busy_start = g_avr->cycle;
    } else if (p->busy_start) {
        uint64_t d = g_avr->cycle - p->busy_start;
        p->total += d;
        p->count++;
        if (d > p->max)
            p->max = d;
    }
}

/* Sleeping is simulated time only: never wait in real time. */
static void sleep_none(avr_t *avr, avr_cycle_count_t howlong)
{
    (void)avr;
    g_idle += howlong + 1;
}

/* ---------------------------------------------------------------- host side */
typedef struct {
    double t;
    uint8_t wire[128];
    size_t n;
    const char *what;
} command_t;

static command_t cmd_frame(double t, const char *what, uint8_t type, const uint8_t *p, size_t n)
{
    command_t c = {t, {0}, 0, what};
    c.n = proto_frame(type, p, n, c.wire);
    return c;
}

static command_t cmd_u16(double t, const char *what, uint8_t type, uint16_t v)
{
    uint8_t p[2];
    proto_put_u16(p, v);
    return cmd_frame(t, what, type, p, 2);
}

static command_t cmd_dials(double t, int16_t roll, int16_t pitch)
{
    uint8_t p[4];
    proto_put_u16(p, (uint16_t)roll);
    proto_put_u16(p + 2, (uint16_t)pitch);
    return cmd_frame(t, "SET_DIALS", PROTO_SET_DIALS, p, 4);
}

static command_t cmd_ranges(double t, uint8_t a, uint16_t g, uint8_t d)
{
    uint8_t p[4] = {a, 0, 0, d};
    proto_put_u16(p + 1, g);
    return cmd_frame(t, "SET_RANGES", PROTO_SET_RANGES, p, 4);
}

static command_t cmd_raw(double t, const char *what, const uint8_t *b, size_t n)
{
    command_t c = {t, {0}, n, what};
    if (n > sizeof c.wire) {
        fprintf(stderr, "harness: raw command of %zu bytes too long\n", n);
        exit(2);
    }
    memcpy(c.wire, b, n);
    return c;
}

/* ---------------------------------------------------------------- decoded */
typedef struct {
    uint64_t cyc; /* cycle at which the delimiter left the UART */
    uint8_t type, plen;
    uint8_t p[PROTO_MAX_PAYLOAD];
} frame_t;

typedef struct {
    frame_t *f;
    size_t n, cap;
    uint32_t bad;
} frames_t;

static frames_t decode(const bytes_t *tx)
{
    frames_t fr = {0};
    proto_rx_t rx;
    proto_rx_init(&rx);
    for (size_t i = 0; i < tx->n; i++) {
        int r = proto_rx_push(&rx, tx->b[i]);
        if (r == PROTO_RX_FRAME) {
            fr.f = grow(fr.f, &fr.cap, fr.n, sizeof *fr.f);
            frame_t *f = &fr.f[fr.n++];
            f->cyc = tx->cyc[i];
            f->type = rx.type;
            f->plen = rx.plen;
            memcpy(f->p, rx.body + 1, rx.plen);
        } else if (r == PROTO_RX_BAD) {
            fr.bad++;
        }
    }
    return fr;
}

/* ---------------------------------------------------------------- scenario */
typedef struct {
    double t0, t1, roll_deg, pitch_deg;
} hold_t;

typedef struct {
    const char *name;
    double duration;
    command_t cmds[32];
    int ncmds;
    hold_t holds[4];
    int nholds;
    double count_t0, count_t1; /* window for the frame count */
    uint16_t rate;             /* rate after the commands */
    int no_sensor;             /* run without the MPU6050 on the bus */
    double unplug_t, replug_t; /* the sensor leaves the bus and comes back */
} scenario_t;

static int find_cmd(const scenario_t *s, const char *what, int nth)
{
    for (int i = 0; i < s->ncmds; i++)
        if (!strcmp(s->cmds[i].what, what) && nth-- == 0)
            return i;
    return -1;
}

/* ACKs and CONFIGs that arrived after command i was sent and before the next */
static const frame_t *reply(const frames_t *fr, const scenario_t *s, int i, uint8_t type, int nth)
{
    uint64_t a = CYC(s->cmds[i].t);
    uint64_t b = i + 1 < s->ncmds ? CYC(s->cmds[i + 1].t) : (uint64_t)-1;
    for (size_t k = 0; k < fr->n; k++)
        if (fr->f[k].type == type && fr->f[k].cyc >= a && fr->f[k].cyc < b && nth-- == 0)
            return &fr->f[k];
    return NULL;
}

static void check_ack(const frames_t *fr, const scenario_t *s, int i, uint8_t cmd,
                      uint8_t status, int want_config)
{
    if (i < 0) {
        check(0, "command missing from the scenario");
        return;
    }
    const frame_t *a = reply(fr, s, i, PROTO_ACK, 0);
    const frame_t *c = reply(fr, s, i, PROTO_CONFIG, 0);
    check(a && a->p[0] == cmd && a->p[1] == status && (want_config ? c != NULL : c == NULL),
          "%-28s at %6.3f s: ACK(0x%02x, %u)%s, got %s(0x%02x, %u) %s", s->cmds[i].what,
          s->cmds[i].t, cmd, status, want_config ? " + CONFIG" : ", no CONFIG", a ? "ACK" : "no ACK",
          a ? a->p[0] : 0, a ? a->p[1] : 0, c ? "+ CONFIG" : "no CONFIG");
}

static double expected_width(double deg)
{
    if (deg > 90)
        deg = 90;
    if (deg < -90)
        deg = -90;
    return 1500.0 + deg * 500.0 / 90.0;
}

static int write_outputs(const char *dir, const scenario_t *s, const mpu_model_t *m,
                         const frames_t *fr)
{
    char path[512];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s_capture.bin", dir, s->name);
    if (!(f = fopen(path, "wb")) || fwrite(g_tx.b, 1, g_tx.n, f) != g_tx.n || fclose(f)) {
        fprintf(stderr, "harness: cannot write %s\n", path);
        return -1;
    }
    snprintf(path, sizeof path, "%s/%s_played.csv", dir, s->name);
    if (!(f = fopen(path, "w"))) {
        fprintf(stderr, "harness: cannot write %s\n", path);
        return -1;
    }
    fprintf(f, "index,cycle,t_s,ax,ay,az,temp,gx,gy,gz,roll_true_deg,pitch_true_deg\n");
    for (size_t i = 0; i < m->nplayed; i++) {
        const played_t *p = &m->played[i];
        fprintf(f, "%zu,%llu,%.9f,%d,%d,%d,%d,%d,%d,%d,%.6f,%.6f\n", i,
                (unsigned long long)p->cycle, p->t, p->raw[0], p->raw[1], p->raw[2], p->raw[3],
                p->raw[4], p->raw[5], p->raw[6], p->roll * 180 / M_PI, p->pitch * 180 / M_PI);
    }
    fclose(f);
    /* decoded samples in the raw-sample CSV clino fuse reads (spec, frames.csv) */
    snprintf(path, sizeof path, "%s/%s_decoded.csv", dir, s->name);
    if (!(f = fopen(path, "w"))) {
        fprintf(stderr, "harness: cannot write %s\n", path);
        return -1;
    }
    fprintf(f, "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,temp_c\n");
    double lsb_a = 8192, lsb_g = 65.5;
    uint64_t wraps = 0;
    uint32_t last = 0;
    int have = 0;
    for (size_t k = 0; k < fr->n; k++) {
        if (fr->f[k].type == PROTO_CONFIG) {
            proto_config_t c;
            proto_parse_config(fr->f[k].p, &c);
            /* the spec's sensitivities as doubles (32.8 is not a float) */
            lsb_a = 32768.0 / c.accel_fs_g;
            lsb_g = c.gyro_fs_dps == 250 ? 131.0 : c.gyro_fs_dps == 500 ? 65.5
                    : c.gyro_fs_dps == 1000 ? 32.8 : 16.4;
            continue;
        }
        if (fr->f[k].type != PROTO_SAMPLE)
            continue;
        proto_sample_t q;
        proto_parse_sample(fr->f[k].p, &q);
        if (have && q.t_us < last)
            wraps++;
        last = q.t_us, have = 1;
        double t = (double)(wraps * 4294967296ull + q.t_us) * 1e-6;
        double kg = M_PI / 180.0 / lsb_g, ka = 9.80665 / lsb_a;
        fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t, q.gx * kg, q.gy * kg,
                q.gz * kg, q.ax * ka, q.ay * ka, q.az * ka, q.temp / 340.0 + 36.53);
    }
    fclose(f);
    snprintf(path, sizeof path, "%s/%s_pulses.csv", dir, s->name);
    if (!(f = fopen(path, "w"))) {
        fprintf(stderr, "harness: cannot write %s\n", path);
        return -1;
    }
    fprintf(f, "pin,rise_cycle,width_us\n");
    for (int ch = 0; ch < 2; ch++)
        for (size_t i = 0; i < g_pulse[ch].n; i++)
            fprintf(f, "%d,%llu,%.4f\n", ch ? 10 : 9, (unsigned long long)g_pulse[ch].p[i].rise,
                    g_pulse[ch].p[i].width_us);
    fclose(f);
    return 0;
}

static void run_scenario(const char *elf, const char *outdir, const scenario_t *s)
{
    printf("\n== scenario %s (%.1f s simulated)\n", s->name, s->duration);
    elf_firmware_t fw;
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(elf, &fw) != 0) {
        fprintf(stderr, "harness: cannot read %s\n", elf);
        exit(2);
    }
    avr_t *avr = avr_make_mcu_by_name("atmega328p");
    if (!avr) {
        fprintf(stderr, "harness: simavr has no atmega328p\n");
        exit(2);
    }
    avr_init(avr);
    avr->frequency = 16000000;
    avr->log = LOG_ERROR;
    avr_load_firmware(avr, &fw);
    avr->frequency = 16000000;
    avr->sleep = sleep_none;
    g_avr = avr;

    memset(&g_tx, 0, sizeof g_tx);
    memset(g_pulse, 0, sizeof g_pulse);
    memset(&g_probe_main, 0, sizeof g_probe_main);
    memset(&g_probe_filter, 0, sizeof g_probe_filter);
    g_idle = 0;

    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~(AVR_UART_FLAG_STDIO | AVR_UART_FLAG_POLL_SLEEP);
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
                            uart_out, NULL);
    avr_irq_t *uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('B'), IOPORT_IRQ_PIN1),
                            pin_servo, &g_pulse[0]);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('B'), IOPORT_IRQ_PIN2),
                            pin_servo, &g_pulse[1]);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('D'), IOPORT_IRQ_PIN4),
                            pin_probe, &g_probe_main);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('D'), IOPORT_IRQ_PIN7),
                            pin_probe, &g_probe_filter);

    static mpu_model_t mpu;
    free(mpu.played);
    mpu_model_init(&mpu, avr);
    mpu.absent = s->no_sensor;

    /* budget window: steady state before the commands */
    double bw0 = 2.0, bw1 = s->ncmds && s->cmds[s->ncmds - 1].t > 6 ? 12.0 : s->duration - 0.5;
    if (s->unplug_t > 0 || s->no_sensor)
        bw0 = 1e9; /* no budget figures from a run with an outage */
    uint64_t idle_at_bw0 = 0, idle_at_bw1 = 0, main_at0 = 0, main_n0 = 0, filt_at0 = 0,
             filt_n0 = 0, main_at1 = 0, main_n1 = 0, filt_at1 = 0, filt_n1 = 0;
    size_t played_at_bw0 = 0, played_at_bw1 = 0;
    int bw_state = 0;

    uint64_t end = CYC(s->duration);
    int next_cmd = 0;
    const uint8_t *in_buf = NULL;
    size_t in_len = 0, in_pos = 0;
    uint64_t next_in = 0;
    int in_isr = -1;
    uint64_t isr_start = 0;
    memset(g_isr_cycles, 0, sizeof g_isr_cycles);
    memset(g_isr_count, 0, sizeof g_isr_count);
    g_isr_in_main = 0;
    uint64_t isr0[NVEC], isr1[NVEC], isrn0[NVEC], isrn1[NVEC], inmain0 = 0, inmain1 = 0;
    while (avr->cycle < end) {
        /* host bytes go in at the line rate (10 bits at 115200 baud each),
         * as a PC's UART sends them; simavr's receive FIFO holds 64 */
        if (in_pos == in_len && next_cmd < s->ncmds && avr->cycle >= CYC(s->cmds[next_cmd].t)) {
            in_buf = s->cmds[next_cmd].wire;
            in_len = s->cmds[next_cmd].n;
            in_pos = 0;
            next_in = avr->cycle;
            next_cmd++;
        }
        if (in_pos < in_len && avr->cycle >= next_in) {
            avr_raise_irq(uart_in, in_buf[in_pos++]);
            next_in += (uint64_t)(F_CPU * 10.0 / 115200.0);
        }
        if (s->unplug_t > 0 && !mpu.absent && avr->cycle >= CYC(s->unplug_t) &&
            avr->cycle < CYC(s->replug_t))
            mpu_model_set_present(&mpu, 0);
        if (s->unplug_t > 0 && mpu.absent && avr->cycle >= CYC(s->replug_t))
            mpu_model_set_present(&mpu, 1);
        if (bw_state == 0 && avr->cycle >= CYC(bw0)) {
            idle_at_bw0 = g_idle, played_at_bw0 = mpu.nplayed;
            main_at0 = g_probe_main.total, main_n0 = g_probe_main.count;
            filt_at0 = g_probe_filter.total, filt_n0 = g_probe_filter.count;
            memcpy(isr0, g_isr_cycles, sizeof isr0);
            memcpy(isrn0, g_isr_count, sizeof isrn0);
            inmain0 = g_isr_in_main;
            bw_state = 1;
        } else if (bw_state == 1 && avr->cycle >= CYC(bw1)) {
            idle_at_bw1 = g_idle, played_at_bw1 = mpu.nplayed;
            main_at1 = g_probe_main.total, main_n1 = g_probe_main.count;
            filt_at1 = g_probe_filter.total, filt_n1 = g_probe_filter.count;
            memcpy(isr1, g_isr_cycles, sizeof isr1);
            memcpy(isrn1, g_isr_count, sizeof isrn1);
            inmain1 = g_isr_in_main;
            bw_state = 2;
        }
        avr_flashaddr_t pc = avr->pc;
        if (in_isr < 0 && pc > 0 && pc < NVEC * 4 && pc % 4 == 0) {
            in_isr = (int)(pc / 4);
            isr_start = avr->cycle;
        }
        int reti = in_isr >= 0 && avr->flash[pc] == 0x18 && avr->flash[pc + 1] == 0x95;
        int st = avr_run(avr);
        if (reti) {
            g_isr_cycles[in_isr] += avr->cycle - isr_start;
            g_isr_count[in_isr]++;
            if (g_probe_main.level)
                g_isr_in_main += avr->cycle - isr_start;
            in_isr = -1;
        }
        if (st == cpu_Done || st == cpu_Crashed) {
            check(0, "the simulated CPU stopped (state %d) at %.6f s", st, avr->cycle / F_CPU);
            break;
        }
    }

    frames_t fr = decode(&g_tx);
    if (write_outputs(outdir, s, &mpu, &fr) != 0)
        failures++;
    printf("  %zu bytes from the board, %zu frames, %u bad; %zu samples played, %u TWI NAKs\n",
           g_tx.n, fr.n, fr.bad, mpu.nplayed, mpu.naks);
    check(fr.bad == 0, "no bad frame in the board's stream (%u)", fr.bad);

    if (s->no_sensor) {
        size_t nsamp = 0;
        for (size_t k = 0; k < fr.n; k++)
            nsamp += fr.f[k].type == PROTO_SAMPLE;
        check(fr.n > 0 && fr.f[0].type == PROTO_CONFIG, "no sensor: CONFIG at boot all the same");
        check(nsamp == 0 && mpu.nplayed == 0, "no sensor: no SAMPLE frame (%zu)", nsamp);
        check(mpu.naks >= 3, "no sensor: the firmware keeps looking for it (%u address NAKs)",
              mpu.naks);
        check_ack(&fr, s, 0, PROTO_REQUEST_CONFIG, 0, 1);
        size_t off = 0;
        for (int ch = 0; ch < 2; ch++)
            for (size_t k = 0; k < g_pulse[ch].n; k++)
                off += g_pulse[ch].p[k].width_us != 1500.0;
        check(g_pulse[0].n > 100 && off == 0,
              "no sensor: both dials stay at 1500 us (%zu pulses, %zu off centre)",
              g_pulse[0].n + g_pulse[1].n, off);
        goto done;
    }

    /* ---- 0. boot CONFIG ---- */
    check(fr.n > 0 && fr.f[0].type == PROTO_CONFIG, "the first frame is CONFIG");
    if (fr.n > 0 && fr.f[0].type == PROTO_CONFIG) {
        proto_config_t c;
        proto_parse_config(fr.f[0].p, &c);
        check(c.proto_version == 1 && c.board == PROTO_BOARD_UNO && c.rate_hz == 100 &&
                  c.accel_fs_g == 4 && c.gyro_fs_dps == 500 && c.dlpf_cfg == 3 && c.streaming == 1,
              "boot CONFIG: v%u fw %u.%u.%u board %u, %u Hz, +-%u g, +-%u deg/s, DLPF %u, "
              "streaming %u",
              c.proto_version, c.fw_major, c.fw_minor, c.fw_patch, c.board, c.rate_hz,
              c.accel_fs_g, c.gyro_fs_dps, c.dlpf_cfg, c.streaming);
    }
    check(mpu_model_accel_fs(&mpu) == (find_cmd(s, "SET_RANGES ok", 0) >= 0 ? 8 : 4) &&
              (mpu.reg[0x6B] & 0x40) == 0,
          "the chip was woken and set to the ranges last asked for (+-%d g, +-%d deg/s, "
          "DLPF %d, PWR_MGMT_1 0x%02x)",
          mpu_model_accel_fs(&mpu), mpu_model_gyro_fs(&mpu), mpu.reg[0x1A] & 7, mpu.reg[0x6B]);

    /* ---- 1. every played sample in the stream ---- */
    int i_stop = find_cmd(s, "STOP", 0), i_start = find_cmd(s, "START", 0);
    uint64_t stop_c = i_stop >= 0 ? CYC(s->cmds[i_stop].t) : (uint64_t)-1;
    uint64_t start_c = (uint64_t)-1;
    if (i_start >= 0) {
        const frame_t *a = reply(&fr, s, i_start, PROTO_ACK, 0);
        start_c = a ? a->cyc : CYC(s->cmds[i_start].t);
    }
    size_t pi = 0, matched = 0, skipped_ok = 0, skipped_bad = 0, seq_bad = 0, nsample = 0;
    int have_prev = 0;
    uint16_t prev_seq = 0;
    double prev_t = 0;
    int after_start = 0;
    for (size_t k = 0; k < fr.n; k++) {
        if (fr.f[k].type != PROTO_SAMPLE)
            continue;
        nsample++;
        proto_sample_t q;
        proto_parse_sample(fr.f[k].p, &q);
        int16_t raw[7] = {q.ax, q.ay, q.az, q.temp, q.gx, q.gy, q.gz};
        size_t j = pi;
        while (j < mpu.nplayed && memcmp(mpu.played[j].raw, raw, sizeof raw) != 0)
            j++;
        if (j == mpu.nplayed) {
            if (skipped_bad < 5)
                printf("  decoded sample seq %u matches no played sample\n", q.seq);
            skipped_bad++;
            continue;
        }
        for (size_t x = pi; x < j; x++) {
            if (mpu.played[x].cycle >= stop_c && mpu.played[x].cycle <= start_c)
                skipped_ok++;
            else
                skipped_bad++;
        }
        if (!after_start && mpu.played[j].cycle > start_c) {
            after_start = 1;
            if (q.seq != 0)
                seq_bad++;
        } else if (have_prev && q.seq != (uint16_t)(prev_seq + 1) &&
                   !(s->unplug_t > 0 && prev_t < s->unplug_t && mpu.played[j].t > s->replug_t)) {
            if (seq_bad < 5)
                printf("  seq %u follows %u\n", q.seq, prev_seq);
            seq_bad++;
        }
        prev_seq = q.seq, have_prev = 1, prev_t = mpu.played[j].t;
        matched++;
        pi = j + 1;
    }
    for (size_t x = pi; x < mpu.nplayed; x++) /* the last one may still be in flight */
        if (mpu.played[x].cycle < end - CYC(0.02))
            skipped_bad++;
    check(matched > 0 && skipped_bad == 0,
          "every played sample decoded bit-exact and in order: %zu of %zu (%zu played while "
          "stopped, %zu missing or unmatched)",
          matched, mpu.nplayed, skipped_ok, skipped_bad);
    check(seq_bad == 0, "seq +1 per sample, 0 after START, a gap only over an outage (%zu breaks)", seq_bad);
    if (i_stop >= 0)
        check(skipped_ok > 0, "no SAMPLE frame between STOP and START (%zu samples held back)",
              skipped_ok);

    /* ---- 2. rate ---- */
    {
        double per = 1e6 / s->rate, maxdev = 0, sum = 0;
        size_t nd = 0, count = 0;
        double off_min = 1e30, off_max = -1e30;
        uint32_t prev_t = 0;
        uint16_t ps = 0;
        int hp = 0;
        size_t pj = 0;
        for (size_t k = 0; k < fr.n; k++) {
            if (fr.f[k].type != PROTO_SAMPLE)
                continue;
            proto_sample_t q;
            proto_parse_sample(fr.f[k].p, &q);
            double ts = q.t_us * 1e-6;
            /* the played sample it carries (same counts) */
            int16_t raw[7] = {q.ax, q.ay, q.az, q.temp, q.gx, q.gy, q.gz};
            while (pj < mpu.nplayed && memcmp(mpu.played[pj].raw, raw, sizeof raw) != 0)
                pj++;
            if (ts >= s->count_t0 && ts < s->count_t1) {
                count++;
                if (pj < mpu.nplayed) {
                    double off = US(mpu.played[pj].cycle) - q.t_us;
                    if (off < off_min)
                        off_min = off;
                    if (off > off_max)
                        off_max = off;
                }
                if (hp && q.seq == (uint16_t)(ps + 1)) {
                    double d = (double)(uint32_t)(q.t_us - prev_t) - per;
                    sum += d + per;
                    nd++;
                    if (fabs(d) > maxdev)
                        maxdev = fabs(d);
                }
            }
            prev_t = q.t_us, ps = q.seq, hp = 1;
        }
        double want = s->rate * (s->count_t1 - s->count_t0);
        check(fabs((double)count - want) <= 1.0,
              "%u Hz: %zu SAMPLE frames stamped in [%.1f, %.1f) s, %.0f expected", s->rate, count,
              s->count_t0, s->count_t1, want);
        check(nd > 0 && maxdev == 0.0,
              "%u Hz: period %.3f us mean over %zu, max deviation %.1f us (stamps are ticks: 0)",
              s->rate,
              nd ? sum / nd : 0.0, nd, maxdev);
        /* the chip latches after four TWI interrupts, each of which another
         * interrupt (Timer0, UART) can delay by up to ~5 us */
        check(off_max - off_min <= 24.0,
              "board clock against the simulated clock: chip latch - t_us in [%.1f, %.1f] us "
              "(latency spread <= 24 us, no drift)",
              off_min, off_max);
    }

    /* ---- 2b. seq against time: a gap in seq is a gap in time, exactly ---- */
    {
        int ia = find_cmd(s, "SET_RATE ok", 0), is = find_cmd(s, "START", 0);
        const frame_t *ra = ia >= 0 ? reply(&fr, s, ia, PROTO_ACK, 0) : NULL;
        const frame_t *sa = is >= 0 ? reply(&fr, s, is, PROTO_ACK, 0) : NULL;
        size_t pairs = 0, bad = 0, gaps = 0;
        uint32_t biggest = 0;
        int have = 0;
        proto_sample_t prev = {0};
        uint64_t prev_cyc = 0;
        for (size_t k = 0; k < fr.n; k++) {
            if (fr.f[k].type != PROTO_SAMPLE)
                continue;
            proto_sample_t q;
            proto_parse_sample(fr.f[k].p, &q);
            int straddle = (ra && prev_cyc < ra->cyc && fr.f[k].cyc > ra->cyc) ||
                           (sa && prev_cyc < sa->cyc && fr.f[k].cyc > sa->cyc);
            if (have && !straddle) {
                uint16_t ds = (uint16_t)(q.seq - prev.seq);
                uint32_t dt = q.t_us - prev.t_us;
                uint32_t per = (uint32_t)(1000000u / (ra && fr.f[k].cyc > ra->cyc ? s->rate : 100));
                pairs++;
                if ((uint32_t)ds * per != dt)
                    bad++;
                if (ds > 1) {
                    gaps++;
                    if (ds > biggest)
                        biggest = ds;
                }
            }
            prev = q, prev_cyc = fr.f[k].cyc, have = 1;
        }
        check(pairs > 0 && bad == 0,
              "seq against t_us: %zu consecutive pairs, every seq step is one period (%zu "
              "not); %zu gaps, the largest %u samples",
              pairs, bad, gaps, biggest);
        if (s->unplug_t > 0) {
            double resumed = 0;
            for (size_t i = 0; i < mpu.nplayed; i++)
                if (mpu.played[i].t > s->replug_t) {
                    resumed = mpu.played[i].t;
                    break;
                }
            check(gaps == 1 && biggest >= (s->replug_t - s->unplug_t) * 100 - 1,
                  "unplugged %.1f-%.1f s: one gap in seq (%u samples) covers it", s->unplug_t,
                  s->replug_t, biggest);
            check(resumed > 0 && resumed - s->replug_t < 1.3,
                  "the firmware set the chip up again: samples resume %.3f s after the replug",
                  resumed - s->replug_t);
            check(mpu_model_accel_fs(&mpu) == 4 && mpu_model_gyro_fs(&mpu) == 500 &&
                      (mpu.reg[0x1A] & 7) == 3 && !(mpu.reg[0x6B] & 0x40),
                  "after the replug the chip is awake at +-%d g, +-%d deg/s, DLPF %d again",
                  mpu_model_accel_fs(&mpu), mpu_model_gyro_fs(&mpu), mpu.reg[0x1A] & 7);
        }
    }

    /* ---- 3. dials ---- */
    {
        /* the instrument's own filter over the played samples */
        clino_calib_t cal;
        calib_init(&cal, &CLINO_CALIB);
        clino_filter_t flt;
        filter_init(&flt, FILTER_K_SOURCE);
        double *er = calloc(mpu.nplayed + 1, sizeof(double));
        double *ep = calloc(mpu.nplayed + 1, sizeof(double));
        uint16_t rate = 100;
        int ar = find_cmd(s, "SET_RATE ok", 0);
        int ir = find_cmd(s, "SET_RANGES ok", 0);
        const frame_t *rate_ack = ar >= 0 ? reply(&fr, s, ar, PROTO_ACK, 0) : NULL;
        const frame_t *range_ack = ir >= 0 ? reply(&fr, s, ir, PROTO_ACK, 0) : NULL;
        /* the firmware's decimation (filter.h): one step per dec samples by
         * seq; the harness's seq is the played index (no START in a scenario
         * that decimates) */
        double sum[6] = {0};
        int nsum = 0;
        float lr = 0, lp = 0;
        for (size_t i = 0; i < mpu.nplayed; i++) {
            const played_t *p = &mpu.played[i];
            if (rate_ack && p->cycle > rate_ack->cyc)
                rate = s->rate;
            if (range_ack && p->cycle > range_ack->cyc)
                calib_set_ranges(&cal, 8, 1000);
            for (int a = 0; a < 3; a++) {
                sum[a] += p->raw[a];
                sum[3 + a] += p->raw[4 + a];
            }
            nsum++;
            uint8_t dec = filter_decimation(rate);
            if (nsum >= dec || (uint16_t)(i % dec) == dec - 1) {
                float inv = 1.0f / (float)nsum, u[6];
                for (int a = 0; a < 6; a++) {
                    u[a] = (float)(int32_t)sum[a] * inv;
                    sum[a] = 0;
                }
                float h = (float)nsum / (float)rate;
                nsum = 0;
                float acc[3], gyr[3];
                calib_acc(&cal, u, acc);
                calib_gyr(&cal, u + 3, gyr);
                filter_update(&flt, gyr, acc, h);
                filter_angles(&flt, &lr, &lp);
            }
            er[i] = lr * 180.0 / M_PI;
            ep[i] = lp * 180.0 / M_PI;
        }
        int idial = find_cmd(s, "SET_DIALS", 0);
        double hd0 = idial >= 0 ? s->cmds[idial].t : 1e9;
        double hd1 = hd0 + 2.0 + 0.1;
        size_t checked = 0, bad = 0, nhost = 0, badhost = 0;
        double maxerr = 0, maxhost = 0;
        double hold_max[4] = {0};
        size_t hold_n[4] = {0};
        for (int ch = 0; ch < 2; ch++) {
            size_t j = 0;
            for (size_t k = 0; k < g_pulse[ch].n; k++) {
                const pulse_t *pu = &g_pulse[ch].p[k];
                double t = pu->rise / F_CPU;
                if (t < 0.5)
                    continue;
                if (t >= hd0 + 0.05 && t < hd0 + 1.95) { /* host dials: 45.00 and -30.00 deg */
                    double w = ch ? 1500.0 - 3000.0 / 18.0 : 1500.0 + 4500.0 / 18.0;
                    double e = fabs(pu->width_us - w);
                    nhost++;
                    if (e > maxhost)
                        maxhost = e;
                    if (e > 0.5 + 0.05)
                        badhost++;
                    continue;
                }
                if (t >= hd0 && t < hd1)
                    continue;
                while (j < mpu.nplayed && mpu.played[j].cycle < pu->rise)
                    j++;
                /* the value latched at this period's start comes from one of the
                 * last few samples processed before the rising edge */
                double best = 1e9;
                for (size_t b = 1; b <= 4 && b <= j; b++) {
                    double w = expected_width(ch ? ep[j - b] : er[j - b]);
                    double e = fabs(pu->width_us - w);
                    if (e < best)
                        best = e;
                }
                checked++;
                double edeg = best * 90.0 / 500.0;
                if (edeg > maxerr)
                    maxerr = edeg;
                if (best > 0.5 + 0.05) {
                    if (bad < 5)
                        printf("  pin %d pulse at %.4f s: %.2f us, filter says %.2f us\n",
                               ch ? 10 : 9, t, pu->width_us,
                               j ? expected_width(ch ? ep[j - 1] : er[j - 1]) : 0.0);
                    bad++;
                }
                for (int h = 0; h < s->nholds; h++) {
                    if (t >= s->holds[h].t0 && t < s->holds[h].t1) {
                        double dial = (pu->width_us - 1500.0) * 90.0 / 500.0;
                        double truth = ch ? s->holds[h].pitch_deg : s->holds[h].roll_deg;
                        double e = fabs(dial - truth);
                        if (e > hold_max[h])
                            hold_max[h] = e;
                        hold_n[h]++;
                    }
                }
            }
        }
        printf("  %zu pulses on pin 9, %zu on pin 10\n", g_pulse[0].n, g_pulse[1].n);
        double t_first = g_pulse[0].n ? g_pulse[0].p[0].rise / F_CPU : 0;
        double t_last = g_pulse[0].n ? g_pulse[0].p[g_pulse[0].n - 1].rise / F_CPU : 0;
        double per = g_pulse[0].n > 1 ? (t_last - t_first) / (g_pulse[0].n - 1) * 1e3 : 0;
        check(fabs(per - 20.0) < 1e-3, "servo period %.6f ms (50 Hz)", per);
        check(checked > 0 && bad == 0,
              "%zu filter-driven pulses match the source filter run here: max %.3f deg "
              "(%zu beyond one Timer1 tick, 0.5 us = 0.09 deg)",
              checked, maxerr, bad);
        for (int h = 0; h < s->nholds; h++)
            check(hold_n[h] > 0 && hold_max[h] <= 0.2,
                  "hold %.1f-%.1f s: dials within %.3f deg of the truth (roll %.0f, pitch %.0f; "
                  "<= 0.2 deg, %zu pulses)",
                  s->holds[h].t0, s->holds[h].t1, hold_max[h], s->holds[h].roll_deg,
                  s->holds[h].pitch_deg, hold_n[h]);
        if (idial >= 0)
            check(nhost > 0 && badhost == 0,
                  "SET_DIALS(45.00, -30.00 deg): %zu pulses at 1750.0/1333.3 us, max error "
                  "%.2f us; the filter takes the dials back 2 s later",
                  nhost, maxhost);
        free(er);
        free(ep);
    }

    /* ---- 4. commands ---- */
    for (int i = 0; i < s->ncmds; i++) {
        const command_t *c = &s->cmds[i];
        if (!strcmp(c->what, "SET_RATE ok"))
            check_ack(&fr, s, i, PROTO_SET_RATE, 0, 1);
        else if (!strcmp(c->what, "SET_RATE 1000 (too fast)") || !strcmp(c->what, "SET_RATE 0") ||
                 !strcmp(c->what, "SET_RATE 401 (past the link budget)"))
            check_ack(&fr, s, i, PROTO_SET_RATE, 1, 0);
        else if (!strcmp(c->what, "REQUEST_CONFIG"))
            check_ack(&fr, s, i, PROTO_REQUEST_CONFIG, 0, 1);
        else if (!strcmp(c->what, "SET_DIALS"))
            check_ack(&fr, s, i, PROTO_SET_DIALS, 0, 0); /* no CONFIG after SET_DIALS */
        else if (!strcmp(c->what, "SET_DIALS 95 deg"))
            check_ack(&fr, s, i, PROTO_SET_DIALS, 1, 0);
        else if (!strcmp(c->what, "SET_RANGES 3 g"))
            check_ack(&fr, s, i, PROTO_SET_RANGES, 1, 0);
        else if (!strcmp(c->what, "SET_RANGES ok"))
            check_ack(&fr, s, i, PROTO_SET_RANGES, 0, 1);
        else if (!strcmp(c->what, "unknown type 0x42"))
            check_ack(&fr, s, i, 0x42, 2, 0);
        else if (!strcmp(c->what, "bad CRC"))
            check_ack(&fr, s, i, PROTO_REQUEST_CONFIG, 3, 0);
        else if (!strcmp(c->what, "SET_RATE with 3 bytes"))
            check_ack(&fr, s, i, PROTO_SET_RATE, 3, 0);
        else if (!strcmp(c->what, "a SAMPLE sent to the board"))
            check_ack(&fr, s, i, PROTO_SAMPLE, 2, 0);
        else if (!strcmp(c->what, "overlong frame"))
            check_ack(&fr, s, i, 0, 3, 0);
        else if (!strcmp(c->what, "garbage"))
            check_ack(&fr, s, i, 0, 3, 0);
        else if (!strcmp(c->what, "STOP"))
            check_ack(&fr, s, i, PROTO_STOP, 0, 0);
        else if (!strcmp(c->what, "START"))
            check_ack(&fr, s, i, PROTO_START, 0, 0);
    }
    {
        int i = find_cmd(s, "SET_RATE ok", 0);
        const frame_t *c = i >= 0 ? reply(&fr, s, i, PROTO_CONFIG, 0) : NULL;
        if (c) {
            proto_config_t cc;
            proto_parse_config(c->p, &cc);
            check(cc.rate_hz == s->rate, "CONFIG after SET_RATE says %u Hz", cc.rate_hz);
        }
        i = find_cmd(s, "SET_RANGES ok", 0);
        c = i >= 0 ? reply(&fr, s, i, PROTO_CONFIG, 0) : NULL;
        if (c) {
            proto_config_t cc;
            proto_parse_config(c->p, &cc);
            check(cc.accel_fs_g == 8 && cc.gyro_fs_dps == 1000 && cc.dlpf_cfg == 2,
                  "CONFIG after SET_RANGES says +-%u g, +-%u deg/s, DLPF %u", cc.accel_fs_g,
                  cc.gyro_fs_dps, cc.dlpf_cfg);
        }
        i = find_cmd(s, "STOP", 0);
        c = i >= 0 ? reply(&fr, s, i, PROTO_SAMPLE, 1) : NULL;
        if (i >= 0)
            check(c == NULL, "STOP: at most the sample already in flight follows the ACK");
    }

    /* ---- 5. budget ---- */
    if (bw_state == 2) {
        uint64_t total = CYC(bw1) - CYC(bw0);
        uint64_t idle = idle_at_bw1 - idle_at_bw0;
        size_t n = played_at_bw1 - played_at_bw0;
        double busy_ps = (double)(total - idle) / (double)n;
        double main_ps = (double)(main_at1 - main_at0) / (double)(main_n1 - main_n0);
        double filt_ps = (double)(filt_at1 - filt_at0) / (double)(filt_n1 - filt_n0);
        double period = F_CPU / s->rate;
        double isr_all = 0;
        printf("  CPU per sample at %u Hz over [%.1f, %.1f) s (%zu samples, %.0f cycles each):\n",
               s->rate, bw0, bw1, n, period);
        printf("    busy (not asleep)            %8.0f cycles  %5.1f %%\n", busy_ps,
               100.0 * busy_ps / period);
        for (int v = 0; v < NVEC; v++) {
            if (isrn1[v] == isrn0[v])
                continue;
            double c = (double)(isr1[v] - isr0[v]) / (double)n;
            isr_all += c;
            printf("    ISR %-26s %8.0f cycles  (%.1f calls, %.0f cycles each)\n",
                   vec_name[v] ? vec_name[v] : "?", c, (double)(isrn1[v] - isrn0[v]) / n,
                   (double)(isr1[v] - isr0[v]) / (double)(isrn1[v] - isrn0[v]));
        }
        double in_main = (double)(inmain1 - inmain0) / (double)n;
        double main_only = main_ps * (double)(main_n1 - main_n0) / (double)n - in_main;
        printf("    main loop, sample work        %8.0f cycles  (frame + filter, D4 window less "
               "the ISRs inside it; %.0f per window, max %llu)\n",
               main_only, main_ps, (unsigned long long)g_probe_main.max);
        printf("      of which the filter step    %8.0f cycles  (%.0f per step, max %llu; D7 "
               "window)\n",
               filt_ps * (double)(filt_n1 - filt_n0) / (double)n, filt_ps,
               (unsigned long long)g_probe_filter.max);
        printf("    the rest (wake-ups, loop)     %8.0f cycles\n", busy_ps - isr_all - main_only);
        printf("BENCH %s rate_hz=%u samples=%zu busy_cycles_per_sample=%.0f cpu_pct=%.2f "
               "isr_cycles_per_sample=%.0f tick_isr=%.0f twi_isr=%.0f "
               "main_cycles_per_sample=%.0f filter_step=%.0f filter_step_max=%llu "
               "main_window_max=%llu\n",
               s->name, s->rate, n, busy_ps, 100.0 * busy_ps / period, isr_all,
               (double)(isr1[7] - isr0[7]) / n, (double)(isr1[24] - isr0[24]) / n, main_only,
               filt_ps, (unsigned long long)g_probe_filter.max,
               (unsigned long long)g_probe_main.max);
    }
done:
    free(fr.f);
    free(g_tx.b);
    free(g_tx.cyc);
    free(g_pulse[0].p);
    free(g_pulse[1].p);
    avr_terminate(avr);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s FIRMWARE.elf OUTDIR [100hz|400hz|unplug|nosensor|all]\n", argv[0]);
        return 2;
    }
    const char *which = argc > 3 ? argv[3] : "all";

    static scenario_t s100;
    s100.name = "100hz";
    s100.duration = 16.5;
    s100.rate = 100;
    s100.count_t0 = 1.0;
    s100.count_t1 = 12.0;
    command_t *c = s100.cmds;
    int n = 0;
    c[n++] = cmd_dials(12.5, 4500, -3000);
    c[n++] = cmd_frame(13.0, "REQUEST_CONFIG", PROTO_REQUEST_CONFIG, NULL, 0);
    c[n++] = cmd_u16(13.1, "SET_RATE 1000 (too fast)", PROTO_SET_RATE, 1000);
    c[n++] = cmd_u16(13.15, "SET_RATE 0", PROTO_SET_RATE, 0);
    c[n++] = cmd_frame(13.2, "unknown type 0x42", 0x42, NULL, 0);
    c[n++] = cmd_ranges(13.25, 3, 500, 3);
    c[n] = cmd_dials(13.3, 9500, 0);
    c[n++].what = "SET_DIALS 95 deg";
    {
        command_t b = cmd_frame(13.35, "bad CRC", PROTO_REQUEST_CONFIG, NULL, 0);
        b.wire[b.n - 2] ^= 0x40; /* the CRC's high byte (no zero in it) */
        c[n++] = b;
    }
    {
        static const uint8_t g[] = {0x01, 0x02, 0x03, 0x00};
        c[n++] = cmd_raw(13.4, "garbage", g, sizeof g);
    }
    {
        static const uint8_t p3[3] = {100, 0, 0};
        c[n++] = cmd_frame(13.45, "SET_RATE with 3 bytes", PROTO_SET_RATE, p3, 3);
        static const uint8_t p20[20] = {1, 2, 3};
        c[n++] = cmd_frame(13.5, "a SAMPLE sent to the board", PROTO_SAMPLE, p20, 20);
        static uint8_t longf[71];
        memset(longf, 0x5A, 70);
        longf[70] = 0;
        c[n++] = cmd_raw(13.55, "overlong frame", longf, sizeof longf);
    }
    c[n++] = cmd_frame(13.6, "STOP", PROTO_STOP, NULL, 0);
    c[n++] = cmd_frame(14.0, "START", PROTO_START, NULL, 0);
    c[n] = cmd_ranges(14.2, 8, 1000, 2);
    c[n++].what = "SET_RANGES ok";
    s100.ncmds = n;
    s100.holds[0] = (hold_t){4.0, 5.0, 30, -15};
    s100.holds[1] = (hold_t){11.0, 12.4, -20, 25};
    s100.holds[2] = (hold_t){15.0, 16.4, -20, 25};
    s100.nholds = 3;

    static scenario_t s400;
    s400.name = "400hz";
    s400.duration = 6.0;
    s400.rate = 400;
    s400.count_t0 = 1.0;
    s400.count_t1 = 5.5;
    s400.cmds[0] = cmd_u16(0.3, "SET_RATE ok", PROTO_SET_RATE, 400);
    s400.cmds[1] = cmd_u16(5.7, "SET_RATE 401 (past the link budget)", PROTO_SET_RATE, 401);
    s400.ncmds = 2;
    s400.holds[0] = (hold_t){4.0, 5.0, 30, -15};
    s400.nholds = 1;

    static scenario_t sunplug;
    sunplug.name = "unplug";
    sunplug.duration = 5.2;
    sunplug.rate = 100;
    sunplug.count_t0 = 0.5;
    sunplug.count_t1 = 1.5;
    sunplug.unplug_t = 2.0;
    sunplug.replug_t = 3.0;
    sunplug.holds[0] = (hold_t){4.5, 5.0, 30, -15};
    sunplug.nholds = 1;

    static scenario_t snone;
    snone.name = "nosensor";
    snone.duration = 3.5;
    snone.rate = 100;
    snone.no_sensor = 1;
    snone.cmds[0] = cmd_frame(2.5, "REQUEST_CONFIG", PROTO_REQUEST_CONFIG, NULL, 0);
    snone.ncmds = 1;

    if (!strcmp(which, "100hz") || !strcmp(which, "all"))
        run_scenario(argv[1], argv[2], &s100);
    if (!strcmp(which, "400hz") || !strcmp(which, "all"))
        run_scenario(argv[1], argv[2], &s400);
    if (!strcmp(which, "unplug") || !strcmp(which, "all"))
        run_scenario(argv[1], argv[2], &sunplug);
    if (!strcmp(which, "nosensor") || !strcmp(which, "all"))
        run_scenario(argv[1], argv[2], &snone);
    printf("\n%s: %d failed check(s)\n", failures ? "FAILED" : "PASSED", failures);
    return failures ? 1 : 0;
}
