/* Servo dials on Timer1; see servo.h. */
#include "servo.h"

#include <avr/io.h>

uint16_t servo_ticks(int16_t cdeg)
{
    if (cdeg > 9000)
        cdeg = 9000;
    if (cdeg < -9000)
        cdeg = -9000;
    /* ticks = 2 * (1500 + cdeg * 500 / 9000), rounded to nearest */
    int32_t num = (int32_t)cdeg * (2 * SERVO_US_PER_90DEG);
    int32_t off = num >= 0 ? 4500 : -4500;
    return (uint16_t)(2 * SERVO_CENTER_US + (num + off) / 9000);
}

void servo_init(void)
{
    DDRB |= _BV(PB1) | _BV(PB2);
    TCCR1A = 0;
    TCCR1B = 0;
    TCNT1 = 0;
    ICR1 = (uint16_t)(2u * SERVO_PERIOD_US - 1u); /* 39999: 20 ms */
    OCR1A = servo_ticks(0) - 1u;
    OCR1B = servo_ticks(0) - 1u;
    /* non-inverting on OC1A and OC1B, mode 14 (fast PWM, TOP = ICR1), clk/8 */
    TCCR1A = _BV(COM1A1) | _BV(COM1B1) | _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS11);
}

void servo_set_cdeg(int16_t roll_cdeg, int16_t pitch_cdeg)
{
    /* OCR1x are double-buffered in PWM modes: no glitch mid-pulse. The pulse
     * is high from BOTTOM through the match, OCR1x + 1 ticks. */
    OCR1A = servo_ticks(roll_cdeg) - 1u;
    OCR1B = servo_ticks(pitch_cdeg) - 1u;
}
