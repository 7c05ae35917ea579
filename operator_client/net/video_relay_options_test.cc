#include "operator_client/net/video_relay_options.h"

#include <gtest/gtest.h>

namespace mostar::client {
namespace {

dds::ParticipantOptions Main(int domain) {
  dds::ParticipantOptions options;
  options.domain_id = domain;
  options.profile = "/etc/mostar/pki/alice.xml";
  options.name = "operator";
  return options;
}

TEST(VideoThroughRelayOptionsTest, DefaultsToTheNextDomainWithTheVideoProfile) {
  dds::ParticipantOptions video;
  std::string error;
  ASSERT_TRUE(VideoThroughRelayOptions(Main(0), -1, &video, &error)) << error;
  EXPECT_EQ(video.domain_id, 1);
  EXPECT_EQ(video.xml_participant_profile, "operator_video");
  EXPECT_EQ(video.profile, "/etc/mostar/pki/alice.xml");  // same identity and file
  EXPECT_EQ(video.name, "operator");
  ASSERT_TRUE(VideoThroughRelayOptions(Main(0), 7, &video, &error)) << error;
  EXPECT_EQ(video.domain_id, 7);
}

TEST(VideoThroughRelayOptionsTest, RefusesTheRobotsDomainAndDomainsAbove232) {
  dds::ParticipantOptions video;
  std::string error;
  EXPECT_FALSE(VideoThroughRelayOptions(Main(3), 3, &video, &error));
  EXPECT_NE(error.find("must differ"), std::string::npos) << error;
  EXPECT_FALSE(VideoThroughRelayOptions(Main(232), -1, &video, &error));
  EXPECT_NE(error.find("--video-domain"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::client
