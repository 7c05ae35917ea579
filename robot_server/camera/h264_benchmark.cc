// H.264 encode and decode time per eye (libx264 ultrafast + zerolatency through libavcodec;
// libavcodec's decoder, one thread) on camera-like frames: 60 frames of the shipped corridor
// scene rendered by the simulator before timing (the robot driving ahead and turning a little,
// with sensor noise), at 640x480 and the cameras' native 1280x960. Goal (issue: Internet video):
// encode <= 6 ms and decode <= 4 ms per eye at 640x480 on one core. Args: width, bitrate kbit/s,
// x264 threads. Counters: bytes per access unit, share of IDRs.
// Run with MOSTAR_SOURCE_DIR set to the repository root.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/h264/h264_decoder.h"
#include "common/h264/h264_encoder.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_world.h"

namespace mostar {
namespace {

constexpr int kFrames = 60;

std::string SourceDir() {
  const char* dir = std::getenv("MOSTAR_SOURCE_DIR");
  return dir ? dir : ".";
}

// The left eye of kFrames rendered pairs at `width_px` (4:3), 30 frames/s of driving.
const std::vector<cv::Mat>& Frames(int width_px) {
  static std::map<int, std::vector<cv::Mat>> cache;
  std::vector<cv::Mat>& frames = cache[width_px];
  if (!frames.empty()) return frames;
  sim::proto::Scene scene;
  sim::proto::SimConfig config;
  std::string error;
  if (!sim::LoadScene(SourceDir() + "/deploy/scenes/corridor.pbtxt", &scene, &error) ||
      !sim::LoadSimConfig(SourceDir() + "/deploy/config/sim_morduc.pbtxt", &config, &error)) {
    throw std::runtime_error(error + " (set MOSTAR_SOURCE_DIR to the repository root)");
  }
  sim::proto::CameraConfig* camera = config.mutable_camera();
  camera->set_focal_px(camera->focal_px() * width_px / camera->width_px());
  camera->set_height_px(camera->height_px() * width_px / camera->width_px());
  camera->set_width_px(width_px);
  sim::World world(scene);
  sim::StereoRenderer renderer(world, sim::CameraParams::FromProto(config.camera()),
                               config.laser().height_m());
  sim::StereoImages out;
  for (int i = 0; i < kFrames; ++i) {
    // 0.5 m/s ahead, 0.3 rad/s turning.
    renderer.Render(Pose2D{0.5 * i / 30.0, 0.0, 0.3 * i / 30.0}, static_cast<uint64_t>(i),
                    /*with_truth=*/false, &out);
    frames.push_back(out.left.clone());
  }
  return frames;
}

h264::EncoderSettings Settings(const benchmark::State& state) {
  h264::EncoderSettings s;
  s.width_px = static_cast<int>(state.range(0));
  s.height_px = s.width_px * 3 / 4;
  s.bitrate_bps = static_cast<int>(state.range(1)) * 1000;
  s.threads = static_cast<int>(state.range(2));
  return s;
}

void BM_H264EncodeOneEye(benchmark::State& state) {
  const std::vector<cv::Mat>& frames = Frames(static_cast<int>(state.range(0)));
  std::string error;
  auto encoder = h264::Encoder::Create(Settings(state), &error);
  if (!encoder) {
    state.SkipWithError(error.c_str());
    return;
  }
  h264::EncodedFrame au;
  size_t bytes = 0;
  int idrs = 0;
  size_t i = 0;
  for (auto _ : state) {
    if (!encoder->Encode(frames[i++ % frames.size()], &au, &error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    bytes += au.data.size();
    idrs += au.idr ? 1 : 0;
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["bytes_per_au"] = static_cast<double>(bytes) / n;
  state.counters["idr_share"] = idrs / n;
}

void BM_H264DecodeOneEye(benchmark::State& state) {
  const std::vector<cv::Mat>& frames = Frames(static_cast<int>(state.range(0)));
  std::string error;
  auto encoder = h264::Encoder::Create(Settings(state), &error);
  auto decoder = h264::Decoder::Create(&error);
  if (!encoder || !decoder) {
    state.SkipWithError(error.c_str());
    return;
  }
  // One stream of the frames, encoded before timing; decoded in a loop (an IDR restarts it).
  std::vector<std::vector<uint8_t>> stream;
  for (size_t i = 0; i < frames.size(); ++i) {
    h264::EncodedFrame au;
    if (i == 0) encoder->ForceIdr();
    if (!encoder->Encode(frames[i], &au, &error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    stream.push_back(au.data);
  }
  cv::Mat picture;
  uint64_t sequence = 0;
  for (auto _ : state) {
    const std::vector<uint8_t>& au = stream[sequence % stream.size()];
    if (decoder->Decode(au.data(), au.size(), sequence++, &picture, &error) !=
        h264::DecodeStatus::kPicture) {
      state.SkipWithError(error.c_str());
      return;
    }
  }
}

void Args(benchmark::internal::Benchmark* b) {
  b->Args({640, 2000, 1})->Args({640, 2000, 2})->Args({1280, 4000, 1})->Args({1280, 4000, 2});
  b->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_H264EncodeOneEye)->Apply(Args);
BENCHMARK(BM_H264DecodeOneEye)
    ->Args({640, 2000, 1})
    ->Args({1280, 4000, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mostar
