/* wrong_mcu.c - an ELF for the ATmega328P (avr5): motionemu must refuse to run it on the 2560. */
int main(void)
{
    for (;;)
        ;
}
