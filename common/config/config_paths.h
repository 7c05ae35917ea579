// Where relative paths point. A path written in a configuration file is relative to that
// file's directory; a path given on the command line is relative to the working directory.
#pragma once

#include <string>

namespace mostar {

// The directory part of `file_path`; "." for a bare file name, "/" for a file in the root.
std::string DirectoryOf(const std::string& file_path);
// `path` relative to `base_dir`: unchanged when empty, absolute, or when `base_dir` is empty.
std::string ResolveRelativeTo(const std::string& path, const std::string& base_dir);
// The installed example configuration folder (`<datadir>/mostar/config`, /usr/share/mostar/config
// in the packages); its scenes and calibration files sit beside it as in deploy/.
std::string InstalledConfigDir();
// A data file named by a configuration file (scene, calibration, intrinsics, recording):
// `path` relative to `config_dir` when a file exists there; otherwise relative to
// `fallback_dir` when one exists there, so that an example copied from the installed folder to
// /etc/mostar keeps finding "../scenes/corridor.pbtxt". When neither exists, the first
// candidate (the caller's error then names it). Absolute and empty paths are unchanged.
std::string ResolveConfigPath(const std::string& path, const std::string& config_dir,
                              const std::string& fallback_dir = InstalledConfigDir());
// `path` made absolute against the current working directory (unchanged when empty or
// absolute, or when the working directory cannot be read).
std::string AbsoluteFromWorkingDirectory(const std::string& path);

}  // namespace mostar
