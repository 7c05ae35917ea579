#include "common/dds/security.h"

#include <algorithm>
#include <cstring>
#include <sstream>
#include <utility>

#include "common/identity/peer_certificate.h"
#include "common/log/log.h"

namespace mostar::dds {

namespace frtps = eprosima::fastrtps;

namespace {

identity::GuidPrefix PrefixOf(const frtps::rtps::GuidPrefix_t& guid_prefix) {
  identity::GuidPrefix prefix;
  std::memcpy(prefix.data(), guid_prefix.value, prefix.size());
  return prefix;
}

// "file:///a/b" or "file:/a/b" -> "/a/b"; false for other URIs.
bool FilePath(const std::string& uri, std::string* path) {
  const std::string scheme = "file:";
  if (uri.compare(0, scheme.size(), scheme) != 0) return false;
  std::string rest = uri.substr(scheme.size());
  if (rest.compare(0, 2, "//") == 0) rest = rest.substr(2);
  if (rest.empty()) return false;
  *path = rest;
  return true;
}

}  // namespace

bool SecuritySettingsFromProperties(const frtps::rtps::PropertyPolicy& properties,
                                    SecuritySettings* settings, std::string* error) {
  using frtps::rtps::PropertyPolicyHelper;
  *settings = SecuritySettings();
  const auto is = [&properties](const char* name, const char* value) {
    const std::string* found = PropertyPolicyHelper::find_property(properties, name);
    return found != nullptr && *found == value;
  };
  settings->access_control = is("dds.sec.access.plugin", "builtin.Access-Permissions");
  settings->cryptography = is("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  if (!is("dds.sec.auth.plugin", "builtin.PKI-DH")) return true;
  settings->authentication = true;
  for (const auto& [name, path] :
       {std::make_pair("dds.sec.auth.builtin.PKI-DH.identity_ca", &settings->identity_ca_path),
        std::make_pair("dds.sec.auth.builtin.PKI-DH.identity_certificate",
                       &settings->identity_certificate_path)}) {
    const std::string* uri = PropertyPolicyHelper::find_property(properties, name);
    if (uri == nullptr || !FilePath(*uri, path)) {
      *error = std::string("DDS Security property ") + name + " must be a file: URI";
      return false;
    }
  }
  return true;
}

SecurityPolicy CheckSecurityPolicy(bool profile_is_loopback, const SecuritySettings& settings,
                                   bool insecure) {
  SecurityPolicy policy;
  if (settings.complete()) {
    policy.verdict = SecurityVerdict::kSecure;
    return policy;
  }
  if (profile_is_loopback) {
    policy.verdict = SecurityVerdict::kLoopback;
    return policy;
  }
  std::string missing;
  for (const auto& [on, plugin] :
       {std::make_pair(settings.authentication, "builtin.PKI-DH"),
        std::make_pair(settings.access_control, "builtin.Access-Permissions"),
        std::make_pair(settings.cryptography, "builtin.AES-GCM-GMAC")}) {
    if (on) continue;
    if (!missing.empty()) missing += ", ";
    missing += plugin;
  }
  if (insecure) {
    policy.verdict = SecurityVerdict::kInsecureAllowed;
    policy.message = "DDS Security is off (--insecure; missing " + missing +
                     "): anyone on the network can read the robot's streams and command it";
  } else {
    policy.verdict = SecurityVerdict::kRefused;
    policy.message =
        "the DDS profile is not loopback and does not enable DDS Security (missing " + missing +
        "): make one with deploy/security/make_pki.sh (docs/security.md), or pass --insecure to "
        "run without it on a network you trust";
  }
  return policy;
}

PeerIdentityListener::PeerIdentityListener(std::unique_ptr<identity::IdentityCa> ca)
    : ca_(std::move(ca)) {}

bool PeerEventLogBudget::Allow(const identity::GuidPrefix& prefix, Event event, SteadyTime now,
                               uint64_t* suppressed) {
  if (!last_refill_) last_refill_ = now;
  while (now - *last_refill_ >= kRefill) {
    *last_refill_ += kRefill;
    tokens_ = std::min(kBurst, tokens_ + 1);
    if (tokens_ == kBurst) last_refill_ = now;
  }
  const auto it = last_.find(prefix);
  if (it != last_.end() && it->second == event) return false;  // said already
  if (tokens_ == 0) {
    ++suppressed_;
    return false;
  }
  --tokens_;
  if (last_.size() >= kMaxRemembered) last_.clear();
  last_[prefix] = event;
  *suppressed = suppressed_;
  suppressed_ = 0;
  return true;
}

void PeerIdentityListener::Log(const identity::GuidPrefix& prefix, PeerEventLogBudget::Event event,
                               const std::string& text) {
  uint64_t suppressed = 0;
  {
    std::lock_guard<std::mutex> lock(log_mutex_);
    if (!log_budget_.Allow(prefix, event, SystemClock::Instance().SteadyNow(), &suppressed)) {
      return;
    }
  }
  const bool warn =
      event == PeerEventLogBudget::Event::kRefused || event == PeerEventLogBudget::Event::kDropped;
  const std::string more =
      suppressed > 0 ? " (" + std::to_string(suppressed) + " participant events not logged)" : "";
  if (warn) {
    MOSTAR_LOG(WARNING) << text << more;
  } else {
    MOSTAR_LOG(INFO) << text << more;
  }
}

PeerIdentityCounters PeerIdentityListener::counters() const {
  PeerIdentityCounters c;
  c.certificates_verified = verified_.load();
  c.certificates_refused = refused_.load();
  c.without_certificate = without_certificate_.load();
  c.authenticated = authenticated_.load();
  return c;
}

std::string PeerIdentityListener::Announcing(const identity::GuidPrefix& prefix) const {
  const std::optional<std::string> id =
      table_.AnnouncedClientId(prefix, /*authenticated_only=*/false);
  return id ? "announcing '" + *id + "'" : "announcing no client certificate";
}

void PeerIdentityListener::on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                                    frtps::rtps::ParticipantDiscoveryInfo&& info) {
  using Status = frtps::rtps::ParticipantDiscoveryInfo;
  const identity::GuidPrefix prefix = PrefixOf(info.info.m_guid.guidPrefix);
  if (info.status == Status::REMOVED_PARTICIPANT || info.status == Status::DROPPED_PARTICIPANT) {
    const bool dropped = info.status == Status::DROPPED_PARTICIPANT;
    std::ostringstream text;
    text << "DDS participant " << info.info.m_guid.guidPrefix << " (" << Announcing(prefix) << ") "
         << (dropped ? "dropped: silent for its lease" : "left");
    Log(prefix, dropped ? PeerEventLogBudget::Event::kDropped : PeerEventLogBudget::Event::kLeft,
        text.str());
    table_.Forget(prefix);
    return;
  }
  std::vector<uint8_t> der;
  if (!identity::CertificateFromUserData(info.info.m_userData.data_vec(), &der)) {
    ++without_certificate_;
    return;
  }
  std::string why;
  const std::optional<std::string> client_id =
      identity::ClientIdOfAnnouncedCertificate(*ca_, prefix, der, &why);
  if (!client_id) {
    ++refused_;
    MOSTAR_LOG_EVERY_SEC(WARNING, 10)
        << "DDS participant " << info.info.m_guid.guidPrefix
        << " announced a certificate that proves no client id: " << why;
    return;
  }
  if (table_.Bind(prefix, *client_id)) ++verified_;
  if (info.status == Status::DISCOVERED_PARTICIPANT) {
    std::ostringstream text;
    text << "DDS participant " << info.info.m_guid.guidPrefix
         << " discovered, announcing the certificate of '" << *client_id
         << "' (a claim: DDS access control grants it what the certificate its handshake proves "
            "may do)";
    Log(prefix, PeerEventLogBudget::Event::kDiscovered, text.str());
  }
}

void PeerIdentityListener::onParticipantAuthentication(
    eprosima::fastdds::dds::DomainParticipant*, frtps::rtps::ParticipantAuthenticationInfo&& info) {
  const identity::GuidPrefix prefix = PrefixOf(info.guid.guidPrefix);
  if (info.status == frtps::rtps::ParticipantAuthenticationInfo::AUTHORIZED_PARTICIPANT) {
    ++authenticated_;
    table_.MarkAuthenticated(prefix);
    std::ostringstream text;
    // PKI-DH proved a certificate of the identity CA but does not say which; the announced one
    // is bound to the GUID, not to the handshake (docs/security.md, Identities).
    text << "DDS participant " << info.guid.guidPrefix
         << " authenticated by a certificate of the identity CA (" << Announcing(prefix)
         << ", unproven: its rights are the permissions of the certificate it proved)";
    Log(prefix, PeerEventLogBudget::Event::kAuthenticated, text.str());
  } else {
    table_.Forget(prefix);
    std::ostringstream text;
    text << "DDS participant " << info.guid.guidPrefix << " failed authentication";
    Log(prefix, PeerEventLogBudget::Event::kRefused, text.str());
  }
}

}  // namespace mostar::dds
