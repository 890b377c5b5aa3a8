#pragma once
// The files the view writes over: its own, never a file it reads or one it did not write. A
// saved scene, its lifter and every PNG carry the view's mark (a first comment line; a PNG
// text chunk right after the image header); a file already under the name one of them goes to
// is replaced only when it carries that mark, and never when it is one of the run's inputs
// (the scene on screen, the script), whatever it carries.
#include <cstddef>
#include <string>
#include <vector>

namespace millwear::view {

// A file the run reads, which nothing the view writes replaces.
struct RunInput {
  std::string file;
  std::string what;  // for the message: "the scene on screen", "the script being run"
};

// Why the view may not write `file` ("" when it may): it is one of `inputs` (the same file,
// however named), or something is there that is not a file whose bytes from `at` begin with
// `mark` (a file the view did not write). `mark_text` says what the mark is, for the message.
std::string overwrite_refusal(const std::string& file, const std::string& mark, std::size_t at,
                              const std::string& mark_text, const std::vector<RunInput>& inputs);

}  // namespace millwear::view
