/* PrintReal.h - the one printer of real numbers in the sketches' replies (avr-libc's dtostrf under
 * it; on the AVR double is float). Two rules, one for each kind of reply:
 *
 *   print_real(out, v, decimals)  at most `decimals` decimals, trailing zeros dropped: "0.02",
 *                                 "1", "-3.5"; -0 as "0", NaN as "nan", beyond +-1e9 "1e9+"/"-1e9+"
 *                                 (the servo sketches' gains and duty).
 *   print_real_exact(out, v, between)
 *                                 the fewest decimals (up to 6) that read back (strtod) as the same
 *                                 number, so a reply fed to motionsim reproduces the firmware's
 *                                 value ("20", "0.5", "333.3"); else 7 significant digits
 *                                 ("1.234567e-01"), as many as avr-libc's conversion gets right
 *                                 (the stepper sketches' ramp parameters). Each try costs about
 *                                 7,000 cycles: `between` (may be 0) is called before each, so a
 *                                 caller can keep other work going (the step planner).
 */
#ifndef MOTIONBOARD_PRINT_REAL_H
#define MOTIONBOARD_PRINT_REAL_H

#include <Arduino.h>

void print_real(Print &out, double v, uint8_t decimals);
void print_real_exact(Print &out, double v, void (*between)());

#endif
