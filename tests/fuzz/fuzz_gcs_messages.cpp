// Every LCM message the GCS decodes (vehicle -> GCS), through the GCS's own entry point
// (GcsLink::Dispatch: decode once, check, feed the model), then a model tick. The first byte
// chooses the channel's topic (GcsLink::Topics(): every topic it decodes).
#include "fuzz_input.hpp"
#include "uav/gcs/gcs_link.hpp"
#include "uav/shared/channels.hpp"
#include "uavmsg/heartbeat_t.hpp"

#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using uav::Topic;
  static const std::vector<Topic> kTopics = uav::gcs::GcsLink::Topics();
  const size_t kCount = kTopics.size();
  if (size < 1) return 0;
  uav::gcs::GcsModel model("fuzz", 1);
  uav::gcs::GcsLink link(nullptr, model, std::nullopt);
  // A vehicle the model already knows, so that messages reach its per-vehicle state.
  static const std::vector<uint8_t> heartbeat = [] {
    uavmsg::heartbeat_t hb{};
    hb.header.vehicle_id = "UAV1";
    hb.source_kind = uavmsg::heartbeat_t::SOURCE_VEHICLE;
    hb.source_name = "UAV1";
    std::vector<uint8_t> b(hb.getEncodedSize());
    hb.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
  }();
  link.Dispatch(uav::Channel("UAV1", Topic::kHeartbeat), heartbeat.data(), static_cast<int>(heartbeat.size()), 0.0);
  link.Dispatch(uav::Channel("UAV1", kTopics[data[0] % kCount]), data + 1, static_cast<int>(size - 1), 1.0);
  model.Tick(2.0);
  return 0;
}
