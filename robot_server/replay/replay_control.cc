#include "robot_server/replay/replay_control.h"

#include <cmath>
#include <sstream>

namespace mostar::replay {
namespace {

constexpr char kUsage[] = "p pause/resume, s [N] step, r RATE, q quit";

bool Fail(const std::string& line, const std::string& why, std::string* error) {
  *error = "replay control '" + line + "': " + why + " (" + kUsage + ")";
  return false;
}

}  // namespace

bool ParseReplayControl(const std::string& line, ReplayControl* control, std::string* error) {
  std::istringstream in(line);
  std::string command;
  *control = ReplayControl{};
  if (!(in >> command)) return true;  // blank
  std::string argument;
  const bool has_argument = static_cast<bool>(in >> argument);
  std::string extra;
  if (in >> extra) return Fail(line, "too many arguments", error);
  if (command == "p" || command == "q") {
    if (has_argument) return Fail(line, "'" + command + "' takes no argument", error);
    control->kind = command == "p" ? ReplayControl::Kind::kTogglePause : ReplayControl::Kind::kQuit;
    return true;
  }
  if (command == "s") {
    control->kind = ReplayControl::Kind::kStep;
    if (!has_argument) return true;
    size_t used = 0;
    long steps = 0;
    try {
      steps = std::stol(argument, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != argument.size() || steps < 1 || steps > 1000000) {
      return Fail(line, "'s' needs a whole number of records from 1 to 1000000", error);
    }
    control->steps = static_cast<int>(steps);
    return true;
  }
  if (command == "r") {
    size_t used = 0;
    double rate = 0;
    try {
      rate = has_argument ? std::stod(argument, &used) : 0;
    } catch (const std::exception&) {
      used = 0;
    }
    if (!has_argument || used != argument.size() || !std::isfinite(rate) || rate <= 0) {
      return Fail(line, "'r' needs a positive rate", error);
    }
    control->kind = ReplayControl::Kind::kSetRate;
    control->rate = rate;
    return true;
  }
  return Fail(line, "unknown command '" + command + "'", error);
}

bool ApplyReplayControl(const ReplayControl& control, record::ReplayPlayer* player) {
  switch (control.kind) {
    case ReplayControl::Kind::kNone:
      return true;
    case ReplayControl::Kind::kTogglePause:
      if (player->paused()) {
        player->Resume();
      } else {
        player->Pause();
      }
      return true;
    case ReplayControl::Kind::kStep:
      player->Step(control.steps);
      return true;
    case ReplayControl::Kind::kSetRate:
      player->SetRate(control.rate);
      return true;
    case ReplayControl::Kind::kQuit:
      return false;
  }
  return true;
}

}  // namespace mostar::replay
