// The GCS's disk fills up while it saves a downloaded map: a clear error naming the file and
// the cause, nothing left in the directory (no partial file, no temporary), the verified map
// kept in memory, and saved once there is room and the operator downloads again.
// Needs a small file system to fill: `gcs.disk_full` (tests/CMakeLists.txt) mounts a tmpfs in a
// private mount namespace and names it in UAV_SMALL_FS; run alone, the test is skipped.
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "uav/gcs/gcs_model.hpp"
#include "uav/shared/file_transfer.hpp"

namespace uav::gcs {
namespace {

namespace fs = std::filesystem;

bool LogHas(const GcsModel& m, const std::string& text) {
  for (const auto& e : m.log().lines())
    if (e.text.find(text) != std::string::npos) return true;
  return false;
}

TEST(MapsDiskFull, ClearErrorNoPartialFileAndTheDownloadCanBeRetried) {
  const char* small_fs = std::getenv("UAV_SMALL_FS");
  if (!small_fs) GTEST_SKIP() << "needs UAV_SMALL_FS, a small file system to fill (the gcs.disk_full test)";
  const fs::path dir = fs::path(small_fs) / "maps";
  fs::create_directories(dir);
  // Fill the file system, leaving less than the map needs.
  const fs::path filler = fs::path(small_fs) / "filler";
  {
    std::ofstream out(filler, std::ios::binary);
    const std::string block(4096, 'f');
    while (out.write(block.data(), block.size())) {
    }
  }
  std::string map(300'000, '\0');
  std::mt19937 rng(5);
  for (char& c : map) c = static_cast<char>(rng());
  FileSender vehicle;
  const FileOffer offer = vehicle.Offer("map_1.tif", map);

  GcsModel model("gcs", 1);
  double t = 0;
  model.OnFileOffer("UAV1", offer, t);
  ASSERT_TRUE(model.StartDownload(dir.string(), t));
  auto fly = [&](double seconds) {
    for (const double end = t + seconds; t < end; t += 0.02) {
      model.Tick(t);
      for (const auto& r : model.maps().TakeOutgoing()) vehicle.OnRequest(r.request);
      for (const auto& c : vehicle.Poll(t).chunks) model.OnFileChunk("UAV1", c, t);
    }
  };
  fly(10);
  EXPECT_TRUE(LogHas(model, "received but not saved")) << "no error logged";
  EXPECT_TRUE(LogHas(model, "No space left on device"));
  EXPECT_TRUE(fs::is_empty(dir)) << "a partial or temporary file was left";

  // Room again; the operator downloads again: written whole, identical, without new chunks.
  fs::remove(filler);
  ASSERT_TRUE(model.StartDownload(dir.string(), t));
  fly(1);
  ASSERT_TRUE(fs::exists(dir / "map_1.tif"));
  std::ifstream in(dir / "map_1.tif", std::ios::binary);
  const std::string saved((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(saved, map);
  EXPECT_TRUE(LogHas(model, "SHA-256 verified"));
}

}  // namespace
}  // namespace uav::gcs
