#include "operator_client/web/http_target.h"

#include <charconv>

namespace mostar::web {
namespace {

bool Decode(std::string_view in, std::string* out) {
  out->clear();
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i] == '+') {
      out->push_back(' ');
    } else if (in[i] == '%') {
      if (i + 2 >= in.size()) return false;
      unsigned value = 0;  // exactly two hex digits
      const char* first = in.data() + i + 1;
      const auto [end, error] = std::from_chars(first, first + 2, value, 16);
      if (error != std::errc() || end != first + 2) return false;
      out->push_back(static_cast<char>(value));
      i += 2;
    } else {
      out->push_back(in[i]);
    }
  }
  return true;
}

}  // namespace

std::optional<HttpTarget> ParseTarget(std::string_view target) {
  if (target.empty() || target[0] != '/' || target.size() > kMaxTargetBytes) return std::nullopt;
  HttpTarget out;
  const size_t q = target.find('?');
  if (!Decode(target.substr(0, q), &out.path)) return std::nullopt;
  if (q == std::string_view::npos) return out;
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const size_t amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    rest = amp == std::string_view::npos ? std::string_view() : rest.substr(amp + 1);
    if (pair.empty()) continue;
    const size_t eq = pair.find('=');
    std::string key, value;
    if (!Decode(pair.substr(0, eq), &key)) return std::nullopt;
    if (eq != std::string_view::npos && !Decode(pair.substr(eq + 1), &value)) return std::nullopt;
    out.query[key] = value;
  }
  return out;
}

}  // namespace mostar::web
