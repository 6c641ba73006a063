#pragma once
// The vehicle's cameras and which vision worker each one feeds: what the sensing assembly
// (sensing.hpp) is built from. The cameras are hal interfaces, so the same workers run on the
// simulator's rendered cameras (simflight/sim_rig.hpp), on recorded sequences and on live
// devices (rig_file.hpp); whoever makes the rig owns the cameras and outlives the sensing.
#include <string>
#include <vector>

namespace uav::hal {
class Camera;
class GimbalCamera;
class StereoCamera;
}  // namespace uav::hal

namespace uav::runtime {

struct SensorRig {
  hal::Camera* survey = nullptr;        // downward: survey captures (CAM) and the map (STITCH)
  hal::GimbalCamera* tracking = nullptr;  // gimballed: target tracking (TRK)
  // Stereo pairs by what runs on them; one pair may feed several (its exposures are shared
  // out in turn). Wires on the obstacle pair are found by the obstacle worker itself.
  hal::StereoCamera* active_stereo = nullptr;  // ASTEREO: height from the projector's dots (4.2)
  hal::StereoCamera* odometry = nullptr;       // VO (ch. 5)
  hal::StereoCamera* obstacles = nullptr;      // STEREO: obstacles (3.5), and wires when `wires` is the same pair
  hal::StereoCamera* wires = nullptr;          // WIRES: power lines (3.6)
  // MDEPTH: depth from motion on the survey or the tracking camera's frames.
  enum class DepthCamera { kNone, kSurvey, kTracking };
  DepthCamera depth = DepthCamera::kNone;
  // Every stereo pair, in the order the rig declares them (for the health report and faults).
  std::vector<hal::StereoCamera*> stereo_pairs;

  bool empty() const {
    return !survey && !tracking && !active_stereo && !odometry && !obstacles && !wires;
  }
};

}  // namespace uav::runtime
