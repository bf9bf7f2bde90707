#include "cmc/output/OutputLock.hpp"

#include "cmc/grid/FilePaths.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace cmc {

namespace fs = std::filesystem;

struct OutputLock::Held {
  int fd = -1;
  fs::path dir;
  bool created = false;  // this process made the folder
  ~Held() {
    // A folder this process made and left empty (a command that stopped on bad input)
    // goes again; the lock file is removed while it is still locked.
    std::error_code ec;
    if (created) {
      bool only_lock = true;
      for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename() != OutputLock::file_name()) only_lock = false;
      if (!ec && only_lock && fs::remove(dir / OutputLock::file_name(), ec)) fs::remove(dir, ec);
    }
    // Empty while nobody holds it (the lock itself goes with the descriptor).
    if (::ftruncate(fd, 0) != 0) { /* nothing to do: close releases the lock */ }
    ::close(fd);
  }
};

namespace {

// The folders this process holds, by canonical path.
std::mutex registry_mutex;
std::map<std::string, std::weak_ptr<OutputLock::Held>>& registry() {
  static std::map<std::string, std::weak_ptr<OutputLock::Held>> r;
  return r;
}

// The holder's process id as its lock file says (it writes it right after locking, so
// an empty file is retried briefly); "unknown" if it cannot be read.
std::string holder_pid(int fd) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    std::string s(buf, n > 0 ? std::size_t(n) : 0);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    if (!s.empty() && s.find_first_not_of("0123456789") == std::string::npos) return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return "unknown";
}

}  // namespace

OutputLock::OutputLock(const fs::path& dir) {
  check_output_folder(dir);  // not the root folder, nor a file (exit 2)
  std::error_code ec;
  const bool created = !fs::exists(dir, ec);
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": cannot create the output folder");
  const std::string key = fs::weakly_canonical(dir, ec).string();
  std::lock_guard<std::mutex> guard(registry_mutex);
  if (auto held = registry()[key].lock()) {
    held_ = held;
    return;
  }
  const fs::path file = dir / file_name();
  for (int attempt = 0;; ++attempt) {
    const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(file.string() + ": cannot open the lock file (" + std::strerror(errno) + ")");
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const std::string pid = err == EWOULDBLOCK ? holder_pid(fd) : "";
      ::close(fd);
      if (err != EWOULDBLOCK)
        throw std::runtime_error(file.string() + ": cannot lock the output folder (" + std::strerror(err) + ")");
      throw OutputBusy(dir.string() + ": output folder in use by another cmc process (pid " + pid + ", lock file " +
                       file.string() + "); wait for it to finish, or choose another --out");
    }
    // The file locked must still be the one at that name (its holder may have removed it
    // with its empty folder just before): otherwise try again.
    struct stat locked {}, named {};
    if (::fstat(fd, &locked) == 0 && ::stat(file.c_str(), &named) == 0 && locked.st_dev == named.st_dev &&
        locked.st_ino == named.st_ino) {
      auto held = std::make_shared<Held>();
      held->fd = fd;
      held->dir = dir;
      held->created = created;
      const std::string pid = std::to_string(::getpid()) + "\n";
      if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != ssize_t(pid.size()))
        throw std::runtime_error(file.string() + ": cannot write the lock file (" + std::strerror(errno) + ")");
      registry()[key] = held;
      held_ = held;
      return;
    }
    ::close(fd);
    if (attempt == 10) throw std::runtime_error(file.string() + ": the lock file keeps changing; is another cmc starting?");
    fs::create_directories(dir, ec);
  }
}

}  // namespace cmc
