// Stand-in for PJRC's Encoder library (not packaged by Debian): counts quadrature edges on
// two pins with the pin-change interrupt, as the real library does on pins without their own
// interrupt. Up to two encoders. It holds no protocol code.
#pragma once
#include <Arduino.h>

class Encoder {
public:
  Encoder(uint8_t pinA, uint8_t pinB);
  int32_t read();
  void write(int32_t position);
  void update();  // called from the pin-change interrupt
private:
  volatile uint8_t *inA_, *inB_;
  uint8_t maskA_, maskB_;
  uint8_t state_;
  uint8_t pinA_, pinB_;
  volatile int32_t position_;
  bool started_;
};
