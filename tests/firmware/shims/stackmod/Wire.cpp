#include "Wire.h"

BridgedWire Wire;

// One framed write: a length byte, then that many bytes. Like the TWI slave (twi.c), only the
// first 32 bytes of a longer write reach the handler (the rest are not acknowledged).
void BridgedWire::pump() {
  while (Serial.available() > 0) {
    int expected = Serial.read();
    if (expected <= 0) continue;
    uint8_t kept = 0;
    for (int i = 0; i < expected; i++) {
      char c;
      if (Serial.readBytes(&c, 1) != 1) break;
      if (kept < sizeof buffer_) buffer_[kept++] = (uint8_t)c;
    }
    length_ = kept;
    index_ = 0;
    if (handler_) handler_(kept);
    length_ = index_ = 0;
  }
}

// The TWI interrupt hands a write over the moment it ends, also while the sketch sits in
// delay(): delay() calls yield() as it waits, and the core calls serialEvent() between loop()s.
void yield() { Wire.pump(); }
void serialEvent() { Wire.pump(); }
