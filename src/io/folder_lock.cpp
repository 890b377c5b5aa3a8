// The output folder's lock: flock on OUT/.millwear.lock.
#include "io/folder_lock.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"

namespace millwear::io {

namespace fs = std::filesystem;

namespace {

// This process's command line, words joined by spaces, on one line.
std::string own_command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  std::string c = s.str();
  for (char& ch : c)
    if (ch == '\0' || ch == '\n' || ch == '\r') ch = ' ';
  while (!c.empty() && c.back() == ' ') c.pop_back();
  if (c.size() > 400) c = c.substr(0, 400) + " ...";
  return c.empty() ? std::string("millwear") : c;
}

// The holder writes its pid right after taking the lock: a refused process that looks in
// that instant finds the file still empty, so it looks again for a moment.
KeyValues read_holder(const std::string& path) {
  for (int i = 0; i < 40; ++i) {
    try {
      KeyValues kv = parse_key_values(read_file(path), path);
      if (!find_value(kv, "pid").empty()) return kv;
    } catch (const InputError&) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  return {};
}

std::string holder_text(const std::string& path) {
  const KeyValues kv = read_holder(path);
  const std::string pid = find_value(kv, "pid"), command = find_value(kv, "command");
  return pid.empty() ? "another process (its pid could not be read from " + path + ")"
                     : "millwear process " + pid + (command.empty() ? "" : " (" + command + ")");
}

[[noreturn]] void refuse(const std::string& folder, const std::string& path) {
  const std::string who = holder_text(path);
  throw InputError(folder, "-o",
                   "an output folder no other run is writing into, but " + who +
                       " holds its lock " + kFolderLockName +
                       "; wait for that process to end, or choose another folder");
}

}  // namespace

std::string folder_holder(const std::string& folder) {
  const std::string path = join_path(folder, kFolderLockName);
  // A read-only descriptor is enough for flock, so a run folder on a read-only disk reads.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";  // no lock file: no holder (a holder removes it as it releases)
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held ? holder_text(path) : "";
}

void check_output_path_text(const std::string& path, const std::string& what) {
  for (const char c : path)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw InputError(path, "-o", what + " without control characters (newline, tab) in its path");
  for (const fs::path& part : fs::path(path))
    if (part.native().size() > kMaxNameBytes)
      throw InputError(path, "-o", what + " whose names are at most " + std::to_string(kMaxNameBytes) +
                                       " bytes each, but one has " + std::to_string(part.native().size()));
}

void check_output_folder(const std::string& path) {
  if (path.empty()) throw InputError("", "-o", "an output folder");
  check_output_path_text(path, "an output folder");
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec))
    throw InputError(path, "-o", "an output folder, but a file of that name exists");
  // The nearest folder on the way that exists must be one this user can write into: a path
  // that cannot be made (a file on the way, no permission) is refused now, not once the work
  // is done. Nothing is made here (screen tasks make their folders side by side).
  // A symbolic link on the way that leads nowhere (its target missing, or a loop) can be
  // neither made nor written through.
  fs::path p = fs::path(path).lexically_normal();
  while (!p.empty() && !fs::exists(p, ec)) {
    std::error_code link_ec;
    if (fs::is_symlink(fs::symlink_status(p, link_ec))) {
      std::error_code target_ec;
      const fs::path target = fs::read_symlink(p, target_ec);
      throw InputError(path, "-o",
                       "an output folder that can be made, but " + p.string() + " is a symbolic link to '" +
                           target.string() + "', which " +
                           (ec && ec != std::errc::no_such_file_or_directory ? "cannot be followed (" + ec.message() + ")"
                                                                            : std::string("does not exist")));
    }
    p = p.parent_path();
  }
  if (p.empty()) p = ".";
  if (!fs::is_directory(p, ec))
    throw InputError(path, "-o", "an output folder that can be made, but " + p.string() + " is a file");
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError(path, "-o",
                     "an output folder that can be made, but " + p.string() + " is not writable (" + std::strerror(errno) + ")");
  // access() passes root everywhere and knows nothing of read-only or virtual file systems
  // (/proc): a file made and removed at once is the test that holds. Its name is a temporary's
  // (unique per process and call; a leftover is cleared like any other temporary).
  const std::string probe = temp_path_for((p / "probe").string());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    throw InputError(path, "-o",
                     "an output folder that can be made, but no file can be made in " + p.string() + " (" +
                         std::strerror(errno) + ")");
  ::close(fd);
  ::unlink(probe.c_str());
}

namespace {

// A folder whose command stopped before writing anything (refused, or failed early) holds
// only its mark and lock: the mark goes, and any command may take the folder.
void unmark_if_nothing_written(const std::string& folder) {
  // The mark, the lock and temporaries are all hidden: a visible entry is something written.
  if (!visible_entries(folder).empty()) return;
  std::error_code ec;
  fs::remove(folder_mark_path(folder), ec);
}

}  // namespace

FolderLock::FolderLock(const std::string& folder, const char* command)
    : folder_(folder), path_(join_path(folder, kFolderLockName)) {
  check_output_folder(folder);
  std::error_code ec;
  made_ = !fs::exists(folder, ec);
  ensure_dir(folder);
  // The file is removed on release; a process that opened it just before that would hold a
  // lock on a file no longer in the folder. So after flock, the file must still be the one
  // at the path, else start again.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0 && errno == ENOENT) {
      // The holder that made the folder released it empty and removed it: make it again.
      ensure_dir(folder);
      continue;
    }
    if (fd < 0)
      throw RunError("cannot create the lock file " + path_ + " (" + std::strerror(errno) + ")");
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd);
      if (err == EWOULDBLOCK) refuse(folder_, path_);
      throw RunError("cannot lock " + path_ + " (" + std::strerror(err) + ")");
    }
    struct stat held {}, named {};
    if (::fstat(fd, &held) != 0 || ::stat(path_.c_str(), &named) != 0 || held.st_ino != named.st_ino ||
        held.st_dev != named.st_dev) {
      ::close(fd);
      continue;
    }
    const std::string text = format_key_values(
        {{"pid", std::to_string(::getpid())}, {"command", own_command_line()}}, "millwear folder lock");
    if (::ftruncate(fd, 0) != 0 || ::write(fd, text.data(), text.size()) != static_cast<ssize_t>(text.size())) {
      const int err = errno;
      ::unlink(path_.c_str());
      ::close(fd);
      throw RunError("cannot write the lock file " + path_ + " (" + std::strerror(err) + ")");
    }
    fd_ = fd;
    if (command) {
      try {
        check_folder_not_taken(folder, command);
        mark_folder(folder, command);
      } catch (...) {
        release();
        throw;
      }
    }
    return;
  }
  throw RunError("cannot lock " + path_ + ": it keeps being replaced");
}

FolderLock::~FolderLock() { release(); }

void FolderLock::release() {
  if (fd_ < 0) return;
  unmark_if_nothing_written(folder_);
  // Unlink while still holding it: a waiting process then finds the path gone and retries.
  ::unlink(path_.c_str());
  ::close(fd_);
  // The folder, if the lock made it and the command left it empty (refused, or stopped before
  // its first file): rmdir removes only an empty folder. The folders made on the way stay:
  // other commands may be making theirs beside it.
  if (made_) ::rmdir(folder_.c_str());
  fd_ = -1;
}

}  // namespace millwear::io
