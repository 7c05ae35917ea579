#include "common/identity/peer_certificate.h"

#include <algorithm>
#include <cstring>

#include "common/identity/certificate_subject.h"

namespace mostar::identity {

namespace {
constexpr char kTag[] = "mostar.cert.der.1:";
constexpr size_t kTagBytes = sizeof(kTag) - 1;
}  // namespace

std::vector<uint8_t> AnnouncedCertificateUserData(const std::vector<uint8_t>& der) {
  std::vector<uint8_t> out;
  out.reserve(kTagBytes + der.size());
  for (size_t i = 0; i < kTagBytes; ++i) out.push_back(static_cast<uint8_t>(kTag[i]));
  out.insert(out.end(), der.begin(), der.end());
  return out;
}

bool CertificateFromUserData(const std::vector<uint8_t>& user_data, std::vector<uint8_t>* der) {
  if (user_data.size() <= kTagBytes || std::memcmp(user_data.data(), kTag, kTagBytes) != 0) {
    return false;
  }
  der->assign(user_data.begin() + kTagBytes, user_data.end());
  return true;
}

std::optional<std::string> ClientIdOfAnnouncedCertificate(const IdentityCa& ca,
                                                          const GuidPrefix& prefix,
                                                          const std::vector<uint8_t>& der,
                                                          std::string* why) {
  const std::optional<SubjectInfo> subject = ca.Verify(der, why);
  if (!subject) return std::nullopt;
  if (!GuidPrefixDerivesFromSubject(prefix, subject->hash)) {
    *why = "the certificate of " + subject->rfc2253 +
           " is not the one the participant's GUID derives from";
    return std::nullopt;
  }
  const std::optional<CertificateSubject> parsed = CertificateSubject::Parse(subject->rfc2253, why);
  if (!parsed) return std::nullopt;
  return parsed->ClientId(why);
}

}  // namespace mostar::identity
