#include "common/config/config_loader.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/config/options.pb.h"

namespace mostar {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;
using google::protobuf::TextFormat;

class CollectFirstError : public google::protobuf::io::ErrorCollector {
 public:
  explicit CollectFirstError(std::string name) : name_(std::move(name)) {}
  void AddError(int line, google::protobuf::io::ColumnNumber column,
                const std::string& message) override {
    if (!first_.empty()) return;
    std::ostringstream out;
    out << name_ << ':' << line + 1 << ':' << column + 1 << ": " << message;
    first_ = out.str();
  }
  void AddWarning(int, google::protobuf::io::ColumnNumber, const std::string&) override {}
  const std::string& first() const { return first_; }

 private:
  std::string name_;
  std::string first_;
};

bool NumericValue(const Message& message, const FieldDescriptor* field, int index, double* value) {
  const Reflection* r = message.GetReflection();
  const bool rep = field->is_repeated();
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT32:
      *value = rep ? r->GetRepeatedInt32(message, field, index) : r->GetInt32(message, field);
      return true;
    case FieldDescriptor::CPPTYPE_INT64:
      *value = static_cast<double>(rep ? r->GetRepeatedInt64(message, field, index)
                                       : r->GetInt64(message, field));
      return true;
    case FieldDescriptor::CPPTYPE_UINT32:
      *value = rep ? r->GetRepeatedUInt32(message, field, index) : r->GetUInt32(message, field);
      return true;
    case FieldDescriptor::CPPTYPE_UINT64:
      *value = static_cast<double>(rep ? r->GetRepeatedUInt64(message, field, index)
                                       : r->GetUInt64(message, field));
      return true;
    case FieldDescriptor::CPPTYPE_FLOAT:
      *value = rep ? r->GetRepeatedFloat(message, field, index) : r->GetFloat(message, field);
      return true;
    case FieldDescriptor::CPPTYPE_DOUBLE:
      *value = rep ? r->GetRepeatedDouble(message, field, index) : r->GetDouble(message, field);
      return true;
    default:
      return false;
  }
}

std::string FormatBound(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// Walks the set fields; `tree` (may be null) gives source locations.
bool Validate(const Message& message, const std::string& name, const std::string& prefix,
              const TextFormat::ParseInfoTree* tree, std::string* error) {
  const Reflection* r = message.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  r->ListFields(message, &fields);
  for (const FieldDescriptor* field : fields) {
    const int count = field->is_repeated() ? r->FieldSize(message, field) : 1;
    const std::string key = prefix.empty() ? field->name() : prefix + "." + field->name();
    for (int i = 0; i < count; ++i) {
      const int index = field->is_repeated() ? i : -1;
      std::string location = name;
      if (tree != nullptr) {
        const auto loc = tree->GetLocation(field, index);
        if (loc.line >= 0) {
          location += ":" + std::to_string(loc.line + 1) + ":" + std::to_string(loc.column + 1);
        }
      }
      const std::string indexed_key =
          field->is_repeated() ? key + "[" + std::to_string(i) + "]" : key;
      if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
        const Message& sub = field->is_repeated() ? r->GetRepeatedMessage(message, field, i)
                                                  : r->GetMessage(message, field);
        const TextFormat::ParseInfoTree* sub_tree =
            tree != nullptr ? tree->GetTreeForNested(field, index) : nullptr;
        if (!Validate(sub, name, indexed_key, sub_tree, error)) return false;
        continue;
      }
      double value = 0;
      if (!NumericValue(message, field, i, &value)) continue;
      if (!std::isfinite(value)) {
        *error = location + ": " + indexed_key + ": value is not a finite number";
        return false;
      }
      if (!field->options().HasExtension(config::range)) continue;
      const config::Range& range = field->options().GetExtension(config::range);
      const bool below = range.has_min() && value < range.min();
      const bool above = range.has_max() && value > range.max();
      if (below || above) {
        std::ostringstream out;
        out << location << ": " << indexed_key << ": " << value << " is outside ["
            << (range.has_min() ? FormatBound(range.min()) : "-inf") << ", "
            << (range.has_max() ? FormatBound(range.max()) : "inf") << "]";
        *error = out.str();
        return false;
      }
    }
  }
  return true;
}

}  // namespace

bool ParseTextConfig(const std::string& text, const std::string& name, Message* message,
                     std::string* error) {
  message->Clear();
  CollectFirstError collector(name);
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&collector);
  TextFormat::ParseInfoTree tree;
  parser.WriteLocationsTo(&tree);
  parser.AllowUnknownField(false);
  if (!parser.ParseFromString(text, message)) {
    *error = collector.first().empty() ? name + ": cannot parse" : collector.first();
    return false;
  }
  return Validate(*message, name, "", &tree, error);
}

bool LoadTextConfig(const std::string& path, Message* message, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open configuration file";
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return ParseTextConfig(text.str(), path, message, error);
}

bool ValidateRanges(const Message& message, const std::string& where, std::string* error) {
  return Validate(message, where, "", nullptr, error);
}

std::string ToTextConfig(const Message& message) {
  std::string out;
  TextFormat::PrintToString(message, &out);
  return out;
}

bool SaveTextConfig(const std::string& path, const Message& message, std::string* error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) {
      *error = path + ": cannot write";
      return false;
    }
    out << "# mostar " << message.GetDescriptor()->full_name() << "\n" << ToTextConfig(message);
    if (!out.good()) {
      *error = path + ": write failed";
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = path + ": cannot rename temporary file";
    return false;
  }
  return true;
}

}  // namespace mostar
