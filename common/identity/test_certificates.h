// Test helpers: certificate authorities and certificates made with OpenSSL in memory, written
// as PEM files when needed (tests only).
#pragma once

#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace mostar::identity::testing {

struct KeyAndCert {
  EVP_PKEY* key = nullptr;
  X509* cert = nullptr;
  KeyAndCert() = default;
  KeyAndCert(const KeyAndCert&) = delete;
  KeyAndCert& operator=(const KeyAndCert&) = delete;
  ~KeyAndCert() {
    X509_free(cert);
    EVP_PKEY_free(key);
  }
};

// A certificate for `cn` (O=mostar) signed by `issuer` (self-signed when null), valid from
// `not_before_s` to `not_after_s` seconds from now.
inline void MakeCertificate(const std::string& cn, const KeyAndCert* issuer, KeyAndCert* out,
                            long not_before_s = -60, long not_after_s = 3600) {
  out->key = EVP_EC_gen("P-256");
  ASSERT_NE(out->key, nullptr);
  out->cert = X509_new();
  X509_set_version(out->cert, 2);
  static long serial = 1;
  ASSERT_EQ(ASN1_INTEGER_set(X509_get_serialNumber(out->cert), serial++), 1);
  X509_gmtime_adj(X509_getm_notBefore(out->cert), not_before_s);
  X509_gmtime_adj(X509_getm_notAfter(out->cert), not_after_s);
  X509_NAME* name = X509_get_subject_name(out->cert);
  X509_NAME_add_entry_by_txt(name, "O", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>("mostar"), -1, -1, 0);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>(cn.c_str()), -1, -1, 0);
  X509_set_issuer_name(
      out->cert, issuer ? X509_get_subject_name(issuer->cert) : X509_get_subject_name(out->cert));
  X509_set_pubkey(out->cert, out->key);
  if (issuer == nullptr) {  // a CA
    X509_EXTENSION* ca =
        X509V3_EXT_conf_nid(nullptr, nullptr, NID_basic_constraints, "critical,CA:TRUE");
    ASSERT_NE(ca, nullptr);
    X509_add_ext(out->cert, ca, -1);
    X509_EXTENSION_free(ca);
  }
  ASSERT_GT(X509_sign(out->cert, issuer ? issuer->key : out->key, EVP_sha256()), 0);
}

inline std::vector<uint8_t> Der(X509* cert) {
  std::vector<uint8_t> der(static_cast<size_t>(i2d_X509(cert, nullptr)));
  unsigned char* p = der.data();
  i2d_X509(cert, &p);
  return der;
}

inline std::string Pem(X509* cert) {
  BIO* bio = BIO_new(BIO_s_mem());
  PEM_write_bio_X509(bio, cert);
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio, &data);
  std::string pem(data, static_cast<size_t>(size));
  BIO_free(bio);
  return pem;
}

// PEM of a private key.
inline std::string KeyPem(EVP_PKEY* key) {
  BIO* bio = BIO_new(BIO_s_mem());
  PEM_write_bio_PrivateKey(bio, key, nullptr, nullptr, 0, nullptr, nullptr);
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio, &data);
  std::string pem(data, static_cast<size_t>(size));
  BIO_free(bio);
  return pem;
}

}  // namespace mostar::identity::testing
