/*
 * The two dials of the source instrument: hobby servos on UNO pins 9 (OC1A,
 * PB1: roll) and 10 (OC1B, PB2: pitch), driven by Timer1 in hardware PWM
 * (fast PWM, TOP = ICR1, prescaler 8: 0.5 us per tick, 20 ms period = 50 Hz).
 * No interrupt is involved, so the pulses have no jitter.
 *
 * Mapping (documented in README.md, "The live instrument"): a dial angle a in
 * degrees, clamped to [-90, +90], gives the pulse width
 *     w = 1500 us + a * (500 us / 90 deg)        (1000 us .. 2000 us)
 * i.e. 5.556 us per degree, 0.09 deg per timer tick. Positive roll (about the
 * chip's +x by the right-hand rule: the +y edge rises) and positive pitch
 * (about +y: the +x edge dips) lengthen the pulse. For a servo that sweeps
 * 180 deg over 500..2500 us set SERVO_US_PER_90DEG to 1000.
 */
#ifndef CLINO_SERVO_H
#define CLINO_SERVO_H

#include <stdint.h>

#define SERVO_CENTER_US 1500
#define SERVO_US_PER_90DEG 500
#define SERVO_PERIOD_US 20000

void servo_init(void);
/* Both dials in centidegrees (clamped to +-9000). */
void servo_set_cdeg(int16_t roll_cdeg, int16_t pitch_cdeg);
/* Pulse width in timer ticks (0.5 us) for an angle in centidegrees. */
uint16_t servo_ticks(int16_t cdeg);

#endif
