// The native resolution path at 640x480 and 1280x960 (the thesis' 1.3 MP cameras), on the
// simulator's rendered stereo pair: the robot's JPEG pair encode (both eyes in parallel, q80),
// the client's decode of one eye at full size and DCT-scaled (1/2, 1/4), and the edge
// processing of one pair (both eyes in parallel, NESC, classification) at full size and on the
// half-size decode with the intrinsics scaled to it. Goals at 1280x960: pair encode <= 4 ms,
// decode for display <= 3 ms per eye, vision <= 3 ms per pair. Wall times (both stages use
// two threads). Run from the repository root or with MOSTAR_SOURCE_DIR set.
#include <benchmark/benchmark.h>

#include <map>
#include <stdexcept>

#include "common/jpeg/jpeg_decoder.h"
#include "operator_client/ui/decode_scaling.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/camera/jpeg_compressor.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar {
namespace {

constexpr int kQuality = 80;

// A simulated pair, its JPEGs and the matching scan and camera models, for a width of 640 or
// 1280 (4:3; the focal length follows the width: the same lens).
struct Fixture {
  camera::StereoImagePair images;
  CompressedStereoPair jpeg;
  vision::VisionInput input;

  explicit Fixture(int width) {
    sim::proto::Scene scene;
    std::string error;
    if (!vision::LoadSimScene("open_room", &scene, &error)) throw std::runtime_error(error);
    sim::proto::SimConfig config;
    config.mutable_laser()->set_resolution(sim::proto::LaserConfig::RES_1_DEG);
    config.mutable_camera()->set_width_px(width);
    config.mutable_camera()->set_height_px(width * 3 / 4);
    config.mutable_camera()->set_focal_px(440.0 * width / 640);
    auto world = sim::SimWorld::Create(scene, config, Time(), &error);
    if (world == nullptr) throw std::runtime_error(error);
    const double laser_height_m = world->laser_params().height_m;
    input.left_camera = vision::SimCameraModel(world->calibration(), Eye::kLeft, laser_height_m);
    input.right_camera = vision::SimCameraModel(world->calibration(), Eye::kRight, laser_height_m);
    input.scan = world->ScanAt(Time());
    const sim::StereoImages rendered = world->StereoAt(Time(), false);
    images.left = rendered.left;
    images.right = rendered.right;
    input.left = rendered.left;
    input.right = rendered.right;
    camera::JpegCompressor compressor(false);
    if (!compressor.Compress(images, {kQuality, 1.0}, &jpeg, &error)) {
      throw std::runtime_error(error);
    }
  }
};

const Fixture& GetFixture(int width) {
  static std::map<int, Fixture> fixtures;
  auto it = fixtures.find(width);
  if (it == fixtures.end()) it = fixtures.emplace(width, Fixture(width)).first;
  return it->second;
}

// Arg: width.
void BM_JpegPairEncode(benchmark::State& state) {
  const Fixture& f = GetFixture(static_cast<int>(state.range(0)));
  camera::JpegCompressor compressor(true);
  CompressedStereoPair out;
  std::string error;
  for (auto _ : state) {
    if (!compressor.Compress(f.images, {kQuality, 1.0}, &out, &error)) {
      state.SkipWithError(error.c_str());
    }
    benchmark::DoNotOptimize(out.left.data.data());
  }
  state.counters["pair_kB"] =
      static_cast<double>(out.left.data.size() + out.right.data.size()) / 1e3;
}
BENCHMARK(BM_JpegPairEncode)->Arg(640)->Arg(1280)->Unit(benchmark::kMillisecond)->UseRealTime();

// Args: width, scale denominator.
void BM_DecodeOneEye(benchmark::State& state) {
  const Fixture& f = GetFixture(static_cast<int>(state.range(0)));
  const int denominator = static_cast<int>(state.range(1));
  JpegDecoder decoder;
  cv::Mat bgr;
  std::string error;
  const std::vector<uint8_t>& jpeg = f.jpeg.left.data;
  for (auto _ : state) {
    if (!decoder.Decode(jpeg.data(), jpeg.size(), denominator, &bgr, &error)) {
      state.SkipWithError(error.c_str());
    }
    benchmark::DoNotOptimize(bgr.data);
  }
  state.counters["out_width"] = bgr.cols;
}
BENCHMARK(BM_DecodeOneEye)
    ->Args({640, 1})
    ->Args({640, 2})
    ->Args({1280, 1})
    ->Args({1280, 2})
    ->Args({1280, 4})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Args: width, scale denominator of the decode the pipeline sees (the intrinsics scaled to it).
void BM_VisionPair(benchmark::State& state) {
  const Fixture& f = GetFixture(static_cast<int>(state.range(0)));
  const int denominator = static_cast<int>(state.range(1));
  vision::VisionInput input = f.input;
  if (denominator > 1) {
    JpegDecoder decoder;
    std::string error;
    if (!decoder.Decode(f.jpeg.left.data.data(), f.jpeg.left.data.size(), denominator, &input.left,
                        &error) ||
        !decoder.Decode(f.jpeg.right.data.data(), f.jpeg.right.data.size(), denominator,
                        &input.right, &error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    ui::ImageScale scale;
    scale.width_px = input.left.cols;
    scale.height_px = input.left.rows;
    for (auto* camera : {&input.left_camera, &input.right_camera}) {
      *camera = std::make_shared<const math::CameraModel>(
          ui::ScaledCalibration((*camera)->calibration(), scale), (*camera)->eye());
    }
  }
  vision::VisionPipeline pipeline{vision::VisionOptions{}};
  vision::VisionResult result;
  for (auto _ : state) {
    pipeline.Process(input, &result);
    benchmark::DoNotOptimize(result.classification.corrected);
  }
  if (!result.ok) state.SkipWithError(result.error.c_str());
  state.counters["neps"] = result.nesc.matched + result.nesc.one_eye + result.nesc.disagree;
  state.counters["matched"] = result.nesc.matched;
}
BENCHMARK(BM_VisionPair)
    ->Args({640, 1})
    ->Args({1280, 1})
    ->Args({1280, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace mostar
