#include "demo_script.hpp"

namespace uav::gcs {

const char* const kDemoScript = R"(# uav-gcs built-in demo: one short flight, every target checked from telemetry.
echo waiting for a vehicle on the bus
wait_until vehicles >= 1 and link == up timeout 30
tick alt
tick x
tick y
type arm
wait_until ack == completed timeout 10
type takeoff 10
wait_until ack == completed timeout 60
assert alt ~ 10 0.5 and x ~ 0 0.5 and y ~ 0 0.5
type hover
wait_until ack == completed timeout 10
wait 3
assert alt ~ 10 0.5
type goto 20 10 15
wait_until ack == completed timeout 90
assert x ~ 20 0.5 and y ~ 10 0.5 and alt ~ 15 0.5
type land
wait_until ack == completed timeout 90
wait_until armed == 0 timeout 10
assert alt ~ 0 0.2 and landed == 1 and x ~ 20 0.5 and y ~ 10 0.5
echo demo flight complete
)";

}  // namespace uav::gcs
