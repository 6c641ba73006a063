// Stereo calibration files (uav-stereo-calibrate writes them; OpenCV FileStorage YAML).
#include <stdexcept>

#include <opencv2/core.hpp>

#include "fuzz_input.hpp"
#include "uav/vision/stereo_calibration.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    uav::vision::ReadStereoCalibration(uav::fuzz::ScratchFile(data, size, "stereo.yml"));
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  } catch (const cv::Exception&) {
  }
  return 0;
}
