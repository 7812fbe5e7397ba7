/* LS7366R.cpp - see LS7366R.h. */
#include "LS7366R.h"

#include <SPI.h>

static const SPISettings ls7366r_spi(4000000, MSBFIRST, SPI_MODE0);

void LS7366R::select()
{
    SPI.beginTransaction(ls7366r_spi);
    digitalWrite(cs_, LOW);
}

void LS7366R::deselect()
{
    digitalWrite(cs_, HIGH);
    SPI.endTransaction();
}

void LS7366R::writeRegister(uint8_t wr_instruction, uint8_t value)
{
    select();
    SPI.transfer(wr_instruction);
    SPI.transfer(value);
    deselect();
}

uint8_t LS7366R::readRegister(uint8_t rd_instruction)
{
    uint8_t v;
    select();
    SPI.transfer(rd_instruction);
    v = SPI.transfer(0x00);
    deselect();
    return v;
}

bool LS7366R::begin()
{
    pinMode(cs_, OUTPUT);
    digitalWrite(cs_, HIGH);
    SPI.begin();
    writeRegister(WR_MDR0, MDR0_X4_FREE_RUN);
    writeRegister(WR_MDR1, MDR1_4_BYTES);
    clear();
    return readRegister(RD_MDR0) == MDR0_X4_FREE_RUN && readRegister(RD_MDR1) == MDR1_4_BYTES;
}

void LS7366R::clear()
{
    select();
    SPI.transfer(CLR_CNTR);
    deselect();
}

int32_t LS7366R::read()
{
    uint32_t v = 0;
    uint8_t i;
    select();
    SPI.transfer(RD_CNTR);
    for (i = 0; i < 4; i++)
        v = (v << 8) | SPI.transfer(0x00);
    deselect();
    return (int32_t)v;
}
