/* ma2_filter.c - two moving averages in series, exact at the samples (see ma2_filter.h). */
#include "ma2_filter.h"

#include <string.h>

motion_status_t ma2_filter_init(ma2_filter_t *f, int16_t *buf, uint16_t buf_len, uint16_t taps1, uint16_t taps2)
{
    if (f == NULL || buf == NULL)
        return MS_ERR_NULL;
    if (taps1 == 0 || taps2 == 0)
        return MS_ERR_TAU_BELOW_TS;
    if ((uint32_t)taps1 + taps2 > buf_len)
        return MS_ERR_TOO_MANY_TAPS;
    f->buf = buf;
    f->taps1 = taps1;
    f->taps2 = taps2;
    f->len = (uint16_t)(taps1 + taps2);
    ma2_filter_reset(f);
    return MS_OK;
}

void ma2_filter_reset(ma2_filter_t *f)
{
    memset(f->buf, 0, (size_t)f->len * sizeof f->buf[0]);
    f->head = 0;
    f->s1 = 0;
    f->s1_old = 0;
    f->t = 0;
}

int64_t ma2_filter_num(const ma2_filter_t *f)
{
    return 2 * f->t + f->s1 - f->s1_old;
}

uint32_t ma2_filter_den(const ma2_filter_t *f)
{
    return 2u * (uint32_t)f->taps1 * f->taps2;
}

/* Index of u[k-m] (1 <= m <= len) in the ring whose oldest entry u[k-len] is at head. */
static uint16_t ago(const ma2_filter_t *f, uint16_t m)
{
    uint32_t i = (uint32_t)f->head + (uint32_t)(f->len - m);
    return (uint16_t)(i >= f->len ? i - f->len : i);
}

int64_t ma2_filter_step(ma2_filter_t *f, int16_t u)
{
    int64_t y_num = ma2_filter_num(f);
    int16_t u_n1 = f->buf[ago(f, f->taps1)]; /* u[k-N1] */
    int16_t u_n2 = f->buf[ago(f, f->taps2)]; /* u[k-N2] */
    int16_t u_old = f->buf[f->head];         /* u[k-N1-N2] */
    f->t += (int64_t)f->s1 - f->s1_old;
    f->s1 += (int32_t)u - u_n1;
    f->s1_old += (int32_t)u_n2 - u_old;
    f->buf[f->head] = u;
    if (++f->head == f->len)
        f->head = 0;
    return y_num;
}
