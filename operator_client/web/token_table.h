// Who may watch: one secret token per observer, read from a tokens file. Pure: no sockets.
//
// File format (text): one observer per line, `NAME TOKEN`, separated by blanks; `#` starts a
// comment line; blank lines are ignored. NAME is a client id (common/identity/client_id.h),
// TOKEN 16 to 256 characters of [A-Za-z0-9._~+/=-] (e.g. `openssl rand -base64 24`). Names and
// tokens must be unique.
//
// Check() hashes the presented token (SHA-256) and compares the digest with every entry's in
// constant time, always visiting every entry: how long a check takes says nothing of how much of
// a token was right, nor which entry matched. Thread-compatible (const after Parse).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mostar::web {

constexpr size_t kMinTokenChars = 16;
constexpr size_t kMaxTokenChars = 256;

class TokenTable {
 public:
  // nullopt with `error` ("line N: reason") when the text breaks the format.
  static std::optional<TokenTable> Parse(std::string_view text, std::string* error);
  // Reads and parses `path`; errors name the file.
  static std::optional<TokenTable> Load(const std::string& path, std::string* error);

  // The observer's name when `token` is one of the table's, else nullopt.
  std::optional<std::string> Check(std::string_view token) const;
  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::string name;
    std::array<unsigned char, 32> digest;  // SHA-256 of the token
  };
  std::vector<Entry> entries_;
};

}  // namespace mostar::web
