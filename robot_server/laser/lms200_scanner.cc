#include "robot_server/laser/lms200_scanner.h"

#include "robot_server/laser/serial_byte_stream.h"

namespace mostar::laser {

Lms200Scanner::Lms200Scanner(std::unique_ptr<ByteStream> stream, const Clock* clock,
                             const Lms200Config& config, Lms200SessionOptions options)
    : stream_(std::move(stream)),
      config_(config),
      session_(stream_.get(), clock, config, std::move(options)) {}

Lms200Scanner::~Lms200Scanner() { Stop(); }

bool Lms200Scanner::Start(ScanCallback on_scan, std::string* error) {
  if (thread_.joinable()) {
    if (error) *error = "scanner already started";
    return false;
  }
  if (!ValidateLms200Config(config_, error)) return false;
  stop_ = false;
  session_.ClearCancel();
  thread_ = std::thread([this, on_scan = std::move(on_scan)] {
    while (!stop_.load()) session_.Step(on_scan);
  });
  return true;
}

void Lms200Scanner::Stop() {
  if (!thread_.joinable()) return;
  stop_ = true;
  session_.RequestCancel();
  thread_.join();
  session_.Shutdown();
}

std::unique_ptr<Lms200Scanner> MakeSerialLms200Scanner(const Lms200Config& config,
                                                       const Clock* clock) {
  return std::make_unique<Lms200Scanner>(
      std::make_unique<SerialByteStream>(config.port(), config.baud()), clock, config);
}

}  // namespace mostar::laser
