#include "Adafruit_NeoPixel.h"
uint16_t Adafruit_NeoPixel::count_ = 0;
uint8_t Adafruit_NeoPixel::brightness_ = 255;
uint32_t Adafruit_NeoPixel::colours_[Adafruit_NeoPixel::kMaxPixels];
