// X.509 identity certificates (OpenSSL): reading one, and checking that a certificate a peer
// shows was issued by our identity CA.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/identity/guid_binding.h"

struct x509_store_st;  // OpenSSL's X509_STORE

namespace mostar::identity {

// Certificates larger than this (DER bytes) are refused unread.
inline constexpr size_t kMaxCertificateBytes = 8192;

struct SubjectInfo {
  std::string rfc2253;  // subject name, RFC 2253, as Fast DDS prints it ("CN=alice,O=mostar")
  Sha256 hash{};        // SHA-256 of the subject name's DER encoding (what PKI-DH hashes)
};

// The subject of a DER certificate, unverified. nullopt with `error` when unreadable.
std::optional<SubjectInfo> SubjectOfCertificate(const std::vector<uint8_t>& der,
                                                std::string* error);

// The first certificate of a PEM file, as DER. False with `error` when unreadable.
bool ReadPemCertificate(const std::string& path, std::vector<uint8_t>* der, std::string* error);

// A trusted identity CA. Verify is thread-safe.
class IdentityCa {
 public:
  // The CA certificate(s) of a PEM file, or of PEM text. Null with `error` when none is read.
  static std::unique_ptr<IdentityCa> LoadFile(const std::string& path, std::string* error);
  static std::unique_ptr<IdentityCa> FromPem(const std::string& pem, std::string* error);
  ~IdentityCa();
  IdentityCa(const IdentityCa&) = delete;
  IdentityCa& operator=(const IdentityCa&) = delete;

  // The subject of `der` when it is a certificate this CA issued, valid now. nullopt with the
  // reason in `error` otherwise (unreadable, too large, another issuer, bad signature, expired
  // or not yet valid).
  std::optional<SubjectInfo> Verify(const std::vector<uint8_t>& der, std::string* error) const;

 private:
  explicit IdentityCa(x509_store_st* store) : store_(store) {}
  x509_store_st* store_;
};

}  // namespace mostar::identity
