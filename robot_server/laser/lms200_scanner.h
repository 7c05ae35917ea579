// LaserScanner for a SICK LMS200: an Lms200Session driven by one thread.
#pragma once

#include <atomic>
#include <memory>
#include <thread>

#include "common/time/time.h"
#include "robot_server/laser/byte_stream.h"
#include "robot_server/laser/laser_scanner.h"
#include "robot_server/laser/lms200_session.h"

namespace mostar::laser {

class Lms200Scanner final : public LaserScanner {
 public:
  // `clock` must outlive the scanner. The stream is owned.
  Lms200Scanner(std::unique_ptr<ByteStream> stream, const Clock* clock, const Lms200Config& config,
                Lms200SessionOptions options = {});
  ~Lms200Scanner() override;

  bool Start(ScanCallback on_scan, std::string* error) override;
  void Stop() override;
  DeviceHealth Health() const override { return session_.Health(); }

  Lms200Session::State state() const { return session_.state(); }

 private:
  std::unique_ptr<ByteStream> stream_;
  Lms200Config config_;
  Lms200Session session_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// A scanner on a serial port named by `config.port()`.
std::unique_ptr<Lms200Scanner> MakeSerialLms200Scanner(const Lms200Config& config,
                                                       const Clock* clock);

}  // namespace mostar::laser
