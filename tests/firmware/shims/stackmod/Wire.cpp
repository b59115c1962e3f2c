#include "Wire.h"

BridgedWire Wire;

void BridgedWire::pump() {
  while (Serial.available() > 0) {
    int expected = Serial.read();
    if (expected <= 0 || expected > (int)sizeof buffer_) continue;
    uint8_t got = (uint8_t)Serial.readBytes((char *)buffer_, expected);
    length_ = got;
    index_ = 0;
    if (handler_) handler_(got);
    length_ = index_ = 0;
  }
}

// The core calls serialEvent() between loop() runs whenever the UART has bytes.
void serialEvent() { Wire.pump(); }
