#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/h264/annexb.h"
#include "common/h264/h264_decoder.h"
#include "common/h264/h264_encoder.h"

namespace mostar::h264 {
namespace {

// A camera-like frame: a textured background panning right by 2 px per frame, a box moving
// across it, and a little noise.
cv::Mat Frame(int index, int width = 320, int height = 240) {
  cv::Mat image(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    auto* row = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < width; ++x) {
      const int u = x + 2 * index;
      row[x] = cv::Vec3b(static_cast<uint8_t>(128 + 60 * std::sin(u * 0.05) * std::cos(y * 0.07)),
                         static_cast<uint8_t>((u / 16 + y / 16) % 2 ? 170 : 90),
                         static_cast<uint8_t>(y * 255 / height));
    }
  }
  cv::rectangle(image, cv::Rect(10 + 4 * index, height / 3, 40, 50), cv::Scalar(20, 220, 240),
                cv::FILLED);
  return image;
}

double MeanAbsDiff(const cv::Mat& a, const cv::Mat& b) {
  return cv::mean(cv::abs(a - b) + cv::abs(b - a))[0];
}

// An encoder of `settings` and a decoder, or a failed assertion.
struct Codecs {
  std::unique_ptr<Encoder> encoder;
  std::unique_ptr<Decoder> decoder;
};
Codecs MakeCodecs(const EncoderSettings& settings) {
  std::string error;
  Codecs c{Encoder::Create(settings, &error), nullptr};
  EXPECT_NE(c.encoder, nullptr) << error;
  c.decoder = Decoder::Create(&error);
  EXPECT_NE(c.decoder, nullptr) << error;
  return c;
}

EncoderSettings Small() {
  EncoderSettings s;
  s.width_px = 320;
  s.height_px = 240;
  s.bitrate_bps = 1'500'000;
  return s;
}

TEST(AnnexBTest, FindsNalTypesAfterThreeAndFourByteStartCodes) {
  const std::vector<uint8_t> au = {0, 0, 0, 1, 0x67, 1, 2, 0, 0, 1, 0x68, 3, 0, 0, 1, 0x65, 4, 5};
  EXPECT_EQ(NalTypes(au), (std::vector<uint8_t>{kNalSps, kNalPps, kNalIdr}));
  EXPECT_TRUE(IsSelfContainedIdr(au));
  const std::vector<uint8_t> p_frame = {0, 0, 0, 1, 0x41, 9, 9};
  EXPECT_EQ(NalTypes(p_frame), (std::vector<uint8_t>{kNalSlice}));
  EXPECT_FALSE(IsSelfContainedIdr(p_frame));
  EXPECT_TRUE(NalTypes(std::vector<uint8_t>{1, 2, 3}).empty());
  EXPECT_TRUE(NalTypes(std::vector<uint8_t>{}).empty());
}

TEST(EncoderSettingsTest, RefusesOddSizesAndOutOfRangeRates) {
  std::string error;
  EXPECT_TRUE(Small().IsValid(&error)) << error;
  EncoderSettings s = Small();
  s.width_px = 321;
  EXPECT_FALSE(s.IsValid(&error));
  EXPECT_NE(error.find("even"), std::string::npos);
  s = Small();
  s.bitrate_bps = 1000;
  EXPECT_FALSE(s.IsValid(&error));
  s = Small();
  s.vbv_frames = 0;
  EXPECT_FALSE(s.IsValid(&error));
  EXPECT_EQ(Encoder::Create(s, &error), nullptr);
}

// Every frame in gives its access unit at once (no lookahead, no B-frames); the first is a
// self-contained IDR and the rest are not; each decodes at once and looks like its source.
TEST(H264Test, EachFrameComesOutAtOnceAndDecodesCloseToItsSource) {
  std::string error;
  Codecs codecs = MakeCodecs(Small());
  ASSERT_TRUE(codecs.encoder && codecs.decoder);
  Encoder* encoder = codecs.encoder.get();
  Decoder* decoder = codecs.decoder.get();
  for (int i = 0; i < 30; ++i) {
    const cv::Mat source = Frame(i);
    EncodedFrame au;
    ASSERT_TRUE(encoder->Encode(source, &au, &error)) << error;
    EXPECT_EQ(au.frame_index, i);
    EXPECT_EQ(au.idr, i == 0) << i;
    if (i == 0) {
      const std::vector<uint8_t> types = NalTypes(au.data);
      EXPECT_EQ(types.front(), kNalSps);
    }
    cv::Mat picture;
    ASSERT_EQ(decoder->Decode(au.data.data(), au.data.size(), 100 + i, &picture, &error),
              DecodeStatus::kPicture)
        << i << ": " << error;
    ASSERT_EQ(picture.size(), source.size());
    // The first pictures are coarse (an IDR in a one-frame VBV buffer), then P frames refine.
    EXPECT_LT(MeanAbsDiff(picture, source), i < 10 ? 10.0 : 6.0) << i;
    EXPECT_GT(MeanAbsDiff(picture, Frame(i + 8)), 15.0) << i;  // the measure tells frames apart
  }
  EXPECT_EQ(decoder->counters().pictures, 30u);
  EXPECT_FALSE(decoder->NeedsIdr());
}

// A lost access unit is silent in libavcodec; the decoder sees the gap in the numbers, shows
// nothing and asks for an IDR until one arrives, then pictures are good again.
TEST(H264Test, AfterALostAccessUnitNothingIsShownUntilAnIdr) {
  std::string error;
  Codecs codecs = MakeCodecs(Small());
  ASSERT_TRUE(codecs.encoder && codecs.decoder);
  Encoder* encoder = codecs.encoder.get();
  Decoder* decoder = codecs.decoder.get();
  cv::Mat picture;
  for (int i = 0; i < 20; ++i) {
    if (i == 12) encoder->ForceIdr();  // the robot answers the request
    EncodedFrame au;
    ASSERT_TRUE(encoder->Encode(Frame(i), &au, &error)) << error;
    if (i == 5) continue;  // lost
    const DecodeStatus status =
        decoder->Decode(au.data.data(), au.data.size(), i, &picture, &error);
    if (i < 5 || i >= 12) {
      EXPECT_EQ(status, DecodeStatus::kPicture) << i << ": " << error;
      EXPECT_LT(MeanAbsDiff(picture, Frame(i)), 10.0) << i;
      EXPECT_FALSE(decoder->NeedsIdr()) << i;
    } else {
      EXPECT_EQ(status, DecodeStatus::kWaitingForIdr) << i;
      EXPECT_TRUE(decoder->NeedsIdr()) << i;
    }
    EXPECT_EQ(au.idr, i == 0 || i == 12) << i;
  }
  EXPECT_EQ(decoder->counters().gaps, 1u);
  EXPECT_EQ(decoder->counters().skipped_waiting, 6u);  // 6..11
}

// A reader that joins mid-stream shows nothing until the next IDR.
TEST(H264Test, AJoiningReaderWaitsForTheFirstIdr) {
  std::string error;
  Codecs codecs = MakeCodecs(Small());
  ASSERT_TRUE(codecs.encoder && codecs.decoder);
  Encoder* encoder = codecs.encoder.get();
  Decoder* decoder = codecs.decoder.get();
  EXPECT_TRUE(decoder->NeedsIdr());
  cv::Mat picture;
  for (int i = 0; i < 8; ++i) {
    if (i == 6) encoder->ForceIdr();
    EncodedFrame au;
    ASSERT_TRUE(encoder->Encode(Frame(i), &au, &error)) << error;
    if (i < 3) continue;  // before the reader joined
    const DecodeStatus status =
        decoder->Decode(au.data.data(), au.data.size(), i, &picture, &error, Pixels::kGrey);
    EXPECT_EQ(status, i < 6 ? DecodeStatus::kWaitingForIdr : DecodeStatus::kPicture) << i;
  }
  EXPECT_EQ(picture.type(), CV_8UC1);
  cv::Mat grey;
  cv::cvtColor(Frame(7), grey, cv::COLOR_BGR2GRAY);
  EXPECT_LT(MeanAbsDiff(picture, grey), 10.0);
}

// Damaged data is an error, never a picture; the decoder then waits for an IDR.
TEST(H264Test, DamagedAccessUnitsAreErrorsNotPictures) {
  std::string error;
  Codecs codecs = MakeCodecs(Small());
  ASSERT_TRUE(codecs.encoder && codecs.decoder);
  Encoder* encoder = codecs.encoder.get();
  Decoder* decoder = codecs.decoder.get();
  cv::Mat picture;
  EncodedFrame au;
  ASSERT_TRUE(encoder->Encode(Frame(0), &au, &error)) << error;
  ASSERT_EQ(decoder->Decode(au.data.data(), au.data.size(), 0, &picture, &error),
            DecodeStatus::kPicture);
  ASSERT_TRUE(encoder->Encode(Frame(1), &au, &error)) << error;
  std::vector<uint8_t> damaged = au.data;
  for (size_t i = 8; i < damaged.size(); i += 3) damaged[i] ^= 0x5a;
  const DecodeStatus status = decoder->Decode(damaged.data(), damaged.size(), 1, &picture, &error);
  EXPECT_NE(status, DecodeStatus::kPicture);
  EXPECT_TRUE(decoder->NeedsIdr());
  const std::vector<uint8_t> garbage(500, 0xff);
  EXPECT_NE(decoder->Decode(garbage.data(), garbage.size(), 2, &picture, &error),
            DecodeStatus::kPicture);
  // A truncated IDR: refused too.
  encoder->ForceIdr();
  ASSERT_TRUE(encoder->Encode(Frame(3), &au, &error)) << error;
  ASSERT_TRUE(au.idr);
  EXPECT_NE(decoder->Decode(au.data.data(), au.data.size() / 2, 3, &picture, &error),
            DecodeStatus::kPicture);
  encoder->ForceIdr();
  ASSERT_TRUE(encoder->Encode(Frame(4), &au, &error)) << error;
  EXPECT_EQ(decoder->Decode(au.data.data(), au.data.size(), 4, &picture, &error),
            DecodeStatus::kPicture)
      << error;
  // An empty access unit and an oversized one: errors with a reason; the stream recovers at the
  // next IDR (an empty packet must not end the decoder's stream).
  EXPECT_EQ(decoder->Decode(nullptr, 0, 5, &picture, &error), DecodeStatus::kError);
  EXPECT_NE(error.find("empty access unit"), std::string::npos) << error;
  const std::vector<uint8_t> huge(Decoder::kMaxAccessUnitBytes + 1, 0);
  EXPECT_EQ(decoder->Decode(huge.data(), huge.size(), 6, &picture, &error), DecodeStatus::kError);
  EXPECT_NE(error.find("at most"), std::string::npos) << error;
  encoder->ForceIdr();
  ASSERT_TRUE(encoder->Encode(Frame(7), &au, &error)) << error;
  EXPECT_EQ(decoder->Decode(au.data.data(), au.data.size(), 7, &picture, &error),
            DecodeStatus::kPicture)
      << error;
}

// The target bitrate follows SetBitrate while encoding (VBV reconfiguration).
TEST(H264Test, TheBitrateFollowsSetBitrate) {
  std::string error;
  EncoderSettings settings = Small();
  settings.bitrate_bps = 3'000'000;
  auto encoder = Encoder::Create(settings, &error);
  ASSERT_NE(encoder, nullptr) << error;
  const auto bytes_over = [&](int first, int count) {
    size_t total = 0;
    for (int i = first; i < first + count; ++i) {
      EncodedFrame au;
      EXPECT_TRUE(encoder->Encode(Frame(i), &au, &error)) << error;
      total += au.data.size();
    }
    return total;
  };
  bytes_over(0, 10);
  const size_t high = bytes_over(10, 30);
  encoder->SetBitrate(300'000);
  EXPECT_EQ(encoder->bitrate_bps(), 300'000);
  bytes_over(40, 10);
  const size_t low = bytes_over(50, 30);
  EXPECT_LT(low * 3, high) << "high " << high << " low " << low;
  // 300 kbit/s at 30 frames/s is 1250 bytes a frame; VBV keeps it near.
  EXPECT_LT(low / 30.0, 1250 * 1.5);
}

// With intra refresh the stream has one IDR, at the start, however long it runs.
TEST(H264Test, IntraRefreshHasNoPeriodicIdrs) {
  std::string error;
  EncoderSettings settings = Small();
  settings.intra_refresh = true;
  settings.keyint_frames = 15;
  auto encoder = Encoder::Create(settings, &error);
  ASSERT_NE(encoder, nullptr) << error;
  int idrs = 0;
  for (int i = 0; i < 60; ++i) {
    EncodedFrame au;
    ASSERT_TRUE(encoder->Encode(Frame(i), &au, &error)) << error;
    idrs += au.idr ? 1 : 0;
  }
  EXPECT_EQ(idrs, 1);
}

TEST(H264Test, WrongInputIsRefusedAndTheNextFrameIsAnIdr) {
  std::string error;
  auto encoder = Encoder::Create(Small(), &error);
  ASSERT_NE(encoder, nullptr) << error;
  EncodedFrame au;
  ASSERT_TRUE(encoder->Encode(Frame(0), &au, &error));
  ASSERT_TRUE(encoder->Encode(Frame(1), &au, &error));
  EXPECT_FALSE(encoder->Encode(Frame(2, 640, 480), &au, &error));
  EXPECT_NE(error.find("320x240"), std::string::npos) << error;
  EXPECT_FALSE(encoder->Encode(cv::Mat(240, 320, CV_16UC1, cv::Scalar(0)), &au, &error));
  ASSERT_TRUE(encoder->Encode(Frame(3), &au, &error)) << error;
  EXPECT_TRUE(au.idr);
}

}  // namespace
}  // namespace mostar::h264
