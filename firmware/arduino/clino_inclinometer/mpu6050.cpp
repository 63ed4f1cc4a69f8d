/* MPU6050 and the interrupt-driven TWI master; see mpu6050.h. */
#include "mpu6050.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/delay.h>

/* TWSR status codes (ATmega328P datasheet, tables 22-2 and 22-3). */
#define TW_START 0x08u
#define TW_REP_START 0x10u
#define TW_MT_SLA_ACK 0x18u
#define TW_MT_DATA_ACK 0x28u
#define TW_MR_SLA_ACK 0x40u
#define TW_MR_DATA_ACK 0x50u
#define TW_MR_DATA_NACK 0x58u

#define TWCR_GO (_BV(TWINT) | _BV(TWEN) | _BV(TWIE))

static volatile uint8_t tw_busy;
static volatile uint8_t tw_ok;
static uint8_t tw_reg;
static uint8_t *volatile tw_buf;
static volatile uint8_t tw_len, tw_idx;
static volatile uint8_t tw_reading; /* 1: read transaction, 0: write */
static volatile uint8_t tw_in_read_phase;
static volatile uint8_t tw_reg_sent;
static void (*volatile tw_done)(uint8_t ok);

void twi_init(void)
{
    TWSR = 0; /* prescaler 1 */
    TWBR = (uint8_t)(((F_CPU / 400000UL) - 16UL) / 2UL);
    TWCR = _BV(TWEN);
}

uint8_t twi_busy(void)
{
    return tw_busy;
}

static void tw_finish(uint8_t ok)
{
    TWCR = _BV(TWINT) | _BV(TWEN) | _BV(TWSTO);
    tw_ok = ok;
    tw_busy = 0;
    void (*cb)(uint8_t) = tw_done;
    if (cb)
        cb(ok);
}

ISR(TWI_vect)
{
    switch (TWSR & 0xF8u) {
    case TW_START:
    case TW_REP_START:
        TWDR = (uint8_t)((MPU_ADDR << 1) | (tw_in_read_phase ? 1u : 0u));
        TWCR = TWCR_GO;
        break;
    case TW_MT_SLA_ACK:
    case TW_MT_DATA_ACK:
        /* A transmitted byte was acknowledged. The driver keeps its own step
         * rather than trusting 0x18 (address) against 0x28 (data): simavr 1.6
         * reports 0x28 after SLA+W, and the step is what we sent anyway. */
        if (!tw_reg_sent) {
            TWDR = tw_reg;
            tw_reg_sent = 1;
            tw_idx = 0;
            TWCR = TWCR_GO;
        } else if (tw_reading) {
            tw_in_read_phase = 1;
            TWCR = TWCR_GO | _BV(TWSTA); /* repeated start */
        } else if (tw_idx < tw_len) {
            TWDR = tw_buf[tw_idx++];
            TWCR = TWCR_GO;
        } else {
            tw_finish(1);
        }
        break;
    case TW_MR_SLA_ACK:
        tw_idx = 0;
        TWCR = TWCR_GO | (tw_len > 1 ? _BV(TWEA) : 0);
        break;
    case TW_MR_DATA_ACK:
        tw_buf[tw_idx++] = TWDR;
        TWCR = TWCR_GO | (tw_idx + 1u < tw_len ? _BV(TWEA) : 0);
        break;
    case TW_MR_DATA_NACK:
        tw_buf[tw_idx++] = TWDR;
        tw_finish(tw_idx == tw_len);
        break;
    default: /* NACK of address or data, arbitration lost, bus error */
        tw_finish(0);
        break;
    }
}

static int tw_begin(uint8_t reg, uint8_t *buf, uint8_t n, uint8_t reading,
                    void (*done)(uint8_t))
{
    uint8_t sreg = SREG;
    cli();
    if (tw_busy) {
        SREG = sreg;
        return -1;
    }
    tw_busy = 1;
    SREG = sreg;
    /* A STOP still going out clears TWSTO when done. */
    for (uint16_t i = 0; (TWCR & _BV(TWSTO)) && i < 2000u; i++)
        ;
    tw_reg = reg;
    tw_buf = buf;
    tw_len = n;
    tw_reading = reading;
    tw_in_read_phase = 0;
    tw_reg_sent = 0;
    tw_done = done;
    tw_ok = 0;
    TWCR = TWCR_GO | _BV(TWSTA);
    return 0;
}

void twi_abort(void)
{
    TWCR = 0;
    tw_busy = 0;
    twi_init();
}

static int tw_wait(void)
{
    /* 20 ms: a 64-byte transfer at 400 kHz takes 1.5 ms. */
    for (uint16_t i = 0; tw_busy && i < 2000u; i++)
        _delay_us(10);
    if (tw_busy) { /* the bus hung: reset the unit */
        twi_abort();
        return -1;
    }
    return tw_ok ? 0 : -1;
}

int twi_start_read(uint8_t reg, uint8_t *buf, uint8_t n, void (*done)(uint8_t ok))
{
    return tw_begin(reg, buf, n, 1, done);
}

int twi_read_regs(uint8_t reg, uint8_t *buf, uint8_t n)
{
    if (tw_begin(reg, buf, n, 1, 0) != 0)
        return -1;
    return tw_wait();
}

int twi_write_reg(uint8_t reg, uint8_t value)
{
    static uint8_t v;
    v = value;
    if (tw_begin(reg, &v, 1, 0, 0) != 0)
        return -1;
    return tw_wait();
}

uint8_t mpu_ranges_valid(const mpu_ranges_t *r)
{
    uint8_t a = r->accel_fs_g;
    uint16_t g = r->gyro_fs_dps;
    return (a == 2 || a == 4 || a == 8 || a == 16) &&
           (g == 250 || g == 500 || g == 1000 || g == 2000) && r->dlpf_cfg <= 6;
}

static uint8_t fs_sel(uint16_t v, uint16_t base)
{
    uint8_t s = 0;
    while (v > base) {
        v >>= 1;
        s++;
    }
    return s;
}

int mpu_set_ranges(const mpu_ranges_t *r)
{
    if (!mpu_ranges_valid(r))
        return -1;
    uint8_t want[4] = {0, r->dlpf_cfg, (uint8_t)(fs_sel(r->gyro_fs_dps, 250) << 3),
                       (uint8_t)(fs_sel(r->accel_fs_g, 2) << 3)};
    for (uint8_t i = 0; i < 4; i++)
        if (twi_write_reg((uint8_t)(MPU_REG_SMPLRT_DIV + i), want[i]) != 0)
            return -1;
    uint8_t got[4];
    if (twi_read_regs(MPU_REG_SMPLRT_DIV, got, 4) != 0)
        return -1;
    for (uint8_t i = 0; i < 4; i++)
        if ((got[i] & (i == 1 ? 0x07u : 0xFFu)) != want[i])
            return -1;
    return 0;
}

int mpu_init(const mpu_ranges_t *r)
{
    uint8_t who = 0;
    if (twi_write_reg(MPU_REG_PWR_MGMT_1, 0x80) != 0) /* device reset */
        return -1;
    _delay_ms(100);
    if (twi_write_reg(MPU_REG_PWR_MGMT_1, 0x01) != 0) /* awake, PLL X gyro */
        return -1;
    _delay_ms(10);
    if (twi_read_regs(MPU_REG_WHO_AM_I, &who, 1) != 0 || (who & 0x7Eu) != MPU_WHO_AM_I)
        return -1;
    return mpu_set_ranges(r);
}

void mpu_unpack(const uint8_t *b, int16_t out[7])
{
    for (uint8_t i = 0; i < 7; i++)
        out[i] = (int16_t)(((uint16_t)b[2 * i] << 8) | b[2 * i + 1]);
}
