#include "uav/vision/tracking_score.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "uav/shared/decimal.hpp"

namespace uav::vision {

std::vector<cv::Rect2d> ReadOtbBoxes(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open ground-truth boxes '" + path + "'");
  std::vector<cv::Rect2d> boxes;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    for (char& c : line)
      if (c == '\t' || c == ' ' || c == '\r') c = ',';
    // Collapse separators so "x, y, w, h" and "x\ty\tw\th" read alike.
    std::string compact;
    for (char c : line)
      if (c != ',' || (!compact.empty() && compact.back() != ',')) compact += c;
    while (!compact.empty() && compact.back() == ',') compact.pop_back();
    if (compact.empty()) continue;
    const auto v = ParseDecimalList(compact, 4);
    if (!v) throw std::runtime_error(path + ":" + std::to_string(n) + ": expected x,y,w,h in pixels, got '" + line + "'");
    const cv::Rect2d r((*v)[0], (*v)[1], (*v)[2], (*v)[3]);
    boxes.push_back(r.width > 0 && r.height > 0 ? r : cv::Rect2d());
  }
  if (boxes.empty()) throw std::runtime_error(path + ": no boxes");
  return boxes;
}

TrackingScore ScoreTracking(const std::vector<std::optional<cv::Rect2d>>& reported,
                            const std::vector<cv::Rect2d>& truth) {
  std::vector<double> overlaps;
  int within_20px = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const cv::Rect2d& t = truth[i];
    if (t.area() <= 0) continue;  // the target is absent: OTB does not score the frame
    double iou = 0.0;
    bool near = false;
    if (i < reported.size() && reported[i] && reported[i]->area() > 0) {
      const cv::Rect2d& r = *reported[i];
      const double inter = (r & t).area();
      iou = inter / (r.area() + t.area() - inter);
      const cv::Point2d dc = (r.tl() + r.br()) * 0.5 - (t.tl() + t.br()) * 0.5;
      near = std::hypot(dc.x, dc.y) <= 20.0;
    }
    overlaps.push_back(iou);
    within_20px += near;
  }
  TrackingScore s;
  s.frames = static_cast<int>(overlaps.size());
  if (overlaps.empty()) return s;
  double auc = 0.0;
  for (int k = 0; k <= 20; ++k) {
    const double threshold = 0.05 * k;
    auc += static_cast<double>(std::count_if(overlaps.begin(), overlaps.end(), [&](double o) { return o > threshold; })) /
           overlaps.size();
  }
  s.success_auc = auc / 21.0;
  s.precision_20px = static_cast<double>(within_20px) / overlaps.size();
  for (double o : overlaps) s.mean_iou += o / overlaps.size();
  return s;
}

}  // namespace uav::vision
