// Numbers as typed (decimal only, everywhere: command bar, parameter files, CLI options) and the
// check every image reader makes before decoding (truncated or garbled files are named).
#include <gtest/gtest.h>

#include <algorithm>
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "uav/shared/command_grammar.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/text_file.hpp"

namespace uav {
namespace {

TEST(Decimal, AcceptsDecimalNotationOnly) {
  EXPECT_EQ(ParseDecimal("10"), 10.0);
  EXPECT_EQ(ParseDecimal("-2.5"), -2.5);
  EXPECT_EQ(ParseDecimal("+.5"), 0.5);
  EXPECT_EQ(ParseDecimal("5."), 5.0);
  EXPECT_EQ(ParseDecimal("1e-4"), 1e-4);
  EXPECT_EQ(ParseDecimal("2E3"), 2000.0);
  for (const char* bad : {"0x10", "0X1p4", "inf", "-inf", "nan", "NAN", "1e400", "", " 1", "1 ", "1,5", "--1", ".", "e5",
                          "1e", "1e+", "10m", "0b101"})
    EXPECT_FALSE(ParseDecimal(bad)) << bad;
}

TEST(Decimal, TheCommandGrammarTakesDecimalNumbersOnly) {
  EXPECT_TRUE(ParseCommand("takeoff 10").ok());
  EXPECT_TRUE(ParseCommand("takeoff 10.5").ok());
  const ParseResult hex = ParseCommand("takeoff 0x10");
  ASSERT_FALSE(hex.ok());
  EXPECT_EQ(hex.error, "takeoff: argument alt_m is not a decimal number (digits only, no hexadecimal): '0x10'");
  EXPECT_FALSE(ParseCommand("goto 0x1 0 10").ok());
  EXPECT_FALSE(ParseCommand("takeoff inf").ok());
}

std::string ParseCli(std::vector<std::string> args) {
  CLI::App app{"t"};
  double focal = 0, fps = 0;
  int frames = 0;
  std::vector<double> box;
  app.add_option("--focal", focal);
  app.add_option("--fps", fps)->check(CLI::Range(1.0, 1000.0));
  app.add_option("--frames", frames);
  app.add_option("--box", box)->delimiter(',');
  RequireDecimalNumbers(app);
  std::reverse(args.begin(), args.end());
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(Decimal, EveryNumberOptionOfACliRefusesNonFiniteAndHex) {
  EXPECT_EQ(ParseCli({"--focal", "500", "--frames", "3", "--box", "1,2.5,3,4"}), "");
  EXPECT_NE(ParseCli({"--focal", "nan"}).find("--focal: 'nan' is not a finite number (decimal digits only)"), std::string::npos)
      << ParseCli({"--focal", "nan"});
  EXPECT_NE(ParseCli({"--focal", "inf"}).find("--focal"), std::string::npos);
  EXPECT_NE(ParseCli({"--frames", "0x10"}).find("--frames: '0x10' is not a finite number"), std::string::npos)
      << ParseCli({"--frames", "0x10"});
  EXPECT_NE(ParseCli({"--frames", "2.5"}).find("--frames"), std::string::npos);
  EXPECT_NE(ParseCli({"--box", "1,nan,3,4"}).find("--box"), std::string::npos);
  // An option with a range of its own too (CLI::Range alone lets NaN through).
  EXPECT_EQ(ParseCli({"--fps", "30"}), "");
  EXPECT_NE(ParseCli({"--fps", "nan"}).find("--fps: 'nan' is not a finite number"), std::string::npos) << ParseCli({"--fps", "nan"});
  EXPECT_NE(ParseCli({"--fps", "2000"}).find("--fps"), std::string::npos);
}

TEST(Decimal, JsonStringsAreEscaped) { EXPECT_EQ(JsonString("a \"b\" \\c\n"), "\"a \\\"b\\\" \\\\c\\n\""); }

std::vector<uint8_t> Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// Real JPEGs (opencv-doc) whole, cut short and garbled; a PNG cut short.
TEST(ImageCheck, NamesTruncatedAndGarbledFilesAndPassesWholeOnes) {
  const std::string data = "/usr/share/doc/opencv-doc/examples/data/";
  for (const char* name : {"aero1.jpg", "left01.jpg", "building.jpg", "graf1.png"}) {
    const auto b = Bytes(data + name);
    ASSERT_FALSE(b.empty()) << name;
    EXPECT_EQ(EncodedImageProblem(b.data(), b.size()), "") << name;
    const std::string cut = EncodedImageProblem(b.data(), b.size() / 2);
    EXPECT_NE(cut, "") << name << " cut in half passed";
  }
  auto jpeg = Bytes(data + "aero1.jpg");
  EXPECT_EQ(EncodedImageProblem(jpeg.data(), jpeg.size() / 2), "corrupt JPEG (Premature end of JPEG file)");
  auto garbled = jpeg;
  for (std::size_t k = 0; k < 2000; ++k) garbled[garbled.size() / 2 + k] = static_cast<uint8_t>((k * 37 + 11) & 0xFF);
  EXPECT_NE(EncodedImageProblem(garbled.data(), garbled.size()).find("corrupt JPEG ("), std::string::npos)
      << EncodedImageProblem(garbled.data(), garbled.size());
  EXPECT_NE(EncodedImageProblem(jpeg.data(), 300).find("corrupt JPEG"), std::string::npos);  // header only
  EXPECT_EQ(EncodedImageProblem(jpeg.data(), 0), "empty file");
  const auto png = Bytes(data + "graf1.png");
  EXPECT_EQ(EncodedImageProblem(png.data(), png.size() - 20), "truncated PNG (no IEND chunk at its end)");
  EXPECT_EQ(ImageFileProblem("/nonexistent.jpg"), "missing or unreadable");
}

}  // namespace
}  // namespace uav
