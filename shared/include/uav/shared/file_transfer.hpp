#pragma once
// File transfer over a lossy datagram bus (issue 7 item 5): the vehicle offers a file, the GCS
// asks for the chunks it is missing, the vehicle sends them. Chunks are small (4 kB, well under
// one datagram: LCM 1.3.1 corrupts or drops large fragmented messages), carry their index and a
// CRC-32, and may arrive lost, duplicated or out of order; the receiver re-requests what is
// missing after a timeout, resumes after a link cut from where it was, and accepts the file only
// when its SHA-256 matches the offer. Plain classes on plain structs: the link workers turn them
// into LCM messages (file_offer_t, file_request_t, file_chunk_t).
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace uav {

struct FileOffer {
  int64_t transfer_id = 0;  // the first 8 bytes of the SHA-256: stable across restarts
  std::string name;         // file name only, no directories
  int64_t size = 0;         // [bytes]
  int32_t chunk_bytes = 0;
  int32_t chunks = 0;
  std::string sha256;       // lowercase hex
};

struct FileRange {
  int32_t first = 0;
  int32_t count = 0;
};

struct FileRequest {
  int64_t transfer_id = 0;
  std::vector<FileRange> ranges;  // chunks wanted
  bool complete = false;          // received and verified: stop offering
};

struct FileChunk {
  int64_t transfer_id = 0;
  int32_t index = 0;
  std::vector<uint8_t> data;
  uint32_t crc32 = 0;  // of data
};

// Throws std::invalid_argument naming what is inconsistent (name with a path, sizes, hash).
void ValidateOffer(const FileOffer& offer);

class FileSender {
 public:
  struct Params {
    int chunk_bytes = 4096;
    double offer_period_s = 1.0;   // re-announce until the receiver reports completion
    int max_chunks_per_poll = 32;  // rate limit: 32 chunks per 20 ms tick = 6.5 MB/s
  };
  FileSender() : FileSender(Params()) {}
  explicit FileSender(const Params& params);

  // Offers `contents` as `name` (no directories); returns the offer.
  FileOffer Offer(const std::string& name, const std::string& contents);
  void OnRequest(const FileRequest& request);

  struct Output {
    std::vector<FileOffer> offers;
    std::vector<FileChunk> chunks;
  };
  Output Poll(double now_s);
  bool Delivered(int64_t transfer_id) const;

 private:
  struct Outgoing {
    FileOffer offer;
    std::string contents;
    std::set<int32_t> queued;
    double last_offer_s = -1e9;
    bool delivered = false;
  };
  Params params_;
  std::map<int64_t, Outgoing> files_;
};

class FileReceiver {
 public:
  struct Params {
    int window_chunks = 128;  // requested and not yet received, at most
    double retry_s = 0.5;     // a chunk requested this long ago and not received is asked again
    int max_attempts = 3;     // whole-file hash mismatches before giving up
  };
  FileReceiver() : FileReceiver(Params()) {}
  explicit FileReceiver(const Params& params);

  // Offers are remembered (the GCS lists them); an invalid one is refused with the reason.
  bool OnOffer(const FileOffer& offer, std::string* error);
  // Starts (or resumes) downloading an offered file.
  bool Start(int64_t transfer_id, std::string* error);
  // A damaged, unknown or out-of-range chunk is dropped (counted in rejected()).
  void OnChunk(const FileChunk& chunk);
  std::vector<FileRequest> Poll(double now_s);

  struct Progress {
    FileOffer offer;
    bool started = false;
    int received = 0;  // chunks
    bool complete = false;
    bool failed = false;
    std::string error;
  };
  std::optional<Progress> progress(int64_t transfer_id) const;
  std::vector<FileOffer> offers() const;
  // The verified contents of a completed transfer, else nullptr.
  const std::string* Contents(int64_t transfer_id) const;
  int rejected() const { return rejected_; }

 private:
  struct Incoming {
    FileOffer offer;
    bool started = false;
    std::string data;
    std::vector<uint8_t> have;
    std::vector<double> asked_s;  // when each chunk was last requested
    int received = 0;
    int attempts = 0;
    bool complete = false, failed = false;
    bool announce_complete = false;  // tell the sender on the next poll (and on each offer after)
    std::string error;
  };
  void Verify(Incoming& in);
  Params params_;
  std::map<int64_t, Incoming> files_;
  int rejected_ = 0;
};

}  // namespace uav
