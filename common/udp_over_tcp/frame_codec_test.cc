#include "common/udp_over_tcp/frame_codec.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "common/udp_over_tcp/frame_queue.h"

namespace mostar::udp_over_tcp {
namespace {

using Datagram = std::vector<uint8_t>;

Datagram Bytes(size_t size, uint8_t seed) {
  Datagram d(size);
  for (size_t i = 0; i < size; ++i) d[i] = static_cast<uint8_t>(seed + i * 7);
  return d;
}

std::vector<uint8_t> Stream(const std::vector<Datagram>& datagrams) {
  std::vector<uint8_t> out(kPreamble.begin(), kPreamble.end());
  for (const auto& d : datagrams) EXPECT_TRUE(AppendFrame(d.data(), d.size(), &out));
  return out;
}

// Feeds `stream` in chunks of the given sizes (cycled); returns the datagrams decoded.
std::vector<Datagram> Decode(FrameDecoder& decoder, const std::vector<uint8_t>& stream,
                             const std::vector<size_t>& chunks, std::string* error) {
  std::vector<Datagram> out;
  size_t pos = 0, k = 0;
  while (pos < stream.size()) {
    const size_t n = std::min(chunks[k++ % chunks.size()], stream.size() - pos);
    if (!decoder.Feed(
            stream.data() + pos, n, [&](const uint8_t* d, size_t s) { out.emplace_back(d, d + s); },
            error)) {
      break;
    }
    pos += n;
  }
  return out;
}

TEST(FrameDecoderTest, SplitsMergedFramesOfOneRead) {
  const std::vector<Datagram> sent = {Bytes(1, 1), Bytes(1400, 2), Bytes(300, 3)};
  FrameDecoder decoder(4096);
  std::string error;
  EXPECT_EQ(Decode(decoder, Stream(sent), {100000}, &error), sent);
  EXPECT_TRUE(error.empty());
  EXPECT_EQ(decoder.buffered_bytes(), 0u);
}

TEST(FrameDecoderTest, JoinsFramesSplitAcrossReadsAtEveryChunking) {
  const std::vector<Datagram> sent = {Bytes(5, 1), Bytes(1452, 2), Bytes(2, 3), Bytes(700, 4)};
  const auto stream = Stream(sent);
  for (size_t chunk = 1; chunk <= 40; ++chunk) {
    FrameDecoder decoder(4096);
    std::string error;
    EXPECT_EQ(Decode(decoder, stream, {chunk}, &error), sent) << "chunk " << chunk;
  }
  std::mt19937 random(7);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<size_t> chunks;
    for (int i = 0; i < 20; ++i) chunks.push_back(1 + random() % 2000);
    FrameDecoder decoder(4096);
    std::string error;
    EXPECT_EQ(Decode(decoder, stream, chunks, &error), sent) << "trial " << trial;
  }
}

TEST(FrameDecoderTest, OversizeLengthIsAnErrorAndTheDecoderStaysFailed) {
  const Datagram big = Bytes(3000, 1);
  FrameDecoder decoder(2048);
  std::string error;
  EXPECT_TRUE(Decode(decoder, Stream({big}), {100000}, &error).empty());
  EXPECT_THAT(error, testing::HasSubstr("3000 bytes exceeds the limit of 2048"));
  EXPECT_TRUE(decoder.failed());
  const auto more = Stream({Bytes(10, 2)});
  EXPECT_FALSE(decoder.Feed(
      more.data() + 4, more.size() - 4, [](const uint8_t*, size_t) {}, &error));
}

TEST(FrameDecoderTest, ZeroLengthIsAnError) {
  std::vector<uint8_t> stream(kPreamble.begin(), kPreamble.end());
  stream.push_back(0);
  stream.push_back(0);
  FrameDecoder decoder(2048);
  std::string error;
  EXPECT_TRUE(Decode(decoder, stream, {1}, &error).empty());
  EXPECT_THAT(error, testing::HasSubstr("length 0"));
}

TEST(FrameDecoderTest, GarbageInsteadOfThePreambleIsAnError) {
  const std::string http = "GET / HTTP/1.1\r\n\r\n";
  FrameDecoder decoder(2048);
  std::string error;
  int delivered = 0;
  EXPECT_FALSE(decoder.Feed(
      reinterpret_cast<const uint8_t*>(http.data()), http.size(),
      [&](const uint8_t*, size_t) { ++delivered; }, &error));
  EXPECT_THAT(error, testing::HasSubstr("bad preamble"));
  EXPECT_EQ(delivered, 0);
  EXPECT_FALSE(decoder.preamble_seen());
}

TEST(FrameDecoderTest, BuffersAtMostOneFrame) {
  FrameDecoder decoder(1000);
  auto stream = Stream({Bytes(1000, 1)});
  stream.pop_back();
  std::string error;
  EXPECT_TRUE(Decode(decoder, stream, {1}, &error).empty());
  EXPECT_EQ(decoder.buffered_bytes(), kLengthBytes + 999);
}

TEST(AppendFrameTest, RefusesEmptyAndOversizeDatagrams) {
  std::vector<uint8_t> out;
  const Datagram big(kMaxDatagramBytes + 1);
  EXPECT_FALSE(AppendFrame(big.data(), 0, &out));
  EXPECT_FALSE(AppendFrame(big.data(), big.size(), &out));
  EXPECT_TRUE(out.empty());
  EXPECT_TRUE(AppendFrame(big.data(), kMaxDatagramBytes, &out));
  EXPECT_EQ(out.size(), kMaxDatagramBytes + kLengthBytes);
  EXPECT_EQ(out[0], 0xff);
  EXPECT_EQ(out[1], 0xff);
}

// Everything the queue hands out, decoded.
std::vector<Datagram> Drain(FrameQueue& queue, size_t write_size) {
  std::vector<uint8_t> stream(kPreamble.begin(), kPreamble.end());
  while (!queue.empty()) {
    const size_t n = std::min(write_size, queue.front_size());
    stream.insert(stream.end(), queue.front_data(), queue.front_data() + n);
    queue.Consume(n);
  }
  FrameDecoder decoder(kMaxDatagramBytes);
  std::string error;
  auto out = Decode(decoder, stream, {100000}, &error);
  EXPECT_TRUE(error.empty()) << error;
  return out;
}

TEST(FrameQueueTest, KeepsOrderWithinCapacity) {
  FrameQueue queue(10000);
  const std::vector<Datagram> sent = {Bytes(100, 1), Bytes(200, 2), Bytes(300, 3)};
  for (const auto& d : sent) EXPECT_EQ(queue.Push(d.data(), d.size()), 0u);
  EXPECT_EQ(queue.bytes(), 606u);
  EXPECT_EQ(Drain(queue, 7), sent);
  EXPECT_EQ(queue.dropped(), 0u);
}

TEST(FrameQueueTest, FullQueueDropsTheOldestAndCountsThem) {
  FrameQueue queue(1000);  // four 200-byte datagrams (202 framed) fit, not five
  std::vector<Datagram> sent;
  for (uint8_t i = 0; i < 10; ++i) sent.push_back(Bytes(200, i));
  size_t dropped = 0;
  for (const auto& d : sent) dropped += queue.Push(d.data(), d.size());
  EXPECT_EQ(dropped, 6u);
  EXPECT_EQ(queue.dropped(), 6u);
  EXPECT_LE(queue.bytes(), 1000u);
  EXPECT_EQ(Drain(queue, 50), std::vector<Datagram>(sent.begin() + 6, sent.end()));
}

TEST(FrameQueueTest, NeverDropsAFrameAlreadyBegun) {
  FrameQueue queue(1000);
  const Datagram first = Bytes(400, 1), second = Bytes(400, 2), third = Bytes(400, 3);
  queue.Push(first.data(), first.size());
  queue.Push(second.data(), second.size());
  // Half of the first frame is on the wire: the stream needs its rest.
  std::vector<uint8_t> stream(kPreamble.begin(), kPreamble.end());
  stream.insert(stream.end(), queue.front_data(), queue.front_data() + 100);
  queue.Consume(100);
  EXPECT_EQ(queue.Push(third.data(), third.size()), 1u);  // the second one goes
  while (!queue.empty()) {
    stream.insert(stream.end(), queue.front_data(), queue.front_data() + queue.front_size());
    queue.Consume(queue.front_size());
  }
  FrameDecoder decoder(4096);
  std::string error;
  EXPECT_EQ(Decode(decoder, stream, {64}, &error), (std::vector<Datagram>{first, third}));
}

TEST(FrameQueueTest, ADatagramLargerThanTheQueueIsDropped) {
  FrameQueue queue(500);
  const Datagram kept = Bytes(100, 1), big = Bytes(600, 2);
  queue.Push(kept.data(), kept.size());
  EXPECT_EQ(queue.Push(big.data(), big.size()), 1u);
  EXPECT_EQ(queue.dropped(), 1u);
  EXPECT_EQ(Drain(queue, 1000), std::vector<Datagram>{kept});
}

TEST(FrameQueueTest, ClearStartsEmpty) {
  FrameQueue queue(500);
  const Datagram d = Bytes(100, 1);
  queue.Push(d.data(), d.size());
  queue.Consume(10);
  queue.Clear();
  EXPECT_TRUE(queue.empty());
  EXPECT_EQ(queue.bytes(), 0u);
  EXPECT_EQ(queue.front_size(), 0u);
}

}  // namespace
}  // namespace mostar::udp_over_tcp
