// Stand-in for the Arduino Servo library (not packaged by Debian): remembers the angle a
// sketch wrote and drives no pin. It holds no protocol code.
#pragma once
#include <Arduino.h>

class Servo {
public:
  uint8_t attach(int pin) { pin_ = pin; return 0; }
  void detach() { pin_ = -1; }
  void write(int angle) { angle_ = angle; }
  int read() { return angle_; }
  bool attached() { return pin_ >= 0; }
private:
  int pin_ = -1;
  int angle_ = 90;
};
