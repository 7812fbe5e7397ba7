/* avr_uart.h - line output for the small AVR test programs run by motionemu (pid_avr/,
 * text_parse_avr/): polled USART0 writes; the harness reads the lines from the emulated port.
 * The caller sets the baud rate (UBRR0) and enables the transmitter. Header-only (static). */
#ifndef AVR_UART_H
#define AVR_UART_H

#include <avr/io.h>
#include <stdint.h>

static void tx(char c)
{
    while (!(UCSR0A & _BV(UDRE0)))
        ;
    UDR0 = (uint8_t)c;
}

/* s and CR LF */
static void println(const char *s)
{
    while (*s)
        tx(*s++);
    tx('\r');
    tx('\n');
}

#endif
