#include "common/identity/certificate.h"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>

#include <cstdio>

namespace mostar::identity {

namespace {

struct X509Deleter {
  void operator()(X509* x) const { X509_free(x); }
};
struct BioDeleter {
  void operator()(BIO* b) const { BIO_free(b); }
};
struct StoreContextDeleter {
  void operator()(X509_STORE_CTX* c) const { X509_STORE_CTX_free(c); }
};
using X509Ptr = std::unique_ptr<X509, X509Deleter>;
using BioPtr = std::unique_ptr<BIO, BioDeleter>;

X509Ptr ParseDer(const std::vector<uint8_t>& der, std::string* error) {
  if (der.empty() || der.size() > kMaxCertificateBytes) {
    *error = "certificate size " + std::to_string(der.size()) + " bytes is outside [1, " +
             std::to_string(kMaxCertificateBytes) + "]";
    return nullptr;
  }
  const unsigned char* p = der.data();
  X509Ptr cert(d2i_X509(nullptr, &p, static_cast<long>(der.size())));
  ERR_clear_error();
  if (!cert) *error = "not a DER certificate";
  return cert;
}

std::optional<SubjectInfo> SubjectOf(X509* cert, std::string* error) {
  const X509_NAME* name = X509_get_subject_name(cert);
  if (name == nullptr) {
    *error = "certificate without a subject";
    return std::nullopt;
  }
  SubjectInfo info;
  unsigned int length = 0;
  if (!X509_NAME_digest(name, EVP_sha256(), info.hash.data(), &length) ||
      length != info.hash.size()) {
    *error = "cannot hash the subject";
    return std::nullopt;
  }
  BioPtr bio(BIO_new(BIO_s_mem()));
  if (!bio || X509_NAME_print_ex(bio.get(), name, 0, XN_FLAG_RFC2253 & ~ASN1_STRFLGS_ESC_MSB) < 0) {
    *error = "cannot print the subject";
    return std::nullopt;
  }
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio.get(), &data);
  if (size > 0 && data != nullptr) info.rfc2253.assign(data, static_cast<size_t>(size));
  return info;
}

std::string OpenSslError() {
  const unsigned long code = ERR_get_error();
  ERR_clear_error();
  if (code == 0) return "unknown OpenSSL error";
  char buffer[256];
  ERR_error_string_n(code, buffer, sizeof(buffer));
  return buffer;
}

}  // namespace

std::optional<SubjectInfo> SubjectOfCertificate(const std::vector<uint8_t>& der,
                                                std::string* error) {
  X509Ptr cert = ParseDer(der, error);
  if (!cert) return std::nullopt;
  return SubjectOf(cert.get(), error);
}

bool ReadPemCertificate(const std::string& path, std::vector<uint8_t>* der, std::string* error) {
  BioPtr bio(BIO_new_file(path.c_str(), "r"));
  if (!bio) {
    ERR_clear_error();
    *error = path + ": cannot open";
    return false;
  }
  X509Ptr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
  if (!cert) {
    *error = path + ": no PEM certificate (" + OpenSslError() + ")";
    return false;
  }
  const int size = i2d_X509(cert.get(), nullptr);
  if (size <= 0 || static_cast<size_t>(size) > kMaxCertificateBytes) {
    *error = path + ": certificate larger than " + std::to_string(kMaxCertificateBytes) + " bytes";
    return false;
  }
  der->resize(static_cast<size_t>(size));
  unsigned char* out = der->data();
  i2d_X509(cert.get(), &out);
  return true;
}

std::unique_ptr<IdentityCa> IdentityCa::FromPem(const std::string& pem, std::string* error) {
  BioPtr bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  X509_STORE* store = X509_STORE_new();
  if (!bio || store == nullptr) {
    X509_STORE_free(store);
    *error = "out of memory";
    return nullptr;
  }
  std::unique_ptr<IdentityCa> ca(new IdentityCa(store));
  int added = 0;
  while (X509Ptr cert{PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr)}) {
    if (X509_STORE_add_cert(store, cert.get()) == 1) ++added;
  }
  ERR_clear_error();  // the loop ends with "no start line"
  if (added == 0) {
    *error = "no CA certificate in the PEM text";
    return nullptr;
  }
  return ca;
}

std::unique_ptr<IdentityCa> IdentityCa::LoadFile(const std::string& path, std::string* error) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    *error = path + ": cannot open";
    return nullptr;
  }
  std::string pem;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), file)) > 0 && pem.size() < (1u << 20)) {
    pem.append(buffer, n);
  }
  std::fclose(file);
  std::unique_ptr<IdentityCa> ca = FromPem(pem, error);
  if (!ca) *error = path + ": " + *error;
  return ca;
}

IdentityCa::~IdentityCa() { X509_STORE_free(store_); }

std::optional<SubjectInfo> IdentityCa::Verify(const std::vector<uint8_t>& der,
                                              std::string* error) const {
  X509Ptr cert = ParseDer(der, error);
  if (!cert) return std::nullopt;
  std::unique_ptr<X509_STORE_CTX, StoreContextDeleter> context(X509_STORE_CTX_new());
  if (!context || X509_STORE_CTX_init(context.get(), store_, cert.get(), nullptr) != 1) {
    *error = "cannot set up the verification: " + OpenSslError();
    return std::nullopt;
  }
  if (X509_verify_cert(context.get()) != 1) {
    *error = std::string("not issued by the identity CA: ") +
             X509_verify_cert_error_string(X509_STORE_CTX_get_error(context.get()));
    ERR_clear_error();
    return std::nullopt;
  }
  return SubjectOf(cert.get(), error);
}

}  // namespace mostar::identity
