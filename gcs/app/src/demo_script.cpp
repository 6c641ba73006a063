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
map_zoom 0 0 -2
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

// U-Lion's survey (thesis 2.6): a 200 x 200 m block at 60 m, planned for its 12 m/s cruise and
// its 27 m turns (lines flown at least two turn radii apart), a capture every 12 m. The vehicle
// takes off vertically, transitions onto the wing for the first long leg, surveys on the wing,
// flies home, circles down to its approach height, transitions back and lands vertically.
const char* const kDemoScriptULion = R"(# uav-gcs built-in demo: U-Lion surveys the village on its wing; the map is downloaded.
echo waiting for U-Lion on the bus
wait_until vehicles >= 1 and link == up timeout 30
wait_until STATE.vehicle == 1 and param.ts_cruise_speed > 0 timeout 30
wait_until video.frames > 3 timeout 30
tick alt
echo planning a 200 x 200 m survey of the village at 60 m on the map, fitted to U-Lion
map_zoom 0 0 -12
click map:edit
map_click 60 -100
map_click 60 100
map_click 260 100
map_click 260 -100
set survey:altitude 60
click survey:fit
set survey:turnaround 20
set survey:trigger 12
assert survey.vertices == 4 and survey.ok == 1 and survey.speed ~ 12 0.01 and survey.turn_radius ~ 26.9 0.1
click survey:upload
wait_until upload == accepted timeout 20
echo mission uploaded: vertical take-off, transition, zig-zag on the wing with the camera, home, landing
type arm
wait_until ack == completed timeout 10
type mission
wait_until ack == in_progress timeout 20
wait_until STATE.vtol_mode == 2 timeout 90
echo on the wing
wait_until STATE.capturing == 1 timeout 90
assert alt ~ 60 2.0 and task == mission and STATE.airspeed ~ 12 2
echo surveying: the live map grows as tiles arrive
wait_until livemap.tiles >= 6 timeout 120
wait_until log contains circling down on the wing timeout 400
echo home: circling down to the approach height, then back to hover to land
wait_until STATE.vtol_mode == 0 timeout 120
wait_until ack == completed timeout 200
wait_until armed == 0 timeout 20
# The estimate's height after five minutes on the barometer and GPS alone (the sonar looks out of
# the belly, level in hover): within 3 m; on the ground is what the touchdown detection says.
assert alt ~ 0 3.0 and landed == 1 and x ~ 0 2 and y ~ 0 2
echo landed at home; the vehicle stitched the map on board
wait_until log contains map ready timeout 60
wait_until download.offered >= 7 and download.saved >= 7 timeout 120
assert log contains SHA-256 verified and gave_up == 0
echo map downloaded and verified
)";

}  // namespace uav::gcs
