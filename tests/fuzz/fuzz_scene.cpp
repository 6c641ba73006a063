// Scene files (resources/scenes/*.scene.json): the simulated world.
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "uav/world/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    uav::world::Scene::Parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.scene.json");
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
