// Board facts the Teensy 3.1 sketch mirtle2017.ino expects from its board package, given for
// an ATmega328P (a MIRTO 328 V2 board) so the sketch compiles unchanged:
//  - there is one UART: `Serial3` is the same port as `Serial`, and the USB-host test
//    (`USB0_OTGSTAT` bit 5) reads 0, so the sketch takes its `Serial` branch;
//  - the pins of that port are 0 and 1 (the sketch reserves "the Pi's serial pins");
//  - the 328 branch of robot_pins.h defines no NeoPixel or tone pin: `neoPixelPin` is then
//    only the strip object's constructor argument, and `#ifdef neoPixelPin`/`#ifdef tonePin`
//    in the sketch stay false, as they would on that board.
#pragma once
#include <Arduino.h>
#define Serial3 Serial
#define USB0_OTGSTAT 0
#define SERIAL3_RX_PIN SERIAL_RX_PIN
#define SERIAL3_TX_PIN SERIAL_TX_PIN
static const uint8_t neoPixelPin = 0;
