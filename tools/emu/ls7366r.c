/* ls7366r.c - LS7366R quadrature counter logic (see ls7366r.h for the datasheet facts used). */
#include "ls7366r.h"

enum { OP_CLR = 0, OP_RD = 1, OP_WR = 2, OP_LOAD = 3 };
enum { REG_MDR0 = 1, REG_MDR1 = 2, REG_DTR = 3, REG_CNTR = 4, REG_OTR = 5, REG_STR = 6 };
enum { STR_CY = 0x80, STR_BW = 0x40, STR_CEN = 0x08, STR_UD = 0x02, STR_S = 0x01 };

static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

int ls7366r_width(const ls7366r_t *c)
{
    return 4 - (c->mdr1 & 3);
}

static uint32_t width_mask(const ls7366r_t *c)
{
    int w = ls7366r_width(c);
    return w == 4 ? 0xffffffffu : ((1u << (8 * w)) - 1u);
}

/* Folds the encoder motion since the last call into CNTR, per quadrature and count mode. */
static void fold(ls7366r_t *c, int64_t quad_now)
{
    int64_t seen = c->quad_seen;
    c->quad_seen = quad_now;
    if (c->mdr1 & 0x04) /* counting disabled */
        return;
    int64_t delta;
    switch (c->mdr0 & 3) {
    case 3: delta = quad_now - seen; break;                                   /* x4 */
    case 2: delta = floor_div(quad_now, 2) - floor_div(seen, 2); break;         /* x2 */
    default: delta = floor_div(quad_now, 4) - floor_div(seen, 4); break;        /* x1, non-quadrature */
    }
    if (delta == 0)
        return;
    if ((c->mdr0 >> 2) & 3)
        c->unsupported++; /* only the free-running count mode is modelled */
    uint32_t mask = width_mask(c);
    int64_t wide = (int64_t)(c->cntr & mask) + delta;
    c->str &= (uint8_t)~(STR_UD | STR_S);
    if (delta > 0)
        c->str |= STR_UD;
    if (wide > (int64_t)mask)
        c->str |= STR_CY;
    if (wide < 0)
        c->str |= STR_BW | STR_S;
    c->cntr = (uint32_t)((uint64_t)wide & mask);
}

void ls7366r_init(ls7366r_t *c, int64_t quad_now)
{
    *c = (ls7366r_t){0};
    c->quad_seen = quad_now;
    c->str = STR_CEN;
}

void ls7366r_select(ls7366r_t *c, int level, int64_t quad_now)
{
    fold(c, quad_now);
    if (level == 0 && !c->selected) {
        c->selected = 1;
        c->byte_index = 0;
        c->out_len = 0;
    } else if (level != 0) {
        c->selected = 0;
    }
}

static void load_out(ls7366r_t *c, uint32_t value, int n)
{
    c->out_len = n;
    for (int i = 0; i < n; i++)
        c->out[i] = (uint8_t)(value >> (8 * (n - 1 - i)));
}

uint8_t ls7366r_transfer(ls7366r_t *c, uint8_t mosi, int64_t quad_now)
{
    fold(c, quad_now);
    if (!c->selected)
        return 0xff; /* MISO is not driven */
    int k = c->byte_index++;
    if (k == 0) {
        c->ir = mosi;
        int op = mosi >> 6, reg = (mosi >> 3) & 7;
        switch (op) {
        case OP_CLR:
            if (reg == REG_MDR0) c->mdr0 = 0;
            else if (reg == REG_MDR1) c->mdr1 = 0;
            else if (reg == REG_CNTR) c->cntr = 0;
            else if (reg == REG_STR) c->str &= STR_CEN;
            else c->unsupported++;
            break;
        case OP_RD:
            if (reg == REG_MDR0) load_out(c, c->mdr0, 1);
            else if (reg == REG_MDR1) load_out(c, c->mdr1, 1);
            else if (reg == REG_CNTR) {
                c->otr = c->cntr;
                load_out(c, c->otr, ls7366r_width(c));
            } else if (reg == REG_OTR) load_out(c, c->otr, ls7366r_width(c));
            else if (reg == REG_STR) load_out(c, c->str, 1);
            else c->unsupported++;
            break;
        case OP_WR:
            if (reg == REG_DTR) c->dtr = 0;
            else if (reg != REG_MDR0 && reg != REG_MDR1) c->unsupported++;
            break;
        case OP_LOAD:
            if (reg == REG_CNTR) c->cntr = c->dtr & width_mask(c);
            else if (reg == REG_OTR) c->otr = c->cntr;
            else c->unsupported++;
            break;
        }
        return 0x00;
    }
    int op = c->ir >> 6, reg = (c->ir >> 3) & 7;
    if (op == OP_RD)
        return (k - 1 < c->out_len) ? c->out[k - 1] : 0x00;
    if (op == OP_WR) {
        if (reg == REG_MDR0 && k == 1) {
            c->mdr0 = mosi;
        } else if (reg == REG_MDR1 && k == 1) {
            c->mdr1 = mosi;
            c->str = (uint8_t)((c->str & ~STR_CEN) | ((mosi & 0x04) ? 0 : STR_CEN));
        } else if (reg == REG_DTR && k <= ls7366r_width(c)) {
            c->dtr = ((c->dtr << 8) | mosi) & width_mask(c);
        }
    }
    return 0x00;
}

uint32_t ls7366r_count(ls7366r_t *c, int64_t quad_now)
{
    fold(c, quad_now);
    return c->cntr;
}
