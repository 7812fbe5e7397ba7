/* emu_spi.c - the ATmega2560 SPI master with its real transfer time, and one attached device.
 *
 * simavr 1.6 completes every SPI byte 100 us after SPDR is written, whatever the clock; that is
 * 25 to 400 times too slow and would distort the timing of a control loop that reads a counter
 * chip. Here the SPDR write handler is replaced: a byte written in master mode (SPE and MSTR set
 * in SPCR) is exchanged with the device after 8 SPI clocks, fosc / {4, 16, 64, 128} per clock
 * (SPR1:0, halved by SPI2X), and then SPIF is raised and SPDR reads the device's answer, as on the
 * chip. The device's chip select is a port pin; its level changes are passed on as they happen.
 * The device sees the clock polarity/phase and bit order it is driven with; the LS7366R needs
 * mode 0 (CPOL = 0, CPHA = 0) and MSB first, anything else is logged as a failure.
 */
#include <stdlib.h>

#include "emu.h"

#define R_SPCR 0x4C
#define R_SPSR 0x4D
#define R_SPDR 0x4E

static avr_spi_t *spi;
static emu_spi_device_t device;
static uint8_t pending_mosi;
static uint64_t bytes;
static int mode_reported;

uint64_t emu_spi_byte_count(void)
{
    return bytes;
}

static avr_cycle_count_t transfer_done(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)when;
    (void)param;
    uint8_t spcr = avr->data[R_SPCR];
    if (!mode_reported && (spcr & 0x2c)) { /* DORD, CPOL, CPHA */
        mode_reported = 1;
        emu_fail(avr->cycle, "spi", "SPCR=0x%02x: the LS7366R needs SPI mode 0, MSB first (DORD=%d CPOL=%d CPHA=%d)", spcr,
                 (spcr >> 5) & 1, (spcr >> 3) & 1, (spcr >> 2) & 1);
    }
    uint8_t miso = device.transfer ? device.transfer(device.ctx, avr->cycle, pending_mosi) : 0xff;
    bytes++;
    spi->input_data_register = miso;
    avr_raise_interrupt(avr, &spi->spi);
    return 0;
}

static void spdr_write(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    (void)param;
    uint8_t spcr = avr->data[R_SPCR];
    avr_regbit_clear(avr, spi->spi.raised); /* writing SPDR clears SPIF (after SPSR was read) */
    avr->data[addr] = v;
    if (!(spcr & 0x40) || !(spcr & 0x10)) /* SPE, MSTR: only the master mode is emulated */
        return;
    static const uint32_t div[4] = {4, 16, 64, 128};
    uint32_t d = div[spcr & 3];
    if (avr->data[R_SPSR] & 1) /* SPI2X */
        d /= 2;
    pending_mosi = v;
    avr_cycle_timer_register(avr, 8 * d, transfer_done, NULL);
}

static void cs_changed(void *param, uint64_t cycle, int level)
{
    (void)param;
    if (device.select)
        device.select(device.ctx, cycle, level);
}

int emu_spi_attach(avr_t *avr, emu_pin_t cs, const emu_spi_device_t *dev)
{
    avr_io_addr_t a = AVR_DATA_TO_IO(R_SPDR);
    spi = (avr_spi_t *)avr->io[a].w.param;
    if (!spi || avr->io[a].r.param != (void *)spi)
        return -1; /* not simavr's SPI module on SPDR: refuse rather than guess */
    device = *dev;
    avr->io[a].w.c = spdr_write;
    return emu_pin_listen(avr, cs, cs_changed, NULL);
}
