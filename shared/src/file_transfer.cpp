#include "uav/shared/file_transfer.hpp"

#include <algorithm>
#include <stdexcept>

#include "uav/shared/sha256.hpp"

namespace uav {

void ValidateOffer(const FileOffer& o) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument("file offer '" + o.name + "': " + what); };
  if (o.name.empty() || o.name.size() > 128 || o.name.find('/') != std::string::npos || o.name == "." || o.name == "..")
    fail("the name must be a plain file name of 1-128 characters");
  if (o.chunk_bytes < 64 || o.chunk_bytes > 8192) fail("chunk_bytes must be 64..8192");
  if (o.size < 0 || o.size > (int64_t(1) << 32)) fail("size must be 0..4 GiB");
  if (o.chunks != (o.size + o.chunk_bytes - 1) / o.chunk_bytes) fail("chunks does not match size / chunk_bytes");
  if (o.sha256.size() != 64 || o.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
    fail("sha256 must be 64 lowercase hex digits");
}

// ---- Sender ----------------------------------------------------------------------------------

FileSender::FileSender(const Params& params) : params_(params) {
  if (params.chunk_bytes < 64 || params.chunk_bytes > 8192) throw std::invalid_argument("chunk_bytes must be 64..8192");
  if (params.max_chunks_per_poll < 1) throw std::invalid_argument("max_chunks_per_poll must be at least 1");
}

FileOffer FileSender::Offer(const std::string& name, const std::string& contents) {
  FileOffer o;
  o.name = name;
  o.size = static_cast<int64_t>(contents.size());
  o.chunk_bytes = params_.chunk_bytes;
  o.chunks = static_cast<int32_t>((o.size + o.chunk_bytes - 1) / o.chunk_bytes);
  o.sha256 = Sha256::HexOf(contents.data(), contents.size());
  o.transfer_id = static_cast<int64_t>(std::stoull(o.sha256.substr(0, 15), nullptr, 16));
  ValidateOffer(o);
  Outgoing& out = files_[o.transfer_id];
  out.offer = o;
  out.contents = contents;
  out.delivered = false;
  out.last_offer_s = -1e9;
  return o;
}

void FileSender::OnRequest(const FileRequest& r) {
  auto it = files_.find(r.transfer_id);
  if (it == files_.end()) return;
  Outgoing& out = it->second;
  if (r.complete) {
    out.delivered = true;
    out.queued.clear();
    return;
  }
  for (const FileRange& range : r.ranges) {
    // In 64 bits: a range near INT32_MAX from a bad request must not wrap round.
    const int64_t first = std::max<int64_t>(0, range.first);
    const int64_t last = std::min<int64_t>(out.offer.chunks, int64_t{range.first} + std::max<int64_t>(0, range.count));
    for (int64_t i = first; i < last; ++i) out.queued.insert(static_cast<int32_t>(i));
  }
}

FileSender::Output FileSender::Poll(double now_s) {
  Output o;
  int budget = params_.max_chunks_per_poll;
  for (auto& [id, out] : files_) {
    if (out.delivered) continue;
    if (now_s - out.last_offer_s >= params_.offer_period_s) {
      o.offers.push_back(out.offer);
      out.last_offer_s = now_s;
    }
    while (budget > 0 && !out.queued.empty()) {
      const int32_t i = *out.queued.begin();
      out.queued.erase(out.queued.begin());
      FileChunk c;
      c.transfer_id = id;
      c.index = i;
      const size_t begin = static_cast<size_t>(i) * out.offer.chunk_bytes;
      const size_t end = std::min(out.contents.size(), begin + out.offer.chunk_bytes);
      c.data.assign(out.contents.begin() + begin, out.contents.begin() + end);
      c.crc32 = Crc32(c.data.data(), c.data.size());
      o.chunks.push_back(std::move(c));
      --budget;
    }
  }
  return o;
}

bool FileSender::Delivered(int64_t id) const {
  auto it = files_.find(id);
  return it != files_.end() && it->second.delivered;
}

// ---- Receiver --------------------------------------------------------------------------------

FileReceiver::FileReceiver(const Params& params) : params_(params) {
  if (params.window_chunks < 1) throw std::invalid_argument("window_chunks must be at least 1");
  if (!(params.retry_s > 0)) throw std::invalid_argument("retry_s must be positive");
}

bool FileReceiver::OnOffer(const FileOffer& offer, std::string* error) {
  try {
    ValidateOffer(offer);
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return false;
  }
  auto it = files_.find(offer.transfer_id);
  if (it != files_.end()) {
    // Already known: a repeated offer of a finished file means the sender missed our report.
    if (it->second.complete) it->second.announce_complete = true;
    return true;
  }
  Incoming& in = files_[offer.transfer_id];
  in.offer = offer;
  return true;
}

bool FileReceiver::Start(int64_t id, std::string* error) {
  auto it = files_.find(id);
  if (it == files_.end()) {
    if (error) *error = "no such file offered";
    return false;
  }
  Incoming& in = it->second;
  if (!in.started || in.failed) {
    in.started = true;
    in.failed = false;
    in.error.clear();
    in.attempts = 0;
    in.data.assign(static_cast<size_t>(in.offer.size), '\0');
    in.have.assign(in.offer.chunks, 0);
    in.asked_s.assign(in.offer.chunks, -1e9);
    in.received = 0;
  }
  if (in.offer.chunks == 0 && !in.complete) Verify(in);
  return true;
}

void FileReceiver::OnChunk(const FileChunk& c) {
  auto it = files_.find(c.transfer_id);
  if (it == files_.end() || !it->second.started || it->second.complete) {
    ++rejected_;
    return;
  }
  Incoming& in = it->second;
  const FileOffer& o = in.offer;
  if (c.index < 0 || c.index >= o.chunks) {
    ++rejected_;
    return;
  }
  const int64_t begin = static_cast<int64_t>(c.index) * o.chunk_bytes;
  const int64_t expected = std::min<int64_t>(o.chunk_bytes, o.size - begin);
  if (static_cast<int64_t>(c.data.size()) != expected || Crc32(c.data.data(), c.data.size()) != c.crc32) {
    ++rejected_;  // damaged: it will be asked for again
    return;
  }
  if (in.have[c.index]) return;  // a duplicate
  std::copy(c.data.begin(), c.data.end(), in.data.begin() + begin);
  in.have[c.index] = 1;
  ++in.received;
  if (in.received == o.chunks) Verify(in);
}

void FileReceiver::Verify(Incoming& in) {
  if (Sha256::HexOf(in.data.data(), in.data.size()) == in.offer.sha256) {
    in.complete = true;
    in.announce_complete = true;
    return;
  }
  // Every chunk passed its CRC yet the whole does not match: start over, a bounded number of times.
  ++in.attempts;
  if (in.attempts >= params_.max_attempts) {
    in.failed = true;
    in.error = "SHA-256 mismatch after " + std::to_string(in.attempts) + " attempts";
    return;
  }
  std::fill(in.have.begin(), in.have.end(), 0);
  std::fill(in.asked_s.begin(), in.asked_s.end(), -1e9);
  in.received = 0;
}

std::vector<FileRequest> FileReceiver::Poll(double now_s) {
  std::vector<FileRequest> out;
  for (auto& [id, in] : files_) {
    if (in.announce_complete) {
      FileRequest r;
      r.transfer_id = id;
      r.complete = true;
      out.push_back(r);
      in.announce_complete = false;
      continue;
    }
    if (!in.started || in.complete || in.failed) continue;
    int outstanding = 0;
    for (int32_t i = 0; i < in.offer.chunks; ++i)
      if (!in.have[i] && now_s - in.asked_s[i] < params_.retry_s) ++outstanding;
    FileRequest r;
    r.transfer_id = id;
    for (int32_t i = 0; i < in.offer.chunks && outstanding < params_.window_chunks; ++i) {
      if (in.have[i] || now_s - in.asked_s[i] < params_.retry_s) continue;
      in.asked_s[i] = now_s;
      ++outstanding;
      if (!r.ranges.empty() && r.ranges.back().first + r.ranges.back().count == i) ++r.ranges.back().count;
      else r.ranges.push_back({i, 1});
    }
    if (!r.ranges.empty()) out.push_back(r);
  }
  return out;
}

std::optional<FileReceiver::Progress> FileReceiver::progress(int64_t id) const {
  auto it = files_.find(id);
  if (it == files_.end()) return std::nullopt;
  const Incoming& in = it->second;
  Progress p;
  p.offer = in.offer;
  p.started = in.started;
  p.received = in.received;
  p.complete = in.complete;
  p.failed = in.failed;
  p.error = in.error;
  return p;
}

std::vector<FileOffer> FileReceiver::offers() const {
  std::vector<FileOffer> out;
  for (const auto& [id, in] : files_) out.push_back(in.offer);
  return out;
}

const std::string* FileReceiver::Contents(int64_t id) const {
  auto it = files_.find(id);
  return it != files_.end() && it->second.complete ? &it->second.data : nullptr;
}

}  // namespace uav
