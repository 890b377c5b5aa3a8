#pragma once
// Atomic file output. Every file a run leaves behind is written under a temporary name
// in the same folder, flushed to disk, then renamed over the final name: a reader (or a
// resumed run after Ctrl-C, SIGTERM or a crash) sees either the old file or the complete
// new one, never a truncated one. rename() is atomic only within one file system, which
// is why the temporary lives next to the target and not in /tmp.
#include <cstdint>
#include <string>

namespace millwear::io {

// Writes `content` to `path` atomically: `.NAME.millwear-tmp.<pid>.<n>` in the same folder
// (NAME the file name of `path`: hidden, and tagged so that no file of the user's is ever
// taken for one), write, fsync, rename, then fsync the folder so the rename itself survives
// a power cut.
// <n> is a per-process counter so that threads writing the same path do not share a
// temporary. The parent folder must exist (see ensure_dir).
// Throws millwear::RunError naming the path on any failure; the temporary is removed.
void write_file_atomic(const std::string& path, const std::string& content);

// Creates `path` and any missing parents (like mkdir -p). Succeeds if it already is a
// folder. Throws millwear::RunError naming the path if it cannot, or if it is a file.
void ensure_dir(const std::string& path);

// True if `path` names an existing regular file.
bool file_exists(const std::string& path);

// The largest file read_file reads: 256 MB, ten times a scan of a million points.
constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t{256} << 20;

// The whole content of a file. Throws millwear::InputError(path, "", ...) if unreadable or
// larger than kMaxInputFileBytes: files read back are the user's (or a previous run's) input.
std::string read_file(const std::string& path);

// The temporary name write_file_atomic would use for `path` next (for tests and for
// tools that let another program write, then rename: see plots/).
std::string temp_path_for(const std::string& path);

// True if a file name (no folder) is one of our temporaries: `.NAME.millwear-tmp.<pid>.<n>`,
// optionally followed by `.EXT` (figures drawn to a temporary base). A user's `x.tmp.1`
// is not one.
bool is_temp_name(const std::string& filename);

// Deletes leftover temporaries (is_temp_name) directly inside `dir`, left by a run that
// was killed between write and rename. Returns how many were removed. Missing dir -> 0.
// Call it only while holding the folder's lock (io/folder_lock.hpp): then no other run is
// writing there and every temporary is stale.
int remove_stale_temps(const std::string& dir);

}  // namespace millwear::io
