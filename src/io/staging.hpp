#pragma once
// A command's new results drawn up beside its earlier ones: written into OUT/.millwear-staging
// (hidden, in OUT so that every move is a rename on one file system) and moved into OUT only
// once all of them are complete. Until then OUT holds the earlier results as they were; a
// command that fails or is stopped before the move leaves them so, and its staging folder is
// removed. Hold OUT's lock (io/folder_lock.hpp) for the staging's whole life.
#include <string>
#include <vector>

namespace millwear::io {

// The staging folder's name inside OUT.
constexpr const char* kStagingName = ".millwear-staging";

class StagedOutputs {
 public:
  // Makes OUT/.millwear-staging empty (a killed command's is stale: the lock says no other
  // command writes there). Throws RunError if it cannot.
  explicit StagedOutputs(const std::string& out);
  // Removes the staging folder (empty once committed).
  ~StagedOutputs();
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;

  const std::string& dir() const { return dir_; }
  const std::string& out() const { return out_; }
  // A path under the staging folder as it will be in OUT (any other path unchanged).
  std::string in_out(const std::string& staged_path) const;
  // A message (a figure's error, a warning) with every mention of the staging folder read as
  // OUT, where its files are once committed.
  std::string in_out_text(std::string text) const;

  // Moves every staged file to the same place in OUT, each by one rename over the earlier
  // file of its name (a reader finds the earlier file or the new one, never none or a part),
  // manifest.json last; then deletes the files the earlier OUT/manifest.json listed that no
  // new file replaced (remove_run_files: never one of `keep`, the command's inputs) and the
  // staging folder. Ctrl-C and SIGTERM are held off meanwhile, and one that came is dropped:
  // the command ends as without it. Throws RunError naming the file that could not be moved.
  void commit(const std::vector<std::string>& keep = {});

 private:
  std::string out_, dir_;
};

}  // namespace millwear::io
