#include "robot_server/camera/bitrate_controller.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "robot_server/camera/fake_stereo_camera.h"

namespace mostar::camera {
namespace {

constexpr double kFrameRateHz = 30;

// Size of one 640x480 stereo pair: roughly what a camera image gives, growing with quality
// and with the number of pixels.
size_t ModelPairBytes(const EncodeSettings& settings) {
  const double q = settings.jpeg.quality / 100.0;
  const double pixels = 2 * 640 * 480 * settings.jpeg.scale * settings.jpeg.scale;
  return static_cast<size_t>(pixels * (0.01 + 0.25 * q * q));
}

struct RunResult {
  BitrateStats stats;
  double tail_offered_bits_per_s = 0;  // mean over the last 5 s
};

// Runs `seconds` of 30 Hz capture through the controller. `link_bits_per_s` > 0 simulates an
// ack-clocked link of that capacity (a pair is skipped while the previous one is in flight).
template <typename SizeFn>
RunResult Simulate(BitrateController* controller, double seconds, SizeFn size_of,
                   double link_bits_per_s = 0, double rtt_s = 0.005) {
  SteadyTime now(std::chrono::seconds(100));
  SteadyTime link_free = now;
  const Duration period = FromSeconds(1.0 / kFrameRateHz);
  const int frames = static_cast<int>(seconds * kFrameRateHz);
  const int tail_start = frames - static_cast<int>(5 * kFrameRateHz);
  double tail_bytes = 0;
  for (int k = 0; k < frames; ++k, now += period) {
    const EncodeSettings settings = controller->Current();
    if (k % settings.frame_rate_divisor != 0) continue;
    const size_t bytes = size_of(settings);
    bool sent = true;
    if (link_bits_per_s > 0) {
      sent = now >= link_free;
      if (sent) link_free = now + FromSeconds(8.0 * bytes / link_bits_per_s + rtt_s);
    }
    controller->OnPairEncoded(now, bytes, sent);
    if (k >= tail_start) tail_bytes += static_cast<double>(bytes);
  }
  return {controller->Stats(), 8.0 * tail_bytes / 5.0};
}

TEST(BitrateControllerTest, UnlimitedTargetClimbsToMaximumQuality) {
  BitrateControllerOptions options;
  options.initial_quality = 50;
  BitrateController controller(options);
  const RunResult result = Simulate(&controller, 5, ModelPairBytes);
  EXPECT_EQ(result.stats.quality, options.max_quality);
  EXPECT_EQ(result.stats.scale, 1.0);
  EXPECT_EQ(result.stats.frame_rate_divisor, 1);
  EXPECT_NEAR(result.stats.pair_rate_hz, 30, 0.5);
}

TEST(BitrateControllerTest, ConvergesToAWanTargetByQualityAlone) {
  BitrateControllerOptions options;
  options.target_bits_per_s = 8e6;
  BitrateController controller(options);
  const RunResult result = Simulate(&controller, 20, ModelPairBytes);
  EXPECT_LE(result.tail_offered_bits_per_s, 8e6 * 1.02);
  EXPECT_GE(result.tail_offered_bits_per_s, 8e6 * 0.75);
  EXPECT_EQ(result.stats.scale, 1.0);
  EXPECT_EQ(result.stats.frame_rate_divisor, 1);
  EXPECT_GT(result.stats.quality, options.min_quality);
  EXPECT_LT(result.stats.quality, options.max_quality);
}

TEST(BitrateControllerTest, HeavyLimitsLowerResolutionAndThenFrameRate) {
  BitrateControllerOptions options;
  options.target_bits_per_s = 1e6;
  BitrateController controller(options);
  const RunResult result = Simulate(&controller, 30, ModelPairBytes);
  EXPECT_LE(result.tail_offered_bits_per_s, 1e6 * 1.05);
  EXPECT_GE(result.tail_offered_bits_per_s, 1e6 * 0.5);
  EXPECT_LT(result.stats.scale, 1.0);
  EXPECT_GT(result.stats.frame_rate_divisor, 1);
}

TEST(BitrateControllerTest, RecoversFullQualityWhenTheTargetIsLifted) {
  BitrateControllerOptions options;
  options.target_bits_per_s = 1e6;
  BitrateController controller(options);
  Simulate(&controller, 30, ModelPairBytes);
  ASSERT_GT(controller.Stats().level, 0);
  controller.SetTargetBitsPerSecond(0);
  const RunResult result = Simulate(&controller, 30, ModelPairBytes);
  EXPECT_EQ(result.stats.level, 0);
  EXPECT_EQ(result.stats.quality, options.max_quality);
}

TEST(BitrateControllerTest, AckClockSkipsBringTheStreamUnderTheLinkRate) {
  BitrateControllerOptions options;  // LAN class: no configured limit
  BitrateController controller(options);
  const double link = 10e6;
  const RunResult result = Simulate(&controller, 30, ModelPairBytes, link);
  EXPECT_GT(result.stats.link_bits_per_s, 0);
  EXPECT_LE(result.tail_offered_bits_per_s, link * 1.1);
  EXPECT_GE(result.stats.achieved_bits_per_s, link * 0.4);
  EXPECT_LT(result.stats.skipped_fraction, 0.3);
  EXPECT_LT(result.stats.quality, options.max_quality);
}

// The same with real JPEG sizes: synthetic camera-like images (320x240, to keep the test
// short) encoded at the controller's settings.
TEST(BitrateControllerTest, ConvergesOnRealJpegSizes) {
  constexpr double kTarget = 1.5e6;
  BitrateControllerOptions options;
  options.target_bits_per_s = kTarget;
  BitrateController controller(options);
  JpegCompressor compressor;
  std::vector<StereoImagePair> frames;
  for (uint64_t i = 0; i < 8; ++i) {
    StereoImagePair pair;
    pair.left = MakeSyntheticImage(320, 240, i * 5, false);
    pair.right = MakeSyntheticImage(320, 240, i * 5, true);
    frames.push_back(pair);
  }
  size_t index = 0;
  const auto jpeg_bytes = [&](const EncodeSettings& settings) {
    CompressedStereoPair out;
    std::string error;
    EXPECT_TRUE(compressor.Compress(frames[index++ % frames.size()], settings.jpeg, &out, &error))
        << error;
    return out.left.data.size() + out.right.data.size();
  };
  const RunResult result = Simulate(&controller, 15, jpeg_bytes);
  EXPECT_LE(result.tail_offered_bits_per_s, kTarget * 1.05);
  EXPECT_GE(result.tail_offered_bits_per_s, kTarget * 0.6);
}

// A WAN link whose capacity steps from 8 to 2 and back to 8 Mbit/s (a cellular hand-over),
// 50 ms one-way, behind the robot's ack-clock (RobotNode): at most kLanes pairs unacknowledged,
// a pair is skipped at the source when every lane waits for its acknowledgement. Pairs queue
// at the bottleneck; ages are capture to fully delivered for the pairs that were sent. Each
// phase lasts 15 s.
struct StepPhase {
  double link_bits_per_s;
  double achieved_after_2s_bits_per_s = 0;  // sent bits from 2 s after the step to its end
  double age_p95_after_2s_s = 0;            // of the pairs sent from 2 s after the step on
  double age_max_s = 0;                     // of every pair sent in the phase
};

void SimulateLinkSteps(BitrateController* controller, std::vector<StepPhase>* phases) {
  constexpr double kOneWayS = 0.05, kPhaseS = 15;
  constexpr size_t kLanes = 4;  // RobotVideoOptions::window_pairs
  SteadyTime now(std::chrono::seconds(100));
  SteadyTime link_busy_until = now;
  std::vector<SteadyTime> lane_free(kLanes, now);  // when each lane's pair is acknowledged
  const Duration period = FromSeconds(1.0 / kFrameRateHz);
  int k = 0;
  for (StepPhase& phase : *phases) {
    std::vector<double> settled_ages;
    double settled_bits = 0;
    const int frames = static_cast<int>(kPhaseS * kFrameRateHz);
    for (int i = 0; i < frames; ++i, ++k, now += period) {
      const EncodeSettings settings = controller->Current();
      if (k % settings.frame_rate_divisor != 0) continue;
      const size_t bytes = ModelPairBytes(settings);
      const auto lane =
          std::find_if(lane_free.begin(), lane_free.end(), [&](SteadyTime t) { return t <= now; });
      const bool sent = lane != lane_free.end();
      if (sent) {
        const double transmit_s = 8.0 * static_cast<double>(bytes) / phase.link_bits_per_s;
        link_busy_until = std::max(link_busy_until, now) + FromSeconds(transmit_s);
        *lane = link_busy_until + FromSeconds(2 * kOneWayS);  // the acknowledgement comes back
        const double age_s = ToSeconds(link_busy_until - now) + kOneWayS;
        phase.age_max_s = std::max(phase.age_max_s, age_s);
        if (i >= 2 * kFrameRateHz) {
          settled_ages.push_back(age_s);
          settled_bits += 8.0 * static_cast<double>(bytes);
        }
      }
      controller->OnPairEncoded(now, bytes, sent);
    }
    std::sort(settled_ages.begin(), settled_ages.end());
    if (!settled_ages.empty()) {
      phase.age_p95_after_2s_s = settled_ages[settled_ages.size() * 95 / 100];
    }
    phase.achieved_after_2s_bits_per_s = settled_bits / (kPhaseS - 2);
  }
}

TEST(BitrateControllerTest, FollowsALinkStepFrom8To2To8MbitWithin2s) {
  BitrateControllerOptions options;
  options.target_bits_per_s = 8e6;  // the WAN class
  BitrateController controller(options);
  std::vector<StepPhase> phases = {{8e6}, {2e6}, {8e6}};
  SimulateLinkSteps(&controller, &phases);
  for (const StepPhase& p : phases) {
    std::printf(
        "link %.0f Mbit/s: achieved %.2f Mbit/s from 2 s on, age p95 %.0f ms, max %.0f ms\n",
        p.link_bits_per_s / 1e6, p.achieved_after_2s_bits_per_s / 1e6, p.age_p95_after_2s_s * 1e3,
        p.age_max_s * 1e3);
  }
  for (const StepPhase& p : phases) {
    // Within 2 s of a step the age is back near the one-way delay, and it never explodes on
    // the way (the ack-clock keeps at most four pairs queued).
    EXPECT_LE(p.age_p95_after_2s_s, 0.05 + 0.1) << p.link_bits_per_s;
    EXPECT_LE(p.age_max_s, 0.5) << p.link_bits_per_s;
    EXPECT_LE(p.achieved_after_2s_bits_per_s, p.link_bits_per_s);
    EXPECT_GE(p.achieved_after_2s_bits_per_s, 0.5 * p.link_bits_per_s) << p.link_bits_per_s;
  }
  // The slow phase uses the 2 Mbit/s it has (not the 500 kbit/s floor), and the last phase
  // gets back most of what the first had.
  EXPECT_GE(phases[2].achieved_after_2s_bits_per_s, 0.8 * phases[0].achieved_after_2s_bits_per_s);
}

TEST(BitrateControllerTest, OptionsValidationNamesTheProblem) {
  std::string error;
  BitrateControllerOptions options;
  EXPECT_TRUE(options.IsValid(&error));
  options.scales = {0.5, 1.0};
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("scales"), std::string::npos);
  options = {};
  options.min_quality = 95;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("quality"), std::string::npos);
}

TEST(DefaultScaleLadderTest, EndsAtAbout320PixelsWideWhateverTheCamera) {
  EXPECT_EQ(DefaultScaleLadder(640), (std::vector<double>{1.0, 0.75, 0.5}));
  EXPECT_EQ(DefaultScaleLadder(1280), (std::vector<double>{1.0, 0.75, 0.5, 0.375, 0.25}));
  EXPECT_EQ(DefaultScaleLadder(320), (std::vector<double>{1.0}));
  EXPECT_EQ(DefaultScaleLadder(100), (std::vector<double>{1.0}));
  EXPECT_EQ(DefaultScaleLadder(960), (std::vector<double>{1.0, 0.75, 0.5, 0.375}));  // to 360 px
  for (int width : {320, 640, 800, 1024, 1280, 1600, 2048}) {
    BitrateControllerOptions options;
    options.scales = DefaultScaleLadder(width);
    std::string error;
    EXPECT_TRUE(options.IsValid(&error)) << width << ": " << error;
    EXPECT_GE(options.scales.back() * width, 320) << width;
  }
}

TEST(BitrateControllerTest, ANative1280x960CameraEndsItsLadderWhereA640x480OneDoes) {
  // The same scene at both sizes: bytes grow with the pixels sent.
  const auto bytes_for_width = [](int width) {
    return [width](const EncodeSettings& settings) {
      EncodeSettings at_640 = settings;
      at_640.jpeg.scale = settings.jpeg.scale * width / 640.0;
      return ModelPairBytes(at_640);
    };
  };
  BitrateStats end[2];
  const int widths[2] = {640, 1280};
  for (int i = 0; i < 2; ++i) {
    BitrateControllerOptions options;
    options.target_bits_per_s = 1e6;
    options.scales = DefaultScaleLadder(widths[i]);
    BitrateController controller(options);
    const RunResult result = Simulate(&controller, 40, bytes_for_width(widths[i]));
    EXPECT_LE(result.tail_offered_bits_per_s, 1e6 * 1.05) << widths[i];
    end[i] = result.stats;
  }
  EXPECT_DOUBLE_EQ(end[0].scale * 640, 320);
  EXPECT_DOUBLE_EQ(end[1].scale * 1280, 320);
  EXPECT_EQ(end[0].frame_rate_divisor, end[1].frame_rate_divisor);
}

}  // namespace
}  // namespace mostar::camera
