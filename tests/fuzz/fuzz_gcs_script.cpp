// GCS scripts (uav-gcs --script): the operator-step language.
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "uav/gcs/script.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    uav::gcs::Script::Parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.gcs");
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
