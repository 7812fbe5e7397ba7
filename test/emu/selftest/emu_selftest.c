/* emu_selftest.c - a tiny ATmega2560 program with behaviour known from first principles, used by
 * test/emu/test_emu.py to prove the harness (tools/emu) right before it judges the sketches.
 * Plain avr-libc, no Arduino core, so every cycle count below follows from the datasheet:
 *  - at boot, with interrupts off: PF1 (D55) toggled 10 times exactly 1000 cycles apart
 *    (sbi PINF = 2 cycles + __builtin_avr_delay_cycles(998));
 *  - Timer1 CTC, prescaler 8, OCR1A = 1999: OC1A (PB5, D11) toggled by hardware every
 *    2000 * 8 = 16000 cycles; the compare ISR toggles PF0 (D54) too;
 *  - Timer3 phase-correct 8-bit PWM, prescaler 64 (Arduino's setting) on OC3C (PE5, D3):
 *    duty = OCR3C / 255, period 510 * 64 = 32640 cycles;
 *  - UART0 9600 baud 8N1 (U2X0 = 1, UBRR0 = 207): one byte = 10 * 8 * 208 = 16640 cycles;
 *  - SPI master fosc/16, mode 0: one byte = 8 * 16 = 128 cycles; LS7366R on CS = PB0 (D53).
 * Commands (lines ending in CR LF): ping, ?, burst, enc, enc2, mdr, spi, adc, pwm <0..255>,
 * dir (PF2 = D56, interrupts off, one change every 1000 cycles: output low, input, pull-up on, output
 * high, output low: the harness must log its direction changes as well as its level changes),
 * reset (jumps to 0), wdt (watchdog reset), halt (cli; sleep), wild (writes beyond the SRAM), void
 * (calls into erased flash), recurse (recursion without end), heapdig (5,000 bytes of heap, then a
 * bounded recursion into it), pastdig (a deep recursion returned from, then the heap grown over
 * where it was), latedig (pastdig, then as deep again: into the heap, above the first lowest SP), dig1 (OC3C off, PE5 high by PORT, as
 * analogWrite(pin, 255)), rev <0..255> (analogWrite(pin, 0) then (pin, v), as on a motor reversal),
 * wrap <k> [<n>] (Timer5 normal mode, clk/1: with interrupts off, waits for TCNT5 >= 65000, writes
 * OCR5A = k, which matches at tick k of the next period, toggles PF3 (D57), waits n nops, then runs
 * calls and returns (long instructions) across the wrap; the compare ISR toggles PF3 again:
 * 65536 - TCNT5 + k cycles after the write, plus the ISR's entry, whatever k; replies "OK wrap k"),
 * rewrap <k> (Timer5 normal mode, clk/1: OCR5B = k written once, mid-period, its compare interrupt on;
 * the compare B ISR toggles PF3 and counts; calls and returns for about 13 wraps, interrupts on:
 * every wrap's match toggles PF3, 65,536 cycles apart; replies "OK rewrap k <matches>"),
 * tifr (Timer5, interrupts off, OCIE5A on: OCR5A and OCR5B match, both flags set, then TIFR5 = OCF5B,
 * which clears only OCF5B; PF3 toggled, interrupts on: the compare A ISR toggles PF3 at once),
 * pins ("OK pins d2=<PINE4> d18=<PIND3> int4=<n>": two inputs, D2 = PE4 with its pull-up on, D18 = PD3
 * without, and n, the falling edges of D2 counted by INT4's interrupt since boot: what the harness's
 * 'pin' command drives from outside),
 * anything else -> "ERR unknown".
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <avr/wdt.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

extern char *__brkval;   /* avr-libc malloc's top (0 before the first malloc) */
extern char __heap_start; /* the linker's: the first byte after .bss */

static void tx(char c)
{
    while (!(UCSR0A & _BV(UDRE0)))
        ;
    UDR0 = (uint8_t)c;
}

static void print(const char *s)
{
    while (*s)
        tx(*s++);
}

static void println(const char *s)
{
    print(s);
    print("\r\n");
}

static uint8_t spi_byte(uint8_t b)
{
    SPDR = b;
    while (!(SPSR & _BV(SPIF)))
        ;
    return SPDR;
}

#define CS_LOW() (PORTB &= (uint8_t)~_BV(PB0))
#define CS_HIGH() (PORTB |= _BV(PB0))

static void ls_write(uint8_t ir, uint8_t v)
{
    CS_LOW();
    spi_byte(ir);
    spi_byte(v);
    CS_HIGH();
}

static uint32_t ls_read(uint8_t ir, uint8_t n)
{
    uint32_t v = 0;
    CS_LOW();
    spi_byte(ir);
    for (uint8_t i = 0; i < n; i++)
        v = (v << 8) | spi_byte(0);
    CS_HIGH();
    return v;
}

/* beyond the ATmega2560's data space (0x0000-0x21FF): no memory answers there */
static volatile uint16_t wild_addr = 0x8000;
/* a word address in the erased flash above this small program (256 KiB flash: 0x00000-0x1FFFF words) */
static volatile uint16_t void_addr = 0xF000;

/* recursion without end: each level keeps a frame alive (the sum uses it after the call) */
static uint16_t deep(uint16_t n)
{
    volatile uint8_t frame[16];
    frame[n & 15] = (uint8_t)n;
    return (uint16_t)(deep(n + 1) + frame[n & 15]);
}

/* a bounded recursion, about 40 bytes of stack a level */
static uint16_t dig(uint16_t n)
{
    volatile uint8_t frame[32];
    frame[n & 31] = (uint8_t)n;
    if (n == 0)
        return 0;
    return (uint16_t)(dig(n - 1) + frame[n & 31]);
}

ISR(TIMER1_COMPA_vect)
{
    PINF = _BV(PF0);
}

static volatile uint16_t int4_falls;

ISR(INT4_vect)
{
    int4_falls++;
}

static void __attribute__((noinline)) call_nothing(void)
{
    __asm__ __volatile__("");
}

ISR(TIMER5_COMPA_vect)
{
    PINF = _BV(PF3);
    TIMSK5 = 0;
}

static volatile uint8_t rewrap_matches;

ISR(TIMER5_COMPB_vect)
{
    PINF = _BV(PF3);
    rewrap_matches = (uint8_t)(rewrap_matches + 1U);
}

#define TOGGLE_1000()                                   \
    do {                                                \
        __asm__ __volatile__("sbi %0, 1" ::"I"(_SFR_IO_ADDR(PINF))); \
        __builtin_avr_delay_cycles(998);                \
    } while (0)

/* one sbi/cbi (2 cycles) then 998 cycles: 1000 cycles per change */
#define SBI_1000(reg, bit)                                                    \
    do {                                                                      \
        __asm__ __volatile__("sbi %0, %1" ::"I"(_SFR_IO_ADDR(reg)), "I"(bit)); \
        __builtin_avr_delay_cycles(998);                                      \
    } while (0)
#define CBI_1000(reg, bit)                                                    \
    do {                                                                      \
        __asm__ __volatile__("cbi %0, %1" ::"I"(_SFR_IO_ADDR(reg)), "I"(bit)); \
        __builtin_avr_delay_cycles(998);                                      \
    } while (0)

int main(void)
{
    MCUSR = 0;
    wdt_disable();
    DDRF = _BV(PF0) | _BV(PF1) | _BV(PF3);
    DDRB = _BV(PB0) | _BV(PB1) | _BV(PB2) | _BV(PB5); /* CS, SCK, MOSI, OC1A */
    DDRE = _BV(PE5);
    CS_HIGH();

    TOGGLE_1000(); TOGGLE_1000(); TOGGLE_1000(); TOGGLE_1000(); TOGGLE_1000();
    TOGGLE_1000(); TOGGLE_1000(); TOGGLE_1000(); TOGGLE_1000(); TOGGLE_1000();

    UCSR0A = _BV(U2X0);
    UBRR0 = 207;
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    UCSR0B = _BV(RXEN0) | _BV(TXEN0);

    SPCR = _BV(SPE) | _BV(MSTR) | _BV(SPR0); /* mode 0, MSB first, fosc/16 */
    ls_write(0x88, 0x03);                    /* WR MDR0: x4, free-running */
    ls_write(0x90, 0x00);                    /* WR MDR1: 4 bytes, counting enabled */
    CS_LOW();
    spi_byte(0x20);                          /* CLR CNTR */
    CS_HIGH();

    TCCR1A = _BV(COM1A0);                    /* toggle OC1A on compare match */
    OCR1A = 1999;
    TCCR1B = _BV(WGM12) | _BV(CS11);         /* CTC, clk/8 */
    TIMSK1 = _BV(OCIE1A);

    TCCR3A = _BV(WGM30);                     /* phase-correct 8-bit, OC3C off until 'pwm' */
    TCCR3B = _BV(CS31) | _BV(CS30);          /* clk/64 */
    PORTE |= _BV(PE4);                       /* D2: input with pull-up; D18 (PD3): input, none */
    EICRB = _BV(ISC41);                      /* INT4 (D2) on a falling edge */
    EIFR = _BV(INTF4);
    EIMSK = _BV(INT4);
    sei();

    println("READY EmuSelfTest");
    char line[64];
    uint8_t len = 0;
    uint16_t count = 0;
    for (;;) {
        if (!(UCSR0A & _BV(RXC0)))
            continue;
        char c = (char)UDR0;
        if (c == '\r')
            continue;
        if (c != '\n') {
            if (len < sizeof line - 1)
                line[len++] = c;
            continue;
        }
        line[len] = 0;
        len = 0;
        count++;
        char buf[48];
        if (!strcmp(line, "ping")) {
            println("OK pong");
        } else if (!strcmp(line, "?")) {
            snprintf(buf, sizeof buf, "n=%u", count);
            println(buf);
        } else if (!strcmp(line, "burst")) {
            println("0123456789");
            println("0123456789");
        } else if (!strcmp(line, "enc")) {
            snprintf(buf, sizeof buf, "OK enc %ld", (long)ls_read(0x60, 4)); /* RD CNTR */
            println(buf);
        } else if (!strcmp(line, "enc2")) {
            ls_write(0x90, 0x02);                                             /* 2-byte mode */
            uint32_t v2 = ls_read(0x60, 2);
            ls_write(0x90, 0x00);
            CS_LOW();
            spi_byte(0xE8);                                                   /* LOAD OTR */
            CS_HIGH();
            snprintf(buf, sizeof buf, "OK enc2 %lu otr %ld", (unsigned long)v2, (long)ls_read(0x68, 4));
            println(buf);
        } else if (!strcmp(line, "mdr")) {
            snprintf(buf, sizeof buf, "OK mdr0=%lu mdr1=%lu", (unsigned long)ls_read(0x48, 1),
                     (unsigned long)ls_read(0x50, 1));
            println(buf);
        } else if (!strcmp(line, "spi")) {
            uint8_t sreg = SREG;
            cli();
            TCCR4A = 0;
            TCCR4B = _BV(CS40);  /* clk/1 */
            uint16_t t0 = TCNT4;
            SPDR = 0;
            while (!(SPSR & _BV(SPIF)))
                ;
            uint16_t t1 = TCNT4;
            (void)SPDR;
            SREG = sreg;
            snprintf(buf, sizeof buf, "OK spi %u", (unsigned)(t1 - t0));
            println(buf);
        } else if (!strcmp(line, "adc")) {
            ADMUX = _BV(REFS0);  /* AVCC reference, channel 0 */
            ADCSRB = 0;
            ADCSRA = _BV(ADEN) | _BV(ADSC) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);
            while (ADCSRA & _BV(ADSC))
                ;
            snprintf(buf, sizeof buf, "OK adc %u", ADC);
            println(buf);
        } else if (!strncmp(line, "pwm ", 4)) {
            int v = atoi(line + 4);
            OCR3C = (uint8_t)v;
            TCCR3A = _BV(WGM30) | _BV(COM3C1);
            snprintf(buf, sizeof buf, "OK pwm %d", v);
            println(buf);
        } else if (!strcmp(line, "udre")) {
            /* the transmitter off and on again (as the core's init() and Serial.begin() do), nothing
             * being sent: UDRE0 reads 1 on the chip. The reply's first byte is then written without
             * polling, so that an emulator that cleared UDRE0 still answers ("OK udre 0"). */
            UCSR0B = 0;
            UCSR0B = _BV(RXEN0) | _BV(TXEN0);
            uint8_t udre = (UCSR0A & _BV(UDRE0)) ? 1 : 0;
            UDR0 = 'O';
            snprintf(buf, sizeof buf, "K udre %u", udre);
            println(buf);
        } else if (!strcmp(line, "dir")) {
            uint8_t sreg = SREG;
            cli();
            SBI_1000(DDRF, PF2);  /* output, PORTF2 = 0: driven low (direction 1, level stays 0) */
            CBI_1000(DDRF, PF2);  /* input (direction 0) */
            SBI_1000(PORTF, PF2); /* input with pull-up: reads 1 (level 1) */
            SBI_1000(DDRF, PF2);  /* output high (direction 1) */
            CBI_1000(PORTF, PF2); /* output low (level 0) */
            SREG = sreg;
            println("OK dir");
        } else if (!strcmp(line, "reset")) {
            println("OK jumping to 0");
            while (!(UCSR0A & _BV(TXC0)))
                ;
            __asm__ __volatile__("jmp 0");
        } else if (!strcmp(line, "wdt")) {
            println("OK watchdog");
            wdt_enable(WDTO_15MS);
            for (;;)
                ;
        } else if (!strcmp(line, "halt")) {
            println("OK halt");
            while (!(UCSR0A & _BV(TXC0)))
                ;
            cli();
            set_sleep_mode(SLEEP_MODE_PWR_DOWN);
            sleep_enable();
            sleep_cpu();
        } else if (!strcmp(line, "wild")) {
            println("OK writing beyond the SRAM");
            while (!(UCSR0A & _BV(TXC0)))
                ;
            *(volatile uint8_t *)wild_addr = 0x55;
            println("OK still running");
        } else if (!strcmp(line, "void")) {
            println("OK jumping into empty flash");
            while (!(UCSR0A & _BV(TXC0)))
                ;
            ((void (*)(void))void_addr)();
        } else if (!strcmp(line, "recurse")) {
            println("OK recursing without end");
            while (!(UCSR0A & _BV(TXC0)))
                ;
            snprintf(buf, sizeof buf, "depth %u", deep(1));
            println(buf);
        } else if (!strcmp(line, "heapdig")) {
            /* 5,000 bytes of heap, then about 4 KB of stack: the stack runs into the heap (its
             * end, __brkval) and stays far above __heap_start */
            volatile uint8_t *heap = (volatile uint8_t *)malloc(5000);
            if (!heap) {
                println("ERR no heap");
            } else {
                heap[0] = 1;
                println("OK digging into the heap");
                while (!(UCSR0A & _BV(TXC0)))
                    ;
                snprintf(buf, sizeof buf, "dug %u", dig(100));
                println(buf);
            }
        } else if (!strcmp(line, "pastdig") || !strcmp(line, "latedig")) {
            /* about 2.4 KB of stack first, returned from; then the heap grown to 1.2 KB below the
             * stack pointer, over where that stack was (no overflow: it is not there any more);
             * latedig then digs as deep again, into the heap, never below its first lowest point */
            uint16_t sp0 = SP;
            char *top = __brkval ? __brkval : &__heap_start;
            volatile uint8_t *heap;
            (void)dig(60);
            heap = (volatile uint8_t *)malloc((size_t)(sp0 - 1200U - (uint16_t)top));
            if (!heap) {
                println("ERR no heap");
            } else {
                heap[0] = 1;
                println("OK heap over the stack's past");
                if (line[0] == 'l') {
                    while (!(UCSR0A & _BV(TXC0)))
                        ;
                    snprintf(buf, sizeof buf, "dug %u", dig(60));
                    println(buf);
                }
            }
        } else if (!strncmp(line, "wrap ", 5)) {
            char *end;
            uint16_t k = (uint16_t)strtoul(line + 5, &end, 10);
            uint8_t phase = (uint8_t)strtoul(end, 0, 10);
            TCCR5A = 0;
            TCCR5B = _BV(CS50); /* normal mode, clk/1 */
            TIMSK5 = 0;
            cli();
            while (TCNT5 < 65000U)
                ;
            OCR5A = k;
            PINF = _BV(PF3);
            TIFR5 = _BV(OCF5A);
            TIMSK5 = _BV(OCIE5A);
            while (phase--)
                __asm__ __volatile__("nop");
            sei();
            /* two wraps of calls and returns (4 and 5 cycles): the wrap falls inside a long instruction */
            for (uint16_t i = 0; i < 9000U; i++)
                call_nothing();
            TIMSK5 = 0;
            sprintf(buf, "OK wrap %u", k);
            println(buf);
        } else if (!strncmp(line, "rewrap ", 7)) {
            uint16_t k = (uint16_t)strtoul(line + 7, 0, 10);
            TCCR5A = 0;
            TCCR5B = _BV(CS50); /* normal mode, clk/1 */
            TIMSK5 = 0;
            cli();
            while (TCNT5 < 30000U || TCNT5 > 40000U)
                ;
            OCR5B = k;
            TIFR5 = _BV(OCF5B);
            rewrap_matches = 0;
            TIMSK5 = _BV(OCIE5B);
            sei();
            /* about 13 wraps of calls and returns: the wraps fall at every phase of the loop */
            for (uint16_t i = 0; i < 60000U; i++)
                call_nothing();
            TIMSK5 = 0;
            sprintf(buf, "OK rewrap %u %u", k, rewrap_matches);
            println(buf);
        } else if (!strcmp(line, "tifr")) {
            TCCR5A = 0;
            TCCR5B = _BV(CS50); /* normal mode, clk/1 */
            TIMSK5 = 0;
            cli();
            OCR5A = TCNT5 + 200U;
            OCR5B = TCNT5 + 300U;
            TIFR5 = _BV(OCF5A) | _BV(OCF5B);
            TIMSK5 = _BV(OCIE5A);
            __builtin_avr_delay_cycles(1000); /* both match: both flags set, compare A's interrupt pending */
            TIFR5 = _BV(OCF5B);               /* clears OCF5B only */
            PINF = _BV(PF3);
            sei();
            __builtin_avr_delay_cycles(1000);
            TIMSK5 = 0;
            println("OK tifr");
        } else if (!strcmp(line, "pins")) {
            uint16_t n;
            cli();
            n = int4_falls;
            sei();
            snprintf(buf, sizeof buf, "OK pins d2=%u d18=%u int4=%u", (unsigned)((PINE >> PE4) & 1),
                     (unsigned)((PIND >> PD3) & 1), (unsigned)n);
            println(buf);
        } else if (!strcmp(line, "dig1")) {
            TCCR3A = _BV(WGM30);   /* analogWrite(pin, 255): OC3C off, PE5 high by PORT */
            PORTE |= _BV(PE5);
            println("OK dig1");
        } else if (!strncmp(line, "rev ", 4)) {
            /* HBridge::setDuty on a reversal: analogWrite(pin, 0), then analogWrite(pin, v). While
             * OC3C is off the pin follows PORT, still high from dig1: a glitch of a few cycles. */
            int v = atoi(line + 4);
            TCCR3A = _BV(WGM30);
            PORTE &= (uint8_t)~_BV(PE5);
            OCR3C = (uint8_t)v;
            TCCR3A = _BV(WGM30) | _BV(COM3C1);
            snprintf(buf, sizeof buf, "OK rev %d", v);
            println(buf);
        } else {
            println("ERR unknown");
        }
    }
}
