// Stand-in for the U8g2 display library (not packaged by Debian): accepts the drawing calls
// asipLCD makes and draws nothing. It holds no protocol code.
#pragma once
#include <Arduino.h>

#define U8G2_R0 0
#define U8X8_PIN_NONE 255
static const uint8_t u8g2_font_crox1hb_tr[1] = {0};

class U8G2_SH1106_128X64_NONAME_F_SW_I2C : public Print {
public:
  U8G2_SH1106_128X64_NONAME_F_SW_I2C(int rotation, uint8_t clock, uint8_t data, uint8_t reset) {
    (void)rotation; (void)clock; (void)data; (void)reset;
  }
  bool begin() { return true; }
  void setFont(const uint8_t *font) { (void)font; }
  void setCursor(int x, int y) { (void)x; (void)y; }
  void sendBuffer() {}
  void clearBuffer() {}
  int getDisplayWidth() { return 128; }
  void setDrawColor(uint8_t colour) { (void)colour; }
  void drawBox(int x, int y, int w, int h) { (void)x; (void)y; (void)w; (void)h; }
  void drawStr(int x, int y, const char *text) { (void)x; (void)y; (void)text; }
  size_t write(uint8_t c) override { (void)c; return 1; }
};
