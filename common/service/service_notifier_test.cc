// ServiceNotifier against a real notification socket, as systemd would listen on it; and
// robot_server end to end: ready, watchdog while its control loop runs, stopping.
#include "common/service/service_notifier.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/domain.h"
#include "common/testing/subprocess.h"

namespace mostar::service {
namespace {

// A datagram socket like systemd's NOTIFY_SOCKET, drained by a thread as systemd does (a full
// queue would block the sender); Messages() returns what arrived.
class NotifySocket {
 public:
  NotifySocket() {
    dir_ = testing::MakeTempDir("mostar_notify_");
    path_ = dir_ + "/notify";
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    path_.copy(address.sun_path, sizeof(address.sun_path) - 1);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
    timeval timeout{0, 50000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
    reader_ = std::thread([this] {
      char buffer[4096];
      while (!stop_) {
        const ssize_t n = ::recv(fd_, buffer, sizeof(buffer), 0);
        if (n <= 0) continue;
        std::lock_guard<std::mutex> lock(mutex_);
        messages_.emplace_back(buffer, n);
      }
    });
  }
  ~NotifySocket() {
    stop_ = true;
    reader_.join();
    ::close(fd_);
    ::unlink(path_.c_str());
    ::rmdir(dir_.c_str());
  }
  const std::string& path() const { return path_; }
  std::vector<std::string> Messages() {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // let the last ones arrive
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_;
  }

 private:
  std::string dir_, path_;
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<std::string> messages_;
  std::thread reader_;
};

// Sets the service manager's variables for the lifetime of the object.
class ServiceEnvironment {
 public:
  ServiceEnvironment(const std::string& socket, const char* watchdog_usec) {
    ::setenv("NOTIFY_SOCKET", socket.c_str(), 1);
    ::setenv("WATCHDOG_USEC", watchdog_usec, 1);
  }
  ~ServiceEnvironment() {
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");
  }
};

int Count(const std::vector<std::string>& messages, const std::string& prefix) {
  int n = 0;
  for (const auto& m : messages) n += m.rfind(prefix, 0) == 0 ? 1 : 0;
  return n;
}

TEST(ServiceNotifierTest, SilentWithoutAServiceManager) {
  ::unsetenv("NOTIFY_SOCKET");
  ServiceNotifier notifier;
  EXPECT_FALSE(notifier.enabled());
  notifier.Ready("up");
  notifier.Alive(SteadyTime(std::chrono::seconds(1)));
  EXPECT_EQ(notifier.watchdog_messages(), 0);
}

TEST(ServiceNotifierTest, ReadyWatchdogAtHalfTheIntervalAndStopping) {
  NotifySocket socket;
  ServiceEnvironment environment(socket.path(), "200000");
  ServiceNotifier notifier;
  ASSERT_TRUE(notifier.enabled());
  EXPECT_EQ(notifier.watchdog_interval(), std::chrono::milliseconds(200));

  notifier.Ready("running");
  // Called every 20 ms for 1 s: one message per 100 ms (half the interval).
  for (int ms = 0; ms <= 1000; ms += 20) notifier.Alive(SteadyTime(std::chrono::milliseconds(ms)));
  notifier.Stopping("bye");
  const auto messages = socket.Messages();
  EXPECT_EQ(Count(messages, "READY=1\nSTATUS=running"), 1);
  EXPECT_EQ(Count(messages, "WATCHDOG=1"), 11);
  EXPECT_EQ(notifier.watchdog_messages(), 11);
  EXPECT_EQ(Count(messages, "STOPPING=1\nSTATUS=bye"), 1);
}

TEST(ServiceNotifierTest, RobotServerIsReadyFeedsTheWatchdogAndSaysItStops) {
  NotifySocket socket;
  const std::string dir = testing::MakeTempDir("mostar_service_");
  ServiceEnvironment environment(socket.path(), "400000");
  testing::Subprocess server;
  std::string error;
  const bool started = server.Start(
      {std::string(MOSTAR_TEST_BINARY_DIR) + "/robot_server/robot_server", "--source",
       "test_pattern", "--duration", "3", "--domain", std::to_string(dds::PerProcessDomainId())},
      dir + "/server.log", &error);
  ASSERT_TRUE(started) << error;
  const auto exit_code = server.Wait(std::chrono::seconds(30));
  ASSERT_TRUE(exit_code.has_value());
  EXPECT_EQ(*exit_code, 0) << testing::ReadFile(dir + "/server.log");
  const auto messages = socket.Messages();
  EXPECT_EQ(Count(messages, "READY=1"), 1);
  // 3 s of control loop, one message per 200 ms.
  EXPECT_GE(Count(messages, "WATCHDOG=1"), 10);
  EXPECT_EQ(Count(messages, "STOPPING=1"), 1);
}

}  // namespace
}  // namespace mostar::service
