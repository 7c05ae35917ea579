#include "common/identity/guid_binding.h"

#include <gtest/gtest.h>

#include <random>

namespace mostar::identity {
namespace {

Sha256 RandomHash(std::mt19937* rng) {
  Sha256 hash;
  for (uint8_t& b : hash) b = static_cast<uint8_t>((*rng)());
  return hash;
}

GuidPrefix RandomPrefix(std::mt19937* rng) {
  GuidPrefix prefix;
  for (uint8_t& b : prefix) b = static_cast<uint8_t>((*rng)());
  return prefix;
}

// The bytes Fast DDS 2.9 PKIDH adjust_participant_key writes for a known hash.
TEST(GuidBindingTest, AdjustsThePrefixAsPkiDhDoes) {
  Sha256 hash{};
  hash[0] = 0xAB;
  hash[1] = 0xCD;
  hash[2] = 0xEF;
  hash[3] = 0x01;
  hash[4] = 0x23;
  hash[5] = 0x45;
  GuidPrefix candidate{};
  candidate.fill(0x77);
  const GuidPrefix adjusted = AdjustGuidPrefix(candidate, hash);
  EXPECT_EQ(adjusted[0], 0x80 | (0xAB >> 1));
  EXPECT_EQ(adjusted[1], static_cast<uint8_t>((0xAB << 7) | (0xCD >> 1)));
  EXPECT_EQ(adjusted[5], static_cast<uint8_t>((0x23 << 7) | (0x45 >> 1)));
  for (int i = 6; i < 12; ++i) EXPECT_EQ(adjusted[i], 0x77);
  EXPECT_TRUE(GuidPrefixDerivesFromSubject(adjusted, hash));
}

// Property: a derived prefix matches its hash whatever the other bits; changing any of the 47
// hash bits in the prefix, or clearing its leading bit, breaks the match.
TEST(GuidBindingTest, OnlyTheLeadingBitAndTheFortySevenHashBitsMatter) {
  std::mt19937 rng(16);
  for (int trial = 0; trial < 200; ++trial) {
    const Sha256 hash = RandomHash(&rng);
    const GuidPrefix prefix = AdjustGuidPrefix(RandomPrefix(&rng), hash);
    ASSERT_TRUE(GuidPrefixDerivesFromSubject(prefix, hash));
    for (int bit = 0; bit < 96; ++bit) {
      GuidPrefix flipped = prefix;
      flipped[bit / 8] ^= static_cast<uint8_t>(0x80 >> (bit % 8));
      const bool significant = bit < 48;  // leading bit + 47 hash bits
      EXPECT_EQ(GuidPrefixDerivesFromSubject(flipped, hash), !significant) << "bit " << bit;
    }
    Sha256 other = hash;
    other[5] ^= 0x01;  // the 48th hash bit is not in the prefix
    EXPECT_TRUE(GuidPrefixDerivesFromSubject(prefix, other));
    other[rng() % 5] ^= static_cast<uint8_t>(1u << (rng() % 8));
    EXPECT_FALSE(GuidPrefixDerivesFromSubject(prefix, other));
  }
}

}  // namespace
}  // namespace mostar::identity
