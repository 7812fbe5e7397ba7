/* MotionSerial.cpp - see MotionSerial.h. */
#include "MotionSerial.h"

const char *MotionSerial::poll(uint8_t max_bytes)
{
    while (max_bytes-- > 0 && port_.available() > 0) {
        int c;
        if (queue_ != 0 && queue_->room() < reserve_)
            break; /* back-pressure: leave the input unread until a reply surely fits */
        c = port_.read();
        motion_status_t err = MS_OK;
        if (c < 0)
            break;
        switch (line_reader_feed(&reader_, (uint8_t)c, &err)) {
        case LINE_READY:
            return reader_.line;
        case LINE_ERROR:
            reply_error(err);
            if (queue_ != 0)
                return NULL; /* one reply per call: the next line waits for the next pass */
            break;
        default:
            break;
        }
    }
    return NULL;
}

void MotionSerial::reply_error(motion_status_t status)
{
    out_.print(F("ERR "));
    out_.println(reinterpret_cast<const __FlashStringHelper *>(motion_status_text(status)));
}

void MotionSerial::reply_error(motion_status_t status, const __FlashStringHelper *detail)
{
    begin_error(status).println(detail);
}

Print &MotionSerial::begin_error(motion_status_t status)
{
    out_.print(F("ERR "));
    out_.print(reinterpret_cast<const __FlashStringHelper *>(motion_status_text(status)));
    out_.print(F(": "));
    return out_;
}
