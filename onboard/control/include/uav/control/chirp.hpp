#pragma once
// The linear chirp of thesis Eq. 2.14, u(t) = A sin(2 pi (f0 + k/2 t) t) with k = (f1 - f0) / T,
// injected on one servo channel while hovering for system identification (thesis 2.4.5).
#include <cmath>

namespace uav::control {

// Servo channels, numbered as the chirp command and the flight log's chirp column (Table 2.3).
enum class ServoChannel { kNone = 0, kAileron = 1, kElevator = 2, kThrottle = 3, kRudder = 4 };

struct Chirp {
  ServoChannel channel = ServoChannel::kNone;
  double amplitude = 0.0;  // A [normalised servo units]
  double f0_hz = 0.0, f1_hz = 0.0;
  double duration_s = 0.0;  // T

  // Eq. 2.14 at t seconds after the start; zero outside [0, T].
  double Value(double t) const {
    if (t < 0.0 || t > duration_s) return 0.0;
    const double k = (f1_hz - f0_hz) / duration_s;
    return amplitude * std::sin(2.0 * M_PI * (f0_hz + 0.5 * k * t) * t);
  }
};

}  // namespace uav::control
