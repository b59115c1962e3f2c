#include "Encoder.h"
#include <avr/interrupt.h>

static Encoder *encoders[2];
static uint8_t encoderCount;

Encoder::Encoder(uint8_t pinA, uint8_t pinB)
    : inA_(0), inB_(0), maskA_(0), maskB_(0), state_(0), pinA_(pinA), pinB_(pinB),
      position_(0), started_(false) {
  if (encoderCount < 2) encoders[encoderCount++] = this;
}

// Pins are configured on first use: constructors of static objects run before the core's
// init(), which would undo port settings made there.
static void start(Encoder *e, uint8_t pinA, uint8_t pinB) {
  (void)e;
  pinMode(pinA, INPUT_PULLUP);
  pinMode(pinB, INPUT_PULLUP);
  *digitalPinToPCMSK(pinA) |= _BV(digitalPinToPCMSKbit(pinA));
  *digitalPinToPCMSK(pinB) |= _BV(digitalPinToPCMSKbit(pinB));
  *digitalPinToPCICR(pinA) |= _BV(digitalPinToPCICRbit(pinA));
  *digitalPinToPCICR(pinB) |= _BV(digitalPinToPCICRbit(pinB));
}

void Encoder::update() {
  if (!started_) return;
  uint8_t s = state_ & 3;
  if (*inA_ & maskA_) s |= 4;
  if (*inB_ & maskB_) s |= 8;
  // new AB in bits 2-3, old AB in bits 0-1: a Gray-code step forward or back
  switch (s) {
    case 1: case 7: case 8: case 14: position_++; break;
    case 2: case 4: case 11: case 13: position_--; break;
    case 3: case 12: position_ += 2; break;
    case 6: case 9: position_ -= 2; break;
    default: break;
  }
  state_ = s >> 2;
}

int32_t Encoder::read() {
  if (!started_) {
    inA_ = portInputRegister(digitalPinToPort(pinA_));
    inB_ = portInputRegister(digitalPinToPort(pinB_));
    maskA_ = digitalPinToBitMask(pinA_);
    maskB_ = digitalPinToBitMask(pinB_);
    start(this, pinA_, pinB_);
    state_ = ((*inA_ & maskA_) ? 1 : 0) | ((*inB_ & maskB_) ? 2 : 0);
    started_ = true;
  }
  uint8_t sreg = SREG;
  cli();
  int32_t p = position_;
  SREG = sreg;
  return p;
}

void Encoder::write(int32_t position) {
  uint8_t sreg = SREG;
  cli();
  position_ = position;
  SREG = sreg;
}

static void updateAll() {
  for (uint8_t i = 0; i < encoderCount; i++) encoders[i]->update();
}

#ifdef PCINT0_vect
ISR(PCINT0_vect) { updateAll(); }
#endif
#ifdef PCINT1_vect
ISR(PCINT1_vect) { updateAll(); }
#endif
#ifdef PCINT2_vect
ISR(PCINT2_vect) { updateAll(); }
#endif
