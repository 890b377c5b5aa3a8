// New results drawn up in OUT/.millwear-staging, moved into OUT once complete (staging.hpp).
#include "io/staging.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"

namespace millwear::io {

namespace fs = std::filesystem;

namespace {

// The renames into a folder made durable (write_file_atomic synced each file's content).
void sync_folder(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Ctrl-C and SIGTERM held off while the files move: a command that died of one then would
// leave OUT with some files new and others earlier. One that comes meanwhile is dropped
// unless they were held off before: the command has done its work and ends as without it.
// By the move the command's worker threads have ended, so this thread is the one a signal
// reaches.
class HeldStops {
 public:
  HeldStops() {
    sigemptyset(&stops_);
    sigaddset(&stops_, SIGINT);
    sigaddset(&stops_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stops_, &before_);
  }
  ~HeldStops() {
    const timespec none{0, 0};
    sigset_t drop;
    sigemptyset(&drop);
    for (int sig : {SIGINT, SIGTERM})
      if (!sigismember(&before_, sig)) sigaddset(&drop, sig);
    while (sigtimedwait(&drop, nullptr, &none) > 0) {
    }
    pthread_sigmask(SIG_SETMASK, &before_, nullptr);
  }
  HeldStops(const HeldStops&) = delete;
  HeldStops& operator=(const HeldStops&) = delete;

 private:
  sigset_t stops_{}, before_{};
};

}  // namespace

StagedOutputs::StagedOutputs(const std::string& out) : out_(out), dir_(join_path(out, kStagingName)) {
  std::error_code ec;
  fs::remove_all(dir_, ec);
  if (ec) throw RunError("cannot clear the staging folder " + dir_ + ": " + ec.message());
  ensure_dir(dir_);
}

StagedOutputs::~StagedOutputs() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::string StagedOutputs::in_out(const std::string& staged_path) const {
  const std::string rel = relative_to(dir_, staged_path);
  return rel.empty() ? staged_path : join_path(out_, rel);
}

std::string StagedOutputs::in_out_text(std::string text) const {
  for (std::size_t at = 0; (at = text.find(dir_, at)) != std::string::npos; at += out_.size())
    text.replace(at, dir_.size(), out_);
  return text;
}

void StagedOutputs::commit(const std::vector<std::string>& keep) {
  const std::vector<std::string> earlier = manifest_files(out_);
  std::vector<std::string> staged;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file()) staged.push_back(relative_to(dir_, it->path().string()));
  if (ec) throw RunError("cannot list the staging folder " + dir_ + ": " + ec.message());
  // The manifest last: once it is in place, every file it lists is.
  std::sort(staged.begin(), staged.end(), [](const std::string& a, const std::string& b) {
    return std::make_pair(a == "manifest.json", a) < std::make_pair(b == "manifest.json", b);
  });
  const HeldStops held;
  std::set<std::string> folders;
  for (const std::string& f : staged) {
    const std::string from = join_path(dir_, f), to = join_path(out_, f);
    const std::string folder = fs::path(to).parent_path().string();
    ensure_dir(folder);
    if (::rename(from.c_str(), to.c_str()) != 0)
      throw RunError("cannot move the new " + f + " into " + out_ + " (" + std::strerror(errno) + ")");
    folders.insert(folder);
  }
  for (const std::string& d : folders) sync_folder(d);
  std::vector<std::string> stale;
  for (const std::string& f : earlier)
    if (std::find(staged.begin(), staged.end(), f) == staged.end()) stale.push_back(f);
  remove_run_files(out_, stale, keep);
  fs::remove_all(dir_, ec);
}

}  // namespace millwear::io
