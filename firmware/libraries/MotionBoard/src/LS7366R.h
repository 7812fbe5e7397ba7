/* LS7366R.h - the LSI/CSI LS7366R 32-bit quadrature counter on the hardware SPI bus.
 *
 * begin() configures it as the servo sketches need: MDR0 = 0x03 (x4 quadrature, free-running,
 * index off, filter clock /1), MDR1 = 0x00 (4-byte counter, counting enabled, no flags), then
 * clears CNTR and reads MDR0/MDR1 back to tell whether a chip answers. read() fetches CNTR with
 * RD CNTR (the chip latches CNTR into OTR and shifts it out, MSB first), so one read is one
 * consistent 32-bit snapshot. Instruction byte: op (00 CLR, 01 RD, 10 WR, 11 LOAD) in bits 7-6,
 * register (001 MDR0, 010 MDR1, 011 DTR, 100 CNTR, 101 OTR, 110 STR) in bits 5-3.
 * SPI mode 0, MSB first, 4 MHz (the datasheet's minimum SCK period is about 240 ns).
 * Cost: read() is 5 bytes at 4 MHz plus chip-select handling, about 30 us.
 */
#ifndef LS7366R_H
#define LS7366R_H

#include <Arduino.h>

class LS7366R {
public:
    static const uint8_t MDR0_X4_FREE_RUN = 0x03;
    static const uint8_t MDR1_4_BYTES = 0x00;

    explicit LS7366R(uint8_t cs_pin) : cs_(cs_pin) {}

    /* Configures the chip and clears the count; true when MDR0/MDR1 read back as written. */
    bool begin();
    /* The 32-bit count (wraps like the chip's counter). */
    int32_t read();
    /* CNTR := 0 */
    void clear();
    uint8_t readRegister(uint8_t rd_instruction);

    static const uint8_t CLR_CNTR = 0x20;
    static const uint8_t RD_MDR0 = 0x48;
    static const uint8_t RD_MDR1 = 0x50;
    static const uint8_t RD_CNTR = 0x60;
    static const uint8_t WR_MDR0 = 0x88;
    static const uint8_t WR_MDR1 = 0x90;

private:
    void select();
    void deselect();
    void writeRegister(uint8_t wr_instruction, uint8_t value);
    uint8_t cs_;
};

#endif
