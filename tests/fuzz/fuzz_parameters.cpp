// Vehicle parameter files (resources/vehicles/*.params) and camera files (resources/cameras/
// *.camera, the same format): parsed against each declaration, a camera's read as a calibration.
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/parameters.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    uav::ParameterSet::Parse(text, "fuzz.params", uav::VehicleParameterSchema()).WithAssignment("mass=2");
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  try {
    uav::IntrinsicsFromParameters(uav::ParameterSet::Parse(text, "fuzz.camera", uav::CameraParameterSchema()));
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
