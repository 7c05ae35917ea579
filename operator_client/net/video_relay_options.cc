#include "operator_client/net/video_relay_options.h"

namespace mostar::client {

bool VideoThroughRelayOptions(const dds::ParticipantOptions& main, int video_domain,
                              dds::ParticipantOptions* video, std::string* error) {
  const int domain = video_domain >= 0 ? video_domain : main.domain_id + 1;
  if (domain == main.domain_id || domain > 232) {
    *error = "the video domain " + std::to_string(domain) +
             " must differ from the robot's domain " + std::to_string(main.domain_id) +
             " and be at most 232 (set --video-domain to the relay's observer domain)";
    return false;
  }
  *video = main;
  video->domain_id = domain;
  video->xml_participant_profile = kVideoParticipantProfile;
  return true;
}

}  // namespace mostar::client
