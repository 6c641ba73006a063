#include <stb_image.h>
#include "uav/gcs/gcs_model.hpp"

#include <cmath>
#include <filesystem>
#include <utility>
#include <limits>

#include "uav/shared/text_file.hpp"

#include "uav/shared/command_grammar.hpp"

namespace uav::gcs {
namespace {
constexpr std::size_t kMaxLogLines = 500;
constexpr std::size_t kMaxSentKept = 100;
// Index: vehicle_state_t.TASK_*.
const char* kTaskNames[] = {"idle", "takeoff", "hover", "goto", "land", "track", "mission", "return"};
constexpr int kTaskCount = 8;
}  // namespace

double SignalGroup::Rate(double now) const {
  int n = 0;
  for (double t : recent) n += now - t <= 1.0;
  return n;
}

double VehicleModel::MessageRate(double now) const {
  int n = 0;
  for (double t : recent_receipts)
    if (now - t <= 1.0) ++n;
  return n;
}

VehicleModel& GcsModel::Vehicle(const std::string& id) {
  auto [it, inserted] = vehicles_.try_emplace(id);
  if (inserted) {
    it->second.id = id;
    if (selected_.empty()) selected_ = id;  // the first vehicle heard is shown
  }
  return it->second;
}

void GcsModel::Log(double now, const std::string& vehicle, const std::string& text, int severity) {
  log_.push_back({now, vehicle, text, severity});
  while (log_.size() > kMaxLogLines) log_.pop_front();
}

void GcsModel::OnHeartbeat(const std::string& vehicle_id, int64_t seq, int task, bool armed,
                           double now) {
  const bool fresh = !vehicles_.count(vehicle_id);
  VehicleModel& v = Vehicle(vehicle_id);
  if (fresh) Log(now, vehicle_id, "vehicle discovered", 6);
  v.last_heartbeat = now;
  v.armed = armed;
  v.task = task >= 0 && task < kTaskCount ? kTaskNames[task] : "unknown";
  TelemetrySample s{vehicle_id, "HEARTBEAT", seq, -1.0, {{"task", task}, {"armed", armed ? 1.0 : 0.0}}};
  OnTelemetry(s, now);
}

void GcsModel::OnTelemetry(const TelemetrySample& s, double now) {
  VehicleModel& v = Vehicle(s.vehicle_id);
  ++v.messages_total;
  v.last_message = now;
  v.recent_receipts.push_back(now);
  while (!v.recent_receipts.empty() && now - v.recent_receipts.front() > 1.0) v.recent_receipts.pop_front();
  auto [it, first] = v.last_seq.try_emplace(s.group, s.seq);
  if (!first) {
    if (s.seq > it->second + 1) v.sequence_gaps += s.seq - it->second - 1;
    if (s.seq > it->second) it->second = s.seq;
  }
  SignalGroup& g = v.groups[s.group];
  g.last_receipt = now;
  ++g.received;
  g.recent.push_back(now);
  while (!g.recent.empty() && now - g.recent.front() > 1.0) g.recent.pop_front();
  if (s.t < 0.0) {  // no time base: latest values only, no history
    for (const auto& [name, value] : s.values) {
      const std::string key = s.group + "." + name;
      if (v.latest.emplace(key, value).second) v.signal_order.push_back(key);
      v.latest[key] = value;
    }
    return;
  }
  for (const auto& [name, value] : s.values) {  // the 50 Hz state is fresher than the heartbeat
    if (s.group != "STATE") break;
    if (name == "armed") v.armed = value > 0.5;
    if (name == "task") v.task = value >= 0 && value < kTaskCount ? kTaskNames[static_cast<int>(value)] : "unknown";
  }
  if (s.group == "STATE") {
    GeodeticPoint home{NAN, NAN, NAN};
    for (const auto& [name, value] : s.values) {
      if (name == "home_lat") home.latitude_deg = value;
      if (name == "home_lon") home.longitude_deg = value;
      if (name == "home_alt") home.altitude_m = value;
    }
    try {
      ValidateGeodetic(home);
      v.home = home;
      if (s.vehicle_id == selected_) planner_.SetOrigin(home);
    } catch (const std::invalid_argument&) {
      // no or bad home in this sample: keep the last good one
    }
  }
  if (v.first_t < 0.0) v.first_t = s.t;
  const double t = s.t - v.first_t;
  for (const auto& [name, value] : s.values) {
    const std::string key = s.group + "." + name;
    if (v.latest.emplace(key, value).second) v.signal_order.push_back(key);
    v.latest[key] = value;
    v.history[key].Push(t, value);
  }
}

void GcsModel::OnAck(const std::string& vehicle_id, const std::string& source, const AckInfo& ack,
                     double now) {
  if (source != gcs_name_) return;  // another GCS's conversation
  for (auto& c : sent_) {
    if (c.command_seq != ack.command_seq || c.vehicle_id != vehicle_id) continue;
    c.acknowledged = true;
    const bool changed = !c.last_ack || c.last_ack->result != ack.result;
    c.last_ack = ack;
    if (changed && ack.result != "in_progress")
      Log(now, vehicle_id, c.text + ": " + ack.result + (ack.reason.empty() ? "" : " (" + ack.reason + ")"),
          ack.result == "rejected" || ack.result == "failed" ? 4 : 6);
  }
}

double VideoFeed::Rate(double now) const {
  int n = 0;
  for (double t : recent) n += now - t <= 1.0;
  return n;
}

void GcsModel::OnVideoFrame(const std::string& vehicle_id, const VideoFrameIn& f, double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  std::string problem;
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = nullptr;
  if (f.jpeg.empty() || f.jpeg.size() > 60000) {
    problem = "JPEG of " + std::to_string(f.jpeg.size()) + " bytes (1..60000 allowed)";
  } else {
    pixels = stbi_load_from_memory(f.jpeg.data(), static_cast<int>(f.jpeg.size()), &w, &h, &channels, 4);
    if (!pixels)
      problem = std::string("undecodable JPEG: ") + stbi_failure_reason();
    else if (w != f.width || h != f.height)
      problem = "JPEG is " + std::to_string(w) + "x" + std::to_string(h) + ", message says " +
                std::to_string(f.width) + "x" + std::to_string(f.height);
  }
  if (!problem.empty()) {
    if (pixels) stbi_image_free(pixels);
    if (v.video.rejected++ == 0) Log(now, vehicle_id, "video frame rejected: " + problem, 4);
    return;
  }
  VideoFeed& feed = v.video;
  feed.rgba.assign(pixels, pixels + static_cast<size_t>(w) * h * 4);
  stbi_image_free(pixels);
  feed.width = w;
  feed.height = h;
  feed.source_width = f.source_width;
  feed.source_height = f.source_height;
  feed.camera = f.camera;
  feed.utime = f.utime;
  ++feed.frames;
  feed.recent.push_back(now);
  while (!feed.recent.empty() && now - feed.recent.front() > 1.0) feed.recent.pop_front();
}

void GcsModel::OnMapTile(const std::string& vehicle_id, const MapTileIn& t, double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  LiveMap& map = v.live_map;
  std::string problem;
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = nullptr;
  if (t.tile_px < 16 || t.tile_px > 1024 || !(t.gsd_m > 0) || !std::isfinite(t.origin_north_m) ||
      !std::isfinite(t.origin_east_m) || t.map_id < map.map_id) {
    problem = "bad tile header (tile_px, gsd, origin or an older map)";
  } else if (t.jpeg.empty() || t.jpeg.size() > 60000) {
    problem = "JPEG of " + std::to_string(t.jpeg.size()) + " bytes (1..60000 allowed)";
  } else {
    pixels = stbi_load_from_memory(t.jpeg.data(), static_cast<int>(t.jpeg.size()), &w, &h, &channels, 4);
    if (!pixels) problem = std::string("undecodable JPEG: ") + stbi_failure_reason();
    else if (w != t.tile_px || h != t.tile_px) problem = "tile JPEG is " + std::to_string(w) + "x" + std::to_string(h);
  }
  if (!problem.empty()) {
    if (pixels) stbi_image_free(pixels);
    if (map.rejected++ == 0) Log(now, vehicle_id, "map tile rejected: " + problem, 4);
    return;
  }
  if (t.map_id > map.map_id) {  // a new survey: a new map
    map = LiveMap();
    map.map_id = t.map_id;
  }
  map.tile_px = t.tile_px;
  map.gsd_m = t.gsd_m;
  map.origin_north_m = t.origin_north_m;
  map.origin_east_m = t.origin_east_m;
  map.georeferenced = t.georeferenced;
  LiveMap::Tile& tile = map.tiles[{t.tile_x, t.tile_y}];
  tile.rgba.assign(pixels, pixels + static_cast<size_t>(w) * h * 4);
  stbi_image_free(pixels);
  // Unmapped pixels travel as black; JPEG leaves them near black.
  for (size_t i = 0; i < tile.rgba.size(); i += 4)
    if (tile.rgba[i] < 8 && tile.rgba[i + 1] < 8 && tile.rgba[i + 2] < 8) tile.rgba[i + 3] = 0;
  ++tile.version;
  ++map.received;
}

void GcsModel::OnStatusText(const std::string& vehicle_id, int severity, const std::string& text,
                            double now) {
  Vehicle(vehicle_id);
  Log(now, vehicle_id, text, severity);
}

bool GcsModel::SubmitCommand(const std::string& text, double now) {
  const ParseResult parsed = ParseCommand(text);
  if (!parsed.ok()) {
    command_error_ = parsed.error;
    return false;
  }
  if (selected_.empty()) {
    command_error_ = "no vehicle selected";
    return false;
  }
  command_error_.clear();
  const std::string canonical = parsed.command->Text();
  if (history_.empty() || history_.back() != text) history_.push_back(text);
  SentCommand c;
  c.command_seq = next_seq_++;
  c.vehicle_id = selected_;
  c.text = canonical;
  c.first_sent = c.last_sent = now;
  c.tries = 1;
  sent_.push_back(c);
  while (sent_.size() > kMaxSentKept) sent_.pop_front();
  outgoing_.push_back({c.vehicle_id, c.command_seq, c.text});
  Log(now, selected_, "sent: " + canonical, 6);
  return true;
}

void GcsModel::SelectVehicle(const std::string& id) {
  if (!vehicles_.count(id) || id == selected_) return;
  selected_ = id;
  // Nothing of one vehicle stays on another's panels.
  frozen_video_.reset();
  frozen_vehicle_.clear();
  plot_hold_.reset();
}

bool GcsModel::FreezeVideo(bool freeze) {
  if (!freeze) {
    frozen_video_.reset();
    frozen_vehicle_.clear();
    return true;
  }
  const VehicleModel* v = selected();
  if (!v || v->video.frames == 0) return false;
  frozen_video_ = v->video;
  frozen_vehicle_ = v->id;
  return true;
}

std::set<std::string> GcsModel::plot_signals() const {
  std::set<std::string> all;
  for (const auto& p : plots_)
    for (const auto& [key, axis] : p.signals) all.insert(key);
  return all;
}

int GcsModel::AddPlot() {
  plots_.emplace_back();
  active_plot_ = static_cast<int>(plots_.size()) - 1;
  return active_plot_;
}

void GcsModel::RemovePlot(int index) {
  if (plots_.size() <= 1 || index < 0 || index >= static_cast<int>(plots_.size())) return;
  plots_.erase(plots_.begin() + index);
  active_plot_ = std::min(active_plot_, static_cast<int>(plots_.size()) - 1);
}

void GcsModel::SetActivePlot(int index) {
  if (index >= 0 && index < static_cast<int>(plots_.size())) active_plot_ = index;
}

void GcsModel::TogglePlotSignal(const std::string& key) { TogglePlotSignal(active_plot_, key, PlotAxis::kLeft); }

void GcsModel::TogglePlotSignal(int plot, const std::string& key, PlotAxis axis) {
  if (plot < 0 || plot >= static_cast<int>(plots_.size())) return;
  auto& signals = plots_[plot].signals;
  if (!signals.erase(key)) signals[key] = axis;
}

void GcsModel::SetSignalAxis(int plot, const std::string& key, PlotAxis axis) {
  if (plot < 0 || plot >= static_cast<int>(plots_.size())) return;
  auto it = plots_[plot].signals.find(key);
  if (it != plots_[plot].signals.end()) it->second = axis;
}

bool GcsModel::SetPlotRange(int plot, PlotAxis axis, bool auto_y, double lo, double hi) {
  if (plot < 0 || plot >= static_cast<int>(plots_.size())) return false;
  PlotSpec& p = plots_[plot];
  const int a = static_cast<int>(axis);
  if (auto_y) {
    p.auto_y[a] = true;
    return true;
  }
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) return false;
  p.auto_y[a] = false;
  p.y_min[a] = lo;
  p.y_max[a] = hi;
  return true;
}

bool GcsModel::SelectTarget(const TrackTarget& target, double now) {
  track_error_.clear();
  auto it = vehicles_.find(selected_);
  if (it == vehicles_.end()) {
    track_error_ = "no vehicle selected";
    return false;
  }
  if (target.method != TrackTarget::kCancel) {
    auto inside = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
    bool ok = inside(target.x) && inside(target.y) && inside(target.x + target.width) &&
              inside(target.y + target.height);
    for (const auto& c : target.corners) ok = ok && inside(c[0]) && inside(c[1]);
    if (!ok) {
      track_error_ = "target outside the image (coordinates must be finite, within 0..1)";
      return false;
    }
    if (!(target.width >= 0.005 && target.height >= 0.005)) {
      track_error_ = "target too small: at least 0.5 % of the image on each side";
      return false;
    }
  }
  VehicleModel& v = it->second;
  const int64_t seq = next_target_seq_++;
  outgoing_track_.push_back({v.id, seq, target});
  v.track_target = target;
  ++v.track_targets_sent;
  char buf[160];
  if (target.method == TrackTarget::kCancel)
    std::snprintf(buf, sizeof buf, "tracking cancelled");
  else
    std::snprintf(buf, sizeof buf, "target %lld sent (%s): x %.3f y %.3f w %.3f h %.3f", static_cast<long long>(seq),
                  target.method == TrackTarget::kFourClicks ? "four corners" : "drag", target.x, target.y,
                  target.width, target.height);
  Log(now, v.id, buf, 6);
  return true;
}

std::vector<OutgoingTrackTarget> GcsModel::TakeOutgoingTrackTargets() { return std::exchange(outgoing_track_, {}); }

void GcsModel::OnTrackStatus(const std::string& vehicle_id, const TrackStatus& st, double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  const bool finite = std::isfinite(st.center_x) && std::isfinite(st.center_y) && std::isfinite(st.width) &&
                      std::isfinite(st.height) && std::isfinite(st.angle_rad);
  const bool known_state = st.state == TrackStatus::kIdle || st.state == TrackStatus::kTracking ||
                           st.state == TrackStatus::kLost;
  // A box may reach past the edge, but a centre far outside the image is a broken message.
  const bool plausible = finite && std::abs(st.center_x - 0.5) <= 1.0 && std::abs(st.center_y - 0.5) <= 1.0 &&
                         st.width >= 0 && st.height >= 0 && st.width <= 2 && st.height <= 2;
  if (!known_state || !plausible) {
    Log(now, vehicle_id, "track status refused: not finite, unknown state or outside the image", 4);
    return;
  }
  v.track = st;
  v.track->received = now;
  OnTelemetry({vehicle_id, "TRACK", st.seq, st.utime * 1e-6,
               {{"state", static_cast<double>(st.state)}, {"center_x", st.center_x}, {"center_y", st.center_y},
                {"width", st.width}, {"height", st.height}}},
              now);
}

void GcsModel::SetPlotWindow(double seconds) {
  if (seconds >= 1.0 && seconds <= 1800.0) plot_window_ = seconds;
}

void GcsModel::OnFileOffer(const std::string& vehicle_id, const FileOffer& offer, double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  const bool known = v.files.progress(offer.transfer_id).has_value();
  std::string error;
  if (!v.files.OnOffer(offer, &error)) {
    Log(now, vehicle_id, "file offer refused: " + error, 4);
    return;
  }
  if (known) return;
  Log(now, vehicle_id, "file offered: " + offer.name + " (" + std::to_string((offer.size + 1023) / 1024) + " kB)", 6);
  // Once there is a download directory, files offered later (the rest of a map's files, the
  // next map) follow into it.
  if (!download_dir_.empty()) StartDownloads(v, now);
}

void GcsModel::OnFileChunk(const std::string& vehicle_id, const FileChunk& chunk, double /*now*/) {
  auto it = vehicles_.find(vehicle_id);
  if (it != vehicles_.end()) it->second.files.OnChunk(chunk);
}

bool GcsModel::StartDownload(const std::string& dir, double now) {
  download_error_.clear();
  VehicleModel* v = selected_.empty() ? nullptr : &vehicles_.at(selected_);
  if (!v) {
    download_error_ = "no vehicle selected";
    return false;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    download_error_ = "cannot use '" + dir + "' as the download directory";
    Log(now, v->id, "download: " + download_error_, 3);
    return false;
  }
  download_dir_ = dir;
  StartDownloads(*v, now);
  Log(now, v->id, "download to " + dir + ": " + std::to_string(v->files.offers().size()) + " file(s) offered so far", 6);
  return true;
}

void GcsModel::StartDownloads(VehicleModel& v, double now) {
  for (const FileOffer& o : v.files.offers()) {
    const auto p = v.files.progress(o.transfer_id);
    if (p->started && !p->failed) continue;
    std::string error;
    if (!v.files.Start(o.transfer_id, &error)) Log(now, v.id, "download of " + o.name + ": " + error, 3);
  }
}

std::vector<OutgoingFileRequest> GcsModel::TakeOutgoingFileRequests() { return std::exchange(outgoing_file_requests_, {}); }

void GcsModel::Tick(double now) {
  for (auto& [id, v] : vehicles_) {
    for (FileRequest& r : v.files.Poll(now)) outgoing_file_requests_.push_back({id, std::move(r)});
    for (const FileOffer& o : v.files.offers()) {
      const auto p = v.files.progress(o.transfer_id);
      if (p->failed && !v.saved.count(o.transfer_id)) {
        v.saved[o.transfer_id] = "";
        Log(now, id, "download of " + o.name + " failed: " + p->error, 3);
      }
      if (!p->complete || v.saved.count(o.transfer_id)) continue;
      const std::string& dir = download_dir_;
      const std::string path = (std::filesystem::path(dir) / o.name).string();
      try {
        std::filesystem::create_directories(dir);
        WriteFileAtomically(path, *v.files.Contents(o.transfer_id));
        v.saved[o.transfer_id] = path;
        Log(now, id, "saved " + path + " (" + std::to_string((o.size + 1023) / 1024) + " kB, SHA-256 verified)", 6);
      } catch (const std::exception& e) {
        v.saved[o.transfer_id] = "";
        Log(now, id, "download of " + o.name + ": " + e.what(), 3);
      }
    }
  }
  for (auto& [id, v] : vehicles_) {
    if (!v.upload) continue;
    const auto before = v.upload->state();
    for (auto& c : v.upload->Tick(now)) outgoing_chunks_.push_back({id, std::move(c)});
    if (before != v.upload->state()) Log(now, id, "mission upload failed: " + v.upload->reason(), 3);
  }
  for (auto& c : sent_) {
    if (c.acknowledged || c.gave_up || now - c.last_sent < kResendTimeout) continue;
    if (c.tries >= kMaxTries) {
      c.gave_up = true;
      Log(now, c.vehicle_id,
          c.text + ": no acknowledgement after " + std::to_string(kMaxTries) + " tries", 3);
      continue;
    }
    ++c.tries;
    c.last_sent = now;
    outgoing_.push_back({c.vehicle_id, c.command_seq, c.text});  // same command_seq
  }
}

void GcsModel::OnMissionAck(const std::string& vehicle_id, const std::string& source,
                            const waypoints::MissionUploadAck& ack, double now) {
  if (source != gcs_name_) return;
  auto it = vehicles_.find(vehicle_id);
  if (it == vehicles_.end() || !it->second.upload) return;
  auto& up = *it->second.upload;
  const auto before = up.state();
  up.OnAck(ack, now);
  if (up.state() == before) return;
  using State = waypoints::MissionUploader::State;
  if (up.state() == State::kAccepted) {
    it->second.mission = up.mission();
    Log(now, vehicle_id, "mission of " + std::to_string(up.total_items()) + " items accepted", 6);
  } else {
    Log(now, vehicle_id, "mission upload " + std::string(up.state() == State::kRejected ? "rejected: " : "failed: ") + up.reason(), 4);
  }
}

bool GcsModel::UploadSurvey(double now) {
  upload_error_.clear();
  auto it = vehicles_.find(selected_);
  if (it == vehicles_.end()) {
    upload_error_ = "no vehicle selected";
    return false;
  }
  if (it->second.upload && it->second.upload->state() == waypoints::MissionUploader::State::kSending) {
    upload_error_ = "an upload to " + selected_ + " is in progress";
    return false;
  }
  if (it->second.home) planner_.SetOrigin(*it->second.home);  // the vehicle's home is the mission's
  std::string error;
  const auto mission = planner_.MakeMission(&error);
  if (!mission) {
    upload_error_ = error;
    return false;
  }
  it->second.upload.emplace(*mission, next_seq_++);
  Log(now, selected_, "uploading mission of " + std::to_string(mission->items.size()) + " items", 6);
  return true;
}

bool GcsModel::ExportPlotCsv(const std::string& path, double t0, double t1, double now) {
  const VehicleModel* v = selected();
  const std::set<std::string> ticked = plot_signals();
  if (!v || ticked.empty() || !std::isfinite(t0) || !std::isfinite(t1) || !(t0 <= t1)) {
    Log(now, "", "CSV export: nothing to export (no vehicle, no ticked signal or an empty range)", 4);
    return false;
  }
  std::vector<const SignalSeries*> series;
  std::vector<std::string> names;
  for (const auto& key : ticked) {
    auto it = v->history.find(key);
    if (it == v->history.end()) continue;
    series.push_back(&it->second);
    names.push_back(key);
  }
  // Merge the sample times of all series (signals of one message share them).
  std::vector<std::size_t> next(series.size());
  for (std::size_t k = 0; k < series.size(); ++k) next[k] = series[k]->LowerBound(t0);
  std::string out = "t";
  for (const auto& n : names) out += "," + n;
  out += "\n";
  char buf[64];
  std::size_t rows = 0;
  for (;;) {
    double t = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < series.size(); ++k)
      if (next[k] < series[k]->size()) t = std::min(t, series[k]->TimeAt(next[k]));
    if (!(t <= t1)) break;
    std::snprintf(buf, sizeof buf, "%.3f", t);
    out += buf;
    for (std::size_t k = 0; k < series.size(); ++k) {
      out += ',';
      if (next[k] < series[k]->size() && series[k]->TimeAt(next[k]) == t) {
        std::snprintf(buf, sizeof buf, "%.9g", series[k]->ValueAt(next[k]));
        out += buf;
        ++next[k];
      }
    }
    out += '\n';
    ++rows;
  }
  try {
    WriteFileAtomically(path, out);
  } catch (const std::exception& e) {
    Log(now, "", std::string("CSV export failed: ") + e.what(), 4);
    return false;
  }
  std::snprintf(buf, sizeof buf, "%.1f..%.1f s", t0, t1);
  Log(now, selected_, "exported " + std::to_string(rows) + " rows of " + std::to_string(names.size()) +
                          " signals (" + buf + ") to " + path, 6);
  return true;
}

bool GcsModel::ExportSurvey(const std::string& path, double now) {
  std::string message;
  const bool ok = planner_.Export(path, &message);
  Log(now, "", message, ok ? 6 : 4);
  return ok;
}

bool GcsModel::ImportSurvey(const std::string& path, double now) {
  std::string message;
  const bool ok = planner_.Import(path, &message);
  if (ok) {
    // Keep the map on the selected vehicle's home when there is one.
    if (const VehicleModel* v = selected(); v && v->home) planner_.SetOrigin(*v->home);
  }
  Log(now, "", message, ok ? 6 : 4);
  return ok;
}

std::vector<OutgoingMissionChunk> GcsModel::TakeOutgoingChunks() {
  std::vector<OutgoingMissionChunk> out;
  out.swap(outgoing_chunks_);
  return out;
}

std::vector<OutgoingCommand> GcsModel::TakeOutgoing() {
  std::vector<OutgoingCommand> out;
  out.swap(outgoing_);
  return out;
}

const VehicleModel* GcsModel::selected() const {
  auto it = vehicles_.find(selected_);
  return it == vehicles_.end() ? nullptr : &it->second;
}

}  // namespace uav::gcs
