// After kill -9 of uav-onboard: are its logs readable, and how much did they lose? Compares the
// newest vehicle state in the vehicle's own event log and CSV flight log with the newest one an
// independent lcm-logger recorded from the bus (the truth of what the vehicle last published).
// Usage: check_logs EVENTS.lcmlog REFERENCE.lcmlog FLIGHT_<start>.csv MAX_LOSS_S
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "uav/wire/messages.hpp"
#include "uavmsg/vehicle_state_t.hpp"

namespace {

struct Scan {
  long events = 0;
  long states = 0;
  int64_t last_state_utime = -1;  // vehicle (simulated) clock
};

Scan Read(const std::string& path) {
  lcm::LogFile log(path, "r");
  Scan s;
  if (!log.good()) return s;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    ++s.events;
    if (e->channel != "UAV1/STATE") continue;
    uavmsg::vehicle_state_t m;
    if (m.decode(e->data, 0, e->datalen) < 0) continue;
    ++s.states;
    if (m.utime > s.last_state_utime) s.last_state_utime = m.utime;
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: check_logs EVENTS.lcmlog REFERENCE.lcmlog FLIGHT.csv MAX_LOSS_S\n");
    return 2;
  }
  const Scan ev = Read(argv[1]), ref = Read(argv[2]);
  const double max_loss = std::atof(argv[4]);
  // The CSV's name carries its start time; its rows carry t from there.
  const std::string csv = argv[3];
  const auto at = csv.rfind("flight_");
  const int64_t start = std::atoll(csv.c_str() + at + 7);
  std::ifstream in(csv);
  std::string line, last;
  long rows = -1;  // header
  while (std::getline(in, line))
    if (!line.empty()) last = line, ++rows;
  const double csv_last = start * 1e-6 + std::atof(last.c_str());
  int failures = 0;
  auto check = [&](bool ok, const char* what, double value) {
    std::printf("%s %s: %.3f\n", ok ? "ok  " : "FAIL", what, value);
    failures += !ok;
  };
  check(ref.states > 100, "reference log has vehicle states", static_cast<double>(ref.states));
  check(ev.states > 100, "event log is readable and has vehicle states", static_cast<double>(ev.states));
  check(rows > 100, "CSV flight log is readable (rows)", static_cast<double>(rows));
  const double truth = ref.last_state_utime * 1e-6;
  check(truth - ev.last_state_utime * 1e-6 <= max_loss, "event log lost [s of vehicle time]", truth - ev.last_state_utime * 1e-6);
  check(truth - csv_last <= max_loss, "CSV flight log lost [s of vehicle time]", truth - csv_last);
  return failures ? 1 : 0;
}
