#include "robot_server/bumper/gpiod_bumper_belt.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <set>

namespace mostar::bumper {

bool GpiodBumperOptions::IsValid(std::string* error) const {
  if (chip.empty()) {
    *error = "bumpers: no GPIO chip";
    return false;
  }
  if (lines.empty() || lines.size() > static_cast<size_t>(kMaxSegments)) {
    *error = "bumpers: need 1.." + std::to_string(kMaxSegments) + " lines";
    return false;
  }
  if (std::set<unsigned>(lines.begin(), lines.end()).size() != lines.size()) {
    *error = "bumpers: a GPIO line is listed twice";
    return false;
  }
  return true;
}

std::unique_ptr<GpiodBumperBelt> GpiodBumperBelt::Open(const GpiodBumperOptions& options,
                                                       std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  gpiod_chip* chip = gpiod_chip_open_lookup(options.chip.c_str());
  if (chip == nullptr) {
    *error = "bumpers: cannot open GPIO chip " + options.chip + ": " + std::strerror(errno);
    return nullptr;
  }
  auto* bulk = new gpiod_line_bulk;
  if (gpiod_chip_get_lines(chip, const_cast<unsigned*>(options.lines.data()),
                           static_cast<unsigned>(options.lines.size()), bulk) != 0) {
    *error = "bumpers: " + options.chip + " has not every configured line: " + std::strerror(errno);
    delete bulk;
    gpiod_chip_close(chip);
    return nullptr;
  }
  gpiod_line_request_config request{};
  request.consumer = "mostar-bumpers";
  request.request_type = GPIOD_LINE_REQUEST_DIRECTION_INPUT;
  request.flags = options.active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
  if (gpiod_line_request_bulk(bulk, &request, nullptr) != 0) {
    *error = "bumpers: cannot request the lines of " + options.chip +
             " as inputs (in use by another program?): " + std::strerror(errno);
    delete bulk;
    gpiod_chip_close(chip);
    return nullptr;
  }
  return std::unique_ptr<GpiodBumperBelt>(new GpiodBumperBelt(chip, bulk, options));
}

GpiodBumperBelt::GpiodBumperBelt(gpiod_chip* chip, void* bulk, GpiodBumperOptions options)
    : chip_(chip), bulk_(bulk), options_(std::move(options)) {}

GpiodBumperBelt::~GpiodBumperBelt() {
  auto* bulk = static_cast<gpiod_line_bulk*>(bulk_);
  gpiod_line_release_bulk(bulk);
  delete bulk;
  gpiod_chip_close(chip_);
}

bool GpiodBumperBelt::Read(uint32_t* pressed, std::string* error) {
  int values[kMaxSegments] = {};
  const bool ok = gpiod_line_get_value_bulk(static_cast<gpiod_line_bulk*>(bulk_), values) == 0;
  std::lock_guard<std::mutex> lock(mutex_);
  ++reads_;
  if (!ok) {
    ++read_errors_;
    last_error_ = std::string("bumpers: reading the GPIO lines failed: ") + std::strerror(errno);
    *error = last_error_;
    return false;
  }
  uint32_t mask = 0;
  for (size_t i = 0; i < options_.lines.size(); ++i) {
    if (values[i] != 0) mask |= 1u << i;  // active-low already applied by the request flag
  }
  last_ = mask;
  last_error_.clear();
  *pressed = mask;
  return true;
}

DeviceHealth GpiodBumperBelt::Health() const {
  std::lock_guard<std::mutex> lock(mutex_);
  DeviceHealth h;
  h.name = "bumpers";
  h.state = last_error_.empty() ? DeviceState::kOk : DeviceState::kError;
  h.message = last_error_;
  h.counters = {{"reads", reads_}, {"read_errors", read_errors_}, {"pressed_mask", last_}};
  return h;
}

}  // namespace mostar::bumper
