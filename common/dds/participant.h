// RAII DDS participant for mostar (Fast DDS 2.9), with one publisher and one subscriber.
//
// Profiles (ParticipantOptions::profile):
//   "loopback" (default): all traffic stays on this machine: UDPv4 restricted to 127.0.0.1 by an
//       interface whitelist, unicast discovery to 127.0.0.1, and shared memory with a segment
//       sized for stereo frames. Used by the demo and the tests.
//   a path ending in ".xml": a Fast DDS XML profiles file; the participant profile named
//       `xml_participant_profile` (default: the role, "robot" or "operator") is used.
// The domain id comes from the options; see domain.h for the flag/environment convention.
// Teardown order is handled here: contained entities first, then the participant.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace mostar::dds {

struct ParticipantOptions {
  int domain_id = 0;                    // 0..232
  std::string profile = "loopback";     // "loopback" or a path to a Fast DDS XML profiles file
  std::string xml_participant_profile;  // profile name inside the XML file (default: name)
  std::string name = "mostar";          // participant name, e.g. "robot" or "operator"
  // Shared-memory segment size for the loopback profile; must hold a few JPEG frames.
  uint32_t shm_segment_bytes = 8u << 20;

  bool IsValid(std::string* error) const;
};

class Participant {
 public:
  // Creates the participant; returns null and sets `error` on failure.
  static std::unique_ptr<Participant> Create(const ParticipantOptions& options, std::string* error);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // Registers `type` (once per type name) and returns the topic `name` (created once).
  // Returns null and sets `error` on failure. Thread-safe.
  eprosima::fastdds::dds::Topic* GetTopic(const std::string& name,
                                          eprosima::fastdds::dds::TypeSupport type,
                                          std::string* error);

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  const ParticipantOptions& options() const { return options_; }

 private:
  explicit Participant(ParticipantOptions options) : options_(std::move(options)) {}

  ParticipantOptions options_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::mutex mutex_;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

}  // namespace mostar::dds
