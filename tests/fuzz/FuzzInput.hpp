// Shared pieces of the libFuzzer targets in tests/fuzz (built with -DCMC_FUZZ=ON, run by
// scripts/fuzz.sh; docs/developer/testing.md).
//
// cmc's readers take a path, so a fuzz input is handed to them as a file, rewritten for
// every input: the readers run exactly as `cmc` runs them. The file lives in a private
// folder in /dev/shm (memory) when there is one, else in $TMPDIR or /tmp, removed at exit.
// (An anonymous memfd opened through /proc/self/fd would do for the text readers, but
// HDF5 resolves the name to a real path and fails on it.)
//
// A target fails (abort, which libFuzzer reports as a crash and saves the input) when a
// reader throws anything other than the error type it documents for bad input, or when a
// result it accepted breaks the reader's documented promises; sanitizer reports, crashes,
// hangs (-timeout) and memory blow-ups (-rss_limit_mb) are caught by libFuzzer itself.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace cmc::fuzz {

class TempFile {
 public:
  explicit TempFile(const char* name) {
    std::string base = "/tmp";
    if (const char* t = std::getenv("TMPDIR"); t && *t) base = t;
    if (::access("/dev/shm", W_OK) == 0) base = "/dev/shm";
    std::string dir = base + "/cmc-fuzz-XXXXXX";
    if (!::mkdtemp(dir.data())) std::perror("mkdtemp"), std::abort();
    dir_ = dir;
    path_ = dir_ + "/" + name;
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    ::unlink(path_.c_str());
    ::rmdir(dir_.c_str());
  }
  // Replaces the file's contents with `bytes`.
  void write(std::string_view bytes) {
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd < 0) std::perror(path_.c_str()), std::abort();
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t w = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (w <= 0) std::perror("write"), std::abort();
      done += std::size_t(w);
    }
    ::close(fd);
  }
  const std::string& path() const { return path_; }

 private:
  std::string dir_, path_;
};

// A finding: print what broke and abort (libFuzzer saves the input as crash-<sha1>).
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "cmc fuzz: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}
inline void require(bool ok, const std::string& what) {
  if (!ok) fail(what);
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace cmc::fuzz
