// The request target of an HTTP request ("/ws?token=abc"), split and percent-decoded. Pure.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace mostar::web {

struct HttpTarget {
  std::string path;                          // "/ws"
  std::map<std::string, std::string> query;  // decoded; a repeated key keeps the last value
};

// nullopt when the target does not start with '/', is longer than kMaxTargetBytes or holds a
// malformed percent escape.
constexpr size_t kMaxTargetBytes = 2048;
std::optional<HttpTarget> ParseTarget(std::string_view target);

}  // namespace mostar::web
