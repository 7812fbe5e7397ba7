/* emu_uart.c - the host end of UART0 (the Mega's USB serial port).
 *
 * Output: every byte the firmware writes to UDR0 arrives on simavr's UART_IRQ_OUTPUT; bytes are
 * collected into lines ending in LF (a CR before it is dropped). Each line is logged as
 * "rx <cycle> <text>" with the cycle at which its LF was written to UDR0.
 * Input: queued bytes are handed to UART_IRQ_INPUT one frame time apart, as a real host would
 * send them, starting one frame after they were queued.
 * simavr 1.6 counts a parity bit in every frame (1 + 8 + 1 + 1 = 11 bits for 8N1), so its UART is
 * 10 % slower than the real one; after every write to the UART's configuration registers the frame
 * length is recomputed here
 * from UCSR0B/UCSR0C/UBRR0 (start + data + parity if enabled + stop bits) so that serial timing
 * is the real chip's: at 9600 baud (U2X0 = 1, UBRR0 = 207) one 8N1 byte is 10 * 8 * 208 = 16640
 * cycles (1.04 ms).
 */
#include <stdlib.h>
#include <string.h>

#include "emu.h"

/* ATmega2560 UART0 registers (data-space addresses) */
#define R_UCSR0A 0xC0
#define R_UCSR0B 0xC1
#define R_UCSR0C 0xC2
#define R_UBRR0L 0xC4
#define R_UBRR0H 0xC5

static avr_uart_t *uart;
static avr_irq_t *irq_in;
static avr_t *the_avr;

static uint8_t *txq; /* host -> firmware */
static size_t txq_len, txq_head, txq_cap;
static int feeding;
static uint64_t dropped;

static emu_line_t *lines; /* firmware -> host */
static size_t line_count, line_cap;
static uint8_t cur[4096];
static size_t cur_len;
static int ready_lines;

static uint32_t fixed_cpb;      /* the frame length we set */
static void uart_config_written(struct avr_irq_t *irq, uint32_t value, void *param);
static uint32_t last_seen_cpb;  /* what simavr had when we last looked */

uint32_t emu_uart_cycles_per_byte(void)
{
    return fixed_cpb ? fixed_cpb : (uint32_t)(uart ? uart->cycles_per_byte : 0);
}

static uint32_t real_cycles_per_byte(avr_t *avr)
{
    uint8_t a = avr->data[R_UCSR0A], b = avr->data[R_UCSR0B], c = avr->data[R_UCSR0C];
    uint32_t ubrr = avr->data[R_UBRR0L] | ((avr->data[R_UBRR0H] & 0x0f) << 8);
    uint32_t cycles_per_bit = (ubrr + 1) * ((a & 0x02) ? 8 : 16); /* U2X0 */
    static const int databits[8] = {5, 6, 7, 8, 8, 8, 8, 9};
    int db = databits[((c >> 1) & 3) | ((b & 0x04) ? 4 : 0)];    /* UCSZ01:0, UCSZ02 */
    int parity = ((c >> 4) & 3) ? 1 : 0;                           /* UPM01:0 */
    int stop = (c & 0x08) ? 2 : 1;                                 /* USBS0 */
    return cycles_per_bit * (uint32_t)(1 + db + parity + stop);
}

/* after every write to UBRR0L/H or UCSR0A/B/C (simavr recomputes its frame time on UBRR writes) */
static void uart_config_written(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)value;
    (void)param;
    avr_t *avr = the_avr;
    /* UDRE0 is set on the chip whenever the transmit buffer is empty, whatever TXEN0; simavr 1.6
     * clears it when TXEN0 goes off (the core's init() writes UCSR0B = 0) and sets it again only
     * after a byte written to UDR0 has gone, so a sketch that polls UDRE0 never sent its first
     * byte (Arduino's Serial does not poll: it enables its interrupt, which simavr raises). Set
     * again here while no byte is on its way. */
    if (uart->tx_cnt == 0 && !avr_regbit_get(avr, uart->udrc.raised))
        avr_regbit_set(avr, uart->udrc.raised);
    if (uart->cycles_per_byte != last_seen_cpb || (fixed_cpb && real_cycles_per_byte(avr) != fixed_cpb)) {
        /* simavr recomputed it (baud register write): put the real frame length in */
        fixed_cpb = real_cycles_per_byte(avr);
        uart->cycles_per_byte = fixed_cpb;
        last_seen_cpb = fixed_cpb;
        emu_log(avr->cycle, "uart", "cycles_per_byte=%u baud=%.1f", fixed_cpb,
                (double)EMU_F_CPU / ((avr->data[R_UBRR0L] | ((avr->data[R_UBRR0H] & 0x0f) << 8)) + 1) /
                    ((avr->data[R_UCSR0A] & 0x02) ? 8 : 16));
    }
}

static void line_done(uint64_t cycle)
{
    size_t n = cur_len;
    if (n && cur[n - 1] == '\r')
        n--;
    if (line_count == line_cap) {
        line_cap = line_cap ? line_cap * 2 : 256;
        lines = realloc(lines, line_cap * sizeof *lines);
        if (!lines) {
            perror("motionemu");
            exit(1);
        }
    }
    emu_line_t *l = &lines[line_count++];
    l->cycle = cycle;
    l->len = n;
    l->text = malloc(n + 1);
    if (!l->text) {
        perror("motionemu");
        exit(1);
    }
    memcpy(l->text, cur, n);
    l->text[n] = 0;
    cur_len = 0;

    emu_log_text(cycle, "rx", (const uint8_t *)l->text, l->len);
    emu_echo(cycle, '<', (const uint8_t *)l->text, l->len);
    if (strncmp(l->text, "READY", 5) == 0) {
        ready_lines++;
        if (ready_lines > 1)
            emu_fail(cycle, "reset", "a second READY line: the firmware restarted");
    }
}

static void (*sink)(uint8_t byte); /* e.g. the pty (emu_pty.c) */

void emu_uart_set_sink(void (*fn)(uint8_t byte))
{
    sink = fn;
}

static void uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    uint8_t c = (uint8_t)value;
    if (sink)
        sink(c);
    if (c == '\n') {
        line_done(the_avr->cycle);
        return;
    }
    if (cur_len == sizeof cur) /* an endless line: cut it into pieces */
        line_done(the_avr->cycle);
    cur[cur_len++] = c;
}

static avr_cycle_count_t feed_next(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)param;
    if (txq_head >= txq_len) {
        feeding = 0;
        txq_head = txq_len = 0;
        return 0;
    }
    uint8_t byte = txq[txq_head++];
    if (!(avr->data[R_UCSR0B] & 0x10)) { /* RXEN0 off: the byte is lost, as on the chip */
        if (!dropped++)
            emu_log(avr->cycle, "warn", "serial input before Serial.begin(): byte 0x%02x lost", byte);
    }
    avr_raise_irq(irq_in, byte);
    return when + emu_uart_cycles_per_byte();
}

void emu_uart_send(const uint8_t *bytes, size_t n)
{
    if (txq_len + n > txq_cap) {
        txq_cap = (txq_len + n) * 2 + 256;
        txq = realloc(txq, txq_cap);
        if (!txq) {
            perror("motionemu");
            exit(1);
        }
    }
    memcpy(txq + txq_len, bytes, n);
    txq_len += n;
    if (!feeding && n) {
        feeding = 1;
        uint32_t cpb = emu_uart_cycles_per_byte();
        avr_cycle_timer_register(the_avr, cpb ? cpb : 16640, feed_next, NULL);
    }
}

size_t emu_uart_pending(void)
{
    return txq_len - txq_head;
}

uint32_t emu_uart_cpu_pc(void)
{
    return the_avr ? (uint32_t)the_avr->pc : 0U;
}

size_t emu_uart_line_count(void)
{
    return line_count;
}

const emu_line_t *emu_uart_line(size_t i)
{
    return i < line_count ? &lines[i] : NULL;
}

int emu_uart_ready_count(void)
{
    return ready_lines;
}

int emu_uart_attach(avr_t *avr)
{
    the_avr = avr;
    for (avr_io_t *io = avr->io_port; io; io = io->next)
        if (io->irq_ioctl_get == AVR_IOCTL_UART_GETIRQ('0'))
            uart = (avr_uart_t *)io;
    if (!uart)
        return -1;
    /* no console echo, and no usleep() while the firmware polls UCSR0A */
    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~(uint32_t)(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    irq_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    avr_irq_t *out = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT);
    if (!irq_in || !out)
        return -1;
    avr_irq_register_notify(out, uart_out, NULL);
    last_seen_cpb = (uint32_t)uart->cycles_per_byte;
    static const uint16_t regs[] = {R_UCSR0A, R_UCSR0B, R_UCSR0C, R_UBRR0L, R_UBRR0H};
    for (size_t i = 0; i < sizeof regs / sizeof regs[0]; i++) {
        avr_irq_t *irq = avr_iomem_getirq(avr, regs[i], NULL, AVR_IOMEM_IRQ_ALL);
        if (!irq)
            return -1;
        avr_irq_register_notify(irq, uart_config_written, NULL);
    }
    return 0;
}
