// PLEN2's firmware answers on the ATmega32u4's USB serial (`Serial`, USB CDC), which the
// emulator does not have. Forced ahead of System.cpp only: its `Serial` (what
// `PLEN2_SYSTEM_USBSERIAL` names) becomes the UART `Serial1` the board's Bluetooth module is
// on, so requests and replies both travel on UART1. Arduino.h comes first so the core's own
// declarations keep their names.
#pragma once
#include <Arduino.h>
#define Serial Serial1
