// Starts and supervises a child process for cross-process tests. Output goes to a file.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace mostar::testing {

class Subprocess {
 public:
  Subprocess() = default;
  ~Subprocess();  // kills the child if still running
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  // argv[0] is the executable path. stdout and stderr go to `output_path`.
  bool Start(const std::vector<std::string>& argv, const std::string& output_path,
             std::string* error);
  // The same with the child's standard input connected to a pipe (see WriteStdin).
  bool StartWithStdin(const std::vector<std::string>& argv, const std::string& output_path,
                      std::string* error);
  // Writes to the child's standard input; false when there is no pipe or the write failed.
  bool WriteStdin(const std::string& text);
  void CloseStdin();
  // Sends a signal (e.g. SIGTERM).
  void Signal(int signal);
  // Waits up to `timeout` for the exit; the exit code (128+signal when killed), or nullopt on
  // timeout.
  std::optional<int> Wait(std::chrono::milliseconds timeout);
  bool running() const { return pid_ > 0; }

 private:
  bool StartImpl(const std::vector<std::string>& argv, const std::string& output_path,
                 bool with_stdin, std::string* error);
  pid_t pid_ = -1;
  int stdin_fd_ = -1;
};

// Reads a whole file ("" when missing).
std::string ReadFile(const std::string& path);
// Waits until the file at `path` contains `text` (checked every 50 ms), at most `timeout`; true
// when it does. For a process's log line that says it is ready.
bool WaitForText(const std::string& path, const std::string& text,
                 std::chrono::milliseconds timeout);
// A fresh directory `prefix` + six random characters under $TMPDIR (default /tmp); "" when it
// cannot be made. When the test program ends normally with every test passed it is removed with
// its contents; otherwise it is kept for inspection and its path printed on stderr.
std::string MakeTempDir(const std::string& prefix);

}  // namespace mostar::testing
