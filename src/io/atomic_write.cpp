#include "io/atomic_write.hpp"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include "common/errors.hpp"

namespace millwear::io {

namespace fs = std::filesystem;

namespace {

std::atomic<unsigned long> g_temp_counter{0};

std::string errno_text(int err) { return std::strerror(err); }

[[noreturn]] void fail(const std::string& path, const std::string& what, int err) {
  throw RunError("cannot write " + path + ": " + what + " (" + errno_text(err) + ")");
}

std::string parent_of(const std::string& path) {
  fs::path p(path);
  fs::path parent = p.parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// fsync on the folder makes the rename durable; some file systems refuse fsync on a
// folder (EINVAL): that is not an error for us, the content itself is already synced.
void sync_dir(const std::string& dir) {
  int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

constexpr const char kTempTag[] = ".millwear-tmp.";

std::string temp_path_for(const std::string& path) {
  const fs::path p(path);
  std::ostringstream s;
  s << '.' << p.filename().string() << kTempTag << ::getpid() << "." << g_temp_counter.fetch_add(1);
  return (p.parent_path() / s.str()).string();
}

bool is_temp_name(const std::string& filename) {
  // .NAME.millwear-tmp.<pid>.<n>, then anything (gnuplot adds .png, .svg to its base).
  if (filename.size() < 2 || filename[0] != '.') return false;
  const std::size_t tag = filename.find(kTempTag, 2);
  if (tag == std::string::npos) return false;
  std::size_t i = tag + sizeof kTempTag - 1;
  auto digits = [&] {
    const std::size_t from = i;
    while (i < filename.size() && std::isdigit(static_cast<unsigned char>(filename[i]))) ++i;
    return i > from;
  };
  if (!digits() || i >= filename.size() || filename[i] != '.') return false;
  ++i;
  return digits() && (i == filename.size() || filename[i] == '.');
}

void write_file_atomic(const std::string& path, const std::string& content) {
  if (path.empty()) throw RunError("cannot write a file with an empty path");
  const std::string tmp = temp_path_for(path);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(path, "cannot create temporary " + tmp, errno);

  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      int err = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      fail(path, "write failed", err);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    int err = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    fail(path, "fsync failed", err);
  }
  if (::close(fd) != 0) {
    int err = errno;
    ::unlink(tmp.c_str());
    fail(path, "close failed", err);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    int err = errno;
    ::unlink(tmp.c_str());
    fail(path, "rename from " + tmp + " failed", err);
  }
  sync_dir(parent_of(path));
}

void ensure_dir(const std::string& path) {
  if (path.empty()) throw RunError("cannot create a folder with an empty path");
  std::error_code ec;
  if (fs::is_directory(path, ec)) return;
  fs::create_directories(path, ec);
  // create_directories can report an error when another thread created it first.
  if (fs::is_directory(path)) return;
  if (fs::exists(path))
    throw RunError("cannot create folder " + path + ": a file with that name exists");
  throw RunError("cannot create folder " + path + ": " + ec.message());
}

bool file_exists(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

std::string read_file(const std::string& path) {
  // A FIFO or a device would block or never end: only a regular file (or a link to one) is
  // read.
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(path, "", fs::is_directory(st) ? "a readable file, but it is a folder"
                                                     : "a readable file, but it is not a regular file (a FIFO, socket or device)");
  // A file is read whole and parsed into several times its size: a size past any input's is
  // refused before it is read (a multi-gigabyte file would exhaust memory first).
  const std::uintmax_t bytes = fs::is_regular_file(st) ? fs::file_size(path, ec) : 0;
  if (!ec && bytes > kMaxInputFileBytes)
    throw InputError(path, "", "a file of at most " + std::to_string(kMaxInputFileBytes >> 20) +
                                   " MB (a liner scan of ten million points), found " +
                                   std::to_string(bytes >> 20) + " MB");
  if (!fs::exists(st)) throw InputError(path, "", "a file there (not found)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "a readable file (it cannot be opened: its permissions?)");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "a readable file (read failed)");
  return s.str();
}

int remove_stale_temps(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return 0;
  int removed = 0;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    if (!is_temp_name(entry.path().filename().string())) continue;
    if (fs::remove(entry.path(), ec)) ++removed;
  }
  return removed;
}

}  // namespace millwear::io
