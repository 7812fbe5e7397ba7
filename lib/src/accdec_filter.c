/* accdec_filter.c - dispatch to the three filter kinds (see accdec_filter.h). */
#include "accdec_filter.h"

#include "filter_param.h"

static const char *const kind_names[ACCDEC_KIND_COUNT] = {"ma", "ma2", "exp"};

const char *accdec_kind_name(accdec_kind_t kind)
{
    return (unsigned)kind < (unsigned)ACCDEC_KIND_COUNT ? kind_names[kind] : NULL;
}

static int same_text(const char *a, const char *b)
{
    while (*a != '\0' && *a == *b) {
        a++;
        b++;
    }
    return *a == *b;
}

motion_status_t accdec_kind_parse(const char *name, accdec_kind_t *kind)
{
    int i;
    if (name == NULL || kind == NULL)
        return MS_ERR_NULL;
    for (i = 0; i < (int)ACCDEC_KIND_COUNT; i++) {
        if (same_text(name, kind_names[i])) {
            *kind = (accdec_kind_t)i;
            return MS_OK;
        }
    }
    return MS_ERR_FILTER_KIND;
}

motion_status_t accdec_configure(accdec_config_t *cfg, accdec_kind_t kind, double tau_s, double tau2_s,
                                 double ts_s, uint16_t buf_len)
{
    accdec_config_t c;
    motion_status_t st;
    if (cfg == NULL)
        return MS_ERR_NULL;
    if ((unsigned)kind >= (unsigned)ACCDEC_KIND_COUNT)
        return MS_ERR_FILTER_KIND;
    c.kind = kind;
    c.taps2 = 0;
    c.gain_q31 = 0;
    st = filt_taps(tau_s, ts_s, &c.taps1);
    if (st != MS_OK)
        return st;
    switch (kind) {
    case ACCDEC_MA:
        if (c.taps1 > buf_len)
            return MS_ERR_TOO_MANY_TAPS;
        break;
    case ACCDEC_MA2:
        st = filt_taps(tau2_s, ts_s, &c.taps2);
        if (st != MS_OK)
            return st;
        if ((uint32_t)c.taps1 + c.taps2 > buf_len)
            return MS_ERR_TOO_MANY_TAPS;
        break;
    default:
        st = exp_filter_gain_q31(c.taps1, &c.gain_q31);
        if (st != MS_OK)
            return st;
        break;
    }
    *cfg = c;
    return MS_OK;
}

uint16_t accdec_buffer_taps(const accdec_config_t *cfg)
{
    switch (cfg->kind) {
    case ACCDEC_MA: return cfg->taps1;
    case ACCDEC_MA2: return (uint16_t)(cfg->taps1 + cfg->taps2);
    default: return 0;
    }
}

uint32_t accdec_den(const accdec_config_t *cfg)
{
    switch (cfg->kind) {
    case ACCDEC_MA: return cfg->taps1;
    case ACCDEC_MA2: return 2u * (uint32_t)cfg->taps1 * cfg->taps2;
    default: return (uint32_t)1 << EXP_FILTER_FRAC_BITS;
    }
}

motion_status_t accdec_start(accdec_filter_t *f, const accdec_config_t *cfg, int16_t *buf, uint16_t buf_len)
{
    motion_status_t st;
    if (f == NULL || cfg == NULL)
        return MS_ERR_NULL;
    switch (cfg->kind) {
    case ACCDEC_MA: st = ma_filter_init(&f->f.ma, buf, buf_len, cfg->taps1); break;
    case ACCDEC_MA2: st = ma2_filter_init(&f->f.ma2, buf, buf_len, cfg->taps1, cfg->taps2); break;
    case ACCDEC_EXP: st = exp_filter_init(&f->f.exp, cfg->gain_q31); break;
    default: st = MS_ERR_FILTER_KIND; break;
    }
    if (st == MS_OK)
        f->cfg = *cfg;
    return st;
}

void accdec_reset(accdec_filter_t *f)
{
    switch (f->cfg.kind) {
    case ACCDEC_MA: ma_filter_reset(&f->f.ma); break;
    case ACCDEC_MA2: ma2_filter_reset(&f->f.ma2); break;
    default: exp_filter_reset(&f->f.exp); break;
    }
}

int64_t accdec_peek(const accdec_filter_t *f)
{
    switch (f->cfg.kind) {
    case ACCDEC_MA: return ma_filter_sum(&f->f.ma);
    case ACCDEC_MA2: return ma2_filter_num(&f->f.ma2);
    default: return exp_filter_frac(&f->f.exp);
    }
}

int64_t accdec_step(accdec_filter_t *f, int16_t u)
{
    switch (f->cfg.kind) {
    case ACCDEC_MA: return ma_filter_step(&f->f.ma, u);
    case ACCDEC_MA2: return ma2_filter_step(&f->f.ma2, u);
    default: return exp_filter_step(&f->f.exp, u);
    }
}

int32_t accdec_milli_quanta(int64_t num, uint32_t den)
{
    /* |num| < 2^31 * den (y within int16 quanta), so 1000 |num| + den/2 < 2^63. */
    int64_t a = num < 0 ? -num : num;
    int64_t r = (a * 1000 + (int64_t)(den / 2)) / (int64_t)den;
    return (int32_t)(num < 0 ? -r : r);
}
