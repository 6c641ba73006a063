// Checks GCS screenshots for content: not blank, the panels drawn (many distinct colours, text
// everywhere), and the two frames different where live data is shown (plot region) so the
// window was not frozen.
#include <cstdio>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: check_screenshot FIRST.png SECOND.png\n");
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
  const struct { const char* name; cv::Rect r; } panels[] = {
      {"status bar has text", cv::Rect(0, 0, W, H * 4 / 100)},
      {"vehicles panel has text", cv::Rect(0, H * 5 / 100, W * 23 / 100, H * 16 / 100)},
      {"state list has text", cv::Rect(0, H * 23 / 100, W * 23 / 100, H * 70 / 100)},
      {"plot has curves", cv::Rect(W * 25 / 100, H * 10 / 100, W * 74 / 100, H * 52 / 100)},
      {"command bar has text", cv::Rect(W * 25 / 100, H * 65 / 100, W * 38 / 100, H * 33 / 100)},
      {"messages panel has text", cv::Rect(W * 65 / 100, H * 65 / 100, W * 34 / 100, H * 33 / 100)}};
  for (const auto& p : panels) {
    const double frac = cv::countNonZero(edges(p.r)) / static_cast<double>(p.r.area());
    check(frac > 0.003, p.name, frac);
  }
  // Live: the plot region changed between the frames.
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  const cv::Rect plot(W * 25 / 100, H * 10 / 100, W * 74 / 100, H * 52 / 100);
  const double changed = cv::countNonZero(diff(plot) > 30) / static_cast<double>(plot.area());
  check(changed > 0.002, "plot changed between frames (live, not frozen)", changed);
  return failures ? 1 : 0;
}
