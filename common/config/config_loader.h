// Configuration files: protobuf text format, validated at start-up.
//
// A file is refused, with an error naming the file, the line and the key, when it has an
// unknown key, a value of the wrong type, a syntax error, or a number outside the range declared
// with the field option `(mostar.config.range)` (common/config/options.proto).
// Example error: "deploy/config/server.pbtxt:12:3: laser.baud: 12345 is outside [9600, 500000]".
#pragma once

#include <google/protobuf/message.h>

#include <string>

namespace mostar {

// Parses `text` into `message` (cleared first). `name` is used in error messages (a path).
// Returns false and sets `error` on any problem; `message` is then unspecified.
bool ParseTextConfig(const std::string& text, const std::string& name,
                     google::protobuf::Message* message, std::string* error);

// Reads and parses the file at `path`; an unreadable file is an error too.
bool LoadTextConfig(const std::string& path, google::protobuf::Message* message,
                    std::string* error);

// Checks the declared ranges of every set numeric field of `message`, recursively. `where` is
// prepended to the error ("name: key: reason"). For messages built in code.
bool ValidateRanges(const google::protobuf::Message& message, const std::string& where,
                    std::string* error);

// Text-format rendering of a message (for saving profiles).
std::string ToTextConfig(const google::protobuf::Message& message);

// Writes `message` to `path` atomically (temporary file, then rename).
bool SaveTextConfig(const std::string& path, const google::protobuf::Message& message,
                    std::string* error);

}  // namespace mostar
