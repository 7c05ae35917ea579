// H.264 decoding for the console, the relay's web bridge and replay: libavcodec's h264 decoder
// with one thread and no frame threading, so every access unit (AU) gives its picture at once.
//
// libavcodec does not report a lost AU (it conceals it by copying a reference, and the picture
// stays wrong until the next IDR), so the caller numbers the AUs of a stream and the decoder
// tracks them: after a gap in the numbers, an error, or a picture with errors, it shows nothing
// (kWaitingForIdr, NeedsIdr() true: ask the robot for an IDR) until an AU with an IDR and its
// SPS/PPS decodes cleanly. A stream is joined the same way: nothing until the first IDR. So a
// broken picture is never shown; the caller keeps the last good one, marked stale.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>

namespace mostar::h264 {

enum class DecodeStatus {
  kPicture,        // `image` holds the AU's picture
  kWaitingForIdr,  // nothing to show until an IDR (after a gap, an error, or at the start)
  kError,          // the AU could not be decoded, or its picture had errors: waiting for an IDR
};
const char* DecodeStatusName(DecodeStatus status);

enum class Pixels { kBgr, kGrey };  // CV_8UC3, or CV_8UC1 (the luma plane: no conversion)

struct DecoderCounters {
  uint64_t pictures = 0;         // kPicture
  uint64_t gaps = 0;             // jumps in the AU numbers (lost or reordered AUs)
  uint64_t errors = 0;           // kError
  uint64_t skipped_waiting = 0;  // AUs not decoded while waiting for an IDR
};

// Not thread-safe: one decoder per stream.
class Decoder {
 public:
  // Null with `error` when libavcodec has no H.264 decoder.
  static std::unique_ptr<Decoder> Create(std::string* error);
  ~Decoder();
  Decoder(const Decoder&) = delete;
  Decoder& operator=(const Decoder&) = delete;

  // The largest access unit accepted (a 1280x960 IDR at a high rate is well under 1 MiB).
  static constexpr size_t kMaxAccessUnitBytes = 16u << 20;

  // Decodes the AU numbered `sequence` (consecutive numbers for consecutive AUs of the stream).
  // An empty AU, or one over kMaxAccessUnitBytes, is an error like any undecodable one.
  DecodeStatus Decode(const uint8_t* data, size_t size, uint64_t sequence, cv::Mat* image,
                      std::string* error, Pixels pixels = Pixels::kBgr);
  // The last AU left the decoder waiting for an IDR: the sender should be asked for one.
  bool NeedsIdr() const { return waiting_; }
  // Shows nothing more until the next IDR (a stereo viewer whose other eye lost its picture
  // keeps both eyes on the same frames).
  void RequireIdr() { waiting_ = true; }
  const DecoderCounters& counters() const { return counters_; }

  struct Codec;  // libavcodec state (implementation detail)

 private:
  explicit Decoder(std::unique_ptr<Codec> codec);
  DecodeStatus Fail(const std::string& message, std::string* error);

  std::unique_ptr<Codec> codec_;
  bool waiting_ = true;
  bool have_sequence_ = false;
  uint64_t last_sequence_ = 0;
  DecoderCounters counters_;
};

}  // namespace mostar::h264
