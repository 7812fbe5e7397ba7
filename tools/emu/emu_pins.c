/* emu_pins.c - Arduino Mega 2560 pin names and pin edge recording.
 *
 * Digital pin n of the Mega maps to a port bit as in the board's schematic (the same table as the
 * Arduino "mega" variant): D0-D1 = PE0-PE1 (USART0), D2 = PE4, D3 = PE5, ..., D54-D69 = PF0-PK7
 * (A0-A15). A pin's level is what simavr's port pin IRQ reports: PORT writes of output pins and
 * timer compare outputs (PWM) both arrive there; repeated equal values are filtered here so that
 * only real edges are logged. A watched pin's direction is logged too ("ddr <cycle> <name> 1" when
 * its DDRx bit is set, 0 when cleared; reset state: input), from simavr's DDR write IRQ, so that a
 * check can tell a pin driven low from an input pin that merely reads 0.
 */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include <avr_ioport.h>

#include "emu.h"

/* Mega 2560 digital pins 0..69 as "<port><bit>" */
static const char *const mega_pins[70] = {
    "E0", "E1", "E4", "E5", "G5", "E3", "H3", "H4", "H5", "H6", /* D0-D9 */
    "B4", "B5", "B6", "B7", "J1", "J0", "H1", "H0", "D3", "D2", /* D10-D19 */
    "D1", "D0", "A0", "A1", "A2", "A3", "A4", "A5", "A6", "A7", /* D20-D29 */
    "C7", "C6", "C5", "C4", "C3", "C2", "C1", "C0", "D7", "G2", /* D30-D39 */
    "G1", "G0", "L7", "L6", "L5", "L4", "L3", "L2", "L1", "L0", /* D40-D49 */
    "B3", "B2", "B1", "B0", "F0", "F1", "F2", "F3", "F4", "F5", /* D50-D59 */
    "F6", "F7", "K0", "K1", "K2", "K3", "K4", "K5", "K6", "K7", /* D60-D69 */
};

static int parse_uint(const char *s, long *out)
{
    if (!*s)
        return -1;
    char *end;
    long v = strtol(s, &end, 10);
    if (*end || v < 0)
        return -1;
    *out = v;
    return 0;
}

static int parse_portbit(const char *s, emu_pin_t *pin)
{
    char port = (char)toupper((unsigned char)s[0]);
    if (port < 'A' || port > 'L' || port == 'I' || !isdigit((unsigned char)s[1]) || s[2])
        return -1;
    int bit = s[1] - '0';
    if (bit > 7)
        return -1;
    pin->port = port;
    pin->bit = (uint8_t)bit;
    return 0;
}

int emu_pin_parse(const char *spec, emu_pin_t *pin)
{
    long n;
    if ((spec[0] == 'D' || spec[0] == 'd') && parse_uint(spec + 1, &n) == 0 && n < 70)
        return parse_portbit(mega_pins[n], pin);
    if (parse_uint(spec, &n) == 0 && n < 70)
        return parse_portbit(mega_pins[n], pin);
    if ((spec[0] == 'A' || spec[0] == 'a') && parse_uint(spec + 1, &n) == 0 && n < 16)
        return parse_portbit(mega_pins[54 + n], pin);
    if ((spec[0] == 'P' || spec[0] == 'p') && strlen(spec) == 3)
        return parse_portbit(spec + 1, pin);
    if (strlen(spec) == 2)
        return parse_portbit(spec, pin);
    return -1;
}

typedef struct listener {
    emu_pin_fn fn;
    void *param;
    struct listener *next;
} listener_t;

typedef struct pin_state {
    avr_t *avr;
    emu_pin_t pin;
    char name[32];
    int watched;
    int level;      /* the level we report */
    int irq_level;  /* the level simavr's port logic last reported */
    int overridden; /* driven by the harness (emulated PWM output), not by PORT */
    int output;     /* its DDRx bit (0 at reset: input) */
    listener_t *listeners;
    struct pin_state *next;
} pin_state_t;

static pin_state_t *pins;

static void set_level_at(pin_state_t *p, int level, uint64_t cycle)
{
    if (level == p->level)
        return;
    if (p->watched)
        emu_log(cycle, "pin", "%s %d", p->name, level);
    /* listeners run before the level is stored: emu_pin_level() still gives the old level */
    for (listener_t *l = p->listeners; l; l = l->next)
        l->fn(l->param, cycle, level);
    p->level = level;
}

static void set_level(pin_state_t *p, int level)
{
    set_level_at(p, level, p->avr->cycle);
}

static void pin_changed(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    pin_state_t *p = param;
    p->irq_level = (value & 0xff) ? 1 : 0;
    if (!p->overridden)
        set_level(p, p->irq_level);
}

static void ddr_changed(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    pin_state_t *p = param;
    int output = (value >> p->pin.bit) & 1; /* the IRQ carries the whole DDRx byte */
    if (output == p->output)
        return;
    p->output = output;
    if (p->watched)
        emu_log(p->avr->cycle, "ddr", "%s %d", p->name, output);
}

static pin_state_t *pin_get(avr_t *avr, emu_pin_t pin)
{
    for (pin_state_t *p = pins; p; p = p->next)
        if (p->pin.port == pin.port && p->pin.bit == pin.bit)
            return p;
    avr_irq_t *irq = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(pin.port), pin.bit);
    avr_irq_t *dir = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(pin.port), IOPORT_IRQ_DIRECTION_ALL);
    if (!irq || !dir)
        return NULL;
    pin_state_t *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->avr = avr;
    p->pin = pin;
    snprintf(p->name, sizeof p->name, "P%c%d", pin.port, pin.bit);
    p->level = 0; /* reset state of every port pin: input, no pull-up */
    avr_irq_register_notify(irq, pin_changed, p);
    avr_irq_register_notify(dir, ddr_changed, p);
    p->next = pins;
    pins = p;
    return p;
}

int emu_pin_watch(avr_t *avr, const char *name, emu_pin_t pin)
{
    pin_state_t *p = pin_get(avr, pin);
    if (!p)
        return -1;
    if (p->watched && strcmp(p->name, name) != 0)
        return -1; /* one name per pin */
    snprintf(p->name, sizeof p->name, "%s", name);
    p->watched = 1;
    return 0;
}

int emu_pin_listen(avr_t *avr, emu_pin_t pin, emu_pin_fn fn, void *param)
{
    pin_state_t *p = pin_get(avr, pin);
    if (!p)
        return -1;
    listener_t *l = calloc(1, sizeof *l);
    if (!l)
        return -1;
    l->fn = fn;
    l->param = param;
    l->next = p->listeners;
    p->listeners = l;
    return 0;
}

void emu_pin_drive(avr_t *avr, emu_pin_t pin, int on, int level, uint64_t cycle)
{
    pin_state_t *p = pin_get(avr, pin);
    if (!p)
        return;
    p->overridden = on;
    set_level_at(p, on ? level : p->irq_level, cycle);
}

int emu_pin_level(avr_t *avr, emu_pin_t pin)
{
    pin_state_t *p = pin_get(avr, pin);
    return p ? p->level : 0;
}

/* Inputs driven from outside: simavr 1.6's "external" state of a port (AVR_IOCTL_IOPORT_SET_EXTERNAL,
 * a mask and a value per port). avr_ioport_update_irqs, run at every PORTx and DDRx write, raises
 * an input pin's IRQ with the external value when its mask bit is set (instead of the pull-up's 1),
 * and the IRQ sets the PINx bit; so the level holds across the firmware's pinMode/pull-up writes.
 * Raising the pin's IRQ now sets PINx at once (and runs the pin change / INTn logic, and our
 * pin_changed, which logs a watched pin's edge). */
static uint8_t ext_mask[12], ext_value[12]; /* ports 'A'..'L' */

int emu_pin_input(avr_t *avr, emu_pin_t pin, int level, int *was_output)
{
    int k = pin.port - 'A';
    uint8_t bit = (uint8_t)(1u << pin.bit);
    avr_ioport_state_t st;
    avr_irq_t *irq = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(pin.port), pin.bit);
    if (k < 0 || k >= 12 || !irq || avr_ioctl(avr, AVR_IOCTL_IOPORT_GETSTATE(pin.port), &st) != 0)
        return -1;
    ext_mask[k] |= bit;
    ext_value[k] = (uint8_t)(level ? ext_value[k] | bit : ext_value[k] & ~bit);
    avr_ioport_external_t ext = {.name = (unsigned long)pin.port, .mask = ext_mask[k], .value = ext_value[k]};
    if (avr_ioctl(avr, AVR_IOCTL_IOPORT_SET_EXTERNAL(pin.port), &ext) != 0)
        return -1;
    *was_output = (st.ddr & bit) != 0;
    if (!*was_output)
        avr_raise_irq(irq, level ? 1 : 0);
    return 0;
}
