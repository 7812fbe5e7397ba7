/* ls7366r.h - the LSI/CSI LS7366R 32-bit quadrature counter with SPI interface, as its datasheet
 * describes it, for the emulator: instruction bytes, registers and chip select.
 *
 * Instruction byte (first byte after SS falls): bits 7:6 = operation (00 CLR, 01 RD, 10 WR,
 * 11 LOAD), bits 5:3 = register (001 MDR0, 010 MDR1, 011 DTR, 100 CNTR, 101 OTR, 110 STR).
 *   CLR MDR0 0x08, CLR MDR1 0x10, CLR CNTR 0x20, CLR STR 0x30
 *   RD MDR0 0x48, RD MDR1 0x50, RD CNTR 0x60 (CNTR -> OTR, then OTR shifted out), RD OTR 0x68,
 *   RD STR 0x70; WR MDR0 0x88, WR MDR1 0x90, WR DTR 0x98; LOAD CNTR 0xE0 (DTR -> CNTR),
 *   LOAD OTR 0xE8 (CNTR -> OTR).
 * Multi-byte registers move MSB first; their width is 4, 3, 2 or 1 bytes (MDR1 bits 1:0 = 00, 01,
 * 10, 11). MDR0 bits 1:0 = quadrature mode (00 non-quadrature A = count, B = direction; 01 x1;
 * 10 x2; 11 x4), bits 3:2 = count mode (00 free-running, 01 single-cycle, 10 range-limit,
 * 11 modulo-n with DTR). MDR1 bit 2 = 1 disables counting. STR: CY BW CMP IDX CEN PLS U/D S
 * (bits 7..0). SS going high ends an instruction.
 * The encoder is given as its x4 quadrature count (every A/B edge), e.g. from the motor plant;
 * the chip turns that into its own count per the mode. The index input is not connected.
 */
#ifndef LS7366R_H
#define LS7366R_H

#include <stdint.h>

typedef struct {
    uint8_t mdr0, mdr1, str;
    uint32_t cntr, dtr, otr;
    int selected;
    int byte_index;     /* bytes seen since SS fell */
    uint8_t ir;         /* the instruction byte of the current transaction */
    uint8_t out[4];     /* bytes to shift out on MISO */
    int out_len;
    int64_t quad_seen;  /* encoder x4 count already folded into CNTR */
    uint32_t unsupported; /* instructions or modes the emulation does not model (counted) */
} ls7366r_t;

void ls7366r_init(ls7366r_t *c, int64_t quad_now);
/* chip select: level 0 = selected (SS is active low) */
void ls7366r_select(ls7366r_t *c, int level, int64_t quad_now);
/* one SPI byte while selected: returns the byte the chip drives on MISO */
uint8_t ls7366r_transfer(ls7366r_t *c, uint8_t mosi, int64_t quad_now);
/* the counter as the chip holds it now (after folding in the encoder motion) */
uint32_t ls7366r_count(ls7366r_t *c, int64_t quad_now);
/* register width in bytes from MDR1 */
int ls7366r_width(const ls7366r_t *c);

#endif
