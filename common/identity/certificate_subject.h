// The subject name of an X.509 identity certificate and the client id it stands for.
//
// Subjects are read in RFC 2253 form, most specific attribute first, e.g.
// "CN=alice,O=mostar" (OpenSSL's XN_FLAG_RFC2253, as Fast DDS prints subjects and as
// deploy/security/make_pki.sh writes them into permissions files). The client id of a subject is
// its common name (CN): the subject must hold exactly one CN, a valid client id (client_id.h).
// Pure: no OpenSSL, no DDS.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mostar::identity {

class CertificateSubject {
 public:
  // Parses an RFC 2253 distinguished name: attributes `type=value` separated by ',' (or '+'
  // inside a multi-valued RDN); values may escape characters as `\c` or `\XX` (hex), or be
  // `#` followed by hex-encoded BER. nullopt with the reason in `error` when malformed.
  static std::optional<CertificateSubject> Parse(std::string_view rfc2253, std::string* error);

  // Values of the attributes of `type` (case-insensitive short name such as "CN", or its
  // dotted OID such as "2.5.4.3"), unescaped, in order of appearance. A `#` value is returned
  // as written (with its '#').
  std::vector<std::string> Values(std::string_view type) const;

  // The client id this subject stands for: its only common name. nullopt with the reason in
  // `error` when there is no CN, more than one, a hex-encoded one, or one that is not a valid
  // client id.
  std::optional<std::string> ClientId(std::string* error) const;

  size_t attribute_count() const { return attributes_.size(); }

 private:
  struct Attribute {
    std::string type;
    std::string value;
    bool hex = false;  // the value was written as '#' + hex-encoded BER
  };
  std::vector<Attribute> attributes_;
};

}  // namespace mostar::identity
