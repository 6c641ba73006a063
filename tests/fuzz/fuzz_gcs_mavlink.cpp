// MAVLink bytes as the GCS's MAVLink link receives them from a vehicle (gcs/link/mavlink_link):
// parsed, recognised, decoded into the model; between the two halves of the input the operator
// selects the vehicle, sends commands, sets a parameter, and uploads and downloads a mission, so
// that what the vehicle "answers" in the second half meets each service's state.
#include "fuzz_input.hpp"
#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/mavlink_link.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace uav::gcs;
  if (size == 0) return 0;
  const std::size_t piece = 1 + data[0] % 64;  // datagram size: the parser keeps state across pushes
  GcsModel model("gcs-fuzz", 1);
  MavlinkLinkParams params;
  params.endpoint = "";
  params.video_port = 0;
  MavlinkLink link(params, model);
  double now = 0.0;
  auto feed = [&](std::size_t from, std::size_t to) {
    for (std::size_t at = from; at < to; at += piece) {
      link.ReceiveBytes(data + at, std::min(piece, to - at), now += 0.05);
      model.Tick(now);
      GcsOutgoing out = model.TakeOutgoing();
      link.Send(out, now);
    }
  };
  const std::size_t half = 1 + (size - 1) / 2;
  feed(1, half);
  if (!model.vehicles().empty()) {
    model.SelectVehicle(model.vehicles().begin()->first);
    for (const char* c : {"arm", "takeoff 10", "goto 5 5 10", "mission", "hover", "param P1 2"}) model.SubmitCommand(c, now);
    model.UploadMission(now);
    model.DownloadMission(now);
    GcsOutgoing out = model.TakeOutgoing();
    link.Send(out, now);
  }
  feed(half, size);
  now += 30.0;  // every service's timeouts
  link.Receive(now);
  return 0;
}
