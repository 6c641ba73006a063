// Mission files: QGroundControl .plan (JSON) and WPL (QGC WPL 110 text), told apart as
// ReadMissionFile does by the content.
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "uav/waypoints/mission_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    if (text.rfind("QGC WPL", 0) == 0) uav::waypoints::ParseWpl(text, "fuzz.waypoints");
    else uav::waypoints::ParsePlan(text, "fuzz.plan");
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
