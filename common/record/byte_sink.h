// Where a RecordingWriter's bytes go: a file, or a fake in tests (disk full after N bytes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace mostar::record {

// An append-only byte destination. Used from one thread at a time. Failures return false with
// a message naming the file and the system error.
class ByteSink {
 public:
  ByteSink() = default;
  ByteSink(const ByteSink&) = delete;
  ByteSink& operator=(const ByteSink&) = delete;
  virtual ~ByteSink() = default;

  // Appends all `size` bytes (handing them to the operating system), or fails; after a failure
  // some of the bytes may have been appended.
  virtual bool Append(const char* data, size_t size, std::string* error) = 0;
  // Makes everything appended so far durable (fdatasync).
  virtual bool Sync(std::string* error) = 0;
  // Cuts the destination back to `size_bytes` (drops a partly appended record).
  virtual bool Truncate(uint64_t size_bytes, std::string* error) = 0;
  virtual bool Close(std::string* error) = 0;
};

// Creates (or truncates) `path`. Null with an error naming the path on failure.
std::unique_ptr<ByteSink> OpenFileSink(const std::string& path, std::string* error);

}  // namespace mostar::record
