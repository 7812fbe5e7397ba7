/* emu_pty.c - UART0 as a pseudo-terminal (motionemu --pty): the emulated Mega's USB serial port.
 *
 * The harness opens a pty master (posix_openpt, grantpt, unlockpt) and names its terminal side
 * (ptsname, e.g. /dev/pts/3). It sets that side raw once (no echo, no line editing, no CR/LF
 * translation, 8 bits); a monitor (make monitor, picocom, pyserial) opens it like /dev/ttyACM0 and
 * may set any baud rate: the emulated UART keeps the rate the firmware programmed, as the Mega's
 * USB bridge does. Bytes typed go to the firmware's UART0 as they come, one frame apart
 * (emu_uart_send); every byte the firmware writes to UDR0 goes to the terminal side.
 * On Linux the master polls POLLHUP while no program has the terminal side open: that is how
 * the harness sees a monitor connect and, later, close the port.
 */
#define _XOPEN_SOURCE 600
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

#include "emu.h"

static int master = -1;
static uint8_t outbuf[1 << 16]; /* firmware -> host, not yet taken by the pty */
static size_t out_len;
static uint64_t out_dropped;
static uint8_t line[4096]; /* the host's current line, for the echo */
static size_t line_len;

int emu_pty_open(char *path, size_t cap)
{
    master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) || unlockpt(master)) {
        fprintf(stderr, "motionemu: cannot open a pseudo-terminal: %s\n", strerror(errno));
        return -1;
    }
    const char *name = ptsname(master);
    if (!name || strlen(name) >= cap) {
        fprintf(stderr, "motionemu: the pseudo-terminal has no usable name\n");
        return -1;
    }
    strcpy(path, name);
    /* raw, set once on the terminal side (the setting stays with the pty when we close it) */
    int slave = open(name, O_RDWR | O_NOCTTY);
    if (slave < 0) {
        fprintf(stderr, "motionemu: cannot open %s: %s\n", name, strerror(errno));
        return -1;
    }
    struct termios t;
    if (tcgetattr(slave, &t) == 0) {
        t.c_iflag &= ~(tcflag_t)(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON);
        t.c_oflag &= ~(tcflag_t)OPOST;
        t.c_lflag &= ~(tcflag_t)(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
        t.c_cflag &= ~(tcflag_t)(CSIZE | PARENB);
        t.c_cflag |= CS8;
        t.c_cc[VMIN] = 1;
        t.c_cc[VTIME] = 0;
        cfsetispeed(&t, B9600);
        cfsetospeed(&t, B9600);
        tcsetattr(slave, TCSANOW, &t);
    }
    close(slave);
    int fl = fcntl(master, F_GETFL);
    fcntl(master, F_SETFL, fl | O_NONBLOCK);
    return 0;
}

int emu_pty_connected(void)
{
    struct pollfd p = {master, POLLIN, 0};
    if (poll(&p, 1, 0) < 0)
        return 0;
    return !(p.revents & POLLHUP);
}

void emu_pty_put(uint8_t byte)
{
    if (out_len == sizeof outbuf) { /* the host reads nothing: the oldest output is lost */
        if (!out_dropped++)
            emu_log(0, "warn", "the host does not read the serial port: output dropped");
        memmove(outbuf, outbuf + 1, out_len - 1);
        out_len--;
    }
    outbuf[out_len++] = byte;
}

static void flush_out(void)
{
    while (out_len) {
        ssize_t w = write(master, outbuf, out_len);
        if (w <= 0)
            return; /* EAGAIN: the pty's buffer is full, try again later */
        memmove(outbuf, outbuf + w, out_len - (size_t)w);
        out_len -= (size_t)w;
    }
}

int emu_pty_service(uint64_t cycle)
{
    flush_out();
    uint8_t buf[256];
    for (;;) {
        ssize_t n = read(master, buf, sizeof buf);
        if (n <= 0)
            break; /* EAGAIN: nothing typed; EIO: the host has closed (seen below) */
        emu_log_text(cycle, "txraw", buf, (size_t)n);
        emu_uart_send(buf, (size_t)n);
        /* the echo: one line per CR, LF or CR LF */
        for (ssize_t i = 0; i < n; i++) {
            uint8_t c = buf[i];
            if (c == '\r' || c == '\n') {
                if (line_len || c == '\r')
                    emu_echo(cycle, '>', line, line_len);
                line_len = 0;
                /* an LF right after a CR ends nothing more */
                if (c == '\r' && i + 1 < n && buf[i + 1] == '\n')
                    i++;
                continue;
            }
            if (line_len < sizeof line)
                line[line_len++] = c;
        }
    }
    return emu_pty_connected() ? 0 : -1;
}
