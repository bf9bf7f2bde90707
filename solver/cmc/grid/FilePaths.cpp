#include "cmc/grid/FilePaths.hpp"

#include <unistd.h>

#include <fstream>

namespace cmc {

namespace fs = std::filesystem;

namespace {
// What a path that is not absent is, for messages.
std::string what_it_is(fs::file_type t) {
  switch (t) {
    case fs::file_type::directory: return "a folder";
    case fs::file_type::regular: return "a regular file";
    case fs::file_type::symlink: return "a symbolic link";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::fifo: return "a FIFO (named pipe)";
    case fs::file_type::socket: return "a socket";
    default: return "neither a regular file nor a folder";
  }
}
}  // namespace

void check_output_file(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (st.type() == fs::file_type::not_found || st.type() == fs::file_type::regular) return;
  if (ec) throw OutputPathError(path.string() + ": cannot be examined (" + ec.message() + "): not written");
  std::string msg = path.string() + ": is " + what_it_is(st.type());
  if (st.type() == fs::file_type::symlink) {
    const fs::path to = fs::read_symlink(path, ec);
    msg += " (to " + (ec ? std::string("?") : to.string()) +
           "); cmc does not replace links or write through them: give the file it points to, or another path";
  } else {
    msg += "; cmc writes only new files and replaces only regular files: give the path of a file";
  }
  throw OutputPathError(msg);
}

void check_output_folder(const fs::path& dir) {
  if (dir.empty()) throw OutputPathError("an empty output folder name: expected a folder");
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(dir, ec), ec);
  if (!ec && canonical == canonical.root_path())
    throw OutputPathError(dir.string() + ": is the root folder; give a folder of its own for cmc's outputs");
  const fs::file_status st = fs::status(dir, ec);  // a link to a folder is a folder
  if (st.type() == fs::file_type::not_found || st.type() == fs::file_type::directory) return;
  if (fs::is_symlink(fs::symlink_status(dir, ec)))
    throw OutputPathError(dir.string() + ": is a symbolic link that cannot be resolved; expected a folder");
  throw OutputPathError(dir.string() + ": is " + what_it_is(st.type()) + ", expected a folder for cmc's outputs");
}

void write_output_file(const fs::path& path, const std::function<void(const fs::path&)>& fill) {
  check_output_file(path);
  const fs::path folder = path.parent_path();
  std::error_code ec;
  if (!folder.empty() && !fs::is_directory(folder, ec))
    throw OutputPathError(path.string() + ": its folder " + folder.string() + " does not exist (or is not a folder)");
  std::string name(1, '.');  // (appended, not "." + ...: GCC 12 warns falsely of the latter)
  name.append(path.filename().string()).append(".tmp").append(std::to_string(::getpid()));
  const fs::path tmp = folder / name;
  fs::remove(tmp, ec);  // one of an earlier process with this id, killed while writing
  try {
    fill(tmp);
    check_output_file(path);  // not replaced by a special file meanwhile
    fs::rename(tmp, path);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

void write_output_text(const fs::path& path, const std::string& text) {
  write_output_file(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write (is the output folder writable?)");
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(tmp.string() + ": write failed (disk full?)");
  });
}

void remove_output_file(const fs::path& path) {
  check_output_file(path);
  std::error_code ec;
  fs::remove(path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot remove the earlier output (" + ec.message() + ")");
}

std::string input_file_problem(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::regular) return "";
  if (st.type() == fs::file_type::directory) return "is a folder, expected a file";
  if (st.type() == fs::file_type::not_found || st.type() == fs::file_type::none) {
    std::error_code lec;
    if (fs::is_symlink(fs::symlink_status(path, lec)))
      return "is a symbolic link that cannot be resolved (a loop, or a missing target)";
    if (ec && ec != std::errc::no_such_file_or_directory) return "cannot be examined (" + ec.message() + ")";
    return "no such file";
  }
  return "is " + what_it_is(st.type()) + ", expected a file on disk";
}

}  // namespace cmc
