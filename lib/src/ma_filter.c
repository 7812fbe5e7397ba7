/* ma_filter.c - moving average over an integer ring buffer (see ma_filter.h). */
#include "ma_filter.h"

#include <string.h>

motion_status_t ma_filter_init(ma_filter_t *f, int16_t *buf, uint16_t buf_len, uint16_t taps)
{
    if (f == NULL || buf == NULL)
        return MS_ERR_NULL;
    if (taps == 0)
        return MS_ERR_TAU_BELOW_TS;
    if (taps > buf_len)
        return MS_ERR_TOO_MANY_TAPS;
    f->buf = buf;
    f->taps = taps;
    ma_filter_reset(f);
    return MS_OK;
}

void ma_filter_reset(ma_filter_t *f)
{
    memset(f->buf, 0, (size_t)f->taps * sizeof f->buf[0]);
    f->head = 0;
    f->sum = 0;
}

int32_t ma_filter_sum(const ma_filter_t *f)
{
    return f->sum;
}

int32_t ma_filter_step(ma_filter_t *f, int16_t u)
{
    int32_t y_sum = f->sum;
    int16_t *oldest = &f->buf[f->head];
    /* |sum| <= N * 32767 < 2^31 for N <= 65535: never overflows. */
    f->sum += (int32_t)u - (int32_t)*oldest;
    *oldest = u;
    if (++f->head == f->taps)
        f->head = 0;
    return y_sum;
}
