// Decoding part of a kept frame (the final render's strips) against decoding it whole.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "image_region.hpp"

namespace uav::vision {
namespace {

struct RegionCase {
  std::string name;
  std::string format;  // ".jpg" colour, "grey.jpg", ".png"
};

class ImageRegion : public ::testing::TestWithParam<RegionCase> {};

TEST_P(ImageRegion, MatchesTheWholeDecodeCut) {
  // A real aerial photo, cut to an odd size so no block boundary lines up with the image's edge.
  const cv::Mat photo = cv::imread("/usr/share/doc/opencv-doc/examples/data/aero1.jpg");
  ASSERT_FALSE(photo.empty()) << "opencv-doc is not installed (.ci/setup installs it)";
  cv::Mat image = photo(cv::Rect(3, 5, 605, 451)).clone();
  std::string ext = GetParam().format;
  if (ext == "grey.jpg") {
    cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
    ext = ".jpg";
  }
  std::vector<uint8_t> file;
  ASSERT_TRUE(cv::imencode(ext, image, file));
  const cv::Mat whole = cv::imdecode(file, cv::IMREAD_COLOR);
  const cv::Rect all(0, 0, whole.cols, whole.rows);
  for (const cv::Rect& region : {cv::Rect(100, 200, 300, 60), cv::Rect(0, 0, 605, 451), cv::Rect(590, 440, 40, 40),
                                 cv::Rect(-20, 130, 77, 211), cv::Rect(301, 17, 1, 1)}) {
    cv::Point origin(-1, -1);
    const cv::Mat part = DecodeRegion(file, region, &origin);
    const cv::Rect wanted = region & all;
    ASSERT_FALSE(part.empty()) << region;
    ASSERT_EQ(part.type(), CV_8UC3);
    const cv::Rect got(origin, part.size());
    EXPECT_EQ(got & wanted, wanted) << "covers " << got << ", not all of " << wanted;
    EXPECT_EQ(got & all, got) << got << " reaches beyond the image";
    cv::Mat diff;
    cv::absdiff(part(wanted - origin), whole(wanted), diff);
    double worst = 0;
    cv::minMaxLoc(diff.reshape(1), nullptr, &worst);
    // The same decoder: identical, but that a cropped decode upsamples the chroma from its own
    // blocks, and a few pixels a row (measured: at most 4 of 304, never 3 grey levels) differ.
    EXPECT_LE(worst, 3.0) << region;
    if (wanted.area() >= 100) {
      EXPECT_GT(cv::countNonZero(diff.reshape(1) == 0), 0.97 * diff.total() * 3) << region;
    }
  }
  cv::Point origin;
  EXPECT_TRUE(DecodeRegion(file, cv::Rect(700, 0, 10, 10), &origin).empty()) << "a region off the image";
}

INSTANTIATE_TEST_SUITE_P(Formats, ImageRegion,
                         ::testing::Values(RegionCase{"jpeg", ".jpg"}, RegionCase{"grey_jpeg", "grey.jpg"},
                                           RegionCase{"png", ".png"}),
                         [](const auto& info) { return info.param.name; });

TEST(ImageRegionRefusal, NotAnImageGivesNothing) {
  cv::Point origin;
  const std::vector<uint8_t> garbage = {0xFF, 0xD8, 0xFF, 0xE0, 1, 2, 3};  // a JPEG's start, then nothing
  EXPECT_TRUE(DecodeRegion(garbage, cv::Rect(0, 0, 10, 10), &origin).empty());
  EXPECT_TRUE(DecodeRegion({}, cv::Rect(0, 0, 10, 10), &origin).empty());
  const std::vector<uint8_t> text = {'h', 'e', 'l', 'l', 'o'};
  EXPECT_TRUE(DecodeRegion(text, cv::Rect(0, 0, 10, 10), &origin).empty());
}

}  // namespace
}  // namespace uav::vision
