/* MotionSerial.cpp - see MotionSerial.h. */
#include "MotionSerial.h"

void MotionSerial::drain_input()
{
    if (!started_) {
        SerialRx::begin(rx_interrupt_);
        started_ = true;
    }
    SerialRx::drain();
}

const char *MotionSerial::poll(uint8_t max_bytes)
{
    drain_input(); /* on every pass, even when no line may be read now (back-pressure) */
    while (max_bytes-- > 0) {
        uint8_t c = 0;
        rx_loss_t loss = {0, 0, 0};
        rx_event_t ev;
        motion_status_t err = MS_OK;
        if (queue_ != 0 && queue_->room() < reserve_)
            break; /* back-pressure: leave the input unread until a reply surely fits */
        ev = SerialRx::get(c, loss);
        if (ev == RX_NONE)
            break;
        if (ev == RX_LOSS) {
            /* input was lost right here: the line in progress and the lines the loss touched are
             * answered together, at once, and none is executed */
            uint16_t lines = loss.lines;
            if (line_reader_lost(&reader_, loss.cont, loss.after_cr) && lines > 0)
                lines--; /* the line in progress already had its ERR */
            if (lines == 0)
                continue; /* e.g. only the LF of a CR LF: no line touched */
            Print &out = begin_error(MS_ERR_INPUT_OVERRUN);
            out.print(lines);
            out.println(lines == 1 ? F(" line lost") : F(" lines lost"));
            if (queue_ != 0)
                return NULL; /* one reply per call */
            continue;
        }
        switch (line_reader_feed(&reader_, c, &err)) {
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
