#include "common/testing/subprocess.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

namespace mostar::testing {

Subprocess::~Subprocess() {
  CloseStdin();
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
}

bool Subprocess::Start(const std::vector<std::string>& argv, const std::string& output_path,
                       std::string* error) {
  return StartImpl(argv, output_path, false, error);
}

bool Subprocess::StartWithStdin(const std::vector<std::string>& argv,
                                const std::string& output_path, std::string* error) {
  return StartImpl(argv, output_path, true, error);
}

bool Subprocess::WriteStdin(const std::string& text) {
  if (stdin_fd_ < 0) return false;
  return ::write(stdin_fd_, text.data(), text.size()) == static_cast<ssize_t>(text.size());
}

void Subprocess::CloseStdin() {
  if (stdin_fd_ >= 0) ::close(stdin_fd_);
  stdin_fd_ = -1;
}

bool Subprocess::StartImpl(const std::vector<std::string>& argv, const std::string& output_path,
                           bool with_stdin, std::string* error) {
  if (argv.empty()) {
    *error = "empty argv";
    return false;
  }
  const int fd = ::open(output_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    *error = "cannot open " + output_path;
    return false;
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int pipe_fds[2] = {-1, -1};
  if (with_stdin && ::pipe(pipe_fds) != 0) {
    ::close(fd);
    *error = "pipe failed";
    return false;
  }
  pid_ = ::fork();
  if (pid_ < 0) {
    ::close(fd);
    *error = "fork failed";
    return false;
  }
  if (pid_ == 0) {
    if (with_stdin) {
      ::dup2(pipe_fds[0], STDIN_FILENO);
      ::close(pipe_fds[0]);
      ::close(pipe_fds[1]);
    }
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::close(fd);
  if (with_stdin) {
    ::close(pipe_fds[0]);
    stdin_fd_ = pipe_fds[1];
  }
  return true;
}

void Subprocess::Signal(int signal) {
  if (pid_ > 0) ::kill(pid_, signal);
}

std::optional<int> Subprocess::Wait(std::chrono::milliseconds timeout) {
  if (pid_ <= 0) return std::nullopt;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      pid_ = -1;
      if (WIFEXITED(status)) return WEXITSTATUS(status);
      if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
      return -1;
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

bool WaitForText(const std::string& path, const std::string& text,
                 std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (ReadFile(path).find(text) != std::string::npos) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

namespace {

std::mutex temp_dirs_mutex;
std::vector<std::string>* temp_dirs = nullptr;  // made on first use, never destroyed

// At exit: removes the directories MakeTempDir made when every test passed, else names them.
void RemoveTempDirsIfPassed() {
  const std::lock_guard<std::mutex> lock(temp_dirs_mutex);
  const bool passed = ::testing::UnitTest::GetInstance()->Passed();
  for (const std::string& dir : *temp_dirs) {
    std::error_code ignored;
    if (passed) {
      std::filesystem::remove_all(dir, ignored);
    } else {
      std::fprintf(stderr, "kept for inspection: %s\n", dir.c_str());
    }
  }
}

}  // namespace

std::string MakeTempDir(const std::string& prefix) {
  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base ? base : "/tmp") + "/" + prefix + "XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) return std::string();
  const std::lock_guard<std::mutex> lock(temp_dirs_mutex);
  if (temp_dirs == nullptr) {
    temp_dirs = new std::vector<std::string>();
    std::atexit(RemoveTempDirsIfPassed);
  }
  temp_dirs->push_back(pattern);
  return pattern;
}

}  // namespace mostar::testing
