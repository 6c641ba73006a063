// File transfer (issue 7 item 5) through a lossy relay of our own: each message may be dropped,
// duplicated or delayed (so reordered); the file must arrive identical every time, resume after
// a link cut, and never accept a damaged chunk.
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <variant>

#include <gtest/gtest.h>

#include "uav/shared/file_transfer.hpp"
#include "uav/shared/sha256.hpp"
#include "unit/lossy_link.hpp"

namespace uav {
namespace {

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(Sha256::HexOf("", 0), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256::HexOf("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  EXPECT_EQ(Sha256::HexOf(two_blocks.data(), two_blocks.size()),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  const std::string million(1000000, 'a');
  Sha256 h;
  for (size_t i = 0; i < million.size(); i += 999) h.Update(million.data() + i, std::min<size_t>(999, million.size() - i));
  EXPECT_EQ(Sha256::Hex(h.Final()), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");  // streamed
  EXPECT_EQ(Crc32("123456789", 9), 0xCBF43926u);
}

std::string RandomFile(size_t size, uint32_t seed) {
  std::mt19937 rng(seed);
  std::string s(size, '\0');
  for (char& c : s) c = static_cast<char>(rng());
  return s;
}

struct TransferResult {
  bool complete = false;
  double seconds = 0;
  int rejected = 0;
};

// Sender on the vehicle, receiver on the GCS, both polled every 20 ms. `cut` drops everything
// between the two times (a link loss).
TransferResult Transfer(const std::string& file, double loss, double duplicate, uint32_t seed, double cut_from = -1,
             double cut_to = -1, bool corrupt_some = false) {
  FileSender sender;
  FileReceiver receiver;
  LossyLink<FileOffer> offers(loss, duplicate, 0.05, seed);
  LossyLink<FileChunk> chunks(loss, duplicate, 0.05, seed + 1);
  LossyLink<FileRequest> requests(loss, duplicate, 0.05, seed + 2);
  const FileOffer offer = sender.Offer("map_1.tif", file);
  std::mt19937 rng(seed + 3);
  TransferResult run;
  bool started = false;
  for (double t = 0; t < 120; t += 0.02) {
    const bool cut = t >= cut_from && t < cut_to;
    offers.Cut(cut);
    chunks.Cut(cut);
    requests.Cut(cut);
    const FileSender::Output out = sender.Poll(t);
    for (const auto& o : out.offers) offers.Send(o, t);
    for (auto c : out.chunks) {
      if (corrupt_some && !c.data.empty() && rng() % 50 == 0) c.data[rng() % c.data.size()] ^= 0x10;  // a flipped bit
      chunks.Send(c, t);
    }
    offers.Deliver(t, [&](const FileOffer& o) {
      std::string error;
      EXPECT_TRUE(receiver.OnOffer(o, &error)) << error;
      if (!started) started = receiver.Start(o.transfer_id, &error);
    });
    chunks.Deliver(t, [&](const FileChunk& c) { receiver.OnChunk(c); });
    for (const auto& r : receiver.Poll(t)) requests.Send(r, t);
    requests.Deliver(t, [&](const FileRequest& r) { sender.OnRequest(r); });
    if (sender.Delivered(offer.transfer_id)) {
      run.seconds = t;
      break;
    }
  }
  const std::string* got = receiver.Contents(offer.transfer_id);
  run.complete = got && *got == file && sender.Delivered(offer.transfer_id);
  run.rejected = receiver.rejected();
  return run;
}

struct LinkCase {
  double loss, duplicate;
};
class FileTransferThroughRelay : public ::testing::TestWithParam<LinkCase> {};

TEST_P(FileTransferThroughRelay, ArrivesIdentical) {
  const LinkCase c = GetParam();
  for (uint32_t seed : {1u, 2u, 3u, 4u, 5u}) {
    const std::string file = RandomFile(1'500'000 + seed * 777, seed);  // a map: ~1.5 MB, 367 chunks
    const TransferResult run = Transfer(file, c.loss, c.duplicate, seed * 10);
    EXPECT_TRUE(run.complete) << "seed " << seed;
    std::printf("[ transfer ] loss %.0f %%, duplicates %.0f %%, seed %u: %.2f s\n", 100 * c.loss, 100 * c.duplicate, seed,
                run.seconds);
  }
}
INSTANTIATE_TEST_SUITE_P(Links, FileTransferThroughRelay,
                         ::testing::Values(LinkCase{0, 0}, LinkCase{0.01, 0.01}, LinkCase{0.05, 0.05}),
                         [](const auto& info) { return "loss" + std::to_string(static_cast<int>(info.param.loss * 100)); });

TEST(FileTransfer, ResumesAfterALinkCut) {
  const std::string file = RandomFile(2'000'000, 9);
  const TransferResult run = Transfer(file, 0.01, 0.01, 90, 0.3, 6.3);  // cut mid-transfer for 6 s
  EXPECT_TRUE(run.complete);
  EXPECT_GT(run.seconds, 6.3);
}

// The vehicle process restarted mid-download: the new process offers the same file (the same
// SHA-256, so the same transfer id), and the GCS asks only for the chunks it still misses.
TEST(FileTransfer, ResumesWhenARestartedVehicleOffersTheSameFileAgain) {
  const std::string file = RandomFile(1'000'000, 21);
  FileReceiver receiver;
  std::string error;
  auto first = std::make_unique<FileSender>();
  const FileOffer offer = first->Offer("map_1.tif", file);
  ASSERT_TRUE(receiver.OnOffer(offer, &error) && receiver.Start(offer.transfer_id, &error)) << error;
  double t = 0;
  auto step = [&](FileSender& sender, int* chunks_sent) {
    for (const auto& r : receiver.Poll(t)) sender.OnRequest(r);
    for (const auto& c : sender.Poll(t).chunks) {
      receiver.OnChunk(c);
      if (chunks_sent) ++*chunks_sent;
    }
    t += 0.02;
  };
  while (receiver.progress(offer.transfer_id)->received < offer.chunks / 2) step(*first, nullptr);
  const int had = receiver.progress(offer.transfer_id)->received;
  first.reset();  // the vehicle process dies
  for (int i = 0; i < 100; ++i, t += 0.02) receiver.Poll(t);  // nobody answers for 2 s
  FileSender restarted;
  const FileOffer again = restarted.Offer("map_1.tif", file);
  ASSERT_EQ(again.transfer_id, offer.transfer_id);
  ASSERT_TRUE(receiver.OnOffer(again, &error)) << error;
  int resent = 0;
  while (!restarted.Delivered(offer.transfer_id) && t < 60) step(restarted, &resent);
  ASSERT_NE(receiver.Contents(offer.transfer_id), nullptr);
  EXPECT_EQ(*receiver.Contents(offer.transfer_id), file);
  EXPECT_LE(resent, offer.chunks - had + 8) << "the restarted vehicle sent chunks the GCS already had";
  std::printf("[ restart ] %d of %d chunks before the restart, %d sent after it\n", had, offer.chunks, resent);
}

TEST(FileTransfer, DamagedChunksAreRejectedAndFetchedAgain) {
  const std::string file = RandomFile(800'000, 11);
  const TransferResult run = Transfer(file, 0.0, 0.0, 110, -1, -1, /*corrupt_some=*/true);
  EXPECT_TRUE(run.complete);
  EXPECT_GT(run.rejected, 0);
}

TEST(FileTransfer, BadOffersAndChunksAreRefused) {
  FileSender sender;
  const FileOffer good = sender.Offer("map.png", RandomFile(10000, 1));
  FileReceiver receiver;
  std::string error;
  FileOffer bad = good;
  bad.name = "../etc/passwd";
  EXPECT_FALSE(receiver.OnOffer(bad, &error));
  EXPECT_NE(error.find("plain file name"), std::string::npos) << error;
  bad = good;
  bad.chunks += 1;
  EXPECT_FALSE(receiver.OnOffer(bad, &error));
  bad = good;
  bad.sha256 = "xyz";
  EXPECT_FALSE(receiver.OnOffer(bad, &error));
  EXPECT_FALSE(receiver.Start(good.transfer_id, &error));  // not offered yet
  ASSERT_TRUE(receiver.OnOffer(good, &error));
  ASSERT_TRUE(receiver.Start(good.transfer_id, &error));
  FileChunk c;
  c.transfer_id = good.transfer_id;
  c.index = good.chunks;  // beyond the file
  receiver.OnChunk(c);
  c.index = 0;
  c.data.assign(10, 0);  // wrong size for chunk 0
  c.crc32 = Crc32(c.data.data(), c.data.size());
  receiver.OnChunk(c);
  c.transfer_id = 42;  // unknown
  receiver.OnChunk(c);
  EXPECT_EQ(receiver.rejected(), 3);
  EXPECT_EQ(receiver.progress(good.transfer_id)->received, 0);
}

}  // namespace
}  // namespace uav
