// Stand-in for the Wire (I2C) library that carries the StackMod author's I2C writes over the
// board's UART instead, because the emulator has no I2C master to write to the module: the
// host sends each I2C write as one length byte then that many bytes, and the sketch's
// onReceive handler gets them exactly as the TWI interrupt would hand them over.
// It holds no protocol code: the packet parser is the author's library, unchanged.
#pragma once
#include <Arduino.h>

class BridgedWire : public Stream {
public:
  void begin(uint8_t address) { address_ = address; }
  void begin() {}
  void onReceive(void (*handler)(int)) { handler_ = handler; }
  void onRequest(void (*handler)(void)) { (void)handler; }
  int available() override { return length_ - index_; }
  int read() override { return index_ < length_ ? buffer_[index_++] : -1; }
  int peek() override { return index_ < length_ ? buffer_[index_] : -1; }
  size_t write(uint8_t c) override { (void)c; return 1; }
  void pump();  // called from serialEvent(): deliver one framed write if it has arrived
private:
  uint8_t address_ = 0;
  void (*handler_)(int) = 0;
  uint8_t buffer_[32];
  uint8_t length_ = 0, index_ = 0;
};

extern BridgedWire Wire;
