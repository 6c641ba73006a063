// Checks GCS screenshots against the default layout table the GCS itself uses (layout.hpp):
// the table fits the screenshot's size; every panel always shown has drawn detail (text, widgets)
// in its rectangle; the two frames differ where live data is shown (the plot) so the window was
// not frozen; the survey is on the map and the tracker's box on the video. With the windows opened
// on demand (sticks, attitude) in a third frame: the command bar's emergency stop and the status
// bar are still in view. Writes each main panel of the first frame as OUT_DIR/panel_<name>.png.
// Usage: check_screenshot FIRST.png SECOND.png OUT_DIR [WITH_WINDOWS.png]
//        check_screenshot --layout FRAME.png      (another display size: the layout alone)
#include <cstdio>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/gcs/layout.hpp"

namespace {

int failures = 0;

void Check(bool ok, const std::string& what, double value) {
  std::printf("%s %s: %.3f\n", ok ? "ok  " : "FAIL", what.c_str(), value);
  failures += !ok;
}

// A window's rectangle in the image, inset by 1 % of the display (its frame and title bar edges).
cv::Rect RectOf(const uav::gcs::WindowPlace& p, const cv::Size& size, bool inset = true) {
  const float in = inset ? 0.01f : 0.0f;
  const int x0 = static_cast<int>((p.x0 + in) * size.width), y0 = static_cast<int>((p.y0 + in) * size.height);
  const int x1 = static_cast<int>((p.x1 - in) * size.width), y1 = static_cast<int>((p.y1 - in) * size.height);
  return cv::Rect(x0, y0, std::max(1, x1 - x0), std::max(1, y1 - y0)) & cv::Rect(0, 0, size.width, size.height);
}

cv::Rect RectOf(const char* window, const cv::Size& size, bool inset = true) {
  return RectOf(*uav::gcs::FindWindowPlace(window), size, inset);
}

// The layout on this display, and every panel always shown drawn where the table puts it.
void CheckLayout(const cv::Mat& frame) {
  for (const std::string& problem : uav::gcs::CheckLayout(static_cast<float>(frame.cols), static_cast<float>(frame.rows)))
    Check(false, "layout: " + problem, 0);
  cv::Mat gray, edges;
  cv::cvtColor(frame, gray, cv::COLOR_BGR2GRAY);
  cv::Canny(gray, edges, 50, 150);
  for (const uav::gcs::WindowPlace& p : uav::gcs::DefaultLayout()) {
    if (p.on_demand || std::string(p.window) == "Replay") continue;  // the replay's panel is not shown live
    const cv::Rect r = RectOf(p, frame.size());
    const double frac = cv::countNonZero(edges(r)) / static_cast<double>(r.area());
    Check(frac > 0.003, std::string(p.window) + " panel has drawn detail where the layout puts it", frac);
  }
}

// The emergency stop's red (ImGui button colour 0.75, 0.1, 0.1) within the command bar.
int EmergencyStopPixels(const cv::Mat& frame) {
  cv::Mat red;
  cv::inRange(frame(RectOf("Command", frame.size(), false)), cv::Scalar(0, 0, 150), cv::Scalar(60, 60, 230), red);
  return cv::countNonZero(red);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--layout") {
    const cv::Mat frame = cv::imread(argv[2]);
    if (frame.empty()) {
      std::fprintf(stderr, "FAIL: cannot read %s\n", argv[2]);
      return 1;
    }
    std::printf("layout at %d x %d\n", frame.cols, frame.rows);
    CheckLayout(frame);
    Check(EmergencyStopPixels(frame) > 300, "emergency stop in view (red pixels in the command bar)", EmergencyStopPixels(frame));
    return failures ? 1 : 0;
  }
  if (argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: check_screenshot FIRST.png SECOND.png OUT_DIR [WITH_WINDOWS.png]\n"
                         "       check_screenshot --layout FRAME.png\n");
    return 2;
  }
  const cv::Mat a = cv::imread(argv[1]), b = cv::imread(argv[2]);
  if (a.empty() || b.empty() || a.size() != b.size()) {
    std::fprintf(stderr, "FAIL: cannot read both screenshots at the same size\n");
    return 1;
  }
  cv::Mat gray;
  cv::cvtColor(a, gray, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(gray, mean, stddev);
  Check(stddev[0] > 10.0, "first frame is not blank (grey std dev)", stddev[0]);
  CheckLayout(a);
  // Live: the plot region changed between the frames.
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  const cv::Rect plot = RectOf("Plot", a.size());
  const double changed = cv::countNonZero(diff(plot) > 30) / static_cast<double>(plot.area());
  Check(changed > 0.002, "plot changed between frames (live, not frozen)", changed);
  // The map shows the survey the script drew: polygon outline (green) and coverage (blue).
  cv::Mat map = a(RectOf("Map", a.size())), green, blue;
  cv::inRange(map, cv::Scalar(60, 190, 50), cv::Scalar(130, 255, 120), green);  // BGR of (80, 220, 100)
  Check(cv::countNonZero(green) > 200, "map shows the survey polygon (green pixels)", cv::countNonZero(green));
  cv::inRange(map, cv::Scalar(70, 50, 35), cv::Scalar(140, 90, 75), blue);  // coverage blended on the background
  Check(cv::countNonZero(blue) > 2000, "map shows the survey coverage (blue pixels)", cv::countNonZero(blue));
  // The tracker's box (green) over the video.
  cv::Mat video = a(RectOf("Video", a.size())), box;
  cv::inRange(video, cv::Scalar(100, 235, 60), cv::Scalar(140, 255, 100), box);  // BGR of (80, 255, 120)
  Check(cv::countNonZero(box) > 100, "video shows the tracker's box (green pixels)", cv::countNonZero(box));
  Check(EmergencyStopPixels(a) > 300, "emergency stop in view (red pixels in the command bar)", EmergencyStopPixels(a));
  if (argc == 5) {
    // The windows opened on demand leave the command bar and the status bar alone.
    const cv::Mat c = cv::imread(argv[4]);
    if (c.size() != a.size()) {
      Check(false, std::string("read ") + argv[4], 0);
    } else {
      Check(EmergencyStopPixels(c) >= 0.9 * EmergencyStopPixels(a),
            "emergency stop still in view with the sticks and attitude windows open", EmergencyStopPixels(c));
      CheckLayout(c);  // the status bar and every panel still drawn
      const cv::Rect sticks = RectOf("Sticks", a.size());
      cv::Mat sticks_diff;
      cv::absdiff(a(sticks), c(sticks), sticks_diff);
      cv::cvtColor(sticks_diff, sticks_diff, cv::COLOR_BGR2GRAY);
      Check(cv::countNonZero(sticks_diff > 30) > 0.05 * sticks.area(), "the sticks window opened where the layout puts it",
            cv::countNonZero(sticks_diff > 30) / static_cast<double>(sticks.area()));
    }
  }
  const struct { const char* name; const char* window; } crops[] = {
      {"status", "Status"},  {"telemetry", "Vehicle state"}, {"video", "Video"},    {"plots", "Plot"},
      {"command", "Command"}, {"messages", "Messages"},      {"map", "Map"},        {"survey", "Survey"},
      {"livemap", "Live map"}, {"prearm", "Pre-arm"},         {"sensing", "Sensing"}, {"obstacles", "Obstacles"}};
  for (const auto& c : crops) {
    const std::string path = std::string(argv[3]) + "/panel_" + c.name + ".png";
    if (!cv::imwrite(path, a(RectOf(c.window, a.size(), false)))) Check(false, "write " + path, 0);
  }
  return failures ? 1 : 0;
}
