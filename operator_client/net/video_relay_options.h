// Where a console takes its camera streams when the pilot watches through mostar_relay
// (operator_client --video-via-relay): a second participant with the same identity and profiles
// file, participant profile "operator_video", on the relay's observer domain (default: the
// robot's domain + 1). Pure: no participant is made here.
#pragma once

#include <string>

#include "common/dds/participant.h"

namespace mostar::client {

inline constexpr char kVideoParticipantProfile[] = "operator_video";

// The video participant's options from the console's own `main` ones; `video_domain` < 0 means
// main's domain + 1. False with `error` set when the domain equals main's or is above 232.
bool VideoThroughRelayOptions(const dds::ParticipantOptions& main, int video_domain,
                              dds::ParticipantOptions* video, std::string* error);

}  // namespace mostar::client
