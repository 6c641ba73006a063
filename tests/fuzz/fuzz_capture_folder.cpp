// A capture folder's session.json and captures.csv (shared/capture_folder), as uav-stitch reads
// them from disk: JSON (starting with '{') as the session, anything else as the rows.
#include <stdexcept>

#include "fuzz_input.hpp"
#include "uav/shared/capture_folder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    if (size > 0 && data[0] == '{') uav::ReadCaptureSession(uav::fuzz::ScratchFile(data, size, "session.json"));
    else uav::ReadCaptureRows(uav::fuzz::ScratchFile(data, size, "captures.csv"));
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
