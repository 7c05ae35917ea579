// Client ids: who an operator console is on the wire (`sender_id` of its messages, the lease
// holder, the key of the robot's role table). With DDS Security a console's client id is the
// common name (CN) of its certificate (certificate_subject.h); the robot drops samples whose
// `sender_id` is not the client id of the authenticated participant that wrote them.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace mostar::identity {

// Longest client id, in bytes; the bound of every id string in idl/mostar_msgs.idl.
inline constexpr size_t kMaxClientIdBytes = 64;

// A valid client id has 1 to kMaxClientIdBytes characters out of [A-Za-z0-9_.-] (the names
// deploy/security/make_pki.sh accepts). False with the reason in `why` (optional) otherwise.
bool IsValidClientId(std::string_view id, std::string* why = nullptr);

}  // namespace mostar::identity
