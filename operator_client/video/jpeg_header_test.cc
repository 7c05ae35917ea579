#include "operator_client/video/jpeg_header.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "operator_client/video/test_jpeg.h"

namespace mostar::client {
namespace {

TEST(JpegHeaderTest, ReadsTheDeclaredSizeWithoutDecoding) {
  const std::vector<uint8_t> jpeg = testing::EncodeJpeg(64, 48, 100);
  JpegHeader header;
  std::string error;
  ASSERT_TRUE(ReadJpegHeader(jpeg.data(), jpeg.size(), &header, &error)) << error;
  EXPECT_EQ(header.width_px, 64);
  EXPECT_EQ(header.height_px, 48);
  EXPECT_EQ(header.components, 3);
  // A few hundred bytes that declare 8000 x 8000 pixels: the header says so, nothing decoded.
  const std::vector<uint8_t> bomb = testing::WithDeclaredSize(jpeg, 8000, 8000);
  ASSERT_TRUE(ReadJpegHeader(bomb.data(), bomb.size(), &header, &error)) << error;
  EXPECT_EQ(header.width_px, 8000);
  EXPECT_EQ(header.height_px, 8000);
  EXPECT_LT(bomb.size(), 2000u);
}

TEST(JpegHeaderTest, RefusesWhatIsNotAJpegHeader) {
  const std::vector<uint8_t> jpeg = testing::EncodeJpeg(64, 48, 100);
  JpegHeader header;
  std::string error;
  EXPECT_FALSE(ReadJpegHeader(nullptr, 0, &header, &error));
  const std::vector<uint8_t> text = {'h', 'e', 'l', 'l', 'o'};
  EXPECT_FALSE(ReadJpegHeader(text.data(), text.size(), &header, &error));
  EXPECT_FALSE(error.empty());
  for (const size_t cut : {size_t{1}, size_t{2}, size_t{20}, size_t{100}}) {
    error.clear();
    EXPECT_FALSE(ReadJpegHeader(jpeg.data(), cut, &header, &error)) << "cut at " << cut;
    EXPECT_FALSE(error.empty());
  }
}

TEST(JpegHeaderTest, FitsTheExpectedSizeOrSmallerOnly) {
  std::string why;
  EXPECT_TRUE(FitsExpectedSize({640, 480, 3}, 640, 480, &why));
  EXPECT_TRUE(FitsExpectedSize({320, 240, 3}, 640, 480, &why)) << "scaled down by the robot";
  EXPECT_FALSE(FitsExpectedSize({641, 480, 3}, 640, 480, &why));
  EXPECT_NE(why.find("641x480"), std::string::npos) << why;
  EXPECT_FALSE(FitsExpectedSize({640, 481, 3}, 640, 480, &why));
  EXPECT_FALSE(FitsExpectedSize({0, 480, 3}, 640, 480, &why));
}

}  // namespace
}  // namespace mostar::client
