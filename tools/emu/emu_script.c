/* emu_script.c - the INPUT script: what the emulated host does on the serial port, and when.
 *
 * One command per line; blank lines and lines starting with '#' are ignored. Times are emulated
 * milliseconds since power-on. Text may hold the escapes \r \n \t \\ and \xNN.
 *   @<ms> <text>       at time <ms>, send <text> and CR LF (at once if <ms> has passed)
 *   send <text>        send <text> and CR LF now ("send" alone sends just CR LF)
 *   raw <text>         send <text> without a line end
 *   repeat <n> <text>  send <text> n times without a line end (e.g. "repeat 1024 x")
 *   wait <regex>       run until a serial line from the firmware matches the POSIX extended
 *                      regex; lines are consumed in order, so each wait sees only lines after the
 *                      previous match. Fails (event "fail ... timeout") after the timeout.
 *   timeout <ms>       timeout of the following waits (default 10000 ms)
 *   drain              run until every queued input byte has been sent
 *   run <ms>           let <ms> of emulated time pass
 *   until <ms>         run until time <ms>
 *   adc <ch> <volts>   set analog input A<ch> (0..15) to <volts> (0..5 V)
 *   pin <pin> <0|1>    drive a digital input from outside (a switch): D3, A0, PE5 or E5 reads 0 or 1
 *                      from now on, whatever its pull-up (emu_pin_input); logged "input <cycle> <pin> <PXn> <level>"
 *   encoder <counts>   with --ls7366r (no motor): move the encoder to <counts> (x4 quadrature);
 *                      motionemu refuses a script that has it without --ls7366r
 *   mark <text>        log "mark <cycle> <text>" (to split a run into sections)
 *   end                stop the emulation here
 * The script ends after its last command, once every queued byte has been sent.
 */
#include <ctype.h>
#include <errno.h>
#include <regex.h>
#include <stdlib.h>
#include <string.h>

#include <avr_adc.h>

#include "emu.h"
#include "text_parse.h"

enum op { OP_AT, OP_SEND, OP_RAW, OP_REPEAT, OP_WAIT, OP_TIMEOUT, OP_DRAIN, OP_RUN, OP_UNTIL, OP_ADC, OP_PIN, OP_ENCODER, OP_MARK,
          OP_END };

typedef struct {
    enum op op;
    int lineno;
    double num;       /* ms, count, channel */
    double num2;      /* volts */
    uint8_t *bytes;   /* decoded text */
    size_t len;
    char *src;        /* the text as written (for the log) */
    const char *name; /* the script it came from (file or --exec) */
    emu_pin_t pin;    /* pin */
    char pin_name[8]; /* the pin as written */
    regex_t re;
} cmd_t;

static cmd_t *cmds;
static size_t ncmds, cmds_cap;
static const char *script_name = "script";

static size_t pc;             /* next command */
static size_t line_cursor;    /* first firmware line not yet consumed by a wait */
static double timeout_ms = 10000.0;
static uint64_t wait_deadline;
static int waiting;           /* current command started (wait/run/until) */
static uint64_t run_until;

#define MS_TO_CYCLES(ms) ((uint64_t)((ms) * (EMU_F_CPU / 1000.0) + 0.5))

static int decode_text(const char *s, uint8_t **out, size_t *len, int lineno)
{
    size_t n = strlen(s);
    uint8_t *b = malloc(n + 3);
    if (!b)
        return -1;
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        if (s[i] != '\\') {
            b[k++] = (uint8_t)s[i];
            continue;
        }
        char e = s[++i];
        switch (e) {
        case 'r': b[k++] = '\r'; break;
        case 'n': b[k++] = '\n'; break;
        case 't': b[k++] = '\t'; break;
        case '\\': b[k++] = '\\'; break;
        case 'x':
            if (isxdigit((unsigned char)s[i + 1]) && isxdigit((unsigned char)s[i + 2])) {
                char hex[3] = {s[i + 1], s[i + 2], 0};
                b[k++] = (uint8_t)strtol(hex, NULL, 16);
                i += 2;
                break;
            }
            /* fall through */
        default:
            fprintf(stderr, "%s:%d: bad escape '\\%c' (use \\r \\n \\t \\\\ or \\xNN)\n", script_name, lineno,
                    e ? e : ' ');
            free(b);
            return -1;
        }
    }
    *out = b;
    *len = k;
    return 0;
}

/* The number at s (up to the next blank), parsed by lib's text_parse (the sketches' and motionsim's parser). */
static int parse_num(const char *s, double lo, double hi, double *out, const char *what, int lineno)
{
    char word[64];
    size_t n = 0;
    while (s[n] && !isspace((unsigned char)s[n]))
        n++;
    if (n >= sizeof word || (memcpy(word, s, n), word[n] = 0, text_parse_real(word, lo, hi, out) != MS_OK)) {
        fprintf(stderr, "%s:%d: %s must be a number in %g..%g, not '%s'\n", script_name, lineno, what, lo, hi, s);
        return -1;
    }
    return 0;
}

static const char *skip_word(const char *s)
{
    while (*s && !isspace((unsigned char)*s))
        s++;
    if (*s)
        s++; /* exactly one separating space: the rest is the argument verbatim */
    return s;
}

static int add_cmd(char *line, int lineno)
{
    size_t n = strlen(line);
    while (n && (line[n - 1] == '\n' || line[n - 1] == '\r'))
        line[--n] = 0;
    const char *s = line;
    while (isspace((unsigned char)*s))
        s++;
    if (!*s || *s == '#')
        return 0;
    if (ncmds == cmds_cap) {
        cmds_cap = cmds_cap ? cmds_cap * 2 : 64;
        cmds = realloc(cmds, cmds_cap * sizeof *cmds);
        if (!cmds)
            return -1;
    }
    cmd_t *c = &cmds[ncmds];
    memset(c, 0, sizeof *c);
    c->lineno = lineno;
    char word[16] = {0};
    size_t wl = 0;
    while (s[wl] && !isspace((unsigned char)s[wl]) && wl < sizeof word - 1) {
        word[wl] = s[wl];
        wl++;
    }
    const char *arg = skip_word(s);
    int rc = 0;
    if (word[0] == '@') {
        c->op = OP_AT;
        rc = parse_num(word + 1, 0, 1e9, &c->num, "the time after '@' (ms)", lineno);
        if (!rc)
            rc = decode_text(arg, &c->bytes, &c->len, lineno);
    } else if (!strcmp(word, "send")) {
        c->op = OP_SEND;
        rc = decode_text(arg, &c->bytes, &c->len, lineno);
    } else if (!strcmp(word, "raw")) {
        c->op = OP_RAW;
        rc = decode_text(arg, &c->bytes, &c->len, lineno);
        if (!rc && c->len == 0) {
            fprintf(stderr, "%s:%d: raw needs text\n", script_name, lineno);
            rc = -1;
        }
    } else if (!strcmp(word, "repeat")) {
        c->op = OP_REPEAT;
        rc = parse_num(arg, 1, 1e6, &c->num, "the repeat count", lineno);
        if (!rc)
            rc = decode_text(skip_word(arg), &c->bytes, &c->len, lineno);
        if (!rc && c->len == 0) {
            fprintf(stderr, "%s:%d: repeat needs text after the count\n", script_name, lineno);
            rc = -1;
        }
    } else if (!strcmp(word, "wait")) {
        c->op = OP_WAIT;
        int e = regcomp(&c->re, arg, REG_EXTENDED | REG_NOSUB);
        if (e) {
            char msg[128];
            regerror(e, &c->re, msg, sizeof msg);
            fprintf(stderr, "%s:%d: bad regex '%s': %s\n", script_name, lineno, arg, msg);
            rc = -1;
        }
    } else if (!strcmp(word, "timeout")) {
        c->op = OP_TIMEOUT;
        rc = parse_num(arg, 1, 1e9, &c->num, "timeout (ms)", lineno);
    } else if (!strcmp(word, "drain")) {
        c->op = OP_DRAIN;
    } else if (!strcmp(word, "run")) {
        c->op = OP_RUN;
        rc = parse_num(arg, 0, 1e9, &c->num, "run time (ms)", lineno);
    } else if (!strcmp(word, "until")) {
        c->op = OP_UNTIL;
        rc = parse_num(arg, 0, 1e9, &c->num, "until time (ms)", lineno);
    } else if (!strcmp(word, "adc")) {
        c->op = OP_ADC;
        rc = parse_num(arg, 0, 15, &c->num, "adc channel", lineno);
        if (!rc)
            rc = parse_num(skip_word(arg), 0, 5, &c->num2, "adc voltage (V)", lineno);
        if (!rc && c->num != (int)c->num) {
            fprintf(stderr, "%s:%d: adc channel must be a whole number\n", script_name, lineno);
            rc = -1;
        }
    } else if (!strcmp(word, "pin")) {
        c->op = OP_PIN;
        char name[16] = {0}, level[16] = {0}, extra[2] = {0};
        int got = sscanf(arg, "%15s %15s %1s", name, level, extra);
        if (got != 2 || emu_pin_parse(name, &c->pin) != 0 || strlen(name) >= sizeof c->pin_name ||
            (strcmp(level, "0") && strcmp(level, "1"))) {
            fprintf(stderr, "%s:%d: pin wants a pin (D3, A0, PE5 or E5) and a level 0 or 1, not '%s'\n", script_name,
                    lineno, arg);
            rc = -1;
        } else {
            strcpy(c->pin_name, name);
            c->num = level[0] - '0';
        }
    } else if (!strcmp(word, "encoder")) {
        c->op = OP_ENCODER;
        rc = parse_num(arg, -9.2e18, 9.2e18, &c->num, "encoder count", lineno);
        if (!rc && c->num != (double)(int64_t)c->num) {
            fprintf(stderr, "%s:%d: encoder count must be a whole number\n", script_name, lineno);
            rc = -1;
        }
    } else if (!strcmp(word, "mark")) {
        c->op = OP_MARK;
    } else if (!strcmp(word, "end")) {
        c->op = OP_END;
    } else {
        fprintf(stderr, "%s:%d: unknown command '%s' (want @<ms>, send, raw, repeat, wait, timeout, drain, run, "
                        "until, adc, pin, encoder, mark, end)\n",
                script_name, lineno, word);
        rc = -1;
    }
    if (rc)
        return -1;
    c->src = strdup(arg);
    c->name = script_name;
    ncmds++;
    return 0;
}

int emu_script_load_text(const char *text, const char *name)
{
    script_name = name;
    char *copy = strdup(text);
    int lineno = 0, bad = 0;
    for (char *save = NULL, *l = strtok_r(copy, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
        lineno++;
        if (add_cmd(l, lineno))
            bad = 1;
    }
    free(copy);
    return bad ? -1 : 0;
}

int emu_script_load(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "motionemu: cannot read input script '%s': %s\n", path, strerror(errno));
        return -1;
    }
    script_name = path;
    char buf[8192];
    int lineno = 0, bad = 0;
    while (fgets(buf, sizeof buf, f)) {
        lineno++;
        if (add_cmd(buf, lineno))
            bad = 1;
    }
    fclose(f);
    return bad ? -1 : 0;
}

int emu_script_encoder_line(const char **name)
{
    for (size_t i = 0; i < ncmds; i++)
        if (cmds[i].op == OP_ENCODER) {
            *name = cmds[i].name;
            return cmds[i].lineno;
        }
    return 0;
}

static void send_bytes(uint64_t cycle, const uint8_t *b, size_t n, int crlf, const char *tag)
{
    emu_log_text(cycle, tag, b, n);
    emu_echo(cycle, '>', b, n);
    emu_uart_send(b, n);
    if (crlf)
        emu_uart_send((const uint8_t *)"\r\n", 2);
}

uint64_t emu_script_step(avr_t *avr, int *finished)
{
    uint64_t now = avr->cycle;
    *finished = 0;
    while (pc < ncmds) {
        cmd_t *c = &cmds[pc];
        switch (c->op) {
        case OP_AT: {
            uint64_t at = MS_TO_CYCLES(c->num);
            if (now < at)
                return at;
            send_bytes(now, c->bytes, c->len, 1, "tx");
            break;
        }
        case OP_SEND:
            send_bytes(now, c->bytes, c->len, 1, "tx");
            break;
        case OP_RAW:
            send_bytes(now, c->bytes, c->len, 0, "txraw");
            break;
        case OP_REPEAT: {
            size_t n = (size_t)c->num;
            uint8_t *b = malloc(n * c->len);
            for (size_t i = 0; i < n; i++)
                memcpy(b + i * c->len, c->bytes, c->len);
            emu_log(now, "txrepeat", "%zu %s", n, c->src);
            emu_echo_note(now, "> %zu x %s", n, c->src);
            emu_uart_send(b, n * c->len);
            free(b);
            break;
        }
        case OP_WAIT: {
            if (!waiting) {
                waiting = 1;
                wait_deadline = now + MS_TO_CYCLES(timeout_ms);
            }
            for (; line_cursor < emu_uart_line_count(); line_cursor++) {
                const emu_line_t *l = emu_uart_line(line_cursor);
                if (regexec(&c->re, l->text, 0, NULL, 0) == 0) {
                    line_cursor++;
                    waiting = 0;
                    goto next;
                }
            }
            if (now >= wait_deadline) {
                emu_fail(now, "timeout", "%s:%d: no line matching '%s' within %g ms (CPU at PC=0x%05x)", script_name,
                         c->lineno, c->src, timeout_ms, (unsigned)emu_uart_cpu_pc());
                waiting = 0;
                pc = ncmds; /* the script cannot go on */
                *finished = 1;
                return UINT64_MAX;
            }
            return wait_deadline; /* or earlier, when a line arrives */
        }
        case OP_TIMEOUT:
            timeout_ms = c->num;
            break;
        case OP_DRAIN:
            if (emu_uart_pending())
                return now + emu_uart_cycles_per_byte();
            break;
        case OP_RUN:
            if (!waiting) {
                waiting = 1;
                run_until = now + MS_TO_CYCLES(c->num);
            }
            if (now < run_until)
                return run_until;
            waiting = 0;
            break;
        case OP_UNTIL: {
            uint64_t at = MS_TO_CYCLES(c->num);
            if (now < at)
                return at;
            break;
        }
        case OP_ADC: {
            /* The datasheet's conversion is ADC = floor(Vin * 1024 / Vref), at most 1023; simavr
             * computes floor(mV * 1023 / Vref_mV) from whole millivolts. Hand it the millivolt
             * value that makes it return the datasheet's code (Vref = AVCC = 5 V). */
            double vref = avr->avcc / 1000.0;
            uint32_t code = (uint32_t)(c->num2 * 1024.0 / vref);
            if (code > 1023)
                code = 1023;
            uint32_t mv = (code * avr->avcc + 1022) / 1023;
            avr_irq_t *irq = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, (int)c->num);
            if (irq)
                avr_raise_irq(irq, mv);
            emu_log(now, "adc", "%d %g code=%u", (int)c->num, c->num2, code);
            break;
        }
        case OP_PIN: {
            int output = 0;
            if (emu_pin_input(avr, c->pin, (int)c->num, &output) != 0)
                emu_fail(now, "script", "%s:%d: pin %s: the port does not answer", c->name, c->lineno, c->pin_name);
            else
                emu_log(now, "input", "%s P%c%d %d%s", c->pin_name, c->pin.port, c->pin.bit, (int)c->num,
                        output ? " output" : "");
            break;
        }
        case OP_ENCODER:
            emu_encoder_set((int64_t)c->num);
            emu_log(now, "encoder", "%lld", (long long)c->num);
            break;
        case OP_MARK:
            emu_log(now, "mark", "%s", c->src);
            break;
        case OP_END:
            pc = ncmds;
            *finished = 1;
            return UINT64_MAX;
        }
    next:
        pc++;
    }
    if (emu_uart_pending())
        return now + emu_uart_cycles_per_byte();
    *finished = 1;
    return UINT64_MAX;
}
