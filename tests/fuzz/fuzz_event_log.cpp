// Onboard event logs (events_<utime>.lcmlog) read by the GCS's replay: indexed, then played to
// the end and sought back, every event through the GCS's decoders.
#include <memory>
#include <stdexcept>

#include "fuzz_input.hpp"
#include "uav/gcs/gcs_link.hpp"
#include "uav/gcs/log_replay.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::unique_ptr<uav::gcs::GcsModel> model;
  std::unique_ptr<uav::gcs::GcsLink> link;
  auto reset = [&]() -> uav::gcs::GcsLink& {
    link.reset();
    model = std::make_unique<uav::gcs::GcsModel>("fuzz", 1);
    model->SetReplay(true);
    link = std::make_unique<uav::gcs::GcsLink>(nullptr, *model, std::nullopt);
    return *link;
  };
  try {
    uav::gcs::LogReplay replay(uav::fuzz::ScratchFile(data, size, "events.lcmlog"), reset);
    replay.SetSpeed(uav::gcs::LogReplay::kMaxSpeed);
    for (int i = 0; i < 100 && !replay.finished(); ++i) replay.Advance(1e3);
    replay.Seek(0.0);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
