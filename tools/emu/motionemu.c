/* motionemu.c - run a sketch's ELF on an emulated ATmega2560 at 16 MHz and log what it does.
 *
 *   motionemu FIRMWARE.elf [--input SCRIPT] [--pin NAME=PIN ...] [--motor SPEC | --ls7366r CS=PIN]
 *             [--matches] [--trace-pc FROM-TO] [--duration MS] [--max-ms MS] [-o LOG] [--echo] [--pty]
 *
 * The log (stdout or -o) has one event per line, "<tag> <cycle> <fields>"; cycles are CPU cycles
 * since power-on (16 per microsecond). Tags: boot, uart, tx/txraw/txrepeat (host -> firmware),
 * rx (a line from the firmware), pin (an edge of a watched pin), match (a compare match of Timer1,
 * with --matches), pc (an instruction run, with --trace-pc), motor (duty/count samples), adc, input
 * (a pin driven by the script), mark, warn, fail, end. Failures (reset, crash, halt, stack overflow, a wait that timed out, an SPI mode the
 * device cannot talk) are "fail" lines and make the exit status 1.
 * --echo prints the serial conversation on stdout as it happens ("[  0.512 s] > 50",
 * "[  0.530 s] < OK 0 50"; the log then goes to -o). --pty runs the firmware in real time with UART0
 * on a pseudo-terminal (emu_pty.c): it prints "pty <path>" on stdout, starts the CPU when a program
 * opens that path (as a Mega resets when its port is opened) and ends when that program closes it,
 * or at SIGINT/SIGTERM/SIGHUP (the end line says "closed" or "interrupted").
 * Exit status: 0 ran and nothing failed; 1 a failure was seen; 2 bad arguments or ELF.
 */
#include <errno.h>
#include <getopt.h>
#include <signal.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <avr_extint.h>
#include <sim_elf.h>

#include "emu.h"
#include "text_parse.h"

static const char usage[] =
    "usage: motionemu FIRMWARE.elf [options]\n"
    "Runs an Arduino Mega 2560 sketch (arduino-cli ELF) in simavr at 16 MHz; writes an event log.\n"
    "  -i, --input FILE       INPUT script: serial lines to send, pins to drive, and when (docs/emulator.md)\n"
    "  -e, --exec TEXT        one script command (repeatable; runs after --input)\n"
    "  -o, --output FILE      event log file (default: stdout)\n"
    "  -p, --pin NAME=PIN     log the edges of a pin; PIN is D54, A0, PF0 or F0 (repeatable)\n"
    "      --motor SPEC       emulate an H-bridge + DC motor (sim/plant_dcmotor) + LS7366R on SPI:\n"
    "                         SPEC = PWM=D3,DIR=D12,CS=D53[,BRAKE=D9][,DIRPOS=1|0][,BRAKEON=1|0]\n"
    "      --ls7366r CS=PIN   an LS7366R alone, its encoder moved by the script's 'encoder' command\n"
    "      --matches          log Timer1's compare matches: 'match <cycle> OC1A|OC1B|OC1C'\n"
    "      --trace-pc FROM-TO every instruction run between these emulated times (ms, at most 50 apart):\n"
    "                         'pc <cycle> <address> I=<0|1>' (byte address, as avr-objdump -d prints it)\n"
    "  -d, --duration MS      run at least until this emulated time (default: until the script ends)\n"
    "      --max-ms MS        give up (fail 'limit') at this emulated time (default 600000; none with --pty)\n"
    "      --echo             print the serial conversation on stdout as it happens (needs -o)\n"
    "      --pty              an interactive board: UART0 on a pseudo-terminal (its path printed on stdout\n"
    "                         as 'pty <path>'), real time; starts when the path is opened, ends when it is closed\n"
    "  -h, --help             this text\n";

static avr_t *avr;
static uint64_t heap_start = 0x200;
static uint16_t brkval_addr; /* avr-libc's __brkval (the heap's end once malloc() has run), or 0 */
static uint16_t board_top_addr; /* MotionBoard's board_heap_top (the heap's end without malloc), or 0 */
static volatile sig_atomic_t stop_signal; /* --pty: SIGINT, SIGTERM or SIGHUP ends the run */

/* The end of static data and heap: __heap_start, or the heap's top once something has been taken
 * from it (malloc's __brkval, or MotionBoard's board_heap_top in a sketch without malloc: the step
 * rings live there, and a stack running into them corrupts the step commands). */
static uint64_t heap_end_now(const avr_t *avr)
{
    uint64_t end = heap_start;
    const uint16_t addr[2] = {brkval_addr, board_top_addr};
    for (int i = 0; i < 2; i++) {
        if (!addr[i])
            continue;
        uint16_t top = (uint16_t)(avr->data[addr[i]] | (avr->data[addr[i] + 1] << 8));
        if (top > end)
            end = top;
    }
    return end;
}

static void on_stop(int sig)
{
    stop_signal = sig;
}

static void logger(avr_t *a, const int level, const char *format, va_list ap)
{
    if (level > LOG_WARNING)
        return;
    char buf[512];
    vsnprintf(buf, sizeof buf, format, ap);
    size_t n = strlen(buf);
    while (n && (buf[n - 1] == '\n' || buf[n - 1] == '\r'))
        buf[--n] = 0;
    /* simavr colours some messages */
    char clean[512];
    size_t k = 0;
    for (size_t i = 0; i < n && k < sizeof clean - 1; i++) {
        if (buf[i] == 0x1b) {
            while (i < n && buf[i] != 'm')
                i++;
            continue;
        }
        clean[k++] = buf[i];
    }
    clean[k] = 0;
    /* the same message again and again (e.g. on every OCR write) is logged once */
    static char seen[32][96];
    static int nseen;
    for (int i = 0; i < nseen; i++)
        if (strncmp(seen[i], clean, sizeof seen[i] - 1) == 0)
            return;
    if (nseen < 32)
        memcpy(seen[nseen++], clean, sizeof seen[0] - 1); /* seen[][95] stays 0 */
    emu_log(a ? a->cycle : 0, "simavr", "%s %s (logged once)", level <= LOG_ERROR ? "error" : "warning", clean);
}

static void no_sleep(avr_t *a, avr_cycle_count_t how_long)
{
    (void)a;
    (void)how_long; /* emulated time only: never wait for the wall clock */
}

/* An arduino-cli ELF for the Mega: 32-bit little-endian ELF, machine AVR (83), arch avr6. */
static int check_elf(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "motionemu: cannot open '%s': %s\n", path, strerror(errno));
        return -1;
    }
    uint8_t h[52];
    size_t n = fread(h, 1, sizeof h, f);
    fclose(f);
    if (n < sizeof h || memcmp(h, "\x7f" "ELF", 4) != 0) {
        fprintf(stderr, "motionemu: '%s' is not an ELF file (build the sketch with 'make firmware')\n", path);
        return -1;
    }
    unsigned machine = h[18] | (h[19] << 8);
    uint32_t flags = h[36] | (h[37] << 8) | ((uint32_t)h[38] << 16) | ((uint32_t)h[39] << 24);
    if (h[4] != 1 || h[5] != 1 || machine != 83) {
        fprintf(stderr, "motionemu: '%s' is an ELF file, but not for the AVR (machine %u)\n", path, machine);
        return -1;
    }
    if ((flags & 0x7f) != 6) {
        fprintf(stderr, "motionemu: '%s' is built for AVR architecture %u, not avr6 (ATmega2560)\n", path,
                (unsigned)(flags & 0x7f));
        return -1;
    }
    return 0;
}

/* Milliseconds 0..1e9, parsed by lib's text_parse (the sketches' and motionsim's parser). */
static int parse_ms(const char *s, double *out)
{
    return text_parse_real(s, 0, 1e9, out) == MS_OK ? 0 : -1;
}

/* --trace-pc "FROM-TO" (ms) -> the first and last cycle; -1 when not that, TO not after FROM or the
 * span above 50 ms (about 600,000 log lines) */
static int parse_span_ms(const char *s, uint64_t *from, uint64_t *to)
{
    char a[64];
    const char *dash = strchr(s, '-');
    double f, t;
    if (!dash || dash == s || (size_t)(dash - s) >= sizeof a)
        return -1;
    memcpy(a, s, (size_t)(dash - s));
    a[dash - s] = '\0';
    if (parse_ms(a, &f) || parse_ms(dash + 1, &t) || t <= f || t - f > 50.0)
        return -1;
    *from = (uint64_t)(f * (EMU_F_CPU / 1000));
    *to = (uint64_t)(t * (EMU_F_CPU / 1000));
    return 0;
}

/* "KEY=VAL,KEY=VAL" -> value of key, or NULL */
static const char *spec_get(const char *spec, const char *key, char *buf, size_t cap)
{
    size_t kl = strlen(key);
    const char *s = spec;
    while (*s) {
        const char *e = strchr(s, ',');
        size_t len = e ? (size_t)(e - s) : strlen(s);
        if (len > kl && strncmp(s, key, kl) == 0 && s[kl] == '=') {
            size_t vl = len - kl - 1;
            if (vl >= cap)
                vl = cap - 1;
            memcpy(buf, s + kl + 1, vl);
            buf[vl] = 0;
            return buf;
        }
        s += len + (e ? 1 : 0);
    }
    return NULL;
}

static int spec_check_keys(const char *spec, const char *const *keys)
{
    const char *s = spec;
    while (*s) {
        const char *e = strchr(s, ',');
        size_t len = e ? (size_t)(e - s) : strlen(s);
        const char *eq = memchr(s, '=', len);
        int ok = 0;
        for (int i = 0; eq && keys[i]; i++)
            if ((size_t)(eq - s) == strlen(keys[i]) && strncmp(s, keys[i], strlen(keys[i])) == 0)
                ok = 1;
        if (!ok) {
            fprintf(stderr, "motionemu: bad item '%.*s' in '%s'\n", (int)len, s, spec);
            return -1;
        }
        s += len + (e ? 1 : 0);
    }
    return 0;
}

static int pin_from_spec(const char *spec, const char *key, emu_pin_t *pin, int required)
{
    char buf[16];
    if (!spec_get(spec, key, buf, sizeof buf)) {
        if (required)
            fprintf(stderr, "motionemu: '%s' needs %s=<pin>\n", spec, key);
        return required ? -1 : 1;
    }
    if (emu_pin_parse(buf, pin)) {
        fprintf(stderr, "motionemu: %s=%s is not a Mega pin (D0..D69, A0..A15, PA0..PL7)\n", key, buf);
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *elf = NULL, *input = NULL, *output = NULL, *motor_spec = NULL, *ls_spec = NULL;
    double duration_ms = 0, max_ms = 600000;
    const char *pins[64];
    int npins = 0;
    const char *execs[256];
    int nexecs = 0;
    int matches = 0, echo = 0, pty = 0, max_given = 0;
    uint64_t trace_from = 1, trace_to = 0; /* --trace-pc, in cycles (none: from > to) */

    /* getopt_long(3), in order ("-": the firmware file comes back as 1 where it stands; ":": a missing
     * value as ':'); "--" ends the options. Whole names only: a unique prefix ("--dur") is refused,
     * as in motionsim. Options that are not repeatable are refused when given twice. Every short
     * option takes a value or ends the parse (-h), so each call starts at the beginning of an
     * argument. */
    enum { OPT_MOTOR = 256, OPT_LS7366R, OPT_MATCHES, OPT_ECHO, OPT_PTY, OPT_TRACE_PC, OPT_MAX_MS };
    static const struct option longopts[] = {
        {"input", required_argument, NULL, 'i'},     {"exec", required_argument, NULL, 'e'},
        {"output", required_argument, NULL, 'o'},    {"pin", required_argument, NULL, 'p'},
        {"motor", required_argument, NULL, OPT_MOTOR}, {"ls7366r", required_argument, NULL, OPT_LS7366R},
        {"duration", required_argument, NULL, 'd'},  {"max-ms", required_argument, NULL, OPT_MAX_MS},
        {"matches", no_argument, NULL, OPT_MATCHES}, {"echo", no_argument, NULL, OPT_ECHO},
        {"pty", no_argument, NULL, OPT_PTY},         {"trace-pc", required_argument, NULL, OPT_TRACE_PC},
        {"help", no_argument, NULL, 'h'},            {NULL, 0, NULL, 0}};
    unsigned char given[OPT_MAX_MS + 1] = {0};
    opterr = 0;
    for (;;) {
        const char *a = optind < argc ? argv[optind] : ""; /* the argument this call reads */
        int li = -1;
        int c = getopt_long(argc, argv, "-:i:e:o:p:d:h", longopts, &li);
        if (c == -1)
            break;
        if (c == 1) {
            if (elf) {
                fprintf(stderr, "motionemu: one firmware file only ('%s' and '%s')\n", elf, optarg);
                return 2;
            }
            elf = optarg;
            continue;
        }
        if (c == '?' && optopt == 0) { /* a long option not in the table (or a prefix of several) */
            fprintf(stderr, "motionemu: unknown option '%.*s'\n%s", (int)strcspn(a, "="), a, usage);
            return 2;
        }
        if (c == '?' && optopt < OPT_MOTOR && optopt != 'h') { /* a short option not in the table */
            fprintf(stderr, "motionemu: unknown option '-%c'\n%s", optopt, usage);
            return 2;
        }
        int id = (c == '?' || c == ':') ? optopt : c;
        const char *name = NULL; /* the option's whole long name */
        for (int k = 0; longopts[k].name; k++)
            if (longopts[k].val == id)
                name = longopts[k].name;
        if (!strncmp(a, "--", 2) && (strcspn(a + 2, "=") != strlen(name) || strncmp(a + 2, name, strlen(name)))) {
            fprintf(stderr, "motionemu: option '%.*s' is abbreviated: write --%s (abbreviations are not accepted)\n",
                    (int)strcspn(a, "="), a, name);
            return 2;
        }
        if (c == ':') {
            fprintf(stderr, "motionemu: option %s needs a value\n%s", a, usage);
            return 2;
        }
        if (c == '?') { /* options without a value given one (--help=1) */
            fprintf(stderr, "motionemu: option --%s takes no value\n", name);
            return 2;
        }
        if (c != 'e' && c != 'p' && given[c]++) { /* --exec and --pin are repeatable */
            fprintf(stderr, "motionemu: --%s given twice\n", name);
            return 2;
        }
        switch (c) {
        case 'h':
            fputs(usage, stdout);
            return 0;
        case 'i':
            input = optarg;
            break;
        case 'e':
            if (nexecs == 256) {
                fprintf(stderr, "motionemu: too many --exec\n");
                return 2;
            }
            execs[nexecs++] = optarg;
            break;
        case 'o':
            output = optarg;
            break;
        case 'p':
            if (npins == 64) {
                fprintf(stderr, "motionemu: too many --pin\n");
                return 2;
            }
            pins[npins++] = optarg;
            break;
        case OPT_MOTOR:
            motor_spec = optarg;
            break;
        case OPT_LS7366R:
            ls_spec = optarg;
            break;
        case OPT_MATCHES:
            matches = 1;
            break;
        case OPT_ECHO:
            echo = 1;
            break;
        case OPT_PTY:
            pty = 1;
            break;
        case OPT_TRACE_PC:
            if (parse_span_ms(optarg, &trace_from, &trace_to)) {
                fprintf(stderr, "motionemu: --trace-pc wants FROM-TO in milliseconds, TO after FROM and at most "
                                "50 ms later (e.g. 2586.5-2586.7), not '%s'\n", optarg);
                return 2;
            }
            break;
        case 'd':
            if (parse_ms(optarg, &duration_ms)) {
                fprintf(stderr, "motionemu: --duration wants milliseconds, not '%s'\n", optarg);
                return 2;
            }
            break;
        case OPT_MAX_MS:
            if (parse_ms(optarg, &max_ms) || max_ms <= 0) {
                fprintf(stderr, "motionemu: --max-ms wants milliseconds, not '%s'\n", optarg);
                return 2;
            }
            max_given = 1;
            break;
        }
    }
    for (; optind < argc; optind++) { /* after "--" */
        if (elf) {
            fprintf(stderr, "motionemu: one firmware file only ('%s' and '%s')\n", elf, argv[optind]);
            return 2;
        }
        elf = argv[optind];
    }
    if (!elf) {
        fprintf(stderr, "motionemu: no firmware file given\n%s", usage);
        return 2;
    }
    if (motor_spec && ls_spec) {
        fprintf(stderr, "motionemu: --motor already includes an LS7366R; give one of --motor, --ls7366r\n");
        return 2;
    }
    if (check_elf(elf))
        return 2;
    int have_script = 0;
    if (input) {
        if (emu_script_load(input))
            return 2;
        have_script = 1;
    }
    for (int i = 0; i < nexecs; i++) {
        if (emu_script_load_text(execs[i], "--exec"))
            return 2;
        have_script = 1;
    }
    const char *enc_script = NULL;
    int enc_line = emu_script_encoder_line(&enc_script);
    if (enc_line && !ls_spec) {
        fprintf(stderr, "motionemu: %s:%d: 'encoder' needs --ls7366r CS=<pin> (with --motor the motor turns the "
                        "encoder)\n", enc_script, enc_line);
        return 2;
    }
    if (!have_script && duration_ms <= 0 && !pty) {
        fprintf(stderr, "motionemu: nothing to run: give --input, --exec, --duration or --pty\n");
        return 2;
    }
    if (echo && !output) {
        fprintf(stderr, "motionemu: --echo prints on stdout: give the log a file with -o\n");
        return 2;
    }
    if (pty && !output) {
        fprintf(stderr, "motionemu: --pty prints the terminal's path on stdout: give the log a file with -o\n");
        return 2;
    }

    FILE *out = stdout;
    if (output && !(out = fopen(output, "w"))) {
        fprintf(stderr, "motionemu: cannot write '%s': %s\n", output, strerror(errno));
        return 2;
    }
    static char outbuf[1 << 16];
    setvbuf(out, outbuf, _IOFBF, sizeof outbuf);
    emu_log_open(out);
    avr_global_logger_set(logger);

    elf_firmware_t fw;
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(elf, &fw) != 0 || fw.flashsize == 0) {
        fprintf(stderr, "motionemu: cannot load '%s' (no code in it?)\n", elf);
        return 2;
    }
    if (fw.flashsize > 256 * 1024) {
        fprintf(stderr, "motionemu: '%s' holds %u bytes: more than the ATmega2560's 256 KiB flash\n", elf,
                fw.flashsize);
        return 2;
    }
    for (uint32_t i = 0; i < fw.symbolcount; i++)
        if (!strcmp(fw.symbol[i]->symbol, "__heap_start"))
            heap_start = fw.symbol[i]->addr & 0xffff; /* data addresses carry 0x800000 in the ELF */
    if (heap_start == 0x200)
        heap_start = 0x200 + fw.datasize + fw.bsssize;
    for (uint32_t i = 0; i < fw.symbolcount; i++)
        if (!strcmp(fw.symbol[i]->symbol, "__brkval"))
            brkval_addr = fw.symbol[i]->addr & 0xffff;
        else if (!strcmp(fw.symbol[i]->symbol, "board_heap_top"))
            board_top_addr = fw.symbol[i]->addr & 0xffff;
    strcpy(fw.mmcu, "atmega2560");
    fw.frequency = EMU_F_CPU;

    avr = avr_make_mcu_by_name(fw.mmcu);
    if (!avr) {
        fprintf(stderr, "motionemu: this libsimavr has no atmega2560\n");
        return 2;
    }
    avr_init(avr);
    avr->log = LOG_WARNING;
    avr_load_firmware(avr, &fw);
    avr->frequency = EMU_F_CPU;
    avr->vcc = avr->avcc = avr->aref = 5000; /* mV: the Mega runs from 5 V, AREF = AVCC */
    avr->sleep = no_sleep;
    /* simavr polls a low INTn pin on every cycle while its EICRA bits are 00 (level mode, the reset
     * default), whether or not the interrupt is enabled: an output pin such as D3 (PE5 = INT5)
     * held low slows emulation 20-fold. Level-triggered INTn then fire once per falling edge;
     * no sketch here uses them. */
    for (uint8_t i = 0; i < 8; i++)
        avr_extint_set_strict_lvl_trig(avr, i, 0);

    if (emu_timer_attach(avr)) {
        fprintf(stderr, "motionemu: this simavr has no 16-bit timers' compare registers where expected\n");
        return 2;
    }
    if (matches && emu_timer_log_matches(avr)) {
        fprintf(stderr, "motionemu: no Timer1 compare channels to watch in this simavr\n");
        return 2;
    }
    if (emu_uart_attach(avr)) {
        fprintf(stderr, "motionemu: no UART0 in this simavr\n");
        return 2;
    }
    for (int i = 0; i < npins; i++) {
        char name[32];
        const char *eq = strchr(pins[i], '=');
        emu_pin_t pin;
        if (!eq || eq == pins[i] || (size_t)(eq - pins[i]) >= sizeof name || emu_pin_parse(eq + 1, &pin)) {
            fprintf(stderr, "motionemu: --pin wants NAME=PIN with PIN one of D0..D69, A0..A15, PA0..PL7, not '%s'\n",
                    pins[i]);
            return 2;
        }
        memcpy(name, pins[i], (size_t)(eq - pins[i]));
        name[eq - pins[i]] = 0;
        if (emu_pin_watch(avr, name, pin)) {
            fprintf(stderr, "motionemu: cannot watch pin %s (already watched under another name?)\n", pins[i]);
            return 2;
        }
        emu_pwm_attach(avr, pin);
    }
    if (motor_spec) {
        static const char *const keys[] = {"PWM", "DIR", "BRAKE", "CS", "DIRPOS", "BRAKEON", NULL};
        emu_motor_config_t cfg = {.dir_high_positive = 1, .brake_high_active = 1};
        char buf[16];
        if (spec_check_keys(motor_spec, keys) || pin_from_spec(motor_spec, "PWM", &cfg.pwm, 1) ||
            pin_from_spec(motor_spec, "DIR", &cfg.dir, 1) || pin_from_spec(motor_spec, "CS", &cfg.cs, 1))
            return 2;
        int rc = pin_from_spec(motor_spec, "BRAKE", &cfg.brake, 0);
        if (rc < 0)
            return 2;
        cfg.have_brake = rc == 0;
        if (spec_get(motor_spec, "DIRPOS", buf, sizeof buf))
            cfg.dir_high_positive = strcmp(buf, "0") != 0;
        if (spec_get(motor_spec, "BRAKEON", buf, sizeof buf))
            cfg.brake_high_active = strcmp(buf, "0") != 0;
        if (emu_motor_attach(avr, &cfg)) {
            fprintf(stderr, "motionemu: cannot attach the motor to '%s'\n", motor_spec);
            return 2;
        }
    }
    if (ls_spec) {
        static const char *const keys[] = {"CS", NULL};
        emu_pin_t cs;
        if (spec_check_keys(ls_spec, keys) || pin_from_spec(ls_spec, "CS", &cs, 1))
            return 2;
        if (emu_encoder_attach(avr, cs)) {
            fprintf(stderr, "motionemu: cannot attach the LS7366R\n");
            return 2;
        }
    }

    char pty_path[256] = "";
    if (pty) {
        if (emu_pty_open(pty_path, sizeof pty_path))
            return 2;
        emu_uart_set_sink(emu_pty_put);
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_stop;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
        sigaction(SIGHUP, &sa, NULL);
        signal(SIGPIPE, SIG_IGN);
        if (!max_given)
            max_ms = 1e9; /* an interactive board runs until it is closed */
        printf("pty %s\n", pty_path);
        fflush(stdout);
        emu_log(0, "pty", "%s", pty_path);
        /* the board starts when the port is opened, as a Mega resets when its port is opened */
        while (!emu_pty_connected() && !stop_signal) {
            struct timespec ts = {0, 20 * 1000 * 1000};
            nanosleep(&ts, NULL);
        }
    }
    if (echo)
        emu_echo_open(stdout);

    emu_log(0, "boot", "elf=%s mcu=atmega2560 f_cpu=%u heap_start=0x%04" PRIx64 " flash=%u", elf, EMU_F_CPU,
            heap_start, fw.flashsize);

    const uint64_t duration = (uint64_t)(duration_ms * (EMU_F_CPU / 1000.0));
    const uint64_t limit = (uint64_t)(max_ms * (EMU_F_CPU / 1000.0));
    uint64_t wake = 0;
    size_t lines_seen = 0;
    int script_done = !have_script;
    int booted = 0;
    long min_free = 0x10000L;
    uint16_t min_sp = 0xffff; /* the deepest the stack went: stack_max in the end line */
    uint16_t prev_sp = 0;
    uint32_t min_sp_pc = 0;
    uint64_t min_sp_cycle = 0;
    int stack_reported = 0;
    const char *reason = "done";
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    const uint64_t io_every = EMU_F_CPU / 1000; /* --pty: the port and the wall clock every emulated ms */
    uint64_t next_io = 0;
    if (pty && stop_signal) {
        reason = "interrupted";
        goto ended;
    }

    for (;;) {
        int st = avr_run(avr);
        if (avr->cycle >= trace_from && avr->cycle <= trace_to)
            emu_log(avr->cycle, "pc", "0x%05x I=%d", avr->pc, avr->sreg[S_I]);
        if (st == cpu_Crashed) {
            emu_fail(avr->cycle, "crash", "simavr stopped the CPU (invalid memory access or opcode) at PC=0x%05x",
                     avr->pc);
            reason = "crash";
            break;
        }
        if (st == cpu_Done) {
            emu_fail(avr->cycle, "halt", "the firmware went to sleep with interrupts off (it has stopped) at PC=0x%05x",
                     avr->pc);
            reason = "halt";
            break;
        }
        if (avr->pc == 0) {
            if (booted) {
                emu_fail(avr->cycle, "reset", "the program counter went back to 0 (reset, watchdog or a jump to "
                                              "an unused interrupt vector)");
                booted = 0;
            }
        } else {
            booted = 1;
            uint16_t sp = (uint16_t)(avr->data[R_SPL] | (avr->data[R_SPH] << 8));
            /* at every instruction, against the end of static data and heap as it is then (heap_end_now):
             * a stack that reached deep before the heap grew there is no overflow, and one that runs
             * into the heap later, above its lowest point so far, is one; the least room seen is the
             * end line's stack_min_free; reported once */
            /* avr-gcc's prologue writes SPH, then (after SREG) SPL: for those two instructions a frame
             * that crosses a 256-byte boundary reads up to 255 bytes off; a change of the high byte
             * alone is such a half-written pointer, and waits for its low byte */
            int half = (sp >> 8) != (prev_sp >> 8) && (sp & 0xff) == (prev_sp & 0xff);
            prev_sp = sp;
            if (sp != 0 && !half) {
                uint64_t bound = heap_end_now(avr);
                long room = (long)sp - (long)bound;
                if (sp < min_sp) {
                    min_sp = sp;
                    min_sp_pc = avr->pc;
                    min_sp_cycle = avr->cycle;
                }
                if (room < min_free)
                    min_free = room;
                if (room < 0 && !stack_reported) {
                    emu_fail(avr->cycle, "stack", "stack pointer 0x%04x below the end of static data and heap 0x%04" PRIx64
                             " (stack overflow)", sp, bound);
                    stack_reported = 1;
                }
            }
        }
        uint64_t now = avr->cycle;
        if (!script_done && (now >= wake || emu_uart_line_count() != lines_seen)) {
            lines_seen = emu_uart_line_count();
            int finished;
            wake = emu_script_step(avr, &finished);
            if (finished)
                script_done = 1;
        }
        if (now >= next_io) {
            next_io = now + io_every;
            if (pty) {
                if (emu_pty_service(now)) {
                    reason = "closed";
                    break;
                }
                /* real time: wait until the wall clock has caught up with the emulated one */
                struct timespec tw;
                clock_gettime(CLOCK_MONOTONIC, &tw);
                double ahead = (double)now / EMU_F_CPU -
                               ((double)(tw.tv_sec - t0.tv_sec) + (double)(tw.tv_nsec - t0.tv_nsec) * 1e-9);
                if (ahead > 0.0005) {
                    struct timespec ts = {(time_t)ahead, (long)((ahead - (double)(time_t)ahead) * 1e9)};
                    nanosleep(&ts, NULL);
                }
            } else if (emu_echo_on() && emu_echo_quiet_ms() >= 10000) {
                emu_echo_note(now, "... (emulating: %.1f s so far)", (double)now / EMU_F_CPU);
            }
            if (stop_signal) {
                reason = "interrupted";
                break;
            }
        }
        if (script_done && now >= duration && !pty)
            break;
        if (now >= limit) {
            emu_fail(now, "limit", "emulated time reached --max-ms %g", max_ms);
            reason = "limit";
            break;
        }
    }
ended:
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double wall = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
    emu_motor_summary(avr->cycle);
    /* free stack: the least room seen between the stack pointer and the end of static data and heap */
    long stack_free = min_free;
    if (emu_fail_count() && !strcmp(reason, "done"))
        reason = "failed";
    emu_log(avr->cycle, "end", "%s t_s=%.6f wall_s=%.3f speed=%.1fx fails=%d stack_min_free=%ld ready=%d stack_max=%ld stack_max_pc=0x%05x stack_max_cycle=%" PRIu64, reason,
            (double)avr->cycle / EMU_F_CPU, wall, wall > 0 ? (double)avr->cycle / EMU_F_CPU / wall : 0.0,
            emu_fail_count(), stack_free, emu_uart_ready_count(), min_sp == 0xffff ? 0L : (long)avr->ramend - (long)min_sp, (unsigned)min_sp_pc, min_sp_cycle);
    emu_log_flush();
    if (out != stdout)
        fclose(out);
    return emu_fail_count() ? 1 : 0;
}
