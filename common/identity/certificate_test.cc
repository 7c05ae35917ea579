// Certificates made here with OpenSSL: a CA, certificates it issued, and a foreign CA.
#include "common/identity/certificate.h"

#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <cstdio>
#include <fstream>

#include "common/identity/certificate_subject.h"
#include "common/identity/peer_certificate.h"
#include "common/identity/test_certificates.h"

namespace mostar::identity {
namespace {

using testing::Der;
using testing::KeyAndCert;
using testing::MakeCertificate;
using testing::Pem;

class CertificateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    MakeCertificate("mostar identity CA", nullptr, &ca_);
    MakeCertificate("rogue CA", nullptr, &rogue_ca_);
    std::string error;
    trusted_ = IdentityCa::FromPem(Pem(ca_.cert), &error);
    ASSERT_NE(trusted_, nullptr) << error;
  }
  KeyAndCert ca_;
  KeyAndCert rogue_ca_;
  std::unique_ptr<IdentityCa> trusted_;
};

TEST_F(CertificateTest, VerifiesACertificateOfItsCaAndGivesItsSubject) {
  KeyAndCert alice;
  MakeCertificate("alice", &ca_, &alice);
  std::string error;
  const std::optional<SubjectInfo> subject = trusted_->Verify(Der(alice.cert), &error);
  ASSERT_TRUE(subject) << error;
  EXPECT_EQ(subject->rfc2253, "CN=alice,O=mostar");
  Sha256 expected;
  unsigned int length = 0;
  ASSERT_TRUE(
      X509_NAME_digest(X509_get_subject_name(alice.cert), EVP_sha256(), expected.data(), &length));
  EXPECT_EQ(subject->hash, expected);
  const auto parsed = CertificateSubject::Parse(subject->rfc2253, &error);
  ASSERT_TRUE(parsed) << error;
  EXPECT_EQ(parsed->ClientId(&error), "alice");
  // Unverified reading gives the same subject.
  const auto unverified = SubjectOfCertificate(Der(alice.cert), &error);
  ASSERT_TRUE(unverified) << error;
  EXPECT_EQ(unverified->hash, expected);
}

TEST_F(CertificateTest, RefusesAnotherIssuerGarbageAndExpiredCertificates) {
  std::string error;
  KeyAndCert forged;
  MakeCertificate("alice", &rogue_ca_, &forged);
  EXPECT_FALSE(trusted_->Verify(Der(forged.cert), &error));
  EXPECT_NE(error.find("not issued by the identity CA"), std::string::npos) << error;

  KeyAndCert expired;
  MakeCertificate("alice", &ca_, &expired, -7200, -3600);
  EXPECT_FALSE(trusted_->Verify(Der(expired.cert), &error));
  EXPECT_NE(error.find("expired"), std::string::npos) << error;

  KeyAndCert alice;
  MakeCertificate("alice", &ca_, &alice);
  std::vector<uint8_t> der = Der(alice.cert);
  der[der.size() - 5] ^= 0xFF;  // in the signature
  EXPECT_FALSE(trusted_->Verify(der, &error));
  der.resize(der.size() / 2);
  EXPECT_FALSE(trusted_->Verify(der, &error));
  EXPECT_FALSE(trusted_->Verify({}, &error));
  EXPECT_FALSE(trusted_->Verify(std::vector<uint8_t>(kMaxCertificateBytes + 1, 0x30), &error));
  EXPECT_NE(error.find("outside"), std::string::npos);
  EXPECT_FALSE(SubjectOfCertificate({0x30, 0x03, 0x02, 0x01, 0x00}, &error));
}

TEST_F(CertificateTest, ReadsPemFilesAndRefusesOthers) {
  KeyAndCert bob;
  MakeCertificate("bob", &ca_, &bob);
  const std::string path = ::testing::TempDir() + "/mostar_bob.cert.pem";
  std::ofstream(path) << Pem(bob.cert);
  std::vector<uint8_t> der;
  std::string error;
  ASSERT_TRUE(ReadPemCertificate(path, &der, &error)) << error;
  EXPECT_EQ(der, Der(bob.cert));
  const std::string ca_path = ::testing::TempDir() + "/mostar_ca.cert.pem";
  std::ofstream(ca_path) << Pem(ca_.cert);
  const auto ca = IdentityCa::LoadFile(ca_path, &error);
  ASSERT_NE(ca, nullptr) << error;
  EXPECT_TRUE(ca->Verify(der, &error)) << error;

  std::ofstream(path) << "not a certificate";
  EXPECT_FALSE(ReadPemCertificate(path, &der, &error));
  EXPECT_EQ(IdentityCa::LoadFile(path, &error), nullptr);
  EXPECT_FALSE(ReadPemCertificate("/nonexistent/x.pem", &der, &error));
  EXPECT_EQ(IdentityCa::LoadFile("/nonexistent/x.pem", &error), nullptr);
  std::remove(path.c_str());
  std::remove(ca_path.c_str());
}

GuidPrefix PrefixFor(X509* cert, uint8_t fill) {
  Sha256 hash;
  unsigned int length = 0;
  X509_NAME_digest(X509_get_subject_name(cert), EVP_sha256(), hash.data(), &length);
  GuidPrefix candidate;
  candidate.fill(fill);
  return AdjustGuidPrefix(candidate, hash);
}

TEST_F(CertificateTest, AnAnnouncedCertificateProvesItsCnForItsOwnGuidOnly) {
  KeyAndCert alice;
  KeyAndCert bob;
  MakeCertificate("alice", &ca_, &alice);
  MakeCertificate("bob", &ca_, &bob);
  std::string why;
  EXPECT_EQ(
      ClientIdOfAnnouncedCertificate(*trusted_, PrefixFor(alice.cert, 1), Der(alice.cert), &why),
      "alice")
      << why;
  // Bob's participant showing Alice's (public) certificate proves nothing.
  EXPECT_FALSE(
      ClientIdOfAnnouncedCertificate(*trusted_, PrefixFor(bob.cert, 1), Der(alice.cert), &why));
  EXPECT_NE(why.find("GUID"), std::string::npos) << why;
  // A certificate from another CA, even for the right GUID.
  KeyAndCert forged;
  MakeCertificate("alice", &rogue_ca_, &forged);
  EXPECT_FALSE(
      ClientIdOfAnnouncedCertificate(*trusted_, PrefixFor(forged.cert, 1), Der(forged.cert), &why));
  // A subject whose CN is no client id.
  KeyAndCert spaced;
  MakeCertificate("alice smith", &ca_, &spaced);
  EXPECT_FALSE(
      ClientIdOfAnnouncedCertificate(*trusted_, PrefixFor(spaced.cert, 1), Der(spaced.cert), &why));
  EXPECT_NE(why.find("CN"), std::string::npos) << why;
}

TEST(AnnouncedCertificateTest, UserDataRoundTripsAndOtherUserDataHoldsNone) {
  const std::vector<uint8_t> der = {0x30, 0x82, 0x01, 0x02, 0xAA};
  std::vector<uint8_t> back;
  ASSERT_TRUE(CertificateFromUserData(AnnouncedCertificateUserData(der), &back));
  EXPECT_EQ(back, der);
  const std::string ros = "enclave=/;";
  EXPECT_FALSE(CertificateFromUserData(std::vector<uint8_t>(ros.begin(), ros.end()), &back));
  EXPECT_FALSE(CertificateFromUserData({}, &back));
  EXPECT_FALSE(CertificateFromUserData(AnnouncedCertificateUserData({}), &back));
}

}  // namespace
}  // namespace mostar::identity
