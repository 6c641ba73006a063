#include "demo_script.hpp"

namespace uav::gcs {

// The main job (issue 7 item 9): the full survey mission, every step checked from what the GCS
// receives. Run by uav-demo in the window (the operator watches it) or headless.
const char* const kDemoScript = R"(# uav-gcs built-in demo: plan, upload and fly a survey; watch the map grow; download it.
echo waiting for a vehicle on the bus
wait_until vehicles >= 1 and link == up timeout 30
wait_until video.frames > 3 timeout 30
tick alt
echo planning a 40 x 60 m survey of the village at 25 m on the map
click map:edit
map_click 5 -30
map_click 5 30
map_click 45 30
map_click 45 -30
set survey:altitude 25
assert survey.vertices == 4 and survey.ok == 1 and survey.altitude ~ 25 0.001
click survey:upload
wait_until upload == accepted timeout 20
echo mission uploaded: take-off, zig-zag with the camera, return home, land
type arm
wait_until ack == completed timeout 10
type mission
wait_until ack == in_progress timeout 20
wait_until STATE.capturing == 1 timeout 90
assert alt ~ 25 1.0 and task == mission
echo surveying: the live map grows as tiles arrive
wait_until livemap.tiles >= 6 timeout 120
wait_until ack == completed timeout 400
wait_until armed == 0 timeout 20
assert alt ~ 0 0.2 and landed == 1 and x ~ 0 0.5 and y ~ 0 0.5
echo landed at home; the vehicle stitched the map on board
wait_until log contains map ready timeout 60
# The map's five files, the mission the vehicle holds and its flight log up to the landing.
wait_until download.offered >= 7 and download.saved >= 7 timeout 120
assert log contains SHA-256 verified and gave_up == 0
echo map downloaded and verified
)";

}  // namespace uav::gcs
