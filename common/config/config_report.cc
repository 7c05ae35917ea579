#include "common/config/config_report.h"

namespace mostar {

bool ConfigReport::HasProblem(const std::string& text) const {
  for (const Problem& p : problems_) {
    if (p.what.find(text) != std::string::npos || p.fix.find(text) != std::string::npos) {
      return true;
    }
  }
  return false;
}

int ConfigReport::Print(const std::string& program, std::ostream& out) const {
  for (const std::string& line : ok_) out << "ok: " << line << "\n";
  for (const Problem& p : problems_) out << "PROBLEM: " << p.what << "\n  fix: " << p.fix << "\n";
  if (problems_.empty()) {
    out << program << ": the configuration is complete (" << ok_.size() << " checks)\n";
    return 0;
  }
  out << program << ": " << problems_.size() << " problem" << (problems_.size() == 1 ? "" : "s")
      << " to fix (" << ok_.size() << " checks passed)\n";
  return 1;
}

}  // namespace mostar
