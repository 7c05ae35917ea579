#include "common/config/config_paths.h"

#include <unistd.h>

#include <climits>

namespace mostar {

std::string DirectoryOf(const std::string& file_path) {
  const size_t slash = file_path.rfind('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return file_path.substr(0, slash);
}

std::string ResolveRelativeTo(const std::string& path, const std::string& base_dir) {
  if (path.empty() || path[0] == '/' || base_dir.empty()) return path;
  if (base_dir.back() == '/') return base_dir + path;
  return base_dir + "/" + path;
}

std::string InstalledConfigDir() { return MOSTAR_INSTALLED_CONFIG_DIR; }

std::string ResolveConfigPath(const std::string& path, const std::string& config_dir,
                              const std::string& fallback_dir) {
  const std::string first = ResolveRelativeTo(path, config_dir);
  if (path.empty() || path[0] == '/' || fallback_dir.empty() || access(first.c_str(), F_OK) == 0) {
    return first;
  }
  const std::string fallback = ResolveRelativeTo(path, fallback_dir);
  return access(fallback.c_str(), F_OK) == 0 ? fallback : first;
}

std::string AbsoluteFromWorkingDirectory(const std::string& path) {
  if (path.empty() || path[0] == '/') return path;
  char cwd[PATH_MAX];
  if (getcwd(cwd, sizeof(cwd)) == nullptr) return path;
  return ResolveRelativeTo(path, cwd);
}

}  // namespace mostar
