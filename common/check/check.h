// MOSTAR_CHECK(condition) << "message": an invariant that holds in every build (unlike assert,
// it is not compiled out by NDEBUG). On failure it prints "file:line: check failed: condition:
// message" to stderr and aborts the process. For bugs only: expected runtime failures return
// an error, bad configuration is refused at start-up (docs/architecture.md, "errors").
#pragma once

#include <sstream>

namespace mostar::internal {

// Collects the message of a failed check; its destructor prints it and aborts.
class CheckFailure {
 public:
  CheckFailure(const char* file, int line, const char* condition);
  CheckFailure(const CheckFailure&) = delete;
  CheckFailure& operator=(const CheckFailure&) = delete;
  [[noreturn]] ~CheckFailure();
  std::ostream& stream() { return message_; }

 private:
  std::ostringstream where_;    // "file:line: check failed: condition"
  std::ostringstream message_;  // what the caller streamed, may be empty
};

// Gives `cond ? (void)0 : Voidify() & stream` a void type on both branches.
struct CheckVoidify {
  void operator&(std::ostream&) {}
};

}  // namespace mostar::internal

#define MOSTAR_CHECK(condition)                      \
  (condition) ? static_cast<void>(0)                 \
              : ::mostar::internal::CheckVoidify() & \
                    ::mostar::internal::CheckFailure(__FILE__, __LINE__, #condition).stream()
