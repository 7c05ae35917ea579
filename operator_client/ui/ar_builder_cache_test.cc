#include "operator_client/ui/ar_builder_cache.h"

#include <gtest/gtest.h>

#include "operator_client/fusion/test_scenes.h"

namespace mostar::ui {
namespace {

// A live slopeTh edit changes the potential outliers handed to edge processing, not only the
// drawn discontinuities: both come from the cache's builder.
TEST(ArBuilderCacheTest, OutlierLabelsFollowTheLiveSlopeThreshold) {
  fusion::testing::Scene wall;
  wall.segments.push_back({3.0, -6.0, 3.0, 6.0});
  LaserScan scan = fusion::testing::MakeScan(wall, 181);
  scan.ranges_m[90] *= 0.93f;  // one point 7 % nearer than the wall
  fusion::ArFeatureOptions options;
  ArBuilderCache cache(options);
  std::string error;
  options.segmentation.slope_threshold = 0.005f;
  EXPECT_TRUE(PotentialOutliers(cache.For(options, &error), scan)[90]);
  options.segmentation.slope_threshold = 2.0f;
  const std::vector<bool> relaxed = PotentialOutliers(cache.For(options, &error), scan);
  ASSERT_EQ(relaxed.size(), scan.ranges_m.size());
  EXPECT_FALSE(relaxed[90]);
  EXPECT_TRUE(error.empty()) << error;
}

TEST(ArBuilderCacheTest, BuildsOncePerChangeOfOptions) {
  fusion::ArFeatureOptions options;
  ArBuilderCache cache(options);
  std::string error;
  const fusion::ArFeatureBuilder* first = &cache.For(options, &error);
  for (int frame = 0; frame < 10; ++frame) EXPECT_EQ(&cache.For(options, &error), first);
  EXPECT_EQ(cache.builds(), 1);
  EXPECT_TRUE(error.empty());
  // An edit in the calibration panel takes effect at the next frame.
  options.segmentation.slope_threshold = 0.2f;
  EXPECT_EQ(cache.For(options, &error).options().segmentation.slope_threshold, 0.2f);
  EXPECT_EQ(cache.For(options, &error).options().segmentation.slope_threshold, 0.2f);
  EXPECT_EQ(cache.builds(), 2);
  options.circles_enabled = false;
  EXPECT_FALSE(cache.For(options, &error).options().circles_enabled);
  EXPECT_EQ(cache.builds(), 3);
}

TEST(ArBuilderCacheTest, InvalidOptionsFallBackToTheConfiguredBuilder) {
  fusion::ArFeatureOptions configured;
  configured.min_distance_m = 0.7f;
  ArBuilderCache cache(configured);
  fusion::ArFeatureOptions bad = configured;
  bad.max_distance_m = 0.1f;  // below min_distance_m
  std::string error;
  EXPECT_EQ(&cache.For(bad, &error), &cache.configured());
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_EQ(&cache.For(bad, &error), &cache.configured());
  EXPECT_FALSE(error.empty()) << "reported while the options stay invalid";
  error.clear();
  EXPECT_EQ(cache.For(configured, &error).options().min_distance_m, 0.7f);
  EXPECT_TRUE(error.empty());
}

TEST(ArBuilderCacheTest, EveryFieldCountsAsAChange) {
  const fusion::ArFeatureOptions base;
  EXPECT_TRUE(SameArOptions(base, base));
  std::vector<fusion::ArFeatureOptions> changed(24, base);
  int i = 0;
  changed[i++].min_distance_m += 0.1f;
  changed[i++].max_distance_m += 0.1f;
  changed[i++].laser_height_m += 0.1f;
  changed[i++].segmentation.slope_threshold += 0.1f;
  changed[i++].segmentation.max_outlier_run_points += 1;
  changed[i++].walls_enabled ^= true;
  changed[i++].wall_height_m += 0.1f;
  changed[i++].wall_bottom_alpha -= 0.1f;
  changed[i++].wall_top_alpha -= 0.1f;
  changed[i++].vertical_lines_enabled ^= true;
  changed[i++].line_alpha -= 0.1f;
  changed[i++].point_alpha -= 0.1f;
  changed[i++].rays_enabled ^= true;
  changed[i++].ray_beam_interval += 1;
  changed[i++].ray_alpha -= 0.1f;
  changed[i++].circles_enabled ^= true;
  changed[i++].circle_spacing_m += 0.1f;
  changed[i++].circle_max_radius_m += 0.1f;
  changed[i++].circle_half_angle_rad -= 0.1f;
  changed[i++].circle_segments_per_turn += 1;
  changed[i++].circle_color.g += 0.1f;
  changed[i++].labels_enabled ^= true;
  changed[i++].label_count += 1;
  changed[i++].label_height_m += 0.1f;
  for (size_t k = 0; k < changed.size(); ++k) {
    EXPECT_FALSE(SameArOptions(base, changed[k])) << "field " << k;
  }
}

TEST(OverlayArOptionsTest, TakesLaserHeightAndShowsRaysAndLinesWhileCalibrating) {
  fusion::ArFeatureOptions ar;
  ar.rays_enabled = false;
  ar.vertical_lines_enabled = false;
  fusion::ArFeatureOptions o = OverlayArOptions(ar, 0.55, /*calibrating=*/false);
  EXPECT_FLOAT_EQ(o.laser_height_m, 0.55f);
  EXPECT_FALSE(o.rays_enabled);
  EXPECT_FALSE(o.vertical_lines_enabled);
  o = OverlayArOptions(ar, 0.55, /*calibrating=*/true);
  EXPECT_TRUE(o.rays_enabled);
  EXPECT_TRUE(o.vertical_lines_enabled);
}

}  // namespace
}  // namespace mostar::ui
