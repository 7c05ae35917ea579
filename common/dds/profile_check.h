// `--check-config` for a DDS profile: everything Participant::Create would need, checked
// without creating a participant, each problem with its fix (docs/packages.md).
#pragma once

#include <optional>
#include <string>

#include "common/config/config_report.h"
#include "common/dds/participant.h"

namespace mostar::dds {

struct ProfileCheck {
  // The client id (certificate CN) this participant will have with DDS Security.
  std::optional<std::string> own_client_id;
  bool secure = false;           // DDS Security complete
  std::string certificate_path;  // the own certificate's file, with DDS Security
};

// Checks `options.profile` (and its participant profile `options.xml_participant_profile`, or
// `options.name`): the file loads; the participant profile exists; DDS Security is complete or
// explicitly off (`options.insecure`); every security file it names is readable, private keys
// also by the service user `service_user` (when that user exists and the caller is root);
// the own certificate was issued by the profile's identity CA and is valid now; the CRL has
// not expired (Fast DDS refuses every certificate then); the addresses of its
// interfaceWhiteList exist on this host now. Results go to `report`. The file is loaded into
// Fast DDS's process-wide profiles: a second file with the same profile names loaded later in
// the same process is ignored by Fast DDS (tests reset them with XMLProfileManager).
ProfileCheck CheckDdsProfile(const ParticipantOptions& options, const std::string& service_user,
                             ConfigReport* report);

}  // namespace mostar::dds
