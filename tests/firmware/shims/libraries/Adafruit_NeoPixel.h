// Stand-in for Adafruit's NeoPixel library (not packaged by Debian): keeps the colours a
// sketch sets in one static table and drives no pin. Its state is static so that a sketch
// which never calls begin() (a board with no pixel pin) reads the same answers as one that
// does, instead of reading through a null pointer. It holds no protocol code.
#pragma once
#include <Arduino.h>

#define NEO_GRB 0
#define NEO_KHZ800 0

class Adafruit_NeoPixel {
public:
  Adafruit_NeoPixel(uint16_t count, uint8_t pin, uint8_t type = NEO_GRB + NEO_KHZ800) {
    (void)pin; (void)type;
    count_ = count > kMaxPixels ? kMaxPixels : count;
  }
  void begin() {}
  void show() {}
  void clear() { for (uint16_t i = 0; i < kMaxPixels; i++) colours_[i] = 0; }
  void setBrightness(uint8_t level) { brightness_ = level; }
  void setPixelColor(uint16_t n, uint32_t colour) { if (n < count_) colours_[n] = colour; }
  void setPixelColor(uint16_t n, uint8_t r, uint8_t g, uint8_t b) { setPixelColor(n, Color(r, g, b)); }
  uint16_t numPixels() const { return count_; }
  static uint32_t Color(uint8_t r, uint8_t g, uint8_t b) {
    return ((uint32_t)r << 16) | ((uint32_t)g << 8) | b;
  }
private:
  static const uint16_t kMaxPixels = 16;
  static uint16_t count_;
  static uint8_t brightness_;
  static uint32_t colours_[kMaxPixels];
};
