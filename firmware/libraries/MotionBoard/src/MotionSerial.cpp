/* MotionSerial.cpp - see MotionSerial.h. */
#include "MotionSerial.h"

/* A full receive buffer (avail bytes): whatever arrives now is dropped by the core, so input may be lost right
 * after the bytes it holds. Remember that point (the first one still ahead, and the latest). */
void MotionSerial::check_overrun(int avail)
{
    if (!(pending_ & 1)) {
        pending_ |= 1;
        first_left_ = (uint8_t)avail;
    } else if (avail != first_left_) {
        pending_ |= 2;
        last_left_ = (uint8_t)avail;
    }
}

bool MotionSerial::lost_before_next()
{
    bool lost = false;
    if (pending_ & 1) {
        if (first_left_ == 0) {
            lost = true;
            pending_ &= (uint8_t)~1;
            if (pending_ & 2) { /* the later point becomes the next one */
                pending_ = 1;
                first_left_ = last_left_;
            }
        }
        if (pending_ & 1)
            first_left_--;
    }
    if (pending_ & 2)
        last_left_--;
    return lost;
}

const char *MotionSerial::poll(uint8_t max_bytes)
{
    int avail = port_.available();
    if (avail <= 0)
        return NULL; /* the usual case: no more work than before the overrun check existed */
    if (rx_full_ != 0 && avail >= (int)rx_full_)
        check_overrun(avail);
    while (max_bytes-- > 0 && port_.available() > 0) {
        int c;
        if (queue_ != 0 && queue_->room() < reserve_)
            break; /* back-pressure: leave the input unread until a reply surely fits */
        c = port_.read();
        motion_status_t err = MS_OK;
        if (c < 0)
            break;
        if (pending_ != 0 && lost_before_next()) {
            /* input was lost here: what follows is the host's next line, whatever state the current
             * one was in (even one already refused, whose end may be what was lost), so it is
             * answered ERR input overrun and discarded to its end: one reply, never none */
            (void)line_reader_overrun(&reader_);
            reply_error(MS_ERR_INPUT_OVERRUN);
            (void)line_reader_feed(&reader_, (uint8_t)c, &err); /* discarded, or its terminator */
            if (queue_ != 0)
                return NULL;
            continue;
        }
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
