#pragma once
// One writer per output folder. A command that writes into OUT holds OUT/.millwear.lock
// (flock, exclusive, non-blocking) for as long as it writes: a second millwear pointed at
// the same folder is refused at once, naming the process that holds it, instead of the two
// mixing their files or deleting each other's temporaries.
//
// The lock file holds the holder's pid and command line (key=value text):
//   # millwear folder lock
//   pid=12345
//   command=millwear run scene.toml -o OUT
// It is removed when the lock is released, and so is the folder if the lock made it and the
// command left it empty, so a finished or refused command leaves the folder as it found it. The kernel drops a flock when its process dies, so a lock file left by a
// killed run does not block the next one: it is simply taken over.
#include <cstddef>
#include <string>

namespace millwear::io {

// Name of the lock file inside a locked folder.
constexpr const char* kFolderLockName = ".millwear.lock";

// The longest file or folder name (in bytes) the common Linux file systems take.
constexpr std::size_t kMaxNameBytes = 255;

// Throws InputError(path, "-o", ...) if an output path (what = "an output folder" or "an output
// file") has a control character (a newline breaks the figures' gnuplot scripts) or a name
// longer than kMaxNameBytes: found before any work, not when the first file is written.
void check_output_path_text(const std::string& path, const std::string& what);

// Throws InputError(path, "-o", "a folder ...") if check_output_path_text does, if `path`
// exists and is not a folder, or if
// the nearest folder on its way that exists is a file or not writable. Makes nothing: call it
// before any work, so that a bad -o stops every command alike.
void check_output_folder(const std::string& path);

// Who holds `folder`'s lock ("millwear process PID (COMMAND)"), or "" if no process does.
// Takes nothing and writes nothing: for a command that only reads a run folder, which must
// not read one still being written.
std::string folder_holder(const std::string& folder);

class FolderLock {
 public:
  // Checks the path (check_output_folder), creates the folder if needed (ensure_dir) and
  // takes its lock. Throws InputError(folder, "-o", ...) naming the holder's pid if another
  // process holds it, RunError if the lock file cannot be made. With a command (a command
  // other than `run`, which tells its own runs apart): also refuses a folder holding another
  // command's results (run_folder.hpp's check_folder_not_taken), under the lock, and marks
  // the folder as this command's (mark_folder). On release, a mark with nothing written
  // beside it is removed.
  explicit FolderLock(const std::string& folder, const char* command = nullptr);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  const std::string& folder() const { return folder_; }
  const std::string& path() const { return path_; }

 private:
  void release();

  std::string folder_, path_;
  bool made_ = false;  // the folder did not exist before the lock
  int fd_ = -1;
};

}  // namespace millwear::io
