#include "operator_client/web/token_table.h"

#include <openssl/crypto.h>
#include <openssl/sha.h>

#include <fstream>
#include <set>
#include <sstream>

#include "common/identity/client_id.h"

namespace mostar::web {
namespace {

std::array<unsigned char, 32> Digest(std::string_view text) {
  std::array<unsigned char, 32> digest{};
  SHA256(reinterpret_cast<const unsigned char*>(text.data()), text.size(), digest.data());
  return digest;
}

bool IsTokenChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '~' || c == '+' || c == '/' || c == '=' || c == '-';
}

}  // namespace

std::optional<TokenTable> TokenTable::Parse(std::string_view text, std::string* error) {
  TokenTable table;
  std::set<std::string> names;
  std::set<std::array<unsigned char, 32>> digests;
  std::istringstream in{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    auto fail = [&](const std::string& why) {
      *error = "line " + std::to_string(number) + ": " + why;
      return std::nullopt;
    };
    std::istringstream fields(line);
    std::string name, token, extra;
    if (!(fields >> name) || name[0] == '#') continue;
    if (!(fields >> token)) return fail("a name without a token");
    if (fields >> extra) return fail("more than NAME TOKEN");
    std::string why;
    if (!identity::IsValidClientId(name, &why)) return fail("name: " + why);
    if (token.size() < kMinTokenChars || token.size() > kMaxTokenChars) {
      return fail("the token of '" + name + "' must have " + std::to_string(kMinTokenChars) +
                  " to " + std::to_string(kMaxTokenChars) + " characters (has " +
                  std::to_string(token.size()) + ")");
    }
    for (char c : token) {
      if (!IsTokenChar(c))
        return fail("the token of '" + name +
                    "' has a character outside "
                    "[A-Za-z0-9._~+/=-]");
    }
    if (!names.insert(name).second) return fail("'" + name + "' is listed twice");
    const std::array<unsigned char, 32> digest = Digest(token);
    if (!digests.insert(digest).second) return fail("the token of '" + name + "' is not unique");
    table.entries_.push_back({name, digest});
  }
  return table;
}

std::optional<TokenTable> TokenTable::Load(const std::string& path, std::string* error) {
  std::ifstream file(path);
  if (!file) {
    *error = path + ": cannot read";
    return std::nullopt;
  }
  std::stringstream text;
  text << file.rdbuf();
  std::optional<TokenTable> table = Parse(text.str(), error);
  if (!table) *error = path + ": " + *error;
  return table;
}

std::optional<std::string> TokenTable::Check(std::string_view token) const {
  const std::array<unsigned char, 32> digest = Digest(token);
  const Entry* match = nullptr;
  for (const Entry& e : entries_) {
    // CRYPTO_memcmp takes the same time whatever the bytes; every entry is visited.
    const bool equal = CRYPTO_memcmp(e.digest.data(), digest.data(), digest.size()) == 0;
    if (equal) match = &e;
  }
  if (match == nullptr) return std::nullopt;
  return match->name;
}

}  // namespace mostar::web
