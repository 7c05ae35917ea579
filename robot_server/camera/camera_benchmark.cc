// Compression speed of one 640x480 stereo pair (goal: <= 3 ms for both eyes), and the encoder
// choice: libjpeg-turbo's libjpeg API (JpegEncoder) against OpenCV's imencode on the same
// library.
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>

#include "common/jpeg/jpeg_decoder.h"
#include "robot_server/camera/fake_stereo_camera.h"
#include "robot_server/camera/jpeg_compressor.h"

namespace mostar::camera {
namespace {

StereoImagePair Pair() {
  StereoImagePair pair;
  pair.left = MakeSyntheticImage(640, 480, 3, false);
  pair.right = MakeSyntheticImage(640, 480, 3, true);
  return pair;
}

void BM_JpegEncoderOneEye(benchmark::State& state) {
  const cv::Mat image = MakeSyntheticImage(640, 480, 3, false);
  JpegEncoder encoder;
  std::vector<uint8_t> out;
  std::string error;
  for (auto _ : state) {
    if (!encoder.Encode(image, {static_cast<int>(state.range(0)), 1.0}, &out, &error)) {
      state.SkipWithError(error.c_str());
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["bytes"] = static_cast<double>(out.size());
}
BENCHMARK(BM_JpegEncoderOneEye)->Arg(80)->Unit(benchmark::kMillisecond);

void BM_OpenCvImencodeOneEye(benchmark::State& state) {
  const cv::Mat image = MakeSyntheticImage(640, 480, 3, false);
  std::vector<uint8_t> out;
  for (auto _ : state) {
    cv::imencode(".jpg", image, out, {cv::IMWRITE_JPEG_QUALITY, static_cast<int>(state.range(0))});
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["bytes"] = static_cast<double>(out.size());
}
BENCHMARK(BM_OpenCvImencodeOneEye)->Arg(80)->Unit(benchmark::kMillisecond);

// Both eyes: args are (parallel, quality, scale percent).
void BM_CompressStereoPair(benchmark::State& state) {
  const StereoImagePair pair = Pair();
  JpegCompressor compressor(state.range(0) != 0);
  CompressedStereoPair out;
  std::string error;
  const JpegSettings settings{static_cast<int>(state.range(1)), state.range(2) / 100.0};
  for (auto _ : state) {
    if (!compressor.Compress(pair, settings, &out, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(out.left.data.data());
  }
  state.counters["pair_bytes"] = static_cast<double>(out.left.data.size() + out.right.data.size());
}
BENCHMARK(BM_CompressStereoPair)
    ->Args({1, 80, 100})
    ->Args({0, 80, 100})
    ->Args({1, 50, 100})
    ->Args({1, 80, 50})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_DecodeOneEye(benchmark::State& state) {
  const cv::Mat image = MakeSyntheticImage(640, 480, 3, false);
  JpegEncoder encoder;
  JpegDecoder decoder;
  std::vector<uint8_t> jpeg;
  std::string error;
  encoder.Encode(image, {80, 1.0}, &jpeg, &error);
  cv::Mat decoded;
  for (auto _ : state) {
    if (!decoder.Decode(jpeg, &decoded, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(decoded.data);
  }
}
BENCHMARK(BM_DecodeOneEye)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mostar::camera
