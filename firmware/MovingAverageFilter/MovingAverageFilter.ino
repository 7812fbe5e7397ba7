// motion-sketch: filter
/* MovingAverageFilter - the acceleration/deceleration filter of the moving-average-filter note running at exactly 100 Hz
 * on an Arduino Mega 2560: moving average (default, tau = 9 s), two-stage S-curve or exponential,
 * the very same lib/ code (accdec_filter.h) that `motionsim filter` runs.
 *
 * Timing (no drift, never delay()): Timer1 in CTC mode fires every 625 ticks of 16 us = 10.000 ms
 * of the crystal. Its interrupt toggles the strobe pin (first thing), writes y[k] (computed during
 * the previous sample) to the PWM, and starts the A0 conversion. The ADC-complete interrupt,
 * 104 us later, takes u[k] (A0 in mV, or the constant from `u`), steps the filter and queues the
 * line "t_ms,u,y" for the serial stream. loop() only parses commands and prints queued lines when
 * the whole line fits in the transmit buffer, so the serial port never delays a sample; a line
 * that finds the queue full is dropped and counted (`drops=` in `?`). Serial: 115200 baud, 8N1.
 * Pins and timers: FilterPins.h. Commands: see README.md ("MovingAverageFilter sketch").
 */
#include <Arduino.h>
#include <util/atomic.h>

#include <FilterPins.h>
#include <MotionSerial.h>
#include <accdec_filter.h>
#include <filter_param.h>
#include <filter_stream.h>
#include <text_parse.h>

#define MAF_BAUD 115200UL
#ifndef MAF_MAX_TAPS
#define MAF_MAX_TAPS 2000u /* ring buffer: 2 bytes per tap; ma tau <= 20 s, ma2 tau + tau2 <= 20 s */
#endif
#define MAF_QUEUE_LEN 16u  /* ring of 16: up to 15 stream lines (150 ms at every = 1) wait for the port */
#define MAF_EVERY_MAX 1000u
#define MAF_U_MAX_V 5.0
static const double TS_S = 0.01; /* 1 / FILTER_SAMPLE_HZ */
/* ADC enabled, interrupt on completion, clk/128 = 125 kHz */
#define ADCSRA_RUN (_BV(ADEN) | _BV(ADIE) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0))

/* ---- state shared with the interrupts (written by the ISRs unless noted) ------------------------ */
static int16_t taps_buf[MAF_MAX_TAPS];
static accdec_filter_t filt;               /* owned by the ADC interrupt after setup() */

enum { PEND_NONE = 0, PEND_RESET = 1, PEND_START = 2 };
static volatile uint8_t pending;           /* loop: request; ADC ISR: applies at the next sample */
static accdec_config_t pending_cfg;        /* loop writes it (atomically) together with pending */

static volatile uint8_t input_const;       /* loop: 1 = constant input, 0 = A0 */
static volatile int16_t const_mv;          /* loop: the constant, mV */
static volatile uint16_t every_n = 1;      /* loop: stream every n-th sample */
static volatile uint16_t every_left;       /* samples to skip before the next line (loop: 0 on change) */

static volatile uint16_t pwm_next;         /* OCR4A for the next sample: y[k+1] in mV */
static float pwm_mv_per_num;               /* 1 / den of the running configuration */
static volatile uint32_t t_ms;             /* t of the sample being processed: 10 k */
static volatile uint8_t busy;              /* 1 from the timer tick until the sample is done; a tick
                                              that finds it set starts no conversion, so ADC_vect
                                              (which runs with interrupts enabled) never nests */
static volatile uint16_t late_count;       /* ticks that found the previous sample unfinished */
static volatile uint32_t drop_count;       /* stream lines dropped: queue full */
static volatile uint16_t cost_cycles, cost_max_cycles; /* ADC interrupt body, Timer5 at clk/1 */

typedef struct {
    uint32_t t_ms;
    int16_t u_mv;
    int64_t num;
    uint32_t den;
} sample_line_t;
static sample_line_t queue[MAF_QUEUE_LEN];
static volatile uint8_t q_head, q_tail;    /* ISR advances head, loop advances tail */

/* ---- loop-owned state ----------------------------------------------------------------------------- */
static MotionSerial serial(Serial);
static accdec_kind_t kind = ACCDEC_MA;
static uint16_t tau_taps = 900, tau2_taps = 300; /* tau = 9 s, tau2 = 3 s */
static uint8_t header_sent;

/* ---- interrupts ----------------------------------------------------------------------------------- */

/* Sample clock, every 10.000 ms. The strobe toggles first; the rest is a few register writes. */
ISR(TIMER1_COMPA_vect)
{
    FILTER_STROBE_PINREG = _BV(FILTER_STROBE_BIT);
    OCR4A = pwm_next;
    if (busy) { /* the previous sample is still running (never seen): skip this one, count it */
        late_count++;
        return;
    }
    busy = 1;
    ADCSRA = ADCSRA_RUN | _BV(ADSC); /* convert A0 now: ADC_vect follows 13 ADC clocks (104 us) later.
                                        A plain write: |= would also write back (clear) ADIF. */
}

/* A0 converted: the sample's filter work, with interrupts enabled again so that the serial port
 * keeps up (a restart after `kind`/`tau` clears up to MAF_MAX_TAPS taps: about 1 ms). */
ISR(ADC_vect)
{
    uint16_t t_start = TCNT5;
    uint16_t code = ADC;
    int16_t u;
    int64_t num;
    uint32_t den;
    sei();
    if (pending != PEND_NONE) {
        if (pending == PEND_START)
            (void)accdec_start(&filt, &pending_cfg, taps_buf, MAF_MAX_TAPS); /* validated by loop */
        else
            accdec_reset(&filt);
        pwm_mv_per_num = 1.0f / (float)accdec_den(&filt.cfg);
        pending = PEND_NONE;
    }
    u = input_const ? const_mv : fstream_adc10_to_mv(code);
    num = accdec_step(&filt, u);
    den = accdec_den(&filt.cfg);
    {
        float mv = (float)accdec_peek(&filt) * pwm_mv_per_num + 0.5f;
        pwm_next = mv <= 0.5f ? 0 : mv >= (float)FILTER_PWM_TOP ? FILTER_PWM_TOP : (uint16_t)mv;
    }
    if (every_left > 0) {
        every_left--;
    } else {
        every_left = every_n - 1u;
        uint8_t next = (uint8_t)((q_head + 1u) % MAF_QUEUE_LEN);
        if (next == q_tail) {
            drop_count++;
        } else {
            sample_line_t *s = &queue[q_head];
            s->t_ms = t_ms;
            s->u_mv = u;
            s->num = num;
            s->den = den;
            q_head = next;
        }
    }
    t_ms += 1000u / FILTER_SAMPLE_HZ;
    cli();
    cost_cycles = (uint16_t)(TCNT5 - t_start);
    if (cost_cycles > cost_max_cycles)
        cost_max_cycles = cost_cycles;
    busy = 0;
}

/* ---- replies -------------------------------------------------------------------------------------- */

/* v / 10^decimals with exactly `decimals` digits (v >= 0). */
static void print_fixed(uint32_t v, uint8_t decimals)
{
    uint32_t scale = 1;
    uint8_t i;
    for (i = 0; i < decimals; i++)
        scale *= 10u;
    Serial.print(v / scale);
    Serial.print('.');
    v %= scale;
    for (i = decimals; i > 0; i--) {
        scale /= 10u;
        Serial.print((char)('0' + (v / scale) % 10u));
    }
}

/* One line of key=value pairs: the configuration and the two fault counters. Live values (t, u, y)
 * are in the stream, so two replies are equal unless something was changed or went wrong. */
static void print_state(void)
{
    uint32_t drops;
    uint16_t late;
    uint8_t in_const;
    int16_t cmv;
    uint16_t every;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        drops = drop_count;
        late = late_count;
        in_const = input_const;
        cmv = const_mv;
        every = every_n;
    }
    Serial.print(F("kind="));
    Serial.print(accdec_kind_name(kind));
    Serial.print(F(" tau="));
    print_fixed(tau_taps, 2); /* taps * 10 ms, in s */
    Serial.print(F(" tau2="));
    print_fixed(tau2_taps, 2);
    Serial.print(F(" ts=0.01 taps="));
    Serial.print(kind == ACCDEC_MA ? tau_taps : kind == ACCDEC_MA2 ? tau_taps + tau2_taps : 0);
    Serial.print(F(" max_taps="));
    Serial.print(MAF_MAX_TAPS);
    Serial.print(F(" input="));
    Serial.print(in_const ? F("const") : F("a0"));
    Serial.print(F(" u="));
    print_fixed((uint32_t)cmv, 3);
    Serial.print(F(" every="));
    Serial.print(every);
    Serial.print(F(" baud="));
    Serial.print(MAF_BAUD);
    Serial.print(F(" drops="));
    Serial.print(drops);
    Serial.print(F(" late="));
    Serial.println(late);
}

/* ---- commands ------------------------------------------------------------------------------------- */

/* Validates (kind, tau, tau2) as one configuration and, if valid, makes it the running one from
 * the next sample (the filter restarts at rest). Nothing changes on error. */
static motion_status_t apply_config(accdec_kind_t k, uint16_t n1, uint16_t n2)
{
    accdec_config_t c;
    motion_status_t st = accdec_configure(&c, k, n1 * TS_S, n2 * TS_S, TS_S, MAF_MAX_TAPS);
    if (st != MS_OK)
        return st;
    kind = k;
    tau_taps = n1;
    tau2_taps = n2;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        pending_cfg = c;
        pending = PEND_START;
    }
    return MS_OK;
}

/* tau/tau2 argument: seconds, a whole number of 10 ms samples (checked by filt_taps). */
static motion_status_t parse_tau(const char *word, uint16_t *taps)
{
    double s;
    motion_status_t st = text_parse_real(word, 0.0, 1000.0, &s);
    if (st != MS_OK)
        return st;
    return filt_taps(s, TS_S, taps);
}

static void reply_ok_tau(const __FlashStringHelper *what, uint16_t taps)
{
    Serial.print(F("OK "));
    Serial.print(what);
    print_fixed(taps, 2);
    Serial.println();
}

static void handle(const char *line)
{
    char cmd[8], arg[24];
    const char *cur = line;
    motion_status_t st;
    int n_cmd = text_next_word(&cur, cmd, sizeof cmd);
    int n_arg = text_next_word(&cur, arg, sizeof arg);
    if (n_cmd < 0) {
        serial.reply_error(MS_ERR_UNKNOWN_COMMAND);
        return;
    }
    if (n_arg < 0) {
        serial.reply_error(MS_ERR_OUT_OF_RANGE, F("argument too long"));
        return;
    }
    if (!text_at_end(cur)) {
        serial.reply_error(MS_ERR_UNKNOWN_COMMAND, F("extra words after the command"));
        return;
    }
    if (text_word_is(cmd, "?") || text_word_is(cmd, "reset") || text_word_is(cmd, "a0") || text_word_is(cmd, "cost")) {
        if (n_arg > 0) {
            serial.reply_error(MS_ERR_UNKNOWN_COMMAND, F("this command takes no value"));
            return;
        }
        if (text_word_is(cmd, "?")) {
            print_state();
        } else if (text_word_is(cmd, "reset")) {
            ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
            {
                if (pending == PEND_NONE)
                    pending = PEND_RESET;
            }
            Serial.println(F("OK reset"));
        } else if (text_word_is(cmd, "a0")) {
            input_const = 0;
            Serial.println(F("OK input=a0"));
        } else {
            uint16_t c, m;
            ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
            {
                c = cost_cycles;
                m = cost_max_cycles;
            }
            Serial.print(F("OK cost kind="));
            Serial.print(accdec_kind_name(kind));
            Serial.print(F(" cycles="));
            Serial.print(c);
            Serial.print(F(" max_cycles="));
            Serial.println(m);
        }
        return;
    }
    if (text_word_is(cmd, "kind")) {
        accdec_kind_t k;
        st = accdec_kind_parse(arg, &k);
        if (st == MS_OK)
            st = apply_config(k, tau_taps, tau2_taps);
        if (st != MS_OK) {
            serial.reply_error(st);
            return;
        }
        Serial.print(F("OK kind="));
        Serial.println(accdec_kind_name(kind));
    } else if (text_word_is(cmd, "tau") || text_word_is(cmd, "tau2")) {
        uint8_t second = text_word_is(cmd, "tau2");
        uint16_t taps = 0;
        st = parse_tau(arg, &taps);
        /* One rule under every kind, so that any kind can follow: tau and tau2 each fit the
         * moving-average buffer (exp needs no buffer, but `kind ma` must work after it). */
        if (st == MS_OK && taps > MAF_MAX_TAPS)
            st = MS_ERR_TOO_MANY_TAPS;
        if (st == MS_OK) {
            if (!second)
                st = apply_config(kind, taps, tau2_taps);
            else if (kind == ACCDEC_MA2)
                st = apply_config(kind, tau_taps, taps);
            else
                tau2_taps = taps; /* kept for ma2: tau + tau2 is checked when kind becomes ma2 */
        }
        if (st == MS_ERR_TOO_MANY_TAPS) {
            serial.begin_error(st).print(F("tau and tau2 at most "));
            print_fixed(MAF_MAX_TAPS, 2);
            Serial.println(F(" s each under every kind (ma2: tau + tau2)"));
            return;
        }
        if (st != MS_OK) {
            serial.reply_error(st);
            return;
        }
        reply_ok_tau(second ? F("tau2=") : F("tau="), taps);
    } else if (text_word_is(cmd, "u")) {
        double v;
        int16_t mv = 0;
        st = text_parse_real(arg, 0.0, MAF_U_MAX_V, &v);
        if (st == MS_OK)
            st = filt_quantise_whole(v, 0.001, &mv);
        if (st != MS_OK) {
            serial.reply_error(st, F("u takes 0 to 5 V in steps of 1 mV"));
            return;
        }
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
        {
            const_mv = mv;
            input_const = 1;
        }
        Serial.print(F("OK u="));
        print_fixed((uint32_t)mv, 3);
        Serial.println();
    } else if (text_word_is(cmd, "every")) {
        int32_t n;
        st = text_parse_int32(arg, 1, MAF_EVERY_MAX, &n);
        if (st != MS_OK) {
            serial.reply_error(st, F("every takes 1 to 1000 samples"));
            return;
        }
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
        {
            every_n = (uint16_t)n;
            every_left = 0; /* the next sample is streamed, then every n-th */
        }
        Serial.print(F("OK every="));
        Serial.println(n);
    } else {
        serial.reply_error(MS_ERR_UNKNOWN_COMMAND);
    }
}

/* ---- the stream --------------------------------------------------------------------------------- */

static void stream_lines(void)
{
    if (!header_sent) {
        if (Serial.availableForWrite() < (int)sizeof(FSTREAM_HEADER) + 1)
            return;
        Serial.println(F(FSTREAM_HEADER));
        header_sent = 1;
    }
    while (q_tail != q_head) {
        char line[FSTREAM_LINE_MAX + 3];
        const sample_line_t *s = &queue[q_tail];
        uint8_t n = fstream_format(line, s->t_ms, s->u_mv, accdec_milli_quanta(s->num, s->den));
        line[n++] = '\r';
        line[n++] = '\n';
        if (Serial.availableForWrite() < n)
            return; /* try again next loop: never wait for the port */
        Serial.write((const uint8_t *)line, n);
        q_tail = (uint8_t)((q_tail + 1u) % MAF_QUEUE_LEN);
    }
}

/* ---- setup and loop ----------------------------------------------------------------------------- */

void setup()
{
    accdec_config_t c;
    Serial.begin(MAF_BAUD);

    /* the filter at rest: moving average, tau = 9 s (the moving-average-filter note) */
    (void)accdec_configure(&c, kind, tau_taps * TS_S, tau2_taps * TS_S, TS_S, MAF_MAX_TAPS);
    (void)accdec_start(&filt, &c, taps_buf, MAF_MAX_TAPS);
    pwm_mv_per_num = 1.0f / (float)accdec_den(&c);

    FILTER_STROBE_DDR |= _BV(FILTER_STROBE_BIT);

    /* PWM on OC4A: phase correct, TOP = ICR4, clk/1: 16 MHz / (2 * 5000) = 1.6 kHz */
    pinMode(FILTER_PWM_PIN, OUTPUT);
    TCCR4A = _BV(COM4A1) | _BV(WGM41);
    TCCR4B = _BV(WGM43) | _BV(CS40);
    ICR4 = FILTER_PWM_TOP;
    OCR4A = 0;

    /* cycle counter for `cost`: Timer5 free running at clk/1 */
    TCCR5A = 0;
    TCCR5B = _BV(CS50);

    /* ADC on A0, AVcc reference, clk/128 = 125 kHz, interrupt on completion */
    ADMUX = _BV(REFS0) | (FILTER_INPUT_ADC_CHANNEL & 0x07);
    ADCSRB &= (uint8_t)~_BV(MUX5);
    DIDR0 |= _BV(FILTER_INPUT_ADC_CHANNEL & 0x07);
    ADCSRA = ADCSRA_RUN;

    Serial.println(F("READY MovingAverageFilter"));

    /* sample clock last, so that sample 0 (t_ms = 0) comes 10 ms after READY */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        TCCR1A = 0;
        TCCR1B = 0;
        TCNT1 = 0;
        OCR1A = FILTER_TIMER1_TOP;
        TIFR1 = _BV(OCF1A);
        TIMSK1 = _BV(OCIE1A);
        TCCR1B = _BV(WGM12) | _BV(CS12); /* CTC on OCR1A, clk/256 */
    }
}

void loop()
{
    const char *line = serial.poll();
    if (line != NULL)
        handle(line);
    stream_lines();
}
