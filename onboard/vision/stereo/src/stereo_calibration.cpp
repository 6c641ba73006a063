#include "uav/vision/stereo_calibration.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <sstream>
#include <string>
#include <string_view>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>
#include <nlohmann/json.hpp>

#include "uav/shared/text_file.hpp"

namespace uav::vision {

namespace {

bool NumberListChars(std::string_view s) {
  return s.find_first_not_of("0123456789.eE+-, []nanifNANIF") == std::string_view::npos;  // .nan, .inf too
}

// OpenCV's FileStorage parser can loop forever or allocate without bound on malformed text (found
// by fuzzing: a 56-byte YAML file hangs it). So a file reaches it only in the shape it writes:
// JSON that parses, or YAML of `key: number`, `key: !!opencv-matrix` with indented rows, cols, dt
// and data lines. The empty string, or the first line that is not, with what it should be.
std::string NotWhatWeWrite(const std::string& text) {
  if (text.size() > 65536) return "larger than 64 kB";
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{')
    return nlohmann::json::accept(text) ? "" : "not valid JSON";
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string_view l(line);
    const size_t indent = l.find_first_not_of(' ');
    if (indent == std::string_view::npos || l[indent] == '#') continue;
    const std::string where = "line " + std::to_string(n) + " ";
    if (n == 1) {
      if (l.rfind("%YAML", 0) != 0 || l.substr(5).find_first_not_of(":. 0123456789") != std::string_view::npos)
        return where + "is not %YAML:1.0";
      continue;
    }
    if (l == "---") continue;
    const size_t colon = l.find(':');
    const std::string_view key = l.substr(indent, colon == std::string_view::npos ? 0 : colon - indent);
    std::string_view value = colon == std::string_view::npos ? l.substr(indent) : l.substr(colon + 1);
    if (!value.empty() && value.front() == ' ') value.remove_prefix(1);
    const bool name = !key.empty() && key.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") ==
                                          std::string_view::npos;
    // The one-line flow style people write by hand: K1: !!opencv-matrix {rows: 3, cols: 3, dt: d, data: [...]}
    const std::string_view flow_tag = "!!opencv-matrix {";
    const bool flow = value.rfind(flow_tag, 0) == 0 && value.back() == '}' &&
                      value.substr(flow_tag.size(), value.size() - flow_tag.size() - 1)
                              .find_first_not_of("0123456789.eE+-, []:rowscldtafuinNANIF") == std::string_view::npos;
    if (indent == 0) {
      if (!name || (value != "!!opencv-matrix" && !flow && !NumberListChars(value)))
        return where + "is not 'key: number' or 'key: !!opencv-matrix'";
    } else if (colon == std::string_view::npos) {
      if (!NumberListChars(value)) return where + "is not a continued data list";
    } else if (key == "rows" || key == "cols") {
      if (value.empty() || value.find_first_not_of("0123456789") != std::string_view::npos) return where + "is not a row or column count";
    } else if (key == "dt") {
      if (value.empty() || value.find_first_not_of("abcdefghijklmnopqrstuvwxyz") != std::string_view::npos) return where + "is not a data type";
    } else if (key != "data" || !NumberListChars(value)) {
      return where + "is not a matrix's rows, cols, dt or data";
    }
  }
  return "";
}
cv::Mat CameraMatrix(const CameraIntrinsics& k) {
  return (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
}

CameraIntrinsics Intrinsics(const cv::Mat& K, const cv::Mat& D, cv::Size size) {
  CameraIntrinsics k;
  k.width = size.width;
  k.height = size.height;
  k.fx = K.at<double>(0, 0);
  k.fy = K.at<double>(1, 1);
  k.cx = K.at<double>(0, 2);
  k.cy = K.at<double>(1, 2);
  for (int i = 0; i < 5; ++i) k.distortion[static_cast<std::size_t>(i)] = i < static_cast<int>(D.total()) ? D.at<double>(i) : 0.0;
  return k;
}

bool FindBoard(const cv::Mat& image, const ChessboardSpec& board, std::vector<cv::Point2f>* corners) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (!cv::findChessboardCorners(grey, cv::Size(board.cols, board.rows), *corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return false;
  cv::cornerSubPix(grey, *corners, cv::Size(11, 11), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01));
  return true;
}
}  // namespace

void ChessboardSpec::Validate() const {
  if (cols < 3 || rows < 3 || cols > 50 || rows > 50)
    throw std::invalid_argument("chessboard: inner corners must be 3..50 each way");
  if (cols == rows) throw std::invalid_argument("chessboard: a square board is ambiguous; use unequal cols and rows");
  if (!(std::isfinite(square_m) && square_m > 0 && square_m < 10))
    throw std::invalid_argument("chessboard: square size must be 0..10 m");
}

StereoCalibration CalibrateStereo(const std::vector<cv::Mat>& left, const std::vector<cv::Mat>& right,
                                  const ChessboardSpec& board) {
  board.Validate();
  if (left.size() != right.size()) throw std::invalid_argument("calibration: as many left images as right ones needed");
  if (left.empty()) throw std::invalid_argument("calibration: no image pairs");
  const cv::Size size = left[0].size();
  std::vector<cv::Point3f> model;
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c < board.cols; ++c)
      model.emplace_back(static_cast<float>(c * board.square_m), static_cast<float>(r * board.square_m), 0.0f);
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image_l, image_r;
  StereoCalibration out;
  for (std::size_t i = 0; i < left.size(); ++i) {
    for (const cv::Mat* m : {&left[i], &right[i]}) {
      if (m->empty()) throw std::invalid_argument("calibration: pair " + std::to_string(i) + " has an empty image");
      if (m->size() != size)
        throw std::invalid_argument("calibration: pair " + std::to_string(i) + " differs in size from the first image");
      if (m->depth() != CV_8U) throw std::invalid_argument("calibration: images must be 8-bit");
    }
    std::vector<cv::Point2f> cl, cr;
    if (!FindBoard(left[i], board, &cl) || !FindBoard(right[i], board, &cr)) continue;
    object.push_back(model);
    image_l.push_back(cl);
    image_r.push_back(cr);
    out.used_pairs.push_back(static_cast<int>(i));
  }
  if (object.size() < 3)
    throw std::invalid_argument("calibration: the whole " + std::to_string(board.cols) + "x" + std::to_string(board.rows) +
                                " board was found in " + std::to_string(object.size()) + " pairs; at least 3 needed");
  // Each camera alone first (a good start), then the pair jointly with the intrinsics refined.
  cv::Mat K1, D1, K2, D2, R, T, E, F;
  std::vector<cv::Mat> rvecs, tvecs;
  const int flags = cv::CALIB_FIX_K3;
  cv::calibrateCamera(object, image_l, size, K1, D1, rvecs, tvecs, flags);
  cv::calibrateCamera(object, image_r, size, K2, D2, rvecs, tvecs, flags);
  out.rms_px = cv::stereoCalibrate(object, image_l, image_r, K1, D1, K2, D2, size, R, T, E, F,
                                   flags | cv::CALIB_USE_INTRINSIC_GUESS,
                                   cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-6));
  if (!std::isfinite(out.rms_px)) throw std::invalid_argument("calibration: the fit did not converge");
  out.rig.left = Intrinsics(K1, D1, size);
  out.rig.right = Intrinsics(K2, D2, size);
  Eigen::Matrix3d R_RL;
  Eigen::Vector3d t_RL;
  cv::cv2eigen(R, R_RL);
  cv::cv2eigen(T, t_RL);
  Eigen::Isometry3d T_RL = Eigen::Isometry3d::Identity();
  T_RL.linear() = R_RL;
  T_RL.translation() = t_RL;
  out.rig.T_LR = T_RL.inverse();
  return out;
}

void WriteStereoCalibration(const std::string& path, const StereoCalibration& c) {
  const std::filesystem::path p(path);
  const std::string ext = p.extension().string();
  if (ext != ".yml" && ext != ".yaml" && ext != ".json")
    throw std::runtime_error("calibration file " + path + ": extension must be .yml, .yaml or .json");
  const Eigen::Isometry3d T_RL = c.rig.T_LR.inverse();
  cv::Mat R, T, D1(1, 5, CV_64F), D2(1, 5, CV_64F);
  cv::eigen2cv(Eigen::Matrix3d(T_RL.linear()), R);
  cv::eigen2cv(Eigen::Vector3d(T_RL.translation()), T);
  for (int i = 0; i < 5; ++i) {
    D1.at<double>(i) = c.rig.left.distortion[static_cast<std::size_t>(i)];
    D2.at<double>(i) = c.rig.right.distortion[static_cast<std::size_t>(i)];
  }
  // The temporary keeps the extension: FileStorage picks the format from it.
  const std::string temporary = (p.parent_path() / ("." + p.stem().string() + ".part" + ext)).string();
  try {
    cv::FileStorage fs(temporary, cv::FileStorage::WRITE);
    if (!fs.isOpened()) throw std::runtime_error("cannot open");
    fs << "image_width" << c.rig.left.width << "image_height" << c.rig.left.height;
    fs << "K1" << CameraMatrix(c.rig.left) << "D1" << D1 << "K2" << CameraMatrix(c.rig.right) << "D2" << D2;
    fs << "R" << R << "T" << T << "rms_px" << c.rms_px;
    fs.release();
  } catch (const std::exception& e) {
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write calibration file " + path + ": " + e.what());
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write calibration file " + path);
  }
}

StereoCalibration ReadStereoCalibration(const std::string& path) {
  auto fail = [&](const std::string& what) { return std::runtime_error("calibration file " + path + ": " + what); };
  if (!std::filesystem::is_regular_file(path)) throw fail("no such file");
  const std::string text = ReadTextFile(path, "calibration file");
  if (const std::string problem = NotWhatWeWrite(text); !problem.empty())
    throw fail(problem + " (a calibration is YAML or JSON as uav-stereo-calibrate writes it)");
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const std::exception& e) {  // cv::Exception, and std::length_error from its YAML parser
    throw fail("not an OpenCV YAML/XML/JSON file");
  }
  if (!fs.isOpened()) throw fail("not an OpenCV YAML/XML/JSON file");
  auto matrix = [&](const char* key, int rows, int cols) {
    cv::Mat m;
    const cv::FileNode node = fs[key];
    if (node.empty()) throw fail(std::string("missing ") + key);
    try {
      // The size first: a matrix header claiming a billion rows must not be allocated.
      if (!node.isMap() || !node["rows"].isInt() || !node["cols"].isInt() ||
          int64_t{static_cast<int>(node["rows"])} * static_cast<int>(node["cols"]) != int64_t{rows} * cols)
        throw fail(std::string(key) + " must have " + std::to_string(rows * cols) + " entries");
      node >> m;
    } catch (const std::runtime_error&) {
      throw;
    } catch (const std::exception&) {
      throw fail(std::string(key) + " is not a matrix");
    }
    if (m.total() != static_cast<std::size_t>(rows * cols)) throw fail(std::string(key) + " must have " + std::to_string(rows * cols) + " entries");
    m.convertTo(m, CV_64F);
    m = m.reshape(1, rows);
    if (!cv::checkRange(m)) throw fail(std::string(key) + " is not finite");
    return m;
  };
  int width = 0, height = 0;
  double rms_px = 0;
  if (fs["image_width"].empty() || fs["image_height"].empty()) throw fail("missing image_width or image_height");
  try {
    fs["image_width"] >> width;
    fs["image_height"] >> height;
    if (!fs["rms_px"].empty()) fs["rms_px"] >> rms_px;
  } catch (const std::exception&) {
    throw fail("image_width, image_height or rms_px is not a number");
  }
  const cv::Size size(width, height);
  StereoCalibration c;
  // One entry after the other, so the first bad one is named.
  const cv::Mat K1 = matrix("K1", 3, 3);
  const cv::Mat D1 = matrix("D1", 1, 5);
  const cv::Mat K2 = matrix("K2", 3, 3);
  const cv::Mat D2 = matrix("D2", 1, 5);
  const cv::Mat R = matrix("R", 3, 3);
  const cv::Mat T = matrix("T", 3, 1);
  c.rig.left = Intrinsics(K1, D1, size);
  c.rig.right = Intrinsics(K2, D2, size);
  c.rms_px = rms_px;
  Eigen::Matrix3d R_RL;
  Eigen::Vector3d t_RL;
  cv::cv2eigen(R, R_RL);
  cv::cv2eigen(T, t_RL);
  if (!(R_RL.transpose() * R_RL).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || R_RL.determinant() < 0)
    throw fail("R is not a rotation");
  Eigen::Isometry3d T_RL = Eigen::Isometry3d::Identity();
  T_RL.linear() = R_RL;
  T_RL.translation() = t_RL;
  c.rig.T_LR = T_RL.inverse();
  try {
    ValidateIntrinsics(c.rig.left);
    ValidateIntrinsics(c.rig.right);
  } catch (const std::exception& e) {
    throw fail(e.what());
  }
  return c;
}

}  // namespace uav::vision
