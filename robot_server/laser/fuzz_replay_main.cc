// Stand-in for libFuzzer's driver on compilers without -fsanitize=fuzzer: replays every file
// given on the command line (or every file in a given directory) through the fuzz target.
// Fails (exit 1, with the reason on stderr) when a path cannot be read, a directory holds no
// input, or nothing at all was replayed: an empty corpus must not pass as a green test.
#include <dirent.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

// Replays `path` (a file, or every file below a directory). Returns the number of inputs
// replayed; sets *failed and reports on stderr when something could not be replayed.
int Replay(const std::string& path, bool* failed) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    std::fprintf(stderr, "fuzz replay: cannot stat %s\n", path.c_str());
    *failed = true;
    return 0;
  }
  if (!S_ISDIR(st.st_mode)) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "fuzz replay: cannot open %s\n", path.c_str());
      *failed = true;
      return 0;
    }
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
    return 1;
  }
  DIR* dir = ::opendir(path.c_str());
  if (dir == nullptr) {
    std::fprintf(stderr, "fuzz replay: cannot open directory %s\n", path.c_str());
    *failed = true;
    return 0;
  }
  int count = 0;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") count += Replay(path + "/" + name, failed);
  }
  ::closedir(dir);
  if (count == 0) {
    std::fprintf(stderr, "fuzz replay: directory %s holds no input\n", path.c_str());
    *failed = true;
  }
  return count;
}

}  // namespace

int main(int argc, char** argv) {
  int count = 0;
  bool failed = false;
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] != '-') count += Replay(argv[i], &failed);  // libFuzzer options are ignored
  }
  std::printf("replayed %d inputs\n", count);
  if (count == 0) {
    std::fprintf(stderr, "fuzz replay: no input replayed (give a corpus directory or files)\n");
    return 1;
  }
  return failed ? 1 : 0;
}
