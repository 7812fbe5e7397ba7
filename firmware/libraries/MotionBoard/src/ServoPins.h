/* ServoPins.h - the one place for the pins of the servo sketches (ProportionalClosedLoop,
 * PIDClosedLoop) on the Arduino Mega 2560 with an Arduino Motor Shield R3 (L298P, channel A)
 * and an LS7366R quadrature counter on the hardware SPI bus.
 *
 *   signal                 pin   notes
 *   LS7366R MISO           D50   hardware SPI (SPI library), mode 0, MSB first, 4 MHz
 *   LS7366R MOSI           D51
 *   LS7366R SCK            D52
 *   LS7366R /SS (CS)       D53   the Mega's SS pin, which must be an output for SPI master anyway
 *   H-bridge PWM (EN A)    D3    Timer3 OC3C, 490 Hz phase-correct, analogWrite 0..255
 *   H-bridge DIR A         D12   high = positive duty (encoder counts increase)
 *   H-bridge BRAKE A       D9    held low (brake off)
 *   (Motor Shield R3 current sense A0 is not used.)
 * Wire the encoder so that positive duty makes the count increase; if it runs the other way,
 * swap the encoder's A and B lines (or the motor leads).
 */
#ifndef SERVO_PINS_H
#define SERVO_PINS_H

#include <stdint.h>

static const uint8_t SERVO_PIN_ENCODER_CS = 53;
static const uint8_t SERVO_PIN_PWM = 3;
static const uint8_t SERVO_PIN_DIR = 12;
static const uint8_t SERVO_PIN_BRAKE = 9;

#endif
