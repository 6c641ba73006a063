#include "uav/shared/visual_odometry.hpp"

namespace uav {

const char* Name(PositionSource s) {
  switch (s) {
    case PositionSource::kGps: return "gps";
    case PositionSource::kVision: return "vision";
    case PositionSource::kInertial: return "inertial";
  }
  return "?";
}

}  // namespace uav
