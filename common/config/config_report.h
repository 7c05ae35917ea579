// What `--check-config` found: each check that passed, and each problem with its fix. The
// programs print it and exit 0 only when there is no problem (docs/packages.md).
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace mostar {

class ConfigReport {
 public:
  struct Problem {
    std::string what;  // what is wrong, naming the file, key or device
    std::string fix;   // what to do about it
  };

  void Ok(const std::string& what) { ok_.push_back(what); }
  void Fail(const std::string& what, const std::string& fix) { problems_.push_back({what, fix}); }

  bool all_well() const { return problems_.empty(); }
  const std::vector<std::string>& ok() const { return ok_; }
  const std::vector<Problem>& problems() const { return problems_; }
  // True when some problem's text contains `text` (for tests).
  bool HasProblem(const std::string& text) const;

  // "ok: ..." lines, then "PROBLEM: ...\n  fix: ..." blocks, then a summary line naming
  // `program`. Returns the exit status: 0 when all is well, 1 otherwise.
  int Print(const std::string& program, std::ostream& out) const;

 private:
  std::vector<std::string> ok_;
  std::vector<Problem> problems_;
};

}  // namespace mostar
