// uav-powerlines-train SET... --out MODEL.yml [--trees N] [--depth N] [--folds N] [--min-probability P]:
// trains the power-line detector's learned verifier. Each SET is a folder with images/ and
// truth/<name>.png (non-zero on a wire), as ../shared/data/powerlines_real. The detector runs on
// every photo without the verifier; each curve it reports is labelled a wire when most of its
// drawn pixels lie within the benchmark's tolerance (0.0075 of the diagonal) of the truth, and
// measured (wire_verifier.hpp). A random forest (OpenCV's RTrees) learns the labels. Before the
// model is written, it is scored by cross-validation over the photos (each fold's photos are
// judged by a forest trained on the others): per set, the curves kept at --min-probability, the
// share of their pixels on a wire before and after, and the share of the wires' pixels kept. The
// JSON report goes to stdout, progress to stderr. The model is written atomically; copy it to
// resources/models/wire_verifier.yml to compile it into the detector. Exit 1 when a set cannot
// be read, 2 on bad options.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ml.hpp>

#include "uav/shared/image_files.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/power_line_detector.hpp"
#include "wire_verifier.hpp"

namespace {

namespace fs = std::filesystem;
using uav::vision::detail::kWireFeatures;

struct Candidate {
  int set = 0, photo = 0;
  double pixels = 0, on_wire = 0;  // drawn pixels, and those within the tolerance of the truth
  uav::vision::WireCurve curve;
  uav::vision::detail::WireFeatureVector features{};
  bool wire() const { return on_wire > 0.5 * pixels; }
};

cv::Ptr<cv::ml::RTrees> Train(const std::vector<Candidate>& all, const std::vector<bool>& use, int trees, int depth) {
  cv::Mat x, y;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!use[i]) continue;
    x.push_back(cv::Mat(1, kWireFeatures, CV_32F, const_cast<float*>(all[i].features.data())).clone());
    y.push_back(static_cast<int>(all[i].wire()));
  }
  cv::Ptr<cv::ml::RTrees> forest = cv::ml::RTrees::create();
  forest->setMaxDepth(depth);
  forest->setMinSampleCount(5);
  forest->setTermCriteria({cv::TermCriteria::MAX_ITER, trees, 0.0});
  forest->train(cv::ml::TrainData::create(x, cv::ml::ROW_SAMPLE, y));
  return forest;
}

double WireVotes(const cv::Ptr<cv::ml::RTrees>& forest, const Candidate& c) {
  cv::Mat votes;
  forest->getVotes(cv::Mat(1, kWireFeatures, CV_32F, const_cast<float*>(c.features.data())), votes, 0);
  double wire = 0, all = 0;
  for (int j = 0; j < votes.cols; ++j) {
    all += votes.at<int>(1, j);
    if (votes.at<int>(0, j) == 1) wire = votes.at<int>(1, j);
  }
  return all > 0 ? wire / all : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-powerlines-train: trains the power-line detector's learned verifier from photos with pixel masks"};
  std::vector<std::string> sets;
  std::string out;
  int trees = 30, depth = 4, folds = 5;
  double min_probability = 0.7;
  cli.add_option("sets", sets, "folders, each with images/ and truth/<name>.png")->required()->check(CLI::ExistingDirectory);
  cli.add_option("--out", out, "model file to write (OpenCV YAML)")->required();
  cli.add_option("--trees", trees, "trees in the forest")->check(CLI::Range(1, 1000))->capture_default_str();
  cli.add_option("--depth", depth, "largest depth of a tree")->check(CLI::Range(1, 20))->capture_default_str();
  cli.add_option("--folds", folds, "cross-validation folds over the photos")->check(CLI::Range(2, 50))->capture_default_str();
  cli.add_option("--min-probability", min_probability, "the detector's threshold, for the report")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);

  struct Photo {
    int set;
    std::string image, truth;
  };
  std::vector<Photo> photos;
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const std::vector<std::string> images = uav::ImageFilesIn(sets[s] + "/images");
    if (images.empty()) {
      std::fprintf(stderr, "uav-powerlines-train: %s/images holds no images\n", sets[s].c_str());
      return 1;
    }
    for (const std::string& image : images)
      photos.push_back({static_cast<int>(s), image, sets[s] + "/truth/" + fs::path(image).stem().string() + ".png"});
  }
  uav::vision::PowerLineParams params;
  params.min_wire_probability = 0.0;  // every curve the tests let through
  const uav::vision::PowerLineDetector detector(params);
  std::vector<Candidate> candidates;
  uav::ProgressBar progress(photos.size());
  for (std::size_t p = 0; p < photos.size(); ++p) {
    progress.Update(p, fs::path(photos[p].image).filename().string());
    // A damaged photo or mask would teach the forest wrong labels: training stops and names it.
    if (const std::string problem = uav::ImageFileProblem(photos[p].image); !problem.empty()) {
      std::fprintf(stderr, "\nuav-powerlines-train: %s: %s\n", photos[p].image.c_str(), problem.c_str());
      return 1;
    }
    const cv::Mat image = cv::imread(photos[p].image, cv::IMREAD_COLOR);
    const cv::Mat truth = std::filesystem::exists(photos[p].truth) && uav::ImageFileProblem(photos[p].truth).empty()
                              ? cv::imread(photos[p].truth, cv::IMREAD_GRAYSCALE)
                              : cv::Mat();
    if (image.empty() || truth.empty() || truth.size() != image.size()) {
      std::fprintf(stderr, "\nuav-powerlines-train: %s: unreadable, or its truth %s missing, damaged or of another size\n",
                   photos[p].image.c_str(), photos[p].truth.c_str());
      return 1;
    }
    cv::Mat gray, to_truth;
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    const cv::Mat thin = uav::vision::ThinStructureResponse(gray, params.max_wire_width_px);
    cv::distanceTransform(truth == 0, to_truth, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    const double tolerance_px = 0.0075 * std::hypot(image.cols, image.rows);
    for (const uav::vision::WireCurve& w : detector.Detect(image)) {
      const cv::Mat drawn = uav::vision::DrawWireMask(image.size(), {w}, 2);
      Candidate c;
      c.set = photos[p].set;
      c.photo = static_cast<int>(p);
      c.pixels = cv::countNonZero(drawn);
      c.on_wire = cv::countNonZero(drawn & (to_truth <= tolerance_px));
      c.features = uav::vision::detail::MeasureWire(gray, thin, w);
      c.curve = w;
      candidates.push_back(c);
    }
  }
  progress.Finish(photos.size());
  int wires = 0;
  for (const Candidate& c : candidates) wires += c.wire();
  if (wires == 0 || wires == static_cast<int>(candidates.size())) {
    std::fprintf(stderr, "uav-powerlines-train: %zu curves, %d of them wires: both kinds are needed to learn\n",
                 candidates.size(), wires);
    return 1;
  }
  // Cross-validation over the photos: fold k's photos are judged by a forest trained on the others.
  std::vector<double> probability(candidates.size(), 0.0);
  for (int k = 0; k < folds; ++k) {
    std::vector<bool> train(candidates.size());
    for (std::size_t i = 0; i < candidates.size(); ++i) train[i] = candidates[i].photo % folds != k;
    const cv::Ptr<cv::ml::RTrees> forest = Train(candidates, train, trees, depth);
    for (std::size_t i = 0; i < candidates.size(); ++i)
      if (!train[i]) probability[i] = WireVotes(forest, candidates[i]);
  }
  nlohmann::json report;
  report["photos"] = photos.size();
  report["curves"] = candidates.size();
  report["wires"] = wires;
  report["trees"] = trees;
  report["depth"] = depth;
  report["min_probability"] = min_probability;
  report["cross_validation"] = {{"folds", folds}, {"sets", nlohmann::json::array()}};
  for (std::size_t s = 0; s < sets.size(); ++s) {
    double pixels = 0, on_wire = 0, kept_pixels = 0, kept_on_wire = 0;
    int curves = 0, kept = 0;
    // The set's F1 as uav-powerlines --truth scores it, without the verifier and with each
    // photo's curves judged by the forest that did not see it.
    uav::vision::MaskTally before, after;
    for (std::size_t p = 0; p < photos.size(); ++p) {
      if (photos[p].set != static_cast<int>(s)) continue;
      const cv::Mat truth = cv::imread(photos[p].truth, cv::IMREAD_GRAYSCALE);
      std::vector<uav::vision::WireCurve> all_curves, kept_curves;
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (candidates[i].photo != static_cast<int>(p)) continue;
        all_curves.push_back(candidates[i].curve);
        if (probability[i] >= min_probability) kept_curves.push_back(candidates[i].curve);
      }
      const double tolerance_px = 0.0075 * std::hypot(truth.cols, truth.rows);
      before.Add(uav::vision::DrawWireMask(truth.size(), all_curves, 2), truth, tolerance_px);
      after.Add(uav::vision::DrawWireMask(truth.size(), kept_curves, 2), truth, tolerance_px);
    }
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const Candidate& c = candidates[i];
      if (c.set != static_cast<int>(s)) continue;
      ++curves;
      pixels += c.pixels, on_wire += c.on_wire;
      if (probability[i] < min_probability) continue;
      ++kept;
      kept_pixels += c.pixels, kept_on_wire += c.on_wire;
    }
    report["cross_validation"]["sets"].push_back({
        {"set", sets[s]},
        {"curves", curves},
        {"curves_kept", kept},
        {"pixels_on_a_wire_before", pixels > 0 ? on_wire / pixels : 0.0},
        {"pixels_on_a_wire_after", kept_pixels > 0 ? kept_on_wire / kept_pixels : 0.0},
        {"wire_pixels_kept", on_wire > 0 ? kept_on_wire / on_wire : 0.0},
        {"f1_before", 100.0 * before.Score().f1},
        {"f1_cross_validated", 100.0 * after.Score().f1},
        {"precision_cross_validated", after.Score().precision},
        {"recall_cross_validated", after.Score().recall},
    });
  }
  const cv::Ptr<cv::ml::RTrees> forest = Train(candidates, std::vector<bool>(candidates.size(), true), trees, depth);
  cv::FileStorage fs_out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs_out << forest->getDefaultName() << "{";  // as cv::Algorithm::save writes it
  forest->write(fs_out);
  fs_out << "}";
  const std::string yaml = fs_out.releaseAndGetString();
  try {
    uav::WriteFileAtomically(out, yaml);
    uav::vision::detail::WireVerifier::FromFile(out);  // it loads as the detector will load it
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-powerlines-train: %s\n", e.what());
    return 1;
  }
  report["out"] = out;
  std::printf("%s\n", report.dump(2).c_str());
  return 0;
}
