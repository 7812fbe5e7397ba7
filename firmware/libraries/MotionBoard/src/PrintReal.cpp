/* PrintReal.cpp - see PrintReal.h. */
#include "PrintReal.h"

#include <stdlib.h>
#include <string.h>

void print_real(Print &out, double v, uint8_t decimals)
{
    char buf[24];
    char *end;
    if (!(v == v)) {
        out.print(F("nan"));
        return;
    }
    if (v > 1e9 || v < -1e9) {
        out.print(v > 0 ? F("1e9+") : F("-1e9+"));
        return;
    }
    dtostrf(v, 1, decimals, buf);
    end = buf + strlen(buf);
    if (decimals > 0) {
        while (end > buf && end[-1] == '0')
            *--end = '\0';
        if (end > buf && end[-1] == '.')
            *--end = '\0';
    }
    if (strcmp(buf, "-0") == 0)
        strcpy(buf, "0");
    out.print(buf);
}

void print_real_exact(Print &out, double v, void (*between)())
{
    char buf[24];
    unsigned char d;
    if (v == 0.0) {
        out.print('0');
        return;
    }
    if (v > -1e9 && v < 1e9 && v == (double)(long)v) {
        out.print((long)v); /* whole numbers (most parameters): no conversion loop */
        return;
    }
    if (!(v < 1e12 && v > -1e12)) { /* never for our bounded parameters; keeps buf safe */
        out.print(v, 0);
        return;
    }
    for (d = 0; d <= 6; d++) {
        if (between)
            between();
        dtostrf(v, 0, d, buf);
        if (strtod(buf, NULL) == v) {
            out.print(buf);
            return;
        }
    }
    dtostre(v, buf, 6, 0);
    out.print(buf);
}
