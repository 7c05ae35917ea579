#include "common/log/stamp_trace.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace mostar {
namespace {

std::string TempPath(const std::string& name) {
  const char* base = std::getenv("TMPDIR");
  return std::string(base ? base : "/tmp") + "/" + name + std::to_string(::getpid());
}

TEST(StampTraceTest, EveryLineFromEveryThreadReachesTheFile) {
  const std::string path = TempPath("mostar_stamp_trace_");
  {
    StampTrace trace;
    ASSERT_TRUE(trace.Open(path));
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
      threads.emplace_back([&trace, t] {
        for (int i = 0; i < 1000; ++i) trace.Add(t % 2 ? "odd" : "even", FromUnixNanos(i), i);
      });
    }
    for (std::thread& thread : threads) thread.join();
    trace.Flush();
    std::ifstream in(path);
    int lines = 0;
    for (std::string line; std::getline(in, line);) {
      ++lines;
      EXPECT_TRUE(line.rfind("odd,", 0) == 0 || line.rfind("even,", 0) == 0) << line;
    }
    EXPECT_EQ(lines, 4000);
    EXPECT_EQ(trace.dropped(), 0u);
  }
  ::unlink(path.c_str());
}

TEST(StampTraceTest, NotOpenedItIsANoOp) {
  StampTrace trace;
  EXPECT_TRUE(trace.Open(""));
  trace.Add("scan", FromUnixNanos(1), 1);
  trace.Flush();
  EXPECT_EQ(trace.dropped(), 0u);
  EXPECT_FALSE(StampTrace().Open("/nonexistent-dir/trace.csv"));
}

// The file is a FIFO nobody reads: the background write blocks as a write on a stalled disk
// would. Add() still returns every time; past the buffer limit the lines are counted as
// dropped, and once the reader drains the FIFO every kept line arrives, then "#dropped,N".
TEST(StampTraceTest, AStalledWriteNeverBlocksAddAndOverflowIsCounted) {
  const std::string path = TempPath("mostar_stamp_trace_fifo_");
  ::unlink(path.c_str());
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  const int reader = ::open(path.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  const std::string topic(100, 't');  // lines of about 120 bytes
  const size_t per_line = topic.size() + 20;
  const size_t lines = 2 * StampTrace::kMaxBufferedBytes / per_line;
  std::string received;
  uint64_t dropped = 0;
  std::thread drain;
  {
    StampTrace trace;
    ASSERT_TRUE(trace.Open(path));
    for (size_t i = 0; i < lines; ++i) trace.Add(topic.c_str(), FromUnixNanos(1000000000), i);
    dropped = trace.dropped();
    // Nothing has been read yet, so the writer is stuck on the FIFO's 64 KB buffer: every Add
    // above returned while it was blocked.
    EXPECT_GT(dropped, 0u);
    EXPECT_LT(dropped, lines);
    drain = std::thread([&] {  // reads until end of file, when the trace closes its side
      ::fcntl(reader, F_SETFL, ::fcntl(reader, F_GETFL) & ~O_NONBLOCK);
      char chunk[65536];
      for (ssize_t n; (n = ::read(reader, chunk, sizeof(chunk))) > 0;) {
        received.append(chunk, static_cast<size_t>(n));
      }
    });
  }  // the destructor writes the rest and "#dropped,N", and closes the file
  drain.join();
  ::close(reader);
  ::unlink(path.c_str());
  size_t kept = 0;
  std::istringstream in(received);
  std::string last;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("#dropped,", 0) == 0) {
      last = line;
    } else {
      ++kept;
    }
  }
  EXPECT_EQ(kept + dropped, lines);
  EXPECT_EQ(last, "#dropped," + std::to_string(dropped));
}

}  // namespace
}  // namespace mostar
