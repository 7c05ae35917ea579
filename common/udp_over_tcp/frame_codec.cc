#include "common/udp_over_tcp/frame_codec.h"

#include <algorithm>
#include <utility>

namespace mostar::udp_over_tcp {

bool AppendFrame(const uint8_t* datagram, size_t size, std::vector<uint8_t>* out) {
  if (size == 0 || size > kMaxDatagramBytes) return false;
  out->push_back(static_cast<uint8_t>(size >> 8));
  out->push_back(static_cast<uint8_t>(size & 0xff));
  out->insert(out->end(), datagram, datagram + size);
  return true;
}

FrameDecoder::FrameDecoder(size_t max_datagram_bytes)
    : max_datagram_bytes_(std::clamp<size_t>(max_datagram_bytes, 1, kMaxDatagramBytes)) {}

bool FrameDecoder::Fail(std::string message, std::string* error) {
  failed_ = true;
  partial_.clear();
  if (error != nullptr) *error = std::move(message);
  return false;
}

bool FrameDecoder::Feed(const uint8_t* data, size_t size, const DatagramFn& on_datagram,
                        std::string* error) {
  if (failed_) return Fail("stream already failed", error);
  size_t pos = 0;
  while (!preamble_seen_ && pos < size) {
    if (data[pos] != kPreamble[preamble_bytes_]) {
      return Fail("bad preamble (not a mostar_wg_tcp peer)", error);
    }
    ++pos;
    preamble_seen_ = ++preamble_bytes_ == kPreamble.size();
  }
  while (pos < size) {
    // Complete the length prefix, then the datagram, in partial_.
    const size_t have = partial_.size();
    if (have < kLengthBytes) {
      const size_t take = std::min(kLengthBytes - have, size - pos);
      partial_.insert(partial_.end(), data + pos, data + pos + take);
      pos += take;
      if (partial_.size() < kLengthBytes) break;
    }
    const size_t length = (size_t{partial_[0]} << 8) | partial_[1];
    if (length == 0) return Fail("frame of length 0", error);
    if (length > max_datagram_bytes_) {
      return Fail("frame of " + std::to_string(length) + " bytes exceeds the limit of " +
                      std::to_string(max_datagram_bytes_),
                  error);
    }
    const size_t missing = kLengthBytes + length - partial_.size();
    if (partial_.size() == kLengthBytes && size - pos >= length) {
      on_datagram(data + pos, length);  // whole datagram in this read: no copy
      pos += length;
      partial_.clear();
      continue;
    }
    const size_t take = std::min(missing, size - pos);
    partial_.insert(partial_.end(), data + pos, data + pos + take);
    pos += take;
    if (take < missing) break;
    on_datagram(partial_.data() + kLengthBytes, length);
    partial_.clear();
  }
  return true;
}

}  // namespace mostar::udp_over_tcp
