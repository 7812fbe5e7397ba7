/* MotionSerial.cpp - see MotionSerial.h. */
#include "MotionSerial.h"

const char *MotionSerial::poll(uint8_t max_bytes)
{
    while (max_bytes-- > 0 && port_.available() > 0) {
        int c = port_.read();
        motion_status_t err = MS_OK;
        if (c < 0)
            break;
        switch (line_reader_feed(&reader_, (uint8_t)c, &err)) {
        case LINE_READY:
            return reader_.line;
        case LINE_ERROR:
            reply_error(err);
            break;
        default:
            break;
        }
    }
    return NULL;
}

void MotionSerial::reply_error(motion_status_t status)
{
    port_.print(F("ERR "));
    port_.println(reinterpret_cast<const __FlashStringHelper *>(motion_status_text(status)));
}

void MotionSerial::reply_error(motion_status_t status, const __FlashStringHelper *detail)
{
    port_.print(F("ERR "));
    port_.print(reinterpret_cast<const __FlashStringHelper *>(motion_status_text(status)));
    port_.print(F(": "));
    port_.println(detail);
}
