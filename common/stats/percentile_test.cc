#include "common/stats/percentile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace mostar {
namespace {

TEST(PercentileTest, EmptyHasNone) { EXPECT_FALSE(Percentile({}, 0.5).has_value()); }

TEST(PercentileTest, NearestRankOfTenSamples) {
  const std::vector<double> v = {10, 1, 9, 2, 8, 3, 7, 4, 6, 5};
  EXPECT_EQ(Percentile(v, 0.0), 1);
  EXPECT_EQ(Percentile(v, 0.1), 1);
  EXPECT_EQ(Percentile(v, 0.5), 5);
  EXPECT_EQ(Percentile(v, 0.51), 6);
  EXPECT_EQ(Percentile(v, 0.95), 10);
  EXPECT_EQ(Percentile(v, 1.0), 10);
}

TEST(PercentileTest, OutOfRangeFractionsAreClamped) {
  EXPECT_EQ(Percentile({3, 1, 2}, -1), 1);
  EXPECT_EQ(Percentile({3, 1, 2}, 7), 3);
}

// Property: at least `fraction` of the samples are <= the result, and fewer are < it.
TEST(PercentileTest, DefinitionHoldsOnRandomSamples) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> value(-50, 50);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> v(1 + random() % 40);
    for (double& x : v) x = std::round(value(random));  // ties on purpose
    const double fraction = (random() % 101) / 100.0;
    const double p = *Percentile(v, fraction);
    const double n = static_cast<double>(v.size());
    const double at_most =
        static_cast<double>(std::count_if(v.begin(), v.end(), [p](double x) { return x <= p; }));
    const double below =
        static_cast<double>(std::count_if(v.begin(), v.end(), [p](double x) { return x < p; }));
    EXPECT_GE(at_most, fraction * n - 1e-9) << "trial " << trial;
    EXPECT_LT(below, std::max(1.0, std::ceil(fraction * n))) << "trial " << trial;
    EXPECT_NE(std::find(v.begin(), v.end(), p), v.end());
  }
}

}  // namespace
}  // namespace mostar
