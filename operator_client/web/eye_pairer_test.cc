#include "operator_client/web/eye_pairer.h"

#include <gtest/gtest.h>

namespace mostar::web {
namespace {

CompressedImage Image(int64_t stamp_ms, uint8_t tag) {
  CompressedImage image;
  image.stamp = FromUnixNanos(stamp_ms * 1000000);
  image.data = {tag};
  return image;
}

TEST(EyePairerTest, PairsEyesWithTheSameStampInEitherOrder) {
  EyePairer pairer;
  EXPECT_FALSE(pairer.Push(Eye::kLeft, Image(100, 1)));
  auto pair = pairer.Push(Eye::kRight, Image(100, 2));
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->left.data[0], 1);
  EXPECT_EQ(pair->right.data[0], 2);
  EXPECT_EQ(pair->sequence, 1u);
  EXPECT_FALSE(pairer.Push(Eye::kRight, Image(200, 4)));
  pair = pairer.Push(Eye::kLeft, Image(200, 3));
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->left.data[0], 3);
  EXPECT_EQ(pair->right.data[0], 4);
  EXPECT_EQ(pair->sequence, 2u);
}

TEST(EyePairerTest, DifferentStampsNeverPair) {
  EyePairer pairer;
  EXPECT_FALSE(pairer.Push(Eye::kLeft, Image(100, 1)));
  EXPECT_FALSE(pairer.Push(Eye::kRight, Image(101, 2)));
  EXPECT_EQ(pairer.stats().pairs, 0u);
}

TEST(EyePairerTest, AnImageWhosePartnerNeverComesIsCountedAndForgotten) {
  EyePairer pairer;
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(pairer.Push(Eye::kLeft, Image(100 + i, 0)));
  EXPECT_EQ(pairer.stats().unpaired, 10u - EyePairer::kMaxPending);
  // The oldest are gone, the newest still pair.
  EXPECT_FALSE(pairer.Push(Eye::kRight, Image(100, 0)));
  EXPECT_TRUE(pairer.Push(Eye::kRight, Image(109, 0)));
}

TEST(EyePairerTest, APairCompletedAfterANewerOneIsLate) {
  EyePairer pairer;
  EXPECT_FALSE(pairer.Push(Eye::kLeft, Image(100, 0)));
  EXPECT_FALSE(pairer.Push(Eye::kLeft, Image(200, 0)));
  EXPECT_TRUE(pairer.Push(Eye::kRight, Image(200, 0)));
  EXPECT_FALSE(pairer.Push(Eye::kRight, Image(100, 0)));
  EXPECT_EQ(pairer.stats().late, 1u);
  EXPECT_EQ(pairer.stats().pairs, 1u);
}

}  // namespace
}  // namespace mostar::web
