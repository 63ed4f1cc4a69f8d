/*
 * clino_inclinometer: the MPU6050 + Arduino UNO inclinometer of
 * Sapegin & Strokach, "Micromechanical inclinometer", with clino's wire
 * protocol v1 (firmware/protocol/PROTOCOL.md).
 *
 *  - Timer2 ticks at 2 kHz; a phase accumulator turns the tick into the sample
 *    clock (rate_hz, exact mean rate for any integer rate, exact period when
 *    rate divides 2000). At each sample instant the tick interrupt stamps the
 *    sample with the tick's own time (t_us = 500 us per tick since the clock
 *    started at boot, wrapping at 2^32 us like micros(); exact, no interrupt
 *    latency in it) and starts the 14-byte MPU6050 burst read on the TWI;
 *    the TWI interrupt completes it. A sample instant whose read cannot start
 *    (bus still busy) or whose result the main loop has not taken yet is
 *    counted as lost and still advances seq, so the host sees the gap.
 *  - The main loop frames each sample (SAMPLE, COBS + CRC) into the serial
 *    transmit buffer when streaming (a frame that does not fit is dropped
 *    whole, never blocks), runs the source's instrument (calibration eqs 1-2,
 *    Poisson rectangles eq 3-4, complementary filter eq 5, k = 0.05; stepped
 *    at no more than 100 Hz, see filter.h) and sets the dials on pins 9 and
 *    10, unless the host sent dial angles in the last 2 s (SET_DIALS).
 *  - If burst reads keep failing (sensor unplugged or powered off), the chip
 *    is set up again once a second until it answers, with the ranges last
 *    asked for; seq goes on counting the instants missed.
 *  - Host commands (REQUEST_CONFIG, SET_RATE, SET_RANGES, START, STOP,
 *    SET_DIALS) are answered by an ACK; CONFIG follows at boot, on
 *    REQUEST_CONFIG and after an accepted SET_RATE or SET_RANGES (not after
 *    SET_DIALS, which a host sends about ten times a second: PROTOCOL.md).
 *  - Between samples the CPU sleeps (idle mode). Pin 4 (PD4) is high while
 *    the main loop works on a sample and pin 7 (PD7) while the filter runs:
 *    test points for the cycle budget (firmware/simavr measures them). They
 *    are on port D so that no read-modify-write touches port B, whose PB1
 *    and PB2 belong to Timer1 (simavr 1.6 lets a PORTB write override the
 *    compare outputs; the real chip does not).
 */
#include <Arduino.h>
#include <avr/interrupt.h>
#include <avr/sleep.h>

#include "calibration.h"
#include "filter.h"
#include "mpu6050.h"
#include "protocol.h"
#include "servo.h"

#define FW_MAJOR 0
#define FW_MINOR 1
#define FW_PATCH 0
#define BAUD 115200UL
#define DEFAULT_RATE_HZ 100u
/*
 * The link carries 115200 / 10 / 25 = 460 SAMPLE frames/s (the UNO's UART
 * runs at 117647 baud with U2X, 470/s); 400 Hz keeps 13 % for ACK and CONFIG
 * frames and is an exact period of the 2 kHz tick.
 */
#define MAX_RATE_HZ 400u
#define TICK_HZ 2000u
#define DIALS_HOLD_MS 2000u

/* ---- state shared with the interrupts ---- */
static volatile uint16_t rate_hz = DEFAULT_RATE_HZ;
static volatile uint16_t tick_acc;
static volatile uint32_t tick_us; /* the sample clock's time since boot, us */
static volatile uint8_t sampling_on; /* 0 while the sensor is being set up */
static volatile uint16_t next_seq;
/* Samples lost at the source (bus busy, main loop late, sampling paused) and
 * frames the transmit buffer had no room for: the host sees both as gaps in
 * seq; the counters are for a debugger. */
static volatile uint32_t lost_samples;

static uint8_t burst[MPU_BURST_LEN];
static volatile uint16_t burst_seq;
static volatile uint32_t burst_t_us;

static volatile uint8_t ready; /* a complete sample waits in ready_* */
static uint8_t ready_burst[MPU_BURST_LEN];
static volatile uint16_t ready_seq;
static volatile uint32_t ready_t_us;

/* ---- main-loop state ---- */
static mpu_ranges_t ranges = {4, 500, 3};
static uint8_t streaming = 1;
static volatile uint8_t sensor_ok;
static volatile uint8_t seq_running;  /* the sensor answered once: seq counts instants */
static volatile uint8_t fail_streak;  /* burst reads failed in a row */
static volatile uint8_t busy_streak;  /* sample instants found the bus still busy */
static volatile uint8_t sensor_lost;  /* set by the TWI interrupt, seen by the main loop */
#define LOST_AFTER_FAILS 10u          /* 0.1 s at 100 Hz: then set the chip up again */
#define ABORT_AFTER_BUSY 4u
static proto_rx_t rx;
static clino_calib_t calib;
static clino_filter_t filt;
static uint8_t host_dials;
static uint32_t host_dials_ms;
static uint32_t tx_dropped; /* see lost_samples */

static void on_burst_done(uint8_t ok)
{
    /* TWI interrupt context */
    if (!ok) {
        lost_samples++;
        if (++fail_streak >= LOST_AFTER_FAILS)
            sensor_lost = 1; /* unplugged or powered off: set it up again */
        return;
    }
    fail_streak = 0;
    if (ready) { /* main loop still busy with the previous one */
        lost_samples++;
        return;
    }
    for (uint8_t i = 0; i < MPU_BURST_LEN; i++)
        ready_burst[i] = burst[i];
    ready_seq = burst_seq;
    ready_t_us = burst_t_us;
    ready = 1;
}

ISR(TIMER2_COMPA_vect)
{
    tick_us += 1000000UL / TICK_HZ;
    tick_acc += rate_hz;
    if (tick_acc < TICK_HZ)
        return;
    tick_acc -= TICK_HZ;
    if (!sampling_on) {
        if (seq_running) { /* paused or sensor lost: the host sees a gap */
            next_seq++;
            lost_samples++;
        }
        return;
    }
    uint16_t seq = next_seq++;
    if (twi_busy()) {
        lost_samples++;
        if (++busy_streak >= ABORT_AFTER_BUSY) { /* a transfer that never ends */
            twi_abort();
            busy_streak = 0;
        }
        return;
    }
    busy_streak = 0;
    burst_seq = seq;
    /* the sample instant is the tick, whatever the interrupt latency */
    burst_t_us = tick_us;
    if (twi_start_read(MPU_REG_ACCEL_XOUT_H, burst, MPU_BURST_LEN, on_burst_done) != 0)
        lost_samples++;
}

static void sample_clock_init(void)
{
    /* Timer2 CTC, clk/32, OCR2A = 249: 16 MHz / 32 / 250 = 2000 Hz */
    TCCR2A = _BV(WGM21);
    TCCR2B = _BV(CS21) | _BV(CS20);
    OCR2A = (uint8_t)(F_CPU / 32UL / TICK_HZ - 1UL);
    TCNT2 = 0;
    TIMSK2 = _BV(OCIE2A);
}

/* ---- frames out ---- */
static void send_blocking(const uint8_t *buf, size_t n)
{
    Serial.write(buf, n);
}

static void send_ack(uint8_t cmd, uint8_t status)
{
    uint8_t f[PROTO_MAX_WIRE];
    send_blocking(f, proto_frame_ack(cmd, status, f));
}

static void send_config(void)
{
    proto_config_t c;
    c.proto_version = PROTO_VERSION;
    c.fw_major = FW_MAJOR;
    c.fw_minor = FW_MINOR;
    c.fw_patch = FW_PATCH;
    c.board = PROTO_BOARD_UNO;
    c.rate_hz = rate_hz;
    c.accel_fs_g = ranges.accel_fs_g;
    c.gyro_fs_dps = ranges.gyro_fs_dps;
    c.dlpf_cfg = ranges.dlpf_cfg;
    c.streaming = streaming;
    uint8_t f[PROTO_MAX_WIRE];
    send_blocking(f, proto_frame_config(&c, f));
}

static void handle_sample(const uint8_t *b, uint16_t seq, uint32_t t_us);

/* Take the waiting sample, if any, and process it (main loop only). */
static uint8_t drain_ready(void)
{
    if (!ready)
        return 0;
    PORTD |= _BV(PD4);
    uint8_t b[MPU_BURST_LEN];
    cli();
    for (uint8_t i = 0; i < MPU_BURST_LEN; i++)
        b[i] = ready_burst[i];
    uint16_t seq = ready_seq;
    uint32_t t = ready_t_us;
    ready = 0;
    sei();
    handle_sample(b, seq, t);
    PORTD &= (uint8_t)~_BV(PD4);
    return 1;
}

/* ---- sensor set-up (sampling paused while the bus is used here) ---- */
static void pause_sampling(void)
{
    sampling_on = 0;
    while (twi_busy())
        ;
    /* a sample read at the old ranges is processed with them */
    drain_ready();
}

static int setup_sensor(const mpu_ranges_t *r, uint8_t full_init)
{
    pause_sampling();
    int rc = full_init ? mpu_init(r) : mpu_set_ranges(r);
    if (rc == 0)
        calib_set_ranges(&calib, r->accel_fs_g, r->gyro_fs_dps);
    if (full_init)
        sensor_ok = (rc == 0);
    if (sensor_ok) {
        seq_running = 1;
        fail_streak = 0;
        sensor_lost = 0;
    }
    sampling_on = sensor_ok;
    return rc;
}

/* ---- host commands ---- */
static void handle_command(void)
{
    const uint8_t *p = rx.body + 1;
    uint8_t t = rx.type;
    switch (t) {
    case PROTO_REQUEST_CONFIG:
        send_ack(t, PROTO_ACK_OK);
        send_config();
        break;
    case PROTO_SET_RATE: {
        uint16_t r = proto_get_u16(p);
        if (r < 1 || r > MAX_RATE_HZ) {
            send_ack(t, PROTO_ACK_RANGE);
            break;
        }
        drain_ready(); /* a sample taken at the old rate keeps its step h */
        cli();
        rate_hz = r;
        tick_acc = 0;
        sei();
        /* the filter's partial step goes on with the new h */
        send_ack(t, PROTO_ACK_OK);
        send_config();
        break;
    }
    case PROTO_SET_RANGES: {
        mpu_ranges_t r = {p[0], proto_get_u16(p + 1), p[3]};
        if (!mpu_ranges_valid(&r)) {
            send_ack(t, PROTO_ACK_RANGE);
            break;
        }
        if (setup_sensor(&r, 0) != 0) { /* the chip refused: back to the old set */
            setup_sensor(&ranges, 0);
            send_ack(t, PROTO_ACK_RANGE);
            break;
        }
        ranges = r;
        send_ack(t, PROTO_ACK_OK);
        send_config();
        break;
    }
    case PROTO_START:
        cli();
        next_seq = 0;
        sei();
        streaming = 1;
        send_ack(t, PROTO_ACK_OK);
        break;
    case PROTO_STOP:
        streaming = 0;
        send_ack(t, PROTO_ACK_OK);
        break;
    case PROTO_SET_DIALS: {
        int16_t roll = proto_get_i16(p), pitch = proto_get_i16(p + 2);
        if (roll < -9000 || roll > 9000 || pitch < -9000 || pitch > 9000) {
            send_ack(t, PROTO_ACK_RANGE);
            break;
        }
        servo_set_cdeg(roll, pitch);
        host_dials = 1;
        host_dials_ms = millis();
        send_ack(t, PROTO_ACK_OK);
        break;
    }
    default: /* a board -> host type sent to the board */
        send_ack(t, PROTO_ACK_UNKNOWN);
        break;
    }
}

static void poll_serial(void)
{
    while (Serial.available() > 0) {
        int r = proto_rx_push(&rx, (uint8_t)Serial.read());
        if (r == PROTO_RX_FRAME)
            handle_command();
        else if (r == PROTO_RX_BAD)
            send_ack(rx.type, rx.bad_reason == PROTO_BAD_TYPE ? PROTO_ACK_UNKNOWN
                                                              : PROTO_ACK_BAD_FRAME);
    }
}

/* ---- one sample ---- */
static int16_t to_cdeg(float rad)
{
    float c = rad * (18000.0f / 3.14159265f);
    if (c > 9000.0f)
        c = 9000.0f;
    if (c < -9000.0f)
        c = -9000.0f;
    return (int16_t)(c >= 0 ? c + 0.5f : c - 0.5f);
}

static int32_t sum[6]; /* raw accel xyz, gyro xyz since the last filter step */
static uint8_t nsum;

static void handle_sample(const uint8_t *b, uint16_t seq, uint32_t t_us)
{
    int16_t raw[7];
    mpu_unpack(b, raw);
    if (streaming) {
        proto_sample_t s = {seq, t_us, raw[0], raw[1], raw[2], raw[3], raw[4], raw[5], raw[6]};
        uint8_t f[PROTO_MAX_WIRE];
        size_t n = proto_frame_sample(&s, f);
        if ((size_t)Serial.availableForWrite() >= n)
            Serial.write(f, n);
        else
            tx_dropped++;
    }
    for (uint8_t i = 0; i < 3; i++) {
        sum[i] += raw[i];
        sum[3 + i] += raw[4 + i];
    }
    nsum++;
    uint16_t rate = rate_hz;
    uint8_t dec = filter_decimation(rate);
    if (nsum < dec && seq % dec != (uint16_t)(dec - 1u))
        return;
    /* one filter step on the mean of the samples since the last one */
    float inv = 1.0f / (float)nsum, u[6];
    for (uint8_t i = 0; i < 6; i++) {
        u[i] = (float)sum[i] * inv;
        sum[i] = 0;
    }
    float h = (float)nsum / (float)rate;
    nsum = 0;
    float acc[3], gyr[3];
    calib_acc(&calib, u, acc);
    calib_gyr(&calib, u + 3, gyr);
    PORTD |= _BV(PD7);
    filter_update(&filt, gyr, acc, h);
    float roll, pitch;
    filter_angles(&filt, &roll, &pitch);
    PORTD &= (uint8_t)~_BV(PD7);
    if (host_dials && (uint32_t)(millis() - host_dials_ms) >= DIALS_HOLD_MS)
        host_dials = 0;
    if (!host_dials && filt.aligned)
        servo_set_cdeg(to_cdeg(roll), to_cdeg(pitch));
}

void setup()
{
    DDRD |= _BV(PD4);
    DDRD |= _BV(PD7);
    servo_init();
    Serial.begin(BAUD);
    proto_rx_init(&rx);
    calib_init(&calib, &CLINO_CALIB);
    filter_init(&filt, FILTER_K_SOURCE);
    twi_init();
    sample_clock_init();
    setup_sensor(&ranges, 1);
    send_config();
}

void loop()
{
    poll_serial();
    if (sensor_lost && sensor_ok) { /* reads keep failing: the chip went away */
        sampling_on = 0;
        sensor_ok = 0;
    }
    if (!sensor_ok) { /* no MPU6050 answered: try again every second */
        static uint32_t last_try;
        if ((uint32_t)(millis() - last_try) >= 1000u) {
            last_try = millis();
            setup_sensor(&ranges, 1);
        }
        return;
    }
    if (drain_ready())
        return;
    /* Nothing to do: sleep until the next interrupt (tick, TWI, UART, Timer0).
     * sei immediately before sleep is atomic, so no wake-up is missed. */
    set_sleep_mode(SLEEP_MODE_IDLE);
    cli();
    if (!ready && Serial.available() == 0) {
        sleep_enable();
        sei();
        sleep_cpu();
        sleep_disable();
    }
    sei();
}
