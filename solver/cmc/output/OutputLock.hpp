// One owner per output folder. A cmc process that writes into a folder DIR holds an
// exclusive flock(2) on DIR/.cmc.lock (the file holds its process id) from before it
// writes anything there until it is done; a second process that asks for the same folder
// gets OutputBusy at once, with a message naming the folder and the holder's process id
// (`cmc` exits with code 4). The kernel drops the lock when its process ends, however it
// ends (SIGKILL included), so an interrupted run never leaves a stale lock behind and can
// be resumed at once. Within one process a folder may be locked more than once (a command
// that locks its --out early, then the Writer for the same folder): the holds are shared.
// A folder the lock created and that is still empty when the last hold goes (a command
// that stopped on bad input) is removed again, so bad input leaves nothing behind.
#pragma once

#include <filesystem>
#include <memory>
#include <stdexcept>

namespace cmc {

struct OutputBusy : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class OutputLock {
 public:
  OutputLock() = default;  // holds nothing
  // Creates `dir` if needed and locks it; throws OutputBusy when another process holds
  // it, std::runtime_error when the folder or its lock file cannot be made.
  explicit OutputLock(const std::filesystem::path& dir);
  bool held() const { return held_ != nullptr; }
  static const char* file_name() { return ".cmc.lock"; }

  struct Held;  // the open, locked file (OutputLock.cpp)

 private:
  std::shared_ptr<Held> held_;
};

}  // namespace cmc
