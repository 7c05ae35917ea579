#include "common/identity/certificate_subject.h"

#include <cctype>

#include "common/identity/client_id.h"

namespace mostar::identity {

namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool IsKeyword(std::string_view type) {
  if (type.empty() || !std::isalpha(static_cast<unsigned char>(type[0]))) return false;
  for (const char c : type) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') return false;
  }
  return true;
}

bool IsOid(std::string_view type) {
  if (type.empty() || type.front() == '.' || type.back() == '.') return false;
  char previous = '.';
  for (const char c : type) {
    if (c == '.' && previous == '.') return false;
    if (c != '.' && !std::isdigit(static_cast<unsigned char>(c))) return false;
    previous = c;
  }
  return true;
}

bool SameType(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::toupper(static_cast<unsigned char>(a[i])) !=
        std::toupper(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

bool IsCommonName(std::string_view type) { return SameType(type, "CN") || type == "2.5.4.3"; }

}  // namespace

std::optional<CertificateSubject> CertificateSubject::Parse(std::string_view text,
                                                            std::string* error) {
  auto fail = [error](const std::string& reason) -> std::optional<CertificateSubject> {
    if (error != nullptr) *error = reason;
    return std::nullopt;
  };
  CertificateSubject subject;
  size_t i = 0;
  while (i < text.size()) {
    // type '='
    const size_t equals = text.find('=', i);
    if (equals == std::string_view::npos) return fail("attribute without '='");
    Attribute attribute;
    attribute.type = std::string(text.substr(i, equals - i));
    if (!IsKeyword(attribute.type) && !IsOid(attribute.type)) {
      return fail("bad attribute type '" + attribute.type + "'");
    }
    i = equals + 1;
    // value, up to an unescaped ',' or '+'
    if (i < text.size() && text[i] == '#') {
      attribute.hex = true;
      attribute.value = "#";
      ++i;
      size_t digits = 0;
      while (i < text.size() && text[i] != ',' && text[i] != '+') {
        if (HexValue(text[i]) < 0) return fail("bad hex value of " + attribute.type);
        attribute.value += text[i++];
        ++digits;
      }
      if (digits == 0 || digits % 2 != 0) return fail("bad hex value of " + attribute.type);
    } else {
      while (i < text.size() && text[i] != ',' && text[i] != '+') {
        const char c = text[i];
        if (c == '\\') {
          if (i + 1 >= text.size()) return fail("dangling '\\' in " + attribute.type);
          const int high = HexValue(text[i + 1]);
          if (high >= 0) {
            if (i + 2 >= text.size() || HexValue(text[i + 2]) < 0) {
              return fail("bad '\\' hex escape in " + attribute.type);
            }
            attribute.value += static_cast<char>(high * 16 + HexValue(text[i + 2]));
            i += 3;
          } else {
            attribute.value += text[i + 1];
            i += 2;
          }
          continue;
        }
        if (c == '"' || c == '<' || c == '>' || c == ';') {
          return fail(std::string("unescaped '") + c + "' in " + attribute.type);
        }
        attribute.value += c;
        ++i;
      }
    }
    subject.attributes_.push_back(std::move(attribute));
    if (i < text.size()) {
      ++i;  // the separator
      if (i == text.size()) return fail("separator at the end");
    }
  }
  return subject;
}

std::vector<std::string> CertificateSubject::Values(std::string_view type) const {
  std::vector<std::string> values;
  const bool common_name = IsCommonName(type);
  for (const Attribute& a : attributes_) {
    if (common_name ? IsCommonName(a.type) : SameType(a.type, type)) values.push_back(a.value);
  }
  return values;
}

std::optional<std::string> CertificateSubject::ClientId(std::string* error) const {
  auto fail = [error](const std::string& reason) -> std::optional<std::string> {
    if (error != nullptr) *error = reason;
    return std::nullopt;
  };
  const Attribute* common_name = nullptr;
  for (const Attribute& a : attributes_) {
    if (!IsCommonName(a.type)) continue;
    if (common_name != nullptr) return fail("the subject has more than one CN");
    common_name = &a;
  }
  if (common_name == nullptr) return fail("the subject has no CN");
  if (common_name->hex) return fail("the subject's CN is not a string");
  std::string why;
  if (!IsValidClientId(common_name->value, &why)) return fail("CN: " + why);
  return common_name->value;
}

}  // namespace mostar::identity
