// Where relative paths point. A path written in a configuration file is relative to that
// file's directory; a path given on the command line is relative to the working directory.
#pragma once

#include <string>

namespace mostar {

// The directory part of `file_path`; "." for a bare file name, "/" for a file in the root.
std::string DirectoryOf(const std::string& file_path);
// `path` relative to `base_dir`: unchanged when empty, absolute, or when `base_dir` is empty.
std::string ResolveRelativeTo(const std::string& path, const std::string& base_dir);
// `path` made absolute against the current working directory (unchanged when empty or
// absolute, or when the working directory cannot be read).
std::string AbsoluteFromWorkingDirectory(const std::string& path);

}  // namespace mostar
