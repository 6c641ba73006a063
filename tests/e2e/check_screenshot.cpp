// Checks GCS screenshots for content: not blank, the panels drawn (many distinct colours, text
// everywhere), the two frames different where live data is shown (plot region) so the window
// was not frozen, the survey on the map and the tracker's box on the video. With OUT_DIR, writes
// each main panel of the first frame as OUT_DIR/panel_<name>.png.
#include <cstdio>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: check_screenshot FIRST.png SECOND.png [OUT_DIR]\n");
    return 2;
  }
  const cv::Mat a = cv::imread(argv[1]), b = cv::imread(argv[2]);
  if (a.empty() || b.empty() || a.size() != b.size()) {
    std::fprintf(stderr, "FAIL: cannot read both screenshots at the same size\n");
    return 1;
  }
  int failures = 0;
  auto check = [&](bool ok, const char* what, double value) {
    std::printf("%s %s: %.3f\n", ok ? "ok  " : "FAIL", what, value);
    failures += !ok;
  };
  cv::Mat gray;
  cv::cvtColor(a, gray, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(gray, mean, stddev);
  check(stddev[0] > 10.0, "first frame is not blank (grey std dev)", stddev[0]);
  // Every panel region has drawn detail (edges of text and widgets): left column, plot, command
  // bar, messages, status bar; layout fractions as gcs_ui.cpp places them.
  cv::Mat edges;
  cv::Canny(gray, edges, 50, 150);
  const int W = a.cols, H = a.rows;
  auto region = [&](int x0, int y0, int x1, int y1) {  // percent of the window, inset 1 %
    return cv::Rect(W * (x0 + 1) / 100, H * (y0 + 1) / 100, W * (x1 - x0 - 2) / 100, H * (y1 - y0 - 2) / 100);
  };
  const struct { const char* name; cv::Rect r; } panels[] = {
      {"status bar has text", cv::Rect(0, 0, W, H * 4 / 100)},
      {"vehicles panel has text", region(0, 4, 22, 22)},
      {"state list has text", region(0, 22, 22, 64)},
      {"video panel has the camera image", region(0, 64, 22, 100)},
      {"plot has curves", region(22, 4, 62, 55)},
      {"command bar has text", region(22, 55, 62, 77)},
      {"messages panel has text", region(22, 77, 62, 100)},
      {"map has detail", region(62, 4, 100, 50)},
      {"survey panel has text", region(62, 50, 100, 82)},
      {"live map panel has text", region(62, 82, 100, 100)}};
  for (const auto& p : panels) {
    const double frac = cv::countNonZero(edges(p.r)) / static_cast<double>(p.r.area());
    check(frac > 0.003, p.name, frac);
  }
  // Live: the plot region changed between the frames.
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  const cv::Rect plot = region(22, 4, 62, 55);
  const double changed = cv::countNonZero(diff(plot) > 30) / static_cast<double>(plot.area());
  check(changed > 0.002, "plot changed between frames (live, not frozen)", changed);
  // The map shows the survey the script drew: polygon outline (green) and coverage (blue).
  cv::Mat map = a(region(62, 4, 100, 50)), green, blue;
  cv::inRange(map, cv::Scalar(60, 190, 50), cv::Scalar(130, 255, 120), green);  // BGR of (80, 220, 100)
  check(cv::countNonZero(green) > 200, "map shows the survey polygon (green pixels)", cv::countNonZero(green));
  cv::inRange(map, cv::Scalar(70, 50, 35), cv::Scalar(140, 90, 75), blue);  // coverage blended on the background
  check(cv::countNonZero(blue) > 2000, "map shows the survey coverage (blue pixels)", cv::countNonZero(blue));
  // The tracker's box (green) over the video.
  cv::Mat video = a(region(0, 64, 22, 100)), box;
  cv::inRange(video, cv::Scalar(100, 235, 60), cv::Scalar(140, 255, 100), box);  // BGR of (80, 255, 120)
  check(cv::countNonZero(box) > 100, "video shows the tracker's box (green pixels)", cv::countNonZero(box));
  if (argc == 4) {
    const struct { const char* name; int x0, y0, x1, y1; } crops[] = {
        {"status", 0, 0, 100, 4},      {"telemetry", 0, 4, 22, 64}, {"video", 0, 64, 22, 100},
        {"plots", 22, 4, 62, 55},      {"command", 22, 55, 62, 77}, {"messages", 22, 77, 62, 100},
        {"map", 62, 4, 100, 50},       {"survey", 62, 50, 100, 82}, {"livemap", 62, 82, 100, 100}};
    for (const auto& c : crops) {
      const cv::Rect r(W * c.x0 / 100, H * c.y0 / 100, W * (c.x1 - c.x0) / 100, H * (c.y1 - c.y0) / 100);
      const std::string path = std::string(argv[3]) + "/panel_" + c.name + ".png";
      if (!cv::imwrite(path, a(r))) check(false, ("write " + path).c_str(), 0);
    }
  }
  return failures ? 1 : 0;
}
