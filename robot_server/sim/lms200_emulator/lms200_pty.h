// Serves an Lms200Emulator on a pseudo-terminal, so the real driver (libserial) talks to it.
//
// A pty ignores baud rates, so the runner reads the speed the host set on the slave (the
// master sees the slave's termios) and hands it to the emulator with every byte: the
// emulator only understands the host at its own rate and paces its output in real time
// (10 bits per byte). `Unplug()` closes the pty like a pulled USB adapter; `Replug()` opens
// a new one under the same symlink path.
// Threading: one internal thread forwards bytes every millisecond; the public methods may be
// called from any thread.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <thread>

#include "robot_server/sim/lms200_emulator/lms200_emulator.h"

namespace mostar::sim {

class Lms200PtyRunner {
 public:
  // `emulator` must outlive the runner. `link_path`: symlink created to the slave device
  // (replaced if it exists); empty for none.
  Lms200PtyRunner(Lms200Emulator* emulator, std::string link_path);
  ~Lms200PtyRunner();
  Lms200PtyRunner(const Lms200PtyRunner&) = delete;
  Lms200PtyRunner& operator=(const Lms200PtyRunner&) = delete;

  bool Start(std::string* error);
  void Stop();

  // The path the host should open: the symlink if any, else the slave device.
  std::string device_path() const;
  std::string slave_path() const;

  void Unplug();
  bool Replug(std::string* error);

  // Device bytes lost while plugged in because the host did not read them: more than a
  // serial port's kernel receive buffer (kHostBufferBytes) was waiting (a UART overrun).
  uint64_t bytes_overrun() const { return bytes_overrun_.load(); }
  static constexpr size_t kHostBufferBytes = 64 * 1024;

 private:
  bool OpenPtyLocked(std::string* error);
  void ClosePtyLocked();
  void Run();

  Lms200Emulator* emulator_;
  std::string link_path_;
  mutable std::mutex mutex_;  // guards the fds and slave_path_
  int master_fd_ = -1;
  int slave_keeper_fd_ = -1;  // keeps the slave open so the master never sees EIO
  std::string slave_path_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> bytes_overrun_{0};
  std::thread thread_;
};

}  // namespace mostar::sim
