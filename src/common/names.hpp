#pragma once
// Names that end up in file names and CSV fields (scene, design, species and profile names).
// One rule everywhere: letters, digits, '.', '-', '_' and '+', not starting with '.', at most
// kMaxNameLength characters. Such a name needs no quoting in CSV, JSON or a shell, and is a
// plain file name on every file system.
#include <cstddef>
#include <string>

namespace millwear {

constexpr std::size_t kMaxNameLength = 64;

inline bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
         c == '_' || c == '+';
}

inline bool is_safe_name(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameLength || name[0] == '.') return false;
  for (char c : name)
    if (!is_name_char(c)) return false;
  return true;
}

// What a safe name is, for messages.
inline std::string safe_name_rule() {
  return "a name of at most " + std::to_string(kMaxNameLength) +
         " letters, digits, '.', '-', '_' or '+', not starting with '.'";
}

// A safe name made from any text (a file's stem): every other character becomes '_', a
// leading '.' too, cut to kMaxNameLength; "scene" if nothing is left.
inline std::string safe_name_from(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (out.size() == kMaxNameLength) break;
    out += is_name_char(c) ? c : '_';
  }
  if (!out.empty() && out[0] == '.') out[0] = '_';
  return out.empty() ? "scene" : out;
}

}  // namespace millwear
