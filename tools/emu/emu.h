/* emu.h - motionemu: runs a sketch's ELF on an emulated ATmega2560 (libsimavr) and records what
 * its pins and its serial port do, with exact CPU cycle timestamps.
 *
 * The harness is a plain C program around libsimavr 1.6. Pieces, one file each:
 *   motionemu.c     command line, ELF validation and loading, the run loop, reset/crash detection
 *   emu_log.c       the event log (one line per event, format in docs/emulator.md)
 *   emu_pins.c      Arduino Mega pin names (D54, A0, PF0), pin edge recording, inputs driven from outside
 *   emu_uart.c      UART0: paced input bytes, output lines; fixes simavr's 11-bit frame quirk
 *   emu_script.c    the INPUT script (send lines at given times, wait for replies, ...)
 *   emu_spi.c       the SPI master with true transfer timing, talking to an attached device
 *   ls7366r.c       the LS7366R quadrature counter (pure logic, datasheet behaviour)
 *   emu_motor.c     PWM duty measured from pin edges -> the DC-motor plant -> encoder counts
 *   emu_pty.c       --pty: UART0 on a pseudo-terminal, for a monitor (an interactive board)
 * Time is emulated: nothing sleeps (except with --pty, held to the wall clock); a second of
 * firmware time costs about 0.1 s of host time.
 */
#ifndef EMU_H
#define EMU_H

#include <stdint.h>
#include <stdio.h>

#include <sim_avr.h>
#include <avr_uart.h>
#include <avr_spi.h>

#define EMU_F_CPU 16000000u /* Arduino Mega 2560 crystal */

/* ---- event log (emu_log.c) ---- */
void emu_log_open(FILE *f);
void emu_log(uint64_t cycle, const char *tag, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* "<tag> <cycle> <text>" with text escaped: printable ASCII as is, backslash as \\, other bytes \xNN */
void emu_log_text(uint64_t cycle, const char *tag, const uint8_t *s, size_t n);
void emu_log_flush(void);
/* a failure: logged as "fail <cycle> <kind> <text>" and remembered for the exit status */
void emu_fail(uint64_t cycle, const char *kind, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
int emu_fail_count(void);
/* The conversation as it happens (motionemu --echo), one line each, flushed at once:
 * "[  0.512 s] > 50" (host -> firmware), "[  0.530 s] < OK 0 50" (firmware -> host). */
void emu_echo_open(FILE *f);
int emu_echo_on(void);
void emu_echo(uint64_t cycle, char dir, const uint8_t *s, size_t n);
void emu_echo_note(uint64_t cycle, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
uint64_t emu_echo_quiet_ms(void); /* wall-clock ms since the last echo line */
uint64_t emu_wall_ms(void);       /* CLOCK_MONOTONIC in ms */

/* ---- pins (emu_pins.c) ---- */
typedef struct {
    char port; /* 'A'..'L' */
    uint8_t bit;
} emu_pin_t;

/* "D54", "54", "A0" (analog pin 0 = D54), "PF0" or "F0". Returns 0 on success. */
int emu_pin_parse(const char *spec, emu_pin_t *pin);
/* Watch a pin: every level change is logged as "pin <cycle> <name> <level>", every change of its
 * DDRx bit as "ddr <cycle> <name> <1 output | 0 input>" (reset state: input, level 0). */
int emu_pin_watch(avr_t *avr, const char *name, emu_pin_t pin);
/* Calls fn(param, cycle, new_level) on every level change of the pin, before the new level is
 * stored: inside fn, emu_pin_level() of that pin still reports the level before the edge. */
typedef void (*emu_pin_fn)(void *param, uint64_t cycle, int level);
int emu_pin_listen(avr_t *avr, emu_pin_t pin, emu_pin_fn fn, void *param);
/* Current level of the pin. */
int emu_pin_level(avr_t *avr, emu_pin_t pin);
/* on = 1: the harness drives the pin at `level` (an emulated timer output), PORT is ignored;
 * on = 0: the pin follows PORT again. `cycle` is when the edge happens (an emulated timer's
 * exact compare-match cycle; simavr calls back at the next instruction boundary). */
void emu_pin_drive(avr_t *avr, emu_pin_t pin, int on, int level, uint64_t cycle);

/* The outside world drives the pin (a switch, an endstop; script command "pin"): while the pin is
 * an input its PINx bit reads `level` whatever its pull-up (PORTx bit) says, as a switch to GND
 * beats the internal pull-up; pin change and external interrupts see the edge. While the firmware
 * makes it an output, PORT wins (PINx reads PORTx, as simavr does) and the level applies again
 * when it becomes an input. From the call on, until the next call for the pin. *was_output: 1 if
 * the pin is an output now. 0 ok, -1 if the port does not answer. */
int emu_pin_input(avr_t *avr, emu_pin_t pin, int level, int *was_output);

/* ---- phase-correct PWM outputs (emu_pwm.c) ---- */
/* Emulates the output compare pin if `pin` is OCnA/B/C of timers 1, 3, 4, 5 (no-op otherwise). */
int emu_pwm_attach(avr_t *avr, emu_pin_t pin);
/* The period in cycles of the emulated timer whose output compare pin this is, while it runs in
 * a dual-slope PWM mode (0: not an attached OCnx pin, or its timer is stopped). */
uint64_t emu_pwm_period(emu_pin_t pin);

/* ---- UART0 (emu_uart.c) ---- */
typedef struct emu_line {
    uint64_t cycle; /* cycle at which the firmware wrote the line's final LF into UDR0 */
    char *text;     /* without CR/LF, raw bytes (may hold non-printables) */
    size_t len;
} emu_line_t;

int emu_uart_attach(avr_t *avr);

/* emu_timer.c: simavr's timers keep a compare match due right after a wrap, and a TIFRn write clears
 * only the flags written as 1 (see the file); -1 when this simavr lacks the registers. */
int emu_timer_attach(avr_t *avr);
/* after emu_timer_attach: log Timer1's compare matches ("match <cycle> OC1A|OC1B|OC1C") */
int emu_timer_log_matches(avr_t *avr);
/* queue bytes to send to the firmware; they arrive one frame time apart */
void emu_uart_send(const uint8_t *bytes, size_t n);
size_t emu_uart_pending(void);
/* lines received so far (the array grows; index stays valid) */
size_t emu_uart_line_count(void);
/* The CPU's program counter (byte address) now: where a sketch that stopped answering is. */
uint32_t emu_uart_cpu_pc(void);
const emu_line_t *emu_uart_line(size_t i);
uint32_t emu_uart_cycles_per_byte(void);
int emu_uart_ready_count(void);

/* ---- script (emu_script.c) ---- */
int emu_script_load(const char *path); /* 0 ok; prints errors with line numbers */
int emu_script_load_text(const char *text, const char *name);
/* Runs the script as far as it can at this cycle; returns the cycle at which to call it again
 * (UINT64_MAX: only when a new line arrives). Sets *finished when the script has ended. */
uint64_t emu_script_step(avr_t *avr, int *finished);
/* line number (and script name) of the first 'encoder' command, 0 if there is none */
int emu_script_encoder_line(const char **name);

/* ---- UART0 as a pseudo-terminal (emu_pty.c, motionemu --pty) ---- */
/* Opens a pty (posix_openpt, grantpt, unlockpt), sets its terminal side raw (any baud setting is
 * accepted: the emulated UART keeps the firmware's own rate); path: its name (ptsname). 0 ok. */
int emu_pty_open(char *path, size_t cap);
/* 1 while a program has the terminal side open (a monitor, picocom, pyserial) */
int emu_pty_connected(void);
/* Moves bytes: the host's input to the firmware's UART (logged "txraw", echoed per line), the
 * firmware's output (emu_pty_put) to the host. Returns -1 once the host has closed the port. */
int emu_pty_service(uint64_t cycle);
void emu_pty_put(uint8_t byte);
/* the firmware's UART0 output, byte by byte, also goes to fn (NULL: nowhere else) */
void emu_uart_set_sink(void (*fn)(uint8_t byte));

/* ---- SPI master + attached device (emu_spi.c) ---- */
typedef struct {
    void *ctx;
    void (*select)(void *ctx, uint64_t cycle, int cs_level); /* chip select pin level */
    uint8_t (*transfer)(void *ctx, uint64_t cycle, uint8_t mosi); /* one byte, returns MISO */
} emu_spi_device_t;
int emu_spi_attach(avr_t *avr, emu_pin_t cs, const emu_spi_device_t *dev);
uint64_t emu_spi_byte_count(void);

/* ---- DC motor + LS7366R (emu_motor.c) ---- */
typedef struct {
    emu_pin_t pwm, dir, brake, cs;
    int have_brake;
    int dir_high_positive; /* 1: DIR high = positive duty (counts increase) */
    int brake_high_active; /* 1: BRAKE high = braking */
} emu_motor_config_t;
int emu_motor_attach(avr_t *avr, const emu_motor_config_t *cfg);
/* an LS7366R alone (no motor): its encoder position is set by emu_encoder_set (script "encoder") */
int emu_encoder_attach(avr_t *avr, emu_pin_t cs);
void emu_encoder_set(int64_t quad_count);
void emu_motor_summary(uint64_t cycle);

#endif
