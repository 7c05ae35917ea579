// The DDS writer a sample or an event came from, without Fast DDS types: the GUID prefix of its
// participant (which Participant::AnnouncedClientId maps to a client id) and its entity id.
#pragma once

#include <array>
#include <cstdint>

#include "common/identity/guid_binding.h"

namespace mostar::dds {

struct WriterId {
  identity::GuidPrefix participant{};
  std::array<uint8_t, 4> entity{};

  bool operator<(const WriterId& o) const {
    return participant != o.participant ? participant < o.participant : entity < o.entity;
  }
  bool operator==(const WriterId& o) const {
    return participant == o.participant && entity == o.entity;
  }
  bool operator!=(const WriterId& o) const { return !(*this == o); }
};

}  // namespace mostar::dds
