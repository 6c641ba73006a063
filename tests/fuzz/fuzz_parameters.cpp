// Vehicle parameter files (resources/vehicles/*.params) and camera files (resources/cameras/
// *.camera, the same format): parsed, then read as a vehicle and as a camera calibration.
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/parameters.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const uav::ParameterSet p = uav::ParameterSet::Parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.params");
    try {
      uav::IntrinsicsFromParameters(p);
    } catch (const std::invalid_argument&) {
    } catch (const std::out_of_range&) {
    }
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
