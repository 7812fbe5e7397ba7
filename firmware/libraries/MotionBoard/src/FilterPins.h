/* FilterPins.h - pins and timers of the MovingAverageFilter sketch (Arduino Mega 2560), in one
 * place. Change them here only.
 *
 * | signal           | Mega pin | AVR pin   | what                                                    |
 * |------------------|----------|-----------|---------------------------------------------------------|
 * | input voltage    | A0       | PF0/ADC0  | 0-5 V, 10-bit ADC referred to AVcc (5 V): 1023 = 5.000 V |
 * | filtered output  | D6       | PH3/OC4A  | PWM, duty = y / 5 V, 1.6 kHz, 5000 steps of 1 mV         |
 * | sample strobe    | D22      | PA0       | toggles first thing in every 100 Hz sample interrupt     |
 *
 * Timers: Timer1 is the sample clock (CTC mode 4, clk/256 = 62.5 kHz, OCR1A = 624: exactly
 * 625 ticks = 10.000 ms per sample, one tick = 16 us = 256 CPU cycles). Timer4 makes the PWM
 * (phase-correct mode 10, clk/1, TOP = ICR4 = 5000, so OCR4A = y in mV). Timer5 runs free at clk/1
 * and only measures the per-sample cost in CPU cycles (`cost` command). Timer0 stays with the
 * Arduino core (millis). Put an RC low-pass on D6 (e.g. 10 kOhm + 10 uF, 0.1 s) to see the output
 * as a voltage, like the filter note's RC circuit.
 */
#ifndef FILTER_PINS_H
#define FILTER_PINS_H

#include <avr/io.h>

#define FILTER_INPUT_ADC_CHANNEL 0 /* A0 */

#define FILTER_PWM_PIN 6           /* D6 = OC4A */
#define FILTER_PWM_TOP 5000u       /* ICR4: one PWM step = 5 V / 5000 = 1 mV */

#define FILTER_STROBE_PIN 22       /* D22 = PA0 */
#define FILTER_STROBE_DDR DDRA
#define FILTER_STROBE_PINREG PINA  /* writing 1 to a PINx bit toggles the pin (one instruction) */
#define FILTER_STROBE_BIT PA0

#define FILTER_SAMPLE_HZ 100u
#define FILTER_TIMER1_PRESCALE 256u
#define FILTER_TIMER1_TOP (F_CPU / FILTER_TIMER1_PRESCALE / FILTER_SAMPLE_HZ - 1u) /* 624 */

#endif
