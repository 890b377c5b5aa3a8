// PNG encoding by stb_image_write (Debian's libstb), into memory, then one atomic write.
#include "view/png.hpp"

#include <filesystem>

#include <stb_image_write.h>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"

namespace millwear::view {

namespace {
void append(void* context, void* data, int size) {
  auto* out = static_cast<std::string*>(context);
  out->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}
}  // namespace

void write_png(const std::string& file, int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw RunError("screenshot of " + file + ": no image to write");
  std::string bytes;
  if (!stbi_write_png_to_func(append, &bytes, width, height, 3, rgb.data(), width * 3))
    throw RunError("could not encode the PNG image " + file);
  // Its folder made as a recording's is (a script's `screenshot shots/a.png`).
  const std::string folder = std::filesystem::path(file).parent_path().string();
  if (!folder.empty()) io::ensure_dir(folder);
  io::write_file_atomic(file, bytes);
}

}  // namespace millwear::view
