#include "common/identity/certificate_subject.h"

#include <gtest/gtest.h>

#include <random>

namespace mostar::identity {
namespace {

std::optional<std::string> ClientIdOf(const std::string& subject, std::string* error) {
  const std::optional<CertificateSubject> parsed = CertificateSubject::Parse(subject, error);
  if (!parsed) return std::nullopt;
  return parsed->ClientId(error);
}

TEST(CertificateSubjectTest, TheClientIdIsTheCommonName) {
  std::string error;
  EXPECT_EQ(ClientIdOf("CN=alice,O=mostar", &error), "alice") << error;
  EXPECT_EQ(ClientIdOf("O=mostar,CN=bob", &error), "bob") << error;
  EXPECT_EQ(ClientIdOf("cn=carol", &error), "carol") << error;
  EXPECT_EQ(ClientIdOf("2.5.4.3=dave,O=x", &error), "dave") << error;
  EXPECT_EQ(ClientIdOf("CN=erin+OU=lab,O=mostar", &error), "erin") << error;
}

TEST(CertificateSubjectTest, UnescapesValues) {
  std::string error;
  const auto subject = CertificateSubject::Parse(R"(O=a\,b\+c\"d\\e\3Df,CN=x)", &error);
  ASSERT_TRUE(subject) << error;
  ASSERT_EQ(subject->Values("O").size(), 1u);
  EXPECT_EQ(subject->Values("O")[0], "a,b+c\"d\\e=f");
  EXPECT_EQ(subject->attribute_count(), 2u);
}

TEST(CertificateSubjectTest, NoOneCnOrABadCnGivesNoClientId) {
  std::string error;
  EXPECT_FALSE(ClientIdOf("O=mostar", &error));
  EXPECT_NE(error.find("no CN"), std::string::npos);
  EXPECT_FALSE(ClientIdOf("CN=alice,CN=bob", &error));
  EXPECT_NE(error.find("more than one"), std::string::npos);
  EXPECT_FALSE(ClientIdOf("CN=alice,2.5.4.3=bob", &error));
  EXPECT_FALSE(ClientIdOf("CN=#0c05616c696365", &error));
  EXPECT_NE(error.find("not a string"), std::string::npos);
  // An escaped separator is part of the name, and no valid id has one.
  EXPECT_FALSE(ClientIdOf(R"(CN=alice\,O=mostar)", &error));
  EXPECT_FALSE(ClientIdOf("CN=", &error));
  EXPECT_FALSE(ClientIdOf("CN=" + std::string(65, 'a'), &error));
  EXPECT_FALSE(ClientIdOf("", &error));
}

TEST(CertificateSubjectTest, RefusesMalformedNames) {
  for (const char* bad : {"CN", "=alice", "CN=a\\", "CN=a\\4", "CN=a\\4g", "CN=a,", "CN=a\"b",
                          "CN=a;b", "C N=a", "1..2=a", "CN=#abc", "CN=#", "CN=#zz", ",CN=a"}) {
    std::string error;
    EXPECT_FALSE(CertificateSubject::Parse(bad, &error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
}

// Property: any valid id in any position of a name round-trips.
TEST(CertificateSubjectTest, EveryValidIdRoundTrips) {
  const std::string alphabet = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-";
  std::mt19937 rng(7);
  for (int trial = 0; trial < 500; ++trial) {
    std::string id(1 + rng() % 64, 'x');
    for (char& c : id) c = alphabet[rng() % alphabet.size()];
    std::string error;
    const std::string subject =
        trial % 2 ? "CN=" + id + ",O=mostar" : "OU=lab\\, 2,O=mostar+L=here,CN=" + id;
    EXPECT_EQ(ClientIdOf(subject, &error), id) << subject << ": " << error;
  }
}

}  // namespace
}  // namespace mostar::identity
