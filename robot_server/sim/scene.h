// Loading and checking scene files (robot_server/sim/scene.proto, protobuf text format).
#pragma once

#include <string>

#include "robot_server/sim/scene.pb.h"

namespace mostar::sim {

// Reads, parses and validates a scene file. On failure returns false and sets `error` to
// "<file>:<line>:<col>: <key>: <reason>" (syntax, unknown key, range) or
// "<file>: <key>: <reason>" (semantic check).
bool LoadScene(const std::string& path, proto::Scene* scene, std::string* error);

// Same, from text; `name` stands for the file in messages.
bool ParseScene(const std::string& text, const std::string& name, proto::Scene* scene,
                std::string* error);

// Semantic checks that the text format cannot express: a non-empty floor extent, walls of
// non-zero length, every box and cylinder with a positive size, a start pose on the floor.
// `name` prefixes the message ("<name>: box[2].size_x_m: must be set and > 0").
bool ValidateScene(const proto::Scene& scene, const std::string& name, std::string* error);

}  // namespace mostar::sim
