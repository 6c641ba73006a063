// uav-track VIDEO_OR_IMAGE_DIR --box X,Y,W,H [--tracker auto|camshift|dcf|kcf|csrt]
//           [--window adaptive|static] [--out boxes.csv] [--overlay DIR]
// Tracks the box (pixels in the first frame) through a video file or a folder of images (sorted
// by name) and writes one CSV row per frame: frame, x, y, w, h (the box's axis-aligned bounds),
// angle (degrees, clockwise from the image x axis), state, confidence. A progress bar goes to
// stderr and a JSON summary (frames, losses, ms per frame) to stdout. With --overlay every
// frame is also written with the box and search window drawn. Exit 0 on success, 1 when the
// input cannot be read or the box is refused (the reason on stderr), 2 on bad options.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/target_tracker.hpp"
#include "uav/vision/tracking_score.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

// Frames from a video file or a folder of images. A file that cannot be read whole is named and
// skipped (as a camera's dropped frame); a video that ends before the frames its container
// declares is reported as damaged.
class FrameSource {
 public:
  explicit FrameSource(const std::string& path) {
    if (std::filesystem::is_directory(path)) {
      files_ = uav::ImageFilesIn(path);
      if (files_.empty()) throw std::runtime_error(path + ": no images (png, jpg, bmp, tif) in the folder");
      count_ = static_cast<int>(files_.size());
    } else {
      if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": no such file or folder");
      video_.open(path);
      if (!video_.isOpened()) throw std::runtime_error(path + ": not a video OpenCV can read");
      count_ = static_cast<int>(video_.get(cv::CAP_PROP_FRAME_COUNT));
      const double fps = video_.get(cv::CAP_PROP_FPS);
      if (std::isfinite(fps) && fps > 0) rate_hz_ = fps;
    }
  }
  // Frames per second: the video's own, or nullopt (a folder of images, a video that does not say).
  std::optional<double> rate_hz() const { return rate_hz_; }
  int count() const { return count_; }  // 0 when the container does not say
  bool Next(cv::Mat* bgr) {
    while (!files_.empty() && next_ < files_.size()) {
      const std::string& f = files_[next_++];
      std::string problem = uav::ImageFileProblem(f);
      if (problem.empty() && (*bgr = cv::imread(f, cv::IMREAD_COLOR)).empty()) problem = "not an image OpenCV can read";
      if (problem.empty()) return true;
      skipped_.push_back(f + ": " + problem);
      std::fprintf(stderr, "\nuav-track: skipped %s: %s\n", f.c_str(), problem.c_str());
    }
    if (!files_.empty()) return false;
    if (video_.read(*bgr) && !bgr->empty()) return ++read_, true;
    // Containers' counts can be estimates (from duration and rate): a shortfall of more than two
    // frames is a truncated or damaged file.
    if (count_ > 0 && read_ + 2 < count_)
      damaged_ = "the video ends at frame " + std::to_string(read_) + " of the " + std::to_string(count_) +
                 " it declares (truncated or damaged)";
    return false;
  }
  // Position in the sequence of the frame Next() returned last (skipped files count).
  int index() const { return files_.empty() ? read_ - 1 : static_cast<int>(next_) - 1; }
  const std::vector<std::string>& skipped() const { return skipped_; }
  const std::string& damaged() const { return damaged_; }

 private:
  std::vector<std::string> skipped_;
  std::string damaged_;
  int read_ = 0;
  std::vector<std::string> files_;
  std::size_t next_ = 0;
  cv::VideoCapture video_;
  int count_ = 0;
  std::optional<double> rate_hz_;
};

const char* StateName(uav::vision::TrackState s) {
  switch (s) {
    case uav::vision::TrackState::kIdle: return "idle";
    case uav::vision::TrackState::kTracking: return "tracking";
    case uav::vision::TrackState::kLost: return "lost";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Track a target box through a video or an image folder (CamShift, thesis 3.7; KCF, CSRT)"};
  std::string input, box_text, tracker = "auto", window = "adaptive", out_path, overlay_dir;
  app.add_option("input", input, "video file or folder of images")->required();
  app.add_option("--box", box_text, "X,Y,W,H of the target in the first frame, pixels")->required();
  app.add_option("--tracker", tracker, "auto (CamShift where the target's colour stands out, else dcf), camshift, dcf (correlation filter on gradients), kcf or csrt")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "camshift", "dcf", "kcf", "csrt"}));
  app.add_option("--window", window, "CamShift search window: adaptive or static")->capture_default_str()->check(CLI::IsMember({"adaptive", "static"}));
  uav::OutputFile(app.add_option("--out", out_path, "CSV of boxes, one row per frame"));
  app.add_option("--overlay", overlay_dir, "folder for frames with the box drawn");
  std::string truth_path;
  double fps = 0.0;
  app.add_option("--fps", fps,
                 "frames per second of the input (default: the video's own; 30, OTB's rate, for a folder of images): "
                 "the tracker reports a target lost after 0.3 s of low confidence")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--truth", truth_path,
                 "ground-truth boxes, one x,y,w,h per frame (OTB's groundtruth_rect.txt): scores the run (success AUC, "
                 "precision at 20 px)");
  uav::PrepareCommandLine(app);
  CLI11_PARSE(app, argc, argv);

  uav::vision::TrackerParams params;
  cv::Rect2d box;
  try {
    params.kind = uav::vision::ParseTrackerKind(tracker);
    params.window = uav::vision::ParseSearchWindowMode(window);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-track: %s\n", e.what());
    return 2;
  }
  try {
    std::stringstream ss(box_text);
    for (std::string item; std::getline(ss, item, ',');)
      if (!uav::ParseDecimal(item)) throw std::invalid_argument("'" + item + "' is not a finite decimal number");
    const auto parsed = uav::ParseDecimalList(box_text, 4);
    if (!parsed) throw std::invalid_argument("need four numbers");
    const std::vector<double>& v = *parsed;
    box = cv::Rect2d(v[0], v[1], v[2], v[3]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-track: --box must be X,Y,W,H in pixels (%s)\n", e.what());
    return 2;
  }

  try {
    FrameSource source(input);
    const double rate_hz = fps > 0 ? fps : source.rate_hz().value_or(30.0);
    if (!overlay_dir.empty()) std::filesystem::create_directories(overlay_dir);
    std::ofstream csv;
    const std::string tmp = out_path + ".part";
    if (!out_path.empty()) {
      csv.open(tmp);
      if (!csv) throw std::runtime_error(out_path + ": cannot write");
      csv << "frame,x,y,w,h,angle,state,confidence\n";
    }
    uav::vision::TargetTracker tracker_(params);
    cv::Mat frame;
    int n = 0, losses = 0;
    uav::ProgressBar progress(source.count());
    std::vector<double> ms;
    uav::vision::TrackState last = uav::vision::TrackState::kTracking;
    const std::vector<cv::Rect2d> truth = truth_path.empty() ? std::vector<cv::Rect2d>{} : uav::vision::ReadOtbBoxes(truth_path);
    std::vector<std::optional<cv::Rect2d>> reported;  // per sequence position, for the score
    while (source.Next(&frame)) {
      uav::vision::TrackResult r;
      const auto t0 = std::chrono::steady_clock::now();
      if (n == 0) {
        tracker_.Start(frame, source.index() / rate_hz, box);
        r.state = uav::vision::TrackState::kTracking;
        r.confidence = 1.0;
        r.box = cv::RotatedRect(cv::Point2f(static_cast<float>(box.x + 0.5 * box.width), static_cast<float>(box.y + 0.5 * box.height)),
                                cv::Size2f(static_cast<float>(box.width), static_cast<float>(box.height)), 0.0f);
        r.search_window = box;
      } else {
        r = tracker_.Update(frame, source.index() / rate_hz);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      if (r.state == uav::vision::TrackState::kLost && last != uav::vision::TrackState::kLost) ++losses;
      last = r.state;
      const cv::Rect2f b = r.box.boundingRect2f();
      if (reported.size() <= static_cast<std::size_t>(source.index())) reported.resize(source.index() + 1);
      if (r.state == uav::vision::TrackState::kTracking) reported[source.index()] = cv::Rect2d(b);
      if (csv.is_open()) {
        char row[200];
        std::snprintf(row, sizeof row, "%d,%.2f,%.2f,%.2f,%.2f,%.2f,%s,%.3f\n", n, b.x, b.y, b.width, b.height, r.box.angle,
                      StateName(r.state), r.confidence);
        csv << row;
      }
      if (!overlay_dir.empty()) {
        cv::Mat shown = frame.clone();
        cv::rectangle(shown, r.search_window, cv::Scalar(255, 200, 0), 1);
        cv::Point2f corners[4];
        r.box.points(corners);
        const cv::Scalar colour = r.state == uav::vision::TrackState::kTracking ? cv::Scalar(0, 255, 0) : cv::Scalar(0, 0, 255);
        for (int k = 0; k < 4; ++k) cv::line(shown, corners[k], corners[(k + 1) % 4], colour, 2);
        char name[64];
        std::snprintf(name, sizeof name, "/%06d.png", n);
        cv::imwrite(overlay_dir + name, shown);
      }
      ++n;
      progress.Update(n, StateName(r.state));
    }
    progress.Finish(n);
    if (n == 0) throw std::runtime_error(input + ": no frames");
    if (csv.is_open()) {
      csv.close();
      std::filesystem::rename(tmp, out_path);
    }
    std::sort(ms.begin(), ms.end());
    const double median = ms.empty() ? 0.0 : ms[ms.size() / 2];
    std::string score;
    if (!truth.empty()) {
      const uav::vision::TrackingScore sc = uav::vision::ScoreTracking(reported, truth);
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    ", \"truth\": {\"frames\": %d, \"success_auc\": %.1f, \"precision_20px\": %.1f, \"mean_iou\": %.3f}", sc.frames,
                    100 * sc.success_auc, 100 * sc.precision_20px, sc.mean_iou);
      score = buf;
    }
    std::string skipped;
    for (const std::string& s : source.skipped()) skipped += (skipped.empty() ? "" : ", ") + uav::JsonString(s);
    if (!source.damaged().empty()) std::fprintf(stderr, "\nuav-track: %s: %s\n", input.c_str(), source.damaged().c_str());
    std::printf("{\"input\": %s, \"tracker\": \"%s\", \"method\": \"%s\", \"method_reason\": %s, \"window\": \"%s\", \"frames\": %d, \"frame_rate_hz\": %.1f, "
                "\"losses\": %d, \"median_ms_per_frame\": %.3f, \"frames_per_s_median\": %.1f, \"final_state\": \"%s\", \"skipped\": [%s], "
                "\"damaged\": %s%s}\n",
                uav::JsonString(input).c_str(), uav::vision::Name(params.kind), uav::vision::Name(tracker_.method()),
                uav::JsonString(tracker_.method_reason()).c_str(), uav::vision::Name(params.window), n, rate_hz, losses, median,
                median > 0 ? 1000.0 / median : 0.0, StateName(last), skipped.c_str(), uav::JsonString(source.damaged()).c_str(),
                score.c_str());
    // The boxes are written for the frames that were read; the exit status says not all were.
    return source.skipped().empty() && source.damaged().empty() ? 0 : 1;
  } catch (const std::exception& e) {
    if (!out_path.empty()) std::filesystem::remove(out_path + ".part");
    std::fprintf(stderr, "\nuav-track: %s\n", e.what());
    return 1;
  }
}
