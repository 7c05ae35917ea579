// The certificate a participant announces, and the client id it proves.
//
// mostar participants with DDS Security put their identity certificate in their participant
// USER_DATA (AnnouncedCertificateUserData), which discovery sends to every peer. Fast DDS 2.9
// does not tell the application which certificate a remote participant authenticated with, but
// PKI-DH ties its GUID prefix to that certificate's subject (guid_binding.h). So an announced
// certificate that our identity CA issued and whose subject hash matches the announcer's GUID
// prefix is the certificate it authenticated with (or one with the same subject), and its CN is
// the participant's client id.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/identity/certificate.h"
#include "common/identity/guid_binding.h"

namespace mostar::identity {

// USER_DATA holding a DER certificate: a tag, then the DER bytes.
std::vector<uint8_t> AnnouncedCertificateUserData(const std::vector<uint8_t>& der);
// The DER certificate in `user_data`; false when it holds none (another tag, or nothing).
bool CertificateFromUserData(const std::vector<uint8_t>& user_data, std::vector<uint8_t>* der);

// The client id `der` proves for the participant `prefix`: issued by `ca` and valid now,
// subject hash matching `prefix`, subject with one CN that is a valid client id. nullopt with
// the reason in `why` otherwise.
std::optional<std::string> ClientIdOfAnnouncedCertificate(const IdentityCa& ca,
                                                          const GuidPrefix& prefix,
                                                          const std::vector<uint8_t>& der,
                                                          std::string* why);

}  // namespace mostar::identity
